//! A finished sweep as text: the command that reproduces it, the Markdown
//! table `raylab cost` prints and the CSV it writes. These read only a
//! [`CostReport`], so they change with its columns, never with how a
//! sweep runs.

use std::fmt::Write as _;

use super::{CostReport, Knob, Measurement};
use crate::RayKind;
use crate::effects::Effects;

impl Measurement {
    /// Samples per pixel actually taken at `chapter`'s stage.
    fn samples_at(&self, chapter: u8) -> u32 {
        if Effects::for_chapter(chapter).antialiasing {
            self.settings.samples
        } else {
            1
        }
    }

    fn knob_name(&self) -> &'static str {
        self.knob.map_or("reference", Knob::name)
    }
}

/// A relative MSE for the table: three significant digits, `-` without one.
fn format_relative_mse(relative_mse: Option<f64>) -> String {
    relative_mse.map_or_else(|| "-".into(), |value| format!("{value:.2e}"))
}

fn format_psnr(psnr: f64) -> String {
    if psnr.is_finite() {
        format!("{psnr:.1}")
    } else {
        "inf".into()
    }
}

impl CostReport {
    /// The command line that reproduces this report.
    pub fn command(&self, knobs: &[Knob], out: Option<&str>) -> String {
        let mut command = format!("raylab cost --chapter {}", self.chapter);
        if self.scene_name != "built-in scene" {
            let _ = write!(command, " --scene {}", self.scene_name);
        }
        let _ = write!(command, " --width {} --height {}", self.width, self.height);
        let _ = write!(command, " --repeats {}", self.repeats);
        if knobs != Knob::of_chapter(self.chapter).as_slice() {
            for knob in knobs {
                let _ = write!(command, " --knob {}", knob.name());
            }
        }
        if let Some(out) = out {
            let _ = write!(command, " --out {out}");
        }
        command
    }

    /// The report as a Markdown table with a short header.
    pub fn markdown(&self) -> String {
        let mut text = String::new();
        let reference = self.rows.first().map(|r| r.settings);
        let _ = writeln!(
            text,
            "Chapter {} stage, {} ({}x{}); time: median of {}; error against the reference in 8-bit sRGB codes, and its relative MSE in linear light.",
            self.chapter,
            self.scene_name,
            self.width,
            self.height,
            crate::text::count(u64::from(self.repeats), "run")
        );
        if let Some(reference) = reference {
            let samples = if Effects::for_chapter(self.chapter).antialiasing {
                format!("{} jittered spp", reference.samples)
            } else {
                "1 spp (this stage does not supersample)".into()
            };
            let fresnel = if Effects::for_chapter(self.chapter).fresnel {
                ", exact Fresnel on every transparent material"
            } else {
                ""
            };
            let stage = Effects::for_chapter(self.chapter);
            // Paths never skip a ray by its share: roulette ends them.
            let cut_off = if stage.path_tracing {
                String::new()
            } else {
                format!(", min_contribution {}", reference.min_contribution)
            };
            let light_paths = if stage.light_tracing {
                format!(", {} light paths per pixel", reference.light_paths)
            } else {
                String::new()
            };
            let _ = writeln!(
                text,
                "Reference: {samples}{light_paths}, depth {}{cut_off}, scaled offset, stable sphere formula{fresnel} (1 run).",
                reference.max_depth
            );
        }
        text.push('\n');
        text.push_str(
            "| knob | setting | time (ms) | rays | RMSE | PSNR (dB) | pixels off > 1/255 | relMSE (linear) | acne pixels | Pareto |\n",
        );
        text.push_str("|---|---|---:|---:|---:|---:|---:|---:|---:|:-:|\n");
        for row in &self.rows {
            let _ = writeln!(
                text,
                "| {} | {} | {:.1} | {} | {:.3} | {} | {:.2}% | {} | {} | {} |",
                row.knob_name(),
                row.label,
                row.seconds * 1e3,
                row.rays.total(),
                row.error.rmse,
                format_psnr(row.error.psnr_db),
                row.error.share_off * 100.0,
                format_relative_mse(row.error.relative_mse),
                row.rays.self_shadowed_pixels,
                if row.pareto { "yes" } else { "" },
            );
        }
        text
    }

    /// The report as CSV, one row per setting.
    pub fn csv(&self) -> String {
        let mut text = String::from(
            "chapter,scene,knob,setting,samples,sampling,max_depth,min_contribution,ray_offset,fixed_epsilon,sphere_formula,\
             runs,seconds_median,rays_total",
        );
        // A column a kind of ray, `rays_<name>`, in the order of `RayKind::ALL`.
        for kind in RayKind::ALL {
            let _ = write!(text, ",rays_{}", kind.name());
        }
        // The linear column comes last: scripts that read the columns
        // before it by position keep working.
        text += ",rmse_srgb8,psnr_db,share_pixels_off,self_shadowed_pixels,pareto,relative_mse_linear\n";
        for row in &self.rows {
            let s = &row.settings;
            let scene = if row.far_sphere {
                "far sphere"
            } else {
                &self.scene_name
            };
            let _ = write!(
                text,
                "{},{},{},{},{},{},{},{},{},{},{},{},{:.6},{}",
                self.chapter,
                csv_field(scene),
                row.knob_name(),
                csv_field(&row.label),
                row.samples_at(self.chapter),
                format!("{:?}", s.sampling).to_lowercase(),
                s.max_depth,
                s.min_contribution,
                format!("{:?}", s.ray_offset).to_lowercase(),
                s.fixed_epsilon,
                format!("{:?}", s.sphere_formula).to_lowercase(),
                row.runs,
                row.seconds,
                row.rays.total(),
            );
            for (_, count) in row.rays.by_kind() {
                let _ = write!(text, ",{count}");
            }
            let _ = writeln!(
                text,
                ",{:.6},{},{:.6},{},{},{}",
                row.error.rmse,
                if row.error.psnr_db.is_finite() {
                    format!("{:.3}", row.error.psnr_db)
                } else {
                    "inf".into()
                },
                row.error.share_off,
                row.rays.self_shadowed_pixels,
                row.pareto,
                row.error
                    .relative_mse
                    .map(|value| format!("{value:.6e}"))
                    .unwrap_or_default(),
            );
        }
        text
    }
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RenderSettings;
    use crate::cost::ImageError;

    #[test]
    fn the_csv_counts_every_kind_of_ray_and_the_kinds_add_up_to_the_total() {
        let rays = crate::RayCounts {
            cast: [1, 20, 300, 4_000, 50_000, 600_000, 7_000_000],
            ..Default::default()
        };
        let report = CostReport {
            chapter: 14,
            scene_name: "box".into(),
            width: 2,
            height: 2,
            repeats: 1,
            rows: vec![Measurement {
                knob: None,
                label: "reference".into(),
                settings: RenderSettings::default(),
                far_sphere: false,
                seconds: 1.0,
                runs: 1,
                rays,
                error: ImageError::default(),
                pareto: false,
            }],
        };
        let csv = report.csv();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        assert_eq!(header.len(), row.len());
        let column = |name: &str| -> u64 {
            let index = header.iter().position(|column| *column == name);
            index.and_then(|index| row[index].parse().ok()).unwrap_or(0)
        };
        let kinds: u64 = header
            .iter()
            .filter(|name| name.starts_with("rays_") && **name != "rays_total")
            .map(|name| column(name))
            .sum();
        assert_eq!(column("rays_total"), rays.total());
        assert_eq!(kinds, rays.total(), "{csv}");
        // Each kind's column carries its own count (`rays_<name>`), and the
        // header is cost.csv's, with the linear error last.
        for kind in RayKind::ALL {
            assert_eq!(column(&format!("rays_{}", kind.name())), rays.of(kind));
        }
        assert_eq!(
            header.join(","),
            "chapter,scene,knob,setting,samples,sampling,max_depth,min_contribution,ray_offset,\
             fixed_epsilon,sphere_formula,runs,seconds_median,rays_total,rays_primary,rays_shadow,\
             rays_reflection,rays_refraction,rays_bounce,rays_light,rays_to_camera,rmse_srgb8,\
             psnr_db,share_pixels_off,self_shadowed_pixels,pareto,relative_mse_linear"
        );
    }
}
