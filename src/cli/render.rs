//! `raylab render`, `raylab chapters`, `raylab scene`.

use crate::Chapters;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::chapters::{CHAPTERS, LAST_CHAPTER};
use crate::effects::Effects;
use crate::output::ImageKind;
use crate::render::{KeepLinear, Rendered};
use crate::shapes::MarchHistogram;
use crate::{RayCounts, RayKind, RenderSettings, Sampling, Scene, builtin};

#[derive(Debug, Args)]
#[command(
    after_long_help = "An option that the chosen chapter does not use (--samples or \
--sampling before chapter 7, --depth before 6, --epsilon before 4, ...), or a scene without \
lights from chapter 4 on, is not an error: each draws a one-line `warning:` on stderr."
)]
pub struct RenderArgs {
    /// Chapter whose stage to render (see `raylab chapters`): it switches on
    /// the effects of chapters 1 to N [default: the last chapter when --scene
    /// is given]. Without --scene, the chapter's built-in scene is used.
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// A TOML scene file to render instead of the built-in one
    /// (`raylab scene --chapter N` prints one to start from) [default: the
    /// chapter's built-in scene].
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: SettingsOverrides,
    /// Where to write the image [default: chapter-N.png for a built-in
    /// scene; with --scene my-scene.toml, my-scene.png, or my-scene-chN.png
    /// with --chapter N]. A name ending in .png gets 8-bit sRGB (clamped
    /// to what a screen shows); one ending in .exr gets OpenEXR, 32-bit
    /// float linear RGB: the radiance before the sRGB encoding, for other
    /// tools and `raylab diff` in linear light. An existing file is
    /// replaced only if raylab wrote it and it is writable; anything else
    /// needs --force.
    #[arg(short, long, value_name = "OUT.png|OUT.exr")]
    pub output: Option<PathBuf>,
    /// Replace the output even if raylab did not write it or it is
    /// read-only (it keeps its permissions).
    #[arg(long)]
    pub force: bool,
    /// Print the effects simulated and the rays cast by kind.
    #[arg(long)]
    pub stats: bool,
    /// Write the same statistics as JSON to FILE [default: none written].
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,
}

/// Settings that override the scene's `[render]` table. Each default is the
/// scene's own value; the built-in scenes set width, height, samples and
/// depth, and a scene file that leaves a value out gets
/// `RenderSettings::default()`'s. An option the chosen chapter does not use
/// is not an error, but draws a `warning:` line on stderr.
#[derive(Debug, Clone, Default, Args)]
pub struct SettingsOverrides {
    /// Image width in pixels [default: the scene's; 640 in the built-in
    /// scenes, 320 in a scene file without it].
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels [default: the scene's; 480 in the built-in
    /// scenes, 240 in a scene file without it].
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel, used from chapter 7 on; a square for grid and
    /// jittered sampling [default: the scene's; 4 in the built-in scenes of
    /// chapters 7 and 8, else 1].
    #[arg(long)]
    pub samples: Option<u32>,
    /// How samples are placed in a pixel, from chapter 7 on [default: the
    /// scene's, else jittered]. One sample per pixel is always the pixel's
    /// centre, whatever the placement.
    #[arg(long, value_enum)]
    pub sampling: Option<Sampling>,
    /// Maximum reflection/refraction bounces, used from chapter 6 on
    /// [default: the scene's, else 5].
    #[arg(long)]
    pub depth: Option<u32>,
    /// Skip secondary rays whose share of the pixel is below this (0: never
    /// skip), from chapter 6 on [default: the scene's, else 0.001].
    #[arg(long, value_name = "WEIGHT")]
    pub min_contribution: Option<f32>,
    /// Seed of the random sample positions (jittered and random sampling,
    /// chapter 7 on) [default: the scene's, else 0].
    #[arg(long)]
    pub seed: Option<u64>,
    /// How ray-sphere hits are solved, for comparing the two formulas
    /// [default: the scene's, else stable].
    #[arg(long, value_enum)]
    pub sphere_formula: Option<crate::scene::SphereFormula>,
    /// How ray-triangle hits are found, for comparing the two tests, from
    /// chapter 10 on [default: the scene's, else watertight].
    #[arg(long, value_enum)]
    pub triangle_test: Option<crate::scene::TriangleTest>,
    /// Where rays leave a smooth-shaded triangle, from chapter 10 on:
    /// lifted towards the curved surface, or from the flat triangle (to see
    /// the shadow terminator it fixes) [default: the scene's, else lifted].
    #[arg(long, value_enum)]
    pub terminator: Option<crate::scene::TerminatorRule>,
    /// Where secondary rays start, from chapter 4 on: scaled to the hit's
    /// rounding error, or a fixed --epsilon along the ray (for comparison)
    /// [default: fixed if --epsilon is given, else the scene's, else scaled].
    #[arg(long, value_enum)]
    pub ray_offset: Option<crate::scene::OffsetRule>,
    /// The distance used by --ray-offset fixed; giving it implies
    /// --ray-offset fixed [default: the scene's, else 0.0001].
    #[arg(long, allow_negative_numbers = true)]
    pub epsilon: Option<f32>,
    // Its help names the switches from their one list (`without_help`).
    #[arg(
        long,
        value_name = "EFFECTS",
        value_delimiter = ',',
        value_parser = parse_switched_off,
        help = without_help()
    )]
    pub without: Option<Vec<crate::scene::SwitchedOff>>,
    /// Paths traced from the lights per pixel, from chapter 14 on (caustics)
    /// [default: the scene's, else 16].
    #[arg(long, value_name = "PATHS")]
    pub light_paths: Option<u32>,
    /// Worker threads, 1 to 1024 [default: one per core]. The image does not depend on it.
    #[arg(long, value_parser = crate::cli::parse_threads)]
    pub threads: Option<usize>,
}

/// The help of `--without`: every switch's name, from the switches' list.
fn without_help() -> String {
    format!(
        "Effects of the chapter's stage to leave out, by name, comma-separated ({}): the \
         image without them [default: the scene's `without`, else none]",
        crate::scene::SwitchedOff::NAMES.join(", ")
    )
}

fn parse_switched_off(name: &str) -> Result<crate::scene::SwitchedOff, String> {
    crate::scene::SwitchedOff::parse([name.trim()])
}

impl SettingsOverrides {
    /// The scene's settings with these overrides applied, checked.
    pub fn apply(&self, base: RenderSettings) -> Result<RenderSettings> {
        // --epsilon means a fixed offset: taking the distance and then
        // ignoring it (the scaled rule has none) surprised every user.
        let ray_offset = match (self.ray_offset, self.epsilon) {
            (Some(rule), _) => rule,
            (None, Some(_)) => crate::scene::OffsetRule::Fixed,
            (None, None) => base.ray_offset,
        };
        let settings = RenderSettings {
            width: self.width.unwrap_or(base.width),
            height: self.height.unwrap_or(base.height),
            samples: self.samples.unwrap_or(base.samples),
            sampling: self.sampling.unwrap_or(base.sampling),
            max_depth: self.depth.unwrap_or(base.max_depth),
            min_contribution: self.min_contribution.unwrap_or(base.min_contribution),
            seed: self.seed.unwrap_or(base.seed),
            sphere_formula: self.sphere_formula.unwrap_or(base.sphere_formula),
            ray_offset,
            fixed_epsilon: self.epsilon.unwrap_or(base.fixed_epsilon),
            triangle_test: self.triangle_test.unwrap_or(base.triangle_test),
            terminator: self.terminator.unwrap_or(base.terminator),
            light_paths: self.light_paths.unwrap_or(base.light_paths),
            without: self.without.as_ref().map_or(base.without, |sets| {
                sets.iter()
                    .fold(Default::default(), |all, set| all.union(*set))
            }),
            ..base
        };
        settings
            .validate()
            .map_err(|message| anyhow::anyhow!("invalid render settings: {message}"))?;
        Ok(settings)
    }

    /// [`SettingsOverrides::apply`] to `scene`'s settings, with a `warning:`
    /// line on stderr for each of [`SettingsOverrides::unused`].
    pub fn settings_for(&self, scene: &Scene, chapter: u8) -> Result<RenderSettings> {
        let settings = self.apply(scene.render)?;
        for warning in self.unused(scene, chapter, &settings) {
            eprintln!("warning: {warning}");
        }
        Ok(settings)
    }

    /// The options given that rendering `scene` at `chapter` with `settings`
    /// ignores, each with what it needs; and a scene without lights at a
    /// lit stage, which renders dark.
    pub fn unused(&self, scene: &Scene, chapter: u8, settings: &RenderSettings) -> Vec<String> {
        use crate::effects::Lighting;
        let effects = Effects::for_chapter(chapter);
        let mut warnings = self.before_their_chapter(chapter, settings);
        warnings.extend(self.ignored_by_settings(chapter, settings));
        let glows = scene
            .materials()
            .any(|material| material.emission != crate::Vec3::ZERO);
        if effects.lighting != Lighting::Unlit
            && scene.lights.is_empty()
            && !(effects.path_tracing && (glows || scene.background != crate::Vec3::ZERO))
        {
            warnings.push(format!(
                "the scene has no lights: at chapter {chapter} surfaces are lit by the ambient \
                 light alone, so the image is dark; add a [[lights]] table"
            ));
        }
        warnings
    }

    /// The options given for an effect that `chapter` does not simulate
    /// yet, each with the chapter that brings it.
    fn before_their_chapter(&self, chapter: u8, settings: &RenderSettings) -> Vec<String> {
        let mut warnings = Vec::new();
        let mut before = |given: bool, option: String, first: u8, what: &str| {
            if given && chapter < first {
                warnings.push(format!(
                    "{option} has no effect at chapter {chapter}: {what} from chapter {first} on"
                ));
            }
        };
        before(
            self.samples.is_some_and(|n| n > 1),
            format!("--samples {}", settings.samples),
            7,
            "pixels take one sample at their centre until supersampling",
        );
        before(
            self.sampling.is_some(),
            "--sampling".into(),
            7,
            "samples are placed",
        );
        before(
            self.seed.is_some(),
            "--seed".into(),
            7,
            "random sample positions are drawn",
        );
        before(
            self.depth.is_some(),
            "--depth".into(),
            6,
            "rays bounce (reflection)",
        );
        before(
            self.min_contribution.is_some(),
            "--min-contribution".into(),
            6,
            "secondary rays are weighed (reflection)",
        );
        before(
            self.ray_offset.is_some() || self.epsilon.is_some(),
            if self.epsilon.is_some() {
                "--epsilon".into()
            } else {
                "--ray-offset".into()
            },
            4,
            "secondary rays are cast (shadows)",
        );
        before(
            self.sphere_formula.is_some(),
            "--sphere-formula".into(),
            2,
            "spheres are drawn",
        );
        before(
            self.triangle_test.is_some(),
            "--triangle-test".into(),
            10,
            "triangles are drawn",
        );
        before(
            self.terminator.is_some(),
            "--terminator".into(),
            10,
            "smooth-shaded triangles are drawn",
        );
        before(
            self.light_paths.is_some(),
            "--light-paths".into(),
            14,
            "paths are traced from the lights",
        );
        warnings
    }

    /// The options that the other settings make pointless: a sample
    /// placement or seed with one sample per pixel, a distance with the
    /// scaled offset.
    fn ignored_by_settings(&self, chapter: u8, settings: &RenderSettings) -> Vec<String> {
        use crate::scene::OffsetRule;
        let effects = Effects::for_chapter(chapter);
        let mut warnings = Vec::new();
        let on = effects.switchable();
        let asked = settings.without.names();
        for name in &asked {
            if !on.contains(name) {
                warnings.push(format!(
                    "--without {name} has no effect at chapter {chapter}, whose stage has no {name}"
                ));
            }
        }
        let left = effects.without(settings.without).switchable();
        let also: Vec<&str> = on
            .iter()
            .filter(|name| !asked.contains(name) && !left.contains(name))
            .copied()
            .collect();
        if !also.is_empty() && self.without.is_some() {
            warnings.push(format!(
                "--without {} also leaves out {}, built on it at chapter {chapter}",
                asked.join(","),
                also.join(", ")
            ));
        }
        if self.light_paths.is_some() && effects.light_tracing && !left.contains(&"light-tracing") {
            warnings.push(
                "--light-paths has no effect with --without light-tracing: no paths are \
                 traced from the lights"
                    .into(),
            );
        }
        if effects.antialiasing && settings.samples == 1 {
            if self.sampling.is_some() {
                warnings.push(
                    "--sampling has no effect with 1 sample per pixel (a lone sample is the \
                     pixel's centre): add --samples 4 or more"
                        .into(),
                );
            } else if self.seed.is_some() {
                warnings.push(
                    "--seed has no effect with 1 sample per pixel (a lone sample is the \
                     pixel's centre): add --samples 4 or more"
                        .into(),
                );
            }
        }
        if self.epsilon.is_some() && self.ray_offset == Some(OffsetRule::Scaled) {
            warnings.push(
                "--epsilon has no effect with --ray-offset scaled: it is the distance of \
                 --ray-offset fixed"
                    .into(),
            );
        }
        warnings
    }

    /// Runs `work` on a pool of `--threads` threads, or on the global pool.
    pub fn in_pool<T: Send>(&self, work: impl FnOnce() -> T + Send) -> Result<T> {
        match self.threads {
            None => Ok(work()),
            Some(0) => bail!("--threads must be at least 1"),
            Some(threads) => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .context("cannot start the worker threads")?;
                Ok(pool.install(work))
            }
        }
    }
}

/// The scene and stage that `--chapter` and `--scene` select.
pub fn select_scene(chapter: Option<u8>, scene: Option<&Path>) -> Result<(Scene, u8)> {
    match (chapter, scene) {
        (_, Some(path)) => {
            // Through crate::input: a FIFO or /dev/zero as --scene must not
            // block or fill the memory; a scene file is at most 16 MiB.
            let text = crate::input::read_scene_text(path)?;
            // OBJ files named in the scene are found next to it.
            let folder = path.parent().unwrap_or(Path::new(""));
            let scene = Scene::parse_in(
                &text,
                &format!("scene file {}", path.display()),
                Some(folder),
            )?;
            Ok((scene, chapter.unwrap_or(LAST_CHAPTER)))
        }
        (Some(chapter), None) => Ok((builtin::scene(chapter)?, chapter)),
        (None, None) => bail!(
            "say what to render: --chapter N (see `raylab chapters`) for a chapter's built-in scene, \
             --scene FILE for your own, or both"
        ),
    }
}

pub fn render<C: Chapters>(args: &RenderArgs) -> Result<i32> {
    let (scene, chapter) = select_scene(args.chapter, args.scene.as_deref())?;
    let settings = args.overrides.settings_for(&scene, chapter)?;
    let output = output_name(
        args.output.as_deref(),
        args.scene.as_deref(),
        args.chapter,
        chapter,
    );
    let kind = crate::output::image_kind("-o", &output)?;
    let mut outputs = vec![("-o", output.as_path())];
    if let Some(path) = &args.stats_json {
        outputs.push(("--stats-json", path.as_path()));
    }
    // The scene and the OBJ models it names: `--stats-json model.obj` must
    // not replace the mesh being rendered.
    let models: Vec<PathBuf> = match args.scene.as_deref() {
        Some(path) => crate::input::read_scene_text(path)
            .map(|text| Scene::obj_files(&text, path.parent().unwrap_or(Path::new(""))))
            .unwrap_or_default(),
        None => Vec::new(),
    };
    let inputs: Vec<&Path> = args
        .scene
        .as_deref()
        .into_iter()
        .chain(models.iter().map(PathBuf::as_path))
        .collect();
    crate::output::check_outputs(&inputs, &outputs, args.force)?;
    crate::output::check_replaceable_image("-o", &output, args.force, kind)?;
    if let Some(path) = &args.stats_json {
        crate::output::check_replaceable_text(
            "--stats-json",
            path,
            args.force,
            crate::output::markers::STATS_JSON,
        )?;
    }
    let work = estimated_work(&settings, chapter, scene.len());
    if let Some(warning) = long_render_warning(&settings, chapter, scene.len()) {
        eprintln!("{warning}");
    }
    let progress = (std::io::stderr().is_terminal() && work >= PROGRESS_WORK).then(|| {
        let bar = indicatif::ProgressBar::new(u64::from(settings.height));
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} rendering [{bar:40}] {pos}/{len} rows, {eta} left",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    crate::answer_key::take_reported();
    // A comparison wrapper runs raylab's formulas only where the settings
    // ask for them; anywhere else, reaching them is the student's doing.
    crate::answer_key::set_strict(
        settings.sphere_formula == crate::scene::SphereFormula::Stable
            && settings.triangle_test == crate::scene::TriangleTest::Watertight,
    );
    let rendered = args.overrides.in_pool(|| {
        crate::render::render_keeping::<C>(
            &scene,
            chapter,
            &settings,
            progress.as_ref(),
            match kind {
                ImageKind::Png => KeepLinear::No,
                ImageKind::Exr => KeepLinear::Yes,
            },
        )
    })??;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    let answers = crate::answer_key::take_reported();
    if !answers.is_empty() {
        anyhow::bail!(
            "nothing written: the code of chapters 1 to {chapter} ran raylab's own answer \
             instead of yours ({}); write those functions yourself (`cargo run --release -- \
             check --chapter {chapter}` says which)",
            answers.join(", ")
        );
    }
    // The image and its statistics together or not at all.
    let image = match kind {
        ImageKind::Png => {
            crate::output::encode_png(rendered.width, rendered.height, &rendered.rgb)?
        }
        ImageKind::Exr => {
            let not_finite = rendered.linear.iter().filter(|v| !v.is_finite()).count();
            if not_finite > 0 {
                // Written as computed: the file is the renderer's answer,
                // and `raylab diff` names the first such pixel.
                eprintln!(
                    "warning: {not_finite} linear values are NaN or infinite; \
                     the OpenEXR image keeps them (the PNG would show them black or white)"
                );
            }
            crate::output::encode_exr(rendered.width, rendered.height, &rendered.linear)?
        }
    };
    let json = args.stats_json.as_ref().map(|path| {
        (
            path,
            format!("{:#}\n", stats_json(chapter, &settings, &rendered)),
        )
    });
    let mut files = vec![(output.as_path(), image.as_slice())];
    if let Some((path, text)) = &json {
        files.push((path.as_path(), text.as_bytes()));
    }
    crate::output::write_files(&files)?;
    let line = summary_line(chapter, &settings, &rendered, &output);
    println!("{}", crate::text::terminal_safe(&line));
    if args.stats {
        print!("{}", stats_text(&rendered));
    }
    Ok(0)
}

/// The image's name: `-o`, else `chapter-N.png` for a built-in scene, else
/// the scene file's name, with `-chN` when a chapter is asked for. A scene's
/// render never takes the name `chapter-N.png`, the hand-in name `raylab
/// grade` expects: it would replace the student's render of the built-in
/// scene.
fn output_name(
    output: Option<&Path>,
    scene: Option<&Path>,
    asked_chapter: Option<u8>,
    chapter: u8,
) -> PathBuf {
    if let Some(path) = output {
        return path.to_path_buf();
    }
    let Some(scene) = scene else {
        return PathBuf::from(format!("chapter-{chapter}.png"));
    };
    let stem = scene
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    let name = match asked_chapter {
        Some(chapter) => format!("{stem}-ch{chapter}.png"),
        None => format!("{stem}.png"),
    };
    // `--scene chapter-3.toml` must not write `chapter-3.png`: that name is
    // a hand-in's, which `grade` takes for the chapter's built-in scene.
    if crate::grade::chapter_of(&name).is_ok() {
        return PathBuf::from(format!("{stem}-scene.png"));
    }
    PathBuf::from(name)
}

/// The estimated work above which `render` shows a progress bar: about a
/// second of rendering.
const PROGRESS_WORK: u64 = 20_000_000;

/// The estimated work above which `render` warns before it starts: 30
/// times [`PROGRESS_WORK`], where a scene of triangles, the slowest to
/// test, takes a minute.
const WARN_WORK: u64 = 30 * PROGRESS_WORK;

/// The work a render will do, counted in ray-object tests: every primary
/// sample tests every object (secondary rays add more, but a scene's size
/// is what makes a render slow beyond the pixel count: 20,000 spheres at
/// 320x240 take 20 s with one sample per pixel).
fn estimated_work(settings: &RenderSettings, chapter: u8, objects: usize) -> u64 {
    let samples = if crate::effects::Effects::for_chapter(chapter).antialiasing {
        u64::from(settings.samples)
    } else {
        1
    };
    u64::from(settings.width) * u64::from(settings.height) * samples * (objects as u64).max(1)
}

/// The warning printed before a render whose estimated work is
/// [`WARN_WORK`] or more, with the estimate; none from chapter 11 on,
/// where a tree makes the estimate meaningless.
fn long_render_warning(settings: &RenderSettings, chapter: u8, objects: usize) -> Option<String> {
    let effects = crate::effects::Effects::for_chapter(chapter);
    let work = estimated_work(settings, chapter, objects);
    (work >= WARN_WORK && !effects.bvh).then(|| {
        format!(
            "warning: about {work} ray-object tests ({} pixels x {} samples x {objects} \
             objects, with no tree before chapter 11): this render may take minutes; a smaller \
             --width and --height show the scene first",
            u64::from(settings.width) * u64::from(settings.height),
            if effects.antialiasing {
                settings.samples
            } else {
                1
            },
        )
    })
}

fn summary_line(
    chapter: u8,
    settings: &RenderSettings,
    rendered: &Rendered,
    output: &Path,
) -> String {
    let rays = &rendered.rays;
    format!(
        "chapter {chapter}: {}x{}, {} spp, {:.3} s, rays: {} primary, {} shadow, {} reflection, {} refraction{} -> {}",
        rendered.width,
        rendered.height,
        if rendered.effects.antialiasing {
            settings.samples
        } else {
            1
        },
        rendered.seconds,
        rays.of(RayKind::Primary),
        rays.of(RayKind::Shadow),
        rays.of(RayKind::Reflection),
        rays.of(RayKind::Refraction),
        if rendered.effects.path_tracing {
            format!(", {} bounce", rays.of(RayKind::Bounce))
        } else {
            String::new()
        } + &if rendered.effects.light_tracing {
            format!(
                ", {} light, {} to camera",
                rays.of(RayKind::Light),
                rays.of(RayKind::ToCamera)
            )
        } else {
            String::new()
        },
        output.display()
    )
}

fn stats_text(rendered: &Rendered) -> String {
    let rays = &rendered.rays;
    let paths = rendered.effects.path_tracing;
    let mut bounce = if paths {
        format!("  bounce      {}\n", rays.of(RayKind::Bounce))
    } else {
        String::new()
    };
    if rendered.effects.light_tracing {
        bounce += &format!(
            "  light       {}\n  to camera   {}\nlight paths: {} traced, {} of their points \
             joined to the camera landed on a pixel\n",
            rays.of(RayKind::Light),
            rays.of(RayKind::ToCamera),
            rays.light_paths,
            rays.splats
        );
    }
    let fireflies = if paths {
        format!(
            "fireflies (samples above {} times the brightest light seen): {}\n",
            crate::render::FIREFLY_FACTOR,
            rays.bright_samples
        )
    } else {
        String::new()
    };
    format!(
        "effects simulated: {}\ntime: {:.3} s\nrays cast: {} total\n  primary     {}\n  shadow      {}\n  reflection  {}\n  refraction  {}\n{bounce}self-shadowing shadow rays: {} (in {} pixels)\nnon-finite samples: {}\n{fireflies}",
        rendered.effects.names().join(", "),
        rendered.seconds,
        rays.total(),
        rays.of(RayKind::Primary),
        rays.of(RayKind::Shadow),
        rays.of(RayKind::Reflection),
        rays.of(RayKind::Refraction),
        rays.self_shadow_hits,
        rays.self_shadowed_pixels,
        rays.non_finite_samples,
    ) + &implicit_text(rendered)
}

/// The implicit surfaces' share of the work, when the render marched any.
fn implicit_text(rendered: &Rendered) -> String {
    let rays = &rendered.rays;
    if !rendered.effects.implicit {
        return String::new();
    }
    // A march that misses the box makes no evaluation: the mean is over
    // the others.
    let entered = rays.implicit_marches() - rays.march_histogram.counts[0];
    let per_march = rays
        .implicit_evaluations
        .saturating_sub(rays.normal_evaluations) as f64
        / entered.max(1) as f64;
    format!(
        "implicit surfaces: {} marches, {} evaluations of their functions ({per_march:.1} a \
         march that entered a box), {} of them for normals\n",
        rays.implicit_marches(),
        rays.implicit_evaluations,
        rays.normal_evaluations
    ) + &histogram_text(&rays.march_histogram)
}

/// The marches by their evaluations, one bar a bucket: where a render's
/// steps go. The marches that missed the surfaces' boxes made none and
/// are counted apart.
fn histogram_text(histogram: &MarchHistogram) -> String {
    let counts = &histogram.counts;
    let missed = counts[0];
    let marched = histogram.marches() - missed;
    let mut text =
        format!("  {missed} of the marches missed their surface's box and made no evaluation\n");
    let Some(last) = counts
        .iter()
        .rposition(|&count| count > 0)
        .filter(|&last| last > 0)
    else {
        return text;
    };
    let most = counts[1..].iter().copied().max().unwrap_or(0).max(1);
    text += &format!("  the other {marched}, by their evaluations:\n");
    for (bucket, &count) in counts.iter().enumerate().take(last + 1).skip(1) {
        let range = match MarchHistogram::range(bucket) {
            (low, Some(high)) if low == high => low.to_string(),
            (low, Some(high)) => format!("{low}-{high}"),
            (low, None) => format!("{low}+"),
        };
        let share = 100.0 * count as f64 / marched.max(1) as f64;
        let bar = "#".repeat((40 * count).div_ceil(most) as usize);
        text += &format!("  {range:>9} {count:>10} {share:>5.1}% {bar}\n");
    }
    text
}

/// The `"rays"` of `raylab render --json`: the count of each kind by its
/// name, as the page has them too, and their total.
pub(crate) fn rays_json(rays: &RayCounts) -> serde_json::Value {
    let mut json = rays.by_kind_json();
    json.insert("total".into(), rays.total().into());
    json.into()
}

/// The statistics of a render as JSON.
pub fn stats_json(
    chapter: u8,
    settings: &RenderSettings,
    rendered: &Rendered,
) -> serde_json::Value {
    let rays = &rendered.rays;
    serde_json::json!({
        "chapter": chapter,
        "width": rendered.width,
        "height": rendered.height,
        "samples_per_pixel": if rendered.effects.antialiasing { settings.samples } else { 1 },
        "max_depth": settings.max_depth,
        "seconds": rendered.seconds,
        "effects": rendered.effects.names(),
        "rays": rays_json(rays),
        "light_paths": rays.light_paths,
        "splats": rays.splats,
        "bright_samples": rays.bright_samples,
        "self_shadow_hits": rays.self_shadow_hits,
        "self_shadowed_pixels": rays.self_shadowed_pixels,
        "non_finite_samples": rays.non_finite_samples,
        "implicit": {
            "marches": rays.implicit_marches(),
            "evaluations_a_march": rays.march_histogram.counts.iter().enumerate().map(|(bucket, &count)| {
                let (from, to) = MarchHistogram::range(bucket);
                serde_json::json!({ "from": from, "to": to, "marches": count })
            }).collect::<Vec<_>>(),
            "evaluations": rays.implicit_evaluations,
            "normal_evaluations": rays.normal_evaluations,
        },
        "image_fnv1a64": format!("{:016x}", rendered.hash()),
    })
}

/// Writes a text file atomically (see [`crate::output::write_atomically`]).
pub fn write_text_atomic(path: &Path, text: &str) -> Result<()> {
    crate::output::write_atomically(path, |file| file.write_all(text.as_bytes()))?;
    Ok(())
}

pub fn chapters() -> Result<i32> {
    // Columns as wide as their longest entry, so that every row lines up.
    let title_width = CHAPTERS.iter().map(|c| c.title.len()).max().unwrap_or(0);
    let adds_width = CHAPTERS.iter().map(|c| c.adds.len()).max().unwrap_or(0);
    for chapter in CHAPTERS {
        let effects = Effects::for_chapter(chapter.number).names().join(", ");
        println!(
            "{:>2}  {:<title_width$}  adds {:<adds_width$}  effects: {effects}",
            chapter.number, chapter.title, chapter.adds
        );
    }
    Ok(0)
}

#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The chapter whose built-in scene to print (see `raylab chapters`).
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: u8,
}

pub fn scene(args: &SceneArgs) -> Result<i32> {
    let text = builtin::scene_text(args.chapter).context("no such chapter")?;
    print!("{text}");
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The help of --without names every switch (from their list: a name
    /// written by hand would fall behind the next switch).
    #[test]
    fn the_help_of_without_names_every_switch() {
        use clap::CommandFactory;
        #[derive(clap::Parser)]
        struct Wrapper {
            #[command(flatten)]
            settings: SettingsOverrides,
        }
        let command = Wrapper::command();
        let without = command
            .get_arguments()
            .find(|argument| argument.get_id() == "without")
            .expect("a --without argument");
        let help = without
            .get_help()
            .map(|help| help.to_string().replace('\n', " "))
            .unwrap_or_default();
        for name in crate::scene::SwitchedOff::NAMES {
            assert!(
                help.contains(name),
                "--without's help leaves out {name}: {help}"
            );
        }
    }

    #[test]
    fn the_progress_bar_counts_objects_not_only_samples() {
        let settings = |width, height, samples| RenderSettings {
            width,
            height,
            samples,
            ..builtin::scene(8).expect("built-in scene").render
        };
        // 20,000 spheres at 320x240 take about 20 s, though pixels x samples
        // is only 76,800: counting pixels and samples alone would show no bar.
        assert!(estimated_work(&settings(320, 240, 1), 8, 20_000) >= PROGRESS_WORK);
        // A million triangles at 32x24 before chapter 11 (a minute) warns
        // with its estimate; with chapter 11's tree, or at 16x12, it does not.
        let warning = long_render_warning(&settings(32, 24, 1), 10, 1_000_000);
        assert!(warning.is_some_and(|text| text.contains("about 768000000 ray-object tests")),);
        assert_eq!(
            long_render_warning(&settings(32, 24, 1), 11, 1_000_000),
            None
        );
        assert_eq!(
            long_render_warning(&settings(16, 12, 1), 10, 1_000_000),
            None
        );
        // A built-in scene at the default size stays quiet (well under a second).
        let chapter_8 = builtin::scene(8).expect("built-in scene");
        assert!(estimated_work(&chapter_8.render, 8, chapter_8.len()) < PROGRESS_WORK);
        // Samples count only from chapter 7 on, where they are taken.
        assert_eq!(
            estimated_work(&settings(100, 100, 16), 6, 5),
            estimated_work(&settings(100, 100, 1), 6, 5)
        );
        assert_eq!(
            estimated_work(&settings(100, 100, 16), 7, 5),
            16 * estimated_work(&settings(100, 100, 1), 7, 5)
        );
    }

    #[test]
    fn the_render_json_and_the_page_name_the_kinds_of_ray_alike() {
        let mut rays = RayCounts::default();
        for (place, kind) in RayKind::ALL.into_iter().enumerate() {
            rays.cast[kind.index()] = 10 + place as u64;
        }
        rays.implicit_evaluations = 1_000;
        rays.non_finite_samples = 2_000;
        let by_kind = |json: serde_json::Value, own: &[&str]| {
            let mut json = json.as_object().expect("an object").clone();
            for key in own {
                assert!(json.remove(*key).is_some(), "{key} is missing");
            }
            json
        };
        let cli = by_kind(rays_json(&rays), &["total"]);
        let page = by_kind(
            crate::web::rays_json(&rays),
            &["implicit_evaluations", "non_finite_samples"],
        );
        assert_eq!(cli, page);
        assert_eq!(cli.len(), RayKind::COUNT);
        for kind in RayKind::ALL {
            assert_eq!(cli[kind.name()], rays.of(kind), "{kind:?}");
        }
        // The CLI's keys are the ones it has always written.
        let keys: Vec<&str> = cli.keys().map(String::as_str).collect();
        let mut expected = [
            "primary",
            "shadow",
            "reflection",
            "refraction",
            "bounce",
            "light",
            "to_camera",
        ];
        expected.sort_unstable();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, expected);
        assert_eq!(rays_json(&rays)["total"], rays.total());
    }
}
