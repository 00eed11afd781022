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

fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y] = parts[..] else {
        return Err(format!("expected `x,y`, got `{text}`"));
    };
    let number = |part: &str| {
        part.parse::<u32>()
            .map_err(|_| format!("`{part}` is not a whole number of pixels"))
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
            serde_json::to_string_pretty(&json(chapter, &traced, args.sample))?
        );
    } else {
        print!("{}", text(chapter, &traced, args.sample));
    }
    Ok(0)
}

fn kind_name(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Primary => "camera",
        RayKind::Shadow => "shadow",
        RayKind::Reflection => "reflection",
        RayKind::Refraction => "refraction",
    }
}

fn show(v: Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

fn chosen(traced: &PixelTrace, sample: Option<usize>) -> Vec<(usize, &TracedRay)> {
    traced
        .samples
        .iter()
        .enumerate()
        .filter(|(index, _)| sample.is_none_or(|only| only == *index))
        .collect()
}

fn text(chapter: u8, traced: &PixelTrace, sample: Option<usize>) -> String {
    let (x, y) = traced.pixel;
    let mut out = format!(
        "chapter {chapter}, pixel {x},{y}: {} camera {}\n",
        traced.samples.len(),
        if traced.samples.len() == 1 {
            "ray"
        } else {
            "rays"
        }
    );
    for (index, root) in chosen(traced, sample) {
        out += &format!("sample {index}:\n");
        ray_text(root, 1, &mut out);
    }
    if traced.truncated {
        out += &format!(
            "(more than {} rays: the rest are not shown)\n",
            crate::ray_tree::MAX_TRACED_RAYS
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
    let range = format!("{} < t < {}", ray.t_min, ray.t_max);
    let share = match ray.weight {
        Some(weight) => format!(", {weight} of the pixel"),
        None => String::new(),
    };
    out.push_str(&format!(
        "{indent}{} ray from {} along {}, {range}{share}\n",
        kind_name(ray.kind),
        show(ray.ray.origin),
        show(ray.ray.dir)
    ));
    let name = |name: &str| crate::text::terminal_safe(name);
    match (&ray.hit, ray.kind) {
        (Some(hit), RayKind::Shadow) => out.push_str(&format!(
            "{indent}  blocked by \"{}\" (shape {}) at t = {}: {} in shadow\n",
            name(&hit.name),
            hit.shape,
            hit.t,
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
        (Some(hit), _) => out.push_str(&format!(
            "{indent}  hits \"{}\" (shape {}) at t = {}, point {}, geometric normal {}, shading \
             normal {}, albedo {}\n",
            name(&hit.name),
            hit.shape,
            hit.t,
            show(hit.point),
            show(hit.geometric_normal),
            show(hit.shading_normal),
            show(hit.albedo)
        )),
        (None, _) => out.push_str(&format!("{indent}  misses everything: the background\n")),
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

fn light_text(light: Option<usize>) -> String {
    match light {
        Some(index) => format!("light {index}"),
        None => "the light".to_string(),
    }
}

fn json(chapter: u8, traced: &PixelTrace, sample: Option<usize>) -> serde_json::Value {
    let (x, y) = traced.pixel;
    let samples: Vec<serde_json::Value> = chosen(traced, sample)
        .into_iter()
        .map(|(index, root)| serde_json::json!({ "sample": index, "ray": ray_json(root) }))
        .collect();
    serde_json::json!({
        "chapter": chapter,
        "pixel": [x, y],
        "samples": samples,
        "sample_count": traced.samples.len(),
        "color": traced.color.to_array(),
        "srgb": traced.srgb,
        "truncated": traced.truncated,
    })
}

fn ray_json(ray: &TracedRay) -> serde_json::Value {
    let hit = ray.hit.as_ref().map(|hit| {
        serde_json::json!({
            "shape": hit.shape,
            "name": hit.name,
            "t": hit.t,
            "point": hit.point.to_array(),
            "geometric_normal": hit.geometric_normal.to_array(),
            "shading_normal": hit.shading_normal.to_array(),
            "albedo": hit.albedo.to_array(),
            "material": {
                "color": hit.material.color.to_array(),
                "ambient": hit.material.ambient,
                "diffuse": hit.material.diffuse,
                "specular": hit.material.specular,
                "shininess": hit.material.shininess,
                "reflectivity": hit.material.reflectivity,
                "transparency": hit.material.transparency,
                "ior": hit.material.ior,
            },
        })
    });
    serde_json::json!({
        "kind": kind_name(ray.kind),
        "origin": ray.ray.origin.to_array(),
        "direction": ray.ray.dir.to_array(),
        "t_min": ray.t_min,
        "t_max": ray.t_max,
        "weight": ray.weight,
        "hit": hit,
        "light": ray.light,
        "light_share": ray.light_share.map(|share| serde_json::json!({
            "diffuse": share.diffuse.to_array(),
            "specular": share.specular.to_array(),
        })),
        "color": ray.color.map(|color| color.to_array()),
        "children": ray.children.iter().map(ray_json).collect::<Vec<_>>(),
    })
}
