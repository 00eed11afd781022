//! `raylab trace`: every ray of one pixel, as a tree.

use crate::Chapters;
use anyhow::{Result, bail};
use clap::Args;

use super::render::{SettingsOverrides, select_scene};
use crate::ray_tree::{PixelTrace, TracedRay, trace_pixel};
use crate::render::RayKind;
use crate::{Stage, Vec3};

/// Show every ray of one pixel as a tree, in the order the chapter cast
/// them: its kind, origin, direction and range, what it met (object,
/// point, normals, material) and the colour it brought back; shadow rays
/// say which light they looked at and whether it was blocked. The last
/// line is the pixel, exactly as `raylab render` writes it. In a
/// workspace it runs your chapters.
#[derive(Debug, Args)]
pub struct TraceArgs {
    /// Chapter whose stage to trace (see `raylab chapters`) [default: 8].
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// The pixel, `x,y` from the top-left corner.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_pixel)]
    pub pixel: (u32, u32),
    /// A TOML scene file instead of the chapter's built-in scene.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<std::path::PathBuf>,
    /// Show only this sample's tree (from 0), when the pixel takes several.
    #[arg(long, value_name = "K")]
    pub sample: Option<usize>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub overrides: SettingsOverrides,
}

pub(super) fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y] = parts[..] else {
        return Err(format!("expected `x,y`, got `{text}`"));
    };
    let number = |part: &str| {
        part.parse::<u32>().map_err(|_| {
            format!(
                "`{part}` is not a pixel coordinate (a whole number from 0 to {})",
                u32::MAX
            )
        })
    };
    Ok((number(x)?, number(y)?))
}

pub fn trace<C: Chapters>(args: &TraceArgs) -> Result<i32> {
    let chapter = args.chapter.or(args.scene.is_none().then_some(8));
    let (scene, chapter) = select_scene(chapter, args.scene.as_deref())?;
    let settings = args.overrides.settings_for(&scene, chapter)?;
    let stage = Stage::<C>::with_chapters(&scene, chapter, settings)?;
    let (x, y) = args.pixel;
    let Some(traced) = trace_pixel(&stage, (x, y)) else {
        bail!(
            "pixel {x},{y} is outside the {}x{} image",
            settings.width,
            settings.height
        );
    };
    if let Some(sample) = args.sample
        && sample >= traced.samples.len()
    {
        bail!(
            "sample {sample} does not exist: pixel {x},{y} takes {} (from 0)",
            traced.samples.len()
        );
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&traced.to_json(chapter, args.sample))?
        );
    } else {
        print!("{}", text(chapter, &traced, args.sample));
    }
    Ok(0)
}

fn show_wide(v: glam::DVec3) -> String {
    // Six decimals: an 8-bit pixel is a step of 1/255 in sRGB, and what a
    // difference of colours leaves below 1e-6 is rounding.
    let digits = |x: f64| format!("{:.6}", if x.abs() < 5e-7 { 0.0 } else { x });
    format!("({}, {}, {})", digits(v.x), digits(v.y), digits(v.z))
}

fn show(v: Vec3) -> String {
    format!("({}, {}, {})", number(v.x), number(v.y), number(v.z))
}

/// `x` with every digit that tells it from its neighbours (Rust's shortest
/// round-trip form), in exponent form when it is very small or very large:
/// `1e-45`, not 45 zeros, for the smallest subnormal a rounding can leave.
fn number(x: f32) -> String {
    let magnitude = x.abs();
    if magnitude == 0.0 || !magnitude.is_finite() || (1e-4..1e7).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn text(chapter: u8, traced: &PixelTrace, sample: Option<usize>) -> String {
    let (x, y) = traced.pixel;
    let count = traced.samples.len();
    let mut out = if count == 1 {
        format!("chapter {chapter}, pixel {x},{y}: 1 camera ray\n")
    } else {
        // Each ray's share is of its sample's colour; the running sum, of
        // the pixel's.
        format!(
            "chapter {chapter}, pixel {x},{y}: {count} camera rays, one a sample, each sample \
             1/{count} of the pixel\n"
        )
    };
    for (index, root) in traced.chosen(sample) {
        out += &format!("sample {index}:\n");
        ray_text(root, 1, &mut out);
    }
    if traced.truncated {
        out += &format!(
            "(more than {} rays: the rest are not shown)\n",
            crate::ray_tree::MAX_TRACED_RAYS
        );
    }
    if let Some(light) = traced.light_paths {
        out += &format!(
            "light paths (chapter 14): the light they splatted on this pixel adds {} to the \
             camera rays' {}\n",
            show(light),
            show(traced.color - light)
        );
    }
    let [r, g, b] = traced.srgb;
    out += &format!(
        "pixel {x},{y}: linear {} -> sRGB ({r}, {g}, {b}), as the render writes it\n",
        show(traced.color)
    );
    out
}

fn ray_text(ray: &TracedRay, depth: usize, out: &mut String) {
    let indent = "  ".repeat(depth);
    let range = format!("{} < t < {}", number(ray.t_min), number(ray.t_max));
    let share = match ray.weight {
        Some(weight) => format!(", {} of its sample", number(weight)),
        None => String::new(),
    };
    out.push_str(&format!(
        "{indent}{} ray from {} along {}, {range}{share}\n",
        ray.kind.name(),
        show(ray.ray.origin),
        show(ray.ray.dir)
    ));
    let name = |name: &str| crate::text::terminal_safe(name);
    match (&ray.hit, ray.kind) {
        (Some(hit), RayKind::Shadow) => out.push_str(&format!(
            "{indent}  blocked by \"{}\" (shape {}) at t = {}: {} in shadow\n",
            name(&hit.name),
            hit.shape,
            number(hit.t),
            light_text(ray.light)
        )),
        (None, RayKind::Shadow) => {
            out.push_str(&format!(
                "{indent}  nothing in the way: {} lights the point",
                light_text(ray.light)
            ));
            if let Some(share) = ray.light_share {
                out.push_str(&format!(
                    ", adding diffuse {} and specular {}",
                    show(share.diffuse),
                    show(share.specular)
                ));
            }
            out.push('\n');
        }
        (Some(hit), _) => {
            out.push_str(&format!(
                "{indent}  hits \"{}\" (shape {}) at t = {}, point {}, geometric normal {}, \
                 shading normal {}, albedo {}\n",
                name(&hit.name),
                hit.shape,
                number(hit.t),
                show(hit.point),
                show(hit.geometric_normal),
                show(hit.shading_normal),
                show(hit.albedo)
            ));
            if let Some((along, distance)) = off_surface(&ray.ray, hit.t, hit.point) {
                out.push_str(&format!(
                    "{indent}  but the ray at t = {} is at {}, {} from that point on the \
                     surface: is t right?\n",
                    number(hit.t),
                    show(along),
                    number(distance)
                ));
            }
        }
        (None, _) => out.push_str(&format!("{indent}  misses everything: the background\n")),
    }
    if let (Some(own), Some(sum)) = (ray.contribution, ray.running_sum) {
        out.push_str(&format!(
            "{indent}  adds {} of its own to the pixel: running sum {}\n",
            show_wide(own),
            show_wide(sum)
        ));
    }
    for child in &ray.children {
        ray_text(child, depth + 1, out);
    }
    if let Some(color) = ray.color {
        let contribution = match ray.weight {
            Some(weight) if ray.kind != RayKind::Primary => {
                format!(" (times its share: {})", show(color * weight))
            }
            _ => String::new(),
        };
        out.push_str(&format!(
            "{indent}  brings back {}{contribution}\n",
            show(color)
        ));
    }
}

/// Where `ray` is at `t`, and how far that is from `point`, the point on
/// the surface that shading uses (raylab puts a hit back onto its
/// surface), when they are further apart than rounding explains: a `t`
/// that is not where the ray meets the shape reads as a point on it.
fn off_surface(ray: &crate::Ray, t: f32, point: Vec3) -> Option<(Vec3, f32)> {
    let along = ray.at(t);
    let distance = along.distance(point);
    (distance > 1e-3 * (1.0 + along.length().max(point.length()))).then_some((along, distance))
}

fn light_text(light: Option<usize>) -> String {
    match light {
        Some(index) => format!("light {index}"),
        None => "the light".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::{number, off_surface};
    use crate::{Ray, Vec3};

    /// A `t` whose point is not on the surface is flagged, with where the
    /// ray really is; rounding is not.
    #[test]
    fn a_hit_whose_t_is_off_its_surface_is_flagged() {
        let up = Ray::new(Vec3::new(0.0, 1.5, 2.25), Vec3::new(0.0, 0.15, 1.0));
        let t = 9.834386;
        let on_floor = Vec3::new(up.at(t).x, 0.0, up.at(t).z);
        let (along, distance) = off_surface(&up, t, on_floor).expect("flagged");
        assert!((along.y - 2.975158).abs() < 1e-3, "{along}");
        assert!((distance - along.y).abs() < 1e-4, "{distance}");
        let down = Ray::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
        let rounded = down.at(2.0) + Vec3::new(0.0, 1e-6, 0.0);
        assert_eq!(off_surface(&down, 2.0, rounded), None);
    }

    #[test]
    fn numbers_keep_their_digits_without_a_wall_of_zeros() {
        let smallest_subnormal = f32::from_bits(1);
        assert_eq!(number(smallest_subnormal), "1e-45");
        assert_eq!(number(1e-5), "1e-5");
        assert_eq!(number(0.0001), "0.0001");
        assert_eq!(number(0.1), "0.1");
        assert_eq!(number(-1.0 / 3.0), "-0.33333334");
        assert_eq!(number(1e20), "1e20");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(-0.0), "-0");
        assert_eq!(number(f32::INFINITY), "inf");
        assert!(number(f32::NAN).eq_ignore_ascii_case("nan"));
    }
}
