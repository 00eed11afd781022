//! `raylab figure`: one pixel's rays drawn in a slice of the scene, as SVG.

use anyhow::Result;
use clap::Args;

use super::render::{SettingsOverrides, select_scene, write_text_atomic};
use crate::figure::{FigureOptions, figure as lay_out};
use crate::{Chapters, Stage};

/// Draw every ray of one pixel, as `raylab trace` lists them, in the
/// vertical plane through the pixel's camera ray: each shape as the
/// plane cuts it, each ray in its kind's colour (a ray that leaves the
/// plane as its shadow on it), each hit with its shading normal, and the
/// balls sphere tracing steps through. The lessons' figures are made by
/// this command (the line above each figure in a lesson is its command).
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// Chapter whose stage to draw (see `raylab chapters`) [default: 8].
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// The pixel, `x,y` from the top-left corner.
    #[arg(long, allow_hyphen_values = true, value_parser = super::trace::parse_pixel)]
    pub pixel: (u32, u32),
    /// A TOML scene file instead of the chapter's built-in scene.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<std::path::PathBuf>,
    /// Draw only this sample's rays (from 0), when the pixel takes several.
    #[arg(long, value_name = "K")]
    pub sample: Option<usize>,
    /// Look this many times nearer, centred on the first hit (1 shows
    /// every ray; some 1000 shows how far a new ray starts off its surface).
    #[arg(long, default_value_t = 1.0, value_name = "FACTOR")]
    pub zoom: f32,
    /// Also draw the first N of chapter 14's light paths that light this
    /// pixel: each from its light through the scene, then toward the
    /// camera (every path of the image is traced to find them).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub draw_light_paths: usize,
    /// The SVG file to write.
    #[arg(short, long, default_value = "figure.svg", value_name = "FILE")]
    pub output: std::path::PathBuf,
    #[command(flatten)]
    pub overrides: SettingsOverrides,
}

pub fn figure<C: Chapters>(args: &FigureArgs) -> Result<i32> {
    let chapter = args.chapter.or(args.scene.is_none().then_some(8));
    let (scene, chapter) = select_scene(chapter, args.scene.as_deref())?;
    let settings = args.overrides.settings_for(&scene, chapter)?;
    let stage = Stage::<C>::with_chapters(&scene, chapter, settings)?;
    let options = FigureOptions {
        sample: args.sample,
        zoom: args.zoom,
        light_paths: args.draw_light_paths,
    };
    let drawn = lay_out(&stage, chapter, args.pixel, &options)?;
    write_text_atomic(&args.output, &drawn.svg())?;
    eprintln!(
        "wrote {} ({} rays of chapter {chapter}, pixel {},{})",
        args.output.display(),
        drawn.rays.len(),
        args.pixel.0,
        args.pixel.1
    );
    Ok(0)
}
