//! `raylab crosscheck` (our hits against Embree's on every ray of a render)
//! and `raylab probe` (what one ray hits).

use crate::Chapters;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::render::{SettingsOverrides, select_scene};
#[cfg(feature = "embree")]
use crate::crosscheck::{self, Answer};
use crate::implicit_probe::{ImplicitStory, Iterate, Step, story};
use crate::{Hit, Ray, Scene, Shape, Stage, Vec3};

/// How to get the Embree backend, for messages.
#[cfg(not(feature = "embree"))]
pub(super) const ENABLE_EMBREE: &str = "this raylab was built without Embree. To enable it, run \
     `scripts/setup-embree.sh` once (it installs libclang and Embree 4), then build with \
     the `embree` feature, e.g. `cargo run --release --features embree -- crosscheck \
     --chapter 8`. See docs/embree.md.";

#[derive(Debug, Args)]
pub struct CrosscheckArgs {
    /// Chapter whose render to record (see `raylab chapters`) [default: 8].
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// A TOML scene file instead of the chapter's built-in scene.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub overrides: SettingsOverrides,
    /// How many times each backend is timed over all the rays (the median is printed).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub timing_runs: u32,
}

#[derive(Debug, Args)]
pub struct ProbeArgs {
    /// The ray: origin and direction, `ox,oy,oz,dx,dy,dz`.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_ray)]
    pub ray: Ray,
    /// Chapter whose shapes to use (see `raylab chapters`) [default: 8].
    #[arg(short, long, value_parser = crate::chapters::parse_chapter)]
    pub chapter: Option<u8>,
    /// A TOML scene file instead of the chapter's built-in scene.
    #[arg(short, long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
}

fn parse_ray(text: &str) -> Result<Ray, String> {
    let numbers = text
        .split(',')
        .map(|part| {
            let part = part.trim();
            part.parse::<f32>()
                .ok()
                .filter(|number| number.is_finite())
                .ok_or_else(|| format!("`{part}` is not a finite number"))
        })
        .collect::<Result<Vec<f32>, String>>()?;
    let [ox, oy, oz, dx, dy, dz] = numbers[..] else {
        return Err(format!(
            "expected six numbers `ox,oy,oz,dx,dy,dz`, got {}",
            numbers.len()
        ));
    };
    let dir = Vec3::new(dx, dy, dz);
    if dir == Vec3::ZERO {
        return Err("the direction must not be zero".into());
    }
    Ok(Ray::new(Vec3::new(ox, oy, oz), dir))
}

/// The scene and chapter, defaulting to chapter 8.
fn chosen_scene(chapter: Option<u8>, scene: Option<&std::path::Path>) -> Result<(Scene, u8)> {
    select_scene(chapter.or(scene.is_none().then_some(8)), scene)
}

// Without Embree, `C` has nothing to run.
#[cfg_attr(not(feature = "embree"), allow(clippy::extra_unused_type_parameters))]
pub fn crosscheck<C: Chapters>(args: &CrosscheckArgs) -> Result<i32> {
    #[cfg(feature = "embree")]
    {
        with_embree::crosscheck::<C>(args)
    }
    #[cfg(not(feature = "embree"))]
    {
        let _ = args;
        anyhow::bail!("`raylab crosscheck` needs Embree: {ENABLE_EMBREE}")
    }
}

pub fn probe<C: Chapters>(args: &ProbeArgs) -> Result<i32> {
    let (scene, chapter) = chosen_scene(args.chapter, args.scene.as_deref())?;
    let stage = Stage::<C>::with_chapters(&scene, chapter, scene.render)?;
    let ray = args.ray;
    let show = |v: Vec3| format!("({}, {}, {})", v.x, v.y, v.z);
    println!(
        "ray: origin {}, direction {}, hits with 0 < t < inf (t in units of the direction)",
        show(ray.origin),
        show(ray.dir)
    );
    println!("chapter {chapter}'s shapes, each on its own:");
    // Object names come from the scene file: shown escaped, never obeyed.
    let name_of = |object: usize| crate::text::terminal_safe(stage.name(object).unwrap_or("?"));
    // Each shape by the chapters `C` (a student's build holds no other);
    // raylab's own shows a sphere's two roots.
    for (object, shape) in stage.shapes().iter().enumerate() {
        let name = name_of(object);
        let hit = shape.intersect_with::<C>(&ray, 0.0, f32::INFINITY);
        let answer = match shape {
            Shape::Plane(_) => match hit {
                Some(t) => format!("plane, t = {t}"),
                None => "plane, no hit ahead".into(),
            },
            Shape::Sphere(sphere) if !cfg!(feature = "student") => match sphere.roots(&ray) {
                Some((near, far)) => format!("sphere, roots t = {near} and {far}"),
                None => "sphere, no root (the line misses it)".into(),
            },
            Shape::Sphere(_) => match hit {
                Some(t) => format!("sphere, t = {t}"),
                None => "sphere, no hit ahead".into(),
            },
            Shape::Triangle(_) => match hit {
                Some(t) => format!("triangle, t = {t}"),
                None => "triangle, no hit ahead".into(),
            },
            Shape::Implicit(_) => match hit {
                Some(t) => format!("implicit surface, t = {t} (sphere tracing, then Newton)"),
                None => "implicit surface, no hit ahead".into(),
            },
        };
        println!("  {object}: {name:<16} {answer}");
        // The march's story is told against the exact root, one of
        // raylab's answers, which a student's build leaves out.
        #[cfg(not(feature = "student"))]
        if let Shape::Implicit(surface) = shape {
            print!("{}", implicit_story_text(&story::<C>(surface, &ray)));
        }
    }
    let cast = primary_cast(ray);
    let ours = stage.nearest_hit(&cast.ray, cast.t_min, cast.t_max);
    match ours {
        Some(hit) => {
            let surface = stage.shapes()[hit.object].surface_point(&ray, hit.t);
            println!(
                "ours:   \"{}\" (object {}) at t = {}, point {}, normal {}",
                name_of(hit.object),
                hit.object,
                hit.t,
                show(surface.point),
                show(surface.normal)
            );
        }
        None => println!("ours:   no hit"),
    }
    probe_embree(&stage, &scene, &ray, ours)?;
    Ok(0)
}

/// The march and Newton's iterates of one implicit surface, indented
/// under its line.
fn implicit_story_text(story: &ImplicitStory) -> String {
    let Some((enter, leave)) = story.span else {
        return "       the ray misses its box: no evaluation\n".into();
    };
    let digits = |iterate: &Iterate| match iterate.digits {
        Some(digits) => format!("{digits:5.1}"),
        None => "  all".into(),
    };
    let mut text = format!("       in its box for t from {enter} to {leave}\n");
    text += &match story.march {
        Some(t) => format!(
            "       sphere tracing: stops at t = {t} after {} evaluations\n",
            story.march_evaluations
        ),
        None => format!(
            "       sphere tracing: no hit after {} evaluations\n",
            story.march_evaluations
        ),
    };
    let Some(root) = story.root else {
        text += "       no root in the box (f64 reference): nothing for Newton to find\n";
        return text;
    };
    text += &format!("       the first root, in f64: t = {root:.10}\n");
    let table = |iterates: &[Iterate]| {
        let mut rows =
            String::from("         step  how        t               g(t)         digits right\n");
        for (number, iterate) in iterates.iter().enumerate() {
            let how = match iterate.step {
                Step::Start => "start",
                Step::Newton => "Newton",
                Step::Bisection => "bisection",
            };
            rows += &format!(
                "         {number:>4}  {how:<9}  {:<14}  {:<11.4e}  {}\n",
                iterate.t,
                iterate.value,
                digits(iterate)
            );
        }
        rows
    };
    match &story.bracketed {
        Some((bracket, iterates)) => {
            text += &format!(
                "       Newton in the bracket [{}, {}] (the box's entry, and the first f32 past \
                 the root where g changes sign), from its low end (newton_bracketed):\n",
                bracket.low, bracket.high
            );
            text += &table(iterates);
        }
        None => text += "       no sign change just past the root: the ray only touches it\n",
    }
    text += "       Newton alone from the same start, no bracket (t - g / g'):\n";
    text += &table(&story.alone);
    if let Some(last) = story.alone.last()
        && !(last.digits.is_none_or(|digits| digits > 5.0))
    {
        text += &format!(
            "         it ends at t = {}, not at the first root ({root:.7})\n",
            last.t
        );
    }
    text += &match story.answer {
        Some(t) => format!(
            "       intersect_implicit (march, bracket, Newton): t = {t}, {} evaluations\n",
            story.answer_evaluations
        ),
        None => format!(
            "       intersect_implicit: no hit, {} evaluations\n",
            story.answer_evaluations
        ),
    };
    text
}

/// `ray` as a primary ray looking for any hit ahead.
fn primary_cast(ray: Ray) -> crate::CastRay {
    crate::CastRay {
        kind: crate::RayKind::Primary,
        ray,
        t_min: 0.0,
        t_max: f32::INFINITY,
    }
}

#[cfg(not(feature = "embree"))]
fn probe_embree<C: Chapters>(_: &Stage<C>, _: &Scene, _: &Ray, _: Option<Hit>) -> Result<()> {
    println!("embree: not built in ({ENABLE_EMBREE})");
    Ok(())
}

#[cfg(feature = "embree")]
fn probe_embree<C: Chapters>(
    stage: &Stage<C>,
    scene: &Scene,
    ray: &Ray,
    ours: Option<Hit>,
) -> Result<()> {
    let ours = ours.map(Answer::from);
    let (embree, quads) = with_embree::build(stage, scene)?;
    let show = |v: Vec3| format!("({}, {}, {})", v.x, v.y, v.z);
    let theirs = embree.intersect(ray, 0.0, f32::INFINITY);
    match theirs {
        Some(hit) => {
            let agreement = match ours {
                Some(ours) if ours.object == hit.object => format!(
                    ", relative difference of t {:.3e} = {:.1} x f32 epsilon",
                    (hit.t - ours.t).abs() / ours.t,
                    (hit.t - ours.t).abs() / ours.t / f32::EPSILON
                ),
                _ => ", NOT the object we hit".into(),
            };
            println!(
                "embree: {} (object {}) at t = {}, point {}, normal {}{agreement}",
                crate::text::terminal_safe(&format!("{:?}", stage.name(hit.object).unwrap_or("?"))),
                hit.object,
                hit.t,
                show(ray.at(hit.t)),
                show(hit.normal.normalize_or_zero()),
            );
        }
        None if ours.is_some() => println!("embree: no hit, NOT what we found"),
        None => println!("embree: no hit"),
    }
    let reference = crosscheck::Reference {
        shapes: stage.shapes(),
        quads: &quads,
    };
    let cast = primary_cast(*ray);
    let compared = reference.compare(
        &cast,
        theirs.map(|hit| Answer {
            object: hit.object,
            t: hit.t,
        }),
    );
    let verdict = match compared.verdict {
        crosscheck::Verdict::Agree => "agree (within the tolerance)".to_string(),
        crosscheck::Verdict::Boundary(reason) => format!("boundary case: {}", reason.describe()),
        crosscheck::Verdict::Disagree => "DISAGREE beyond the tolerance".to_string(),
        crosscheck::Verdict::EdgeMissed => {
            "DISAGREE: Embree hits a shared edge here, and ours misses it".to_string()
        }
    };
    println!("cross-check: {verdict}");
    Ok(())
}

#[cfg(feature = "embree")]
mod with_embree {
    use super::*;
    use crate::CastRay;
    use crate::cli::EXIT_FAILED_CHECK;
    use crate::crosscheck::{
        Boundary, Compared, EDGE_EPSILONS, GRAZING_EPSILONS, PlaneQuad, Reference,
        SILHOUETTE_EPSILONS, TOLERANCE_EPSILONS, Tally, Verdict, cross_check_with, rays_per_second,
    };
    use crate::embree::EmbreeScene;
    use anyhow::Context;

    /// Embree's copy of the stage's shapes, and the quads for the planes.
    pub fn build<C: Chapters>(
        stage: &Stage<C>,
        scene: &Scene,
    ) -> Result<(EmbreeScene, Vec<Option<PlaneQuad>>)> {
        let (primitives, quads) = crosscheck::primitives(stage.shapes(), scene);
        let embree = EmbreeScene::new(&primitives).context("cannot build the Embree scene")?;
        Ok((embree, quads))
    }

    pub fn crosscheck<C: Chapters>(args: &CrosscheckArgs) -> Result<i32> {
        let (scene, chapter) = chosen_scene(args.chapter, args.scene.as_deref())?;
        let settings = args.overrides.settings_for(&scene, chapter)?;
        let stage = Stage::<C>::with_chapters(&scene, chapter, settings)?;
        let implicit = stage
            .shapes()
            .iter()
            .filter(|shape| shape.as_implicit().is_some());
        let implicit = implicit.count();
        if implicit > 0 {
            anyhow::bail!(
                "this scene has {implicit} implicit surfaces at chapter {chapter}, and Embree \
                 has no such primitive: `raylab crosscheck` compares planes, spheres and \
                 triangles (chapter 12's marcher is compared with the exact torus and sphere, \
                 and with their tessellations in Embree, by raylab's tests)"
            );
        }
        let rays = args.overrides.in_pool(|| {
            crate::record::record_rays_within(&stage, crosscheck::MAX_RECORDED_RAYS)
        })??;
        let (embree, quads) = build(&stage, &scene)?;
        let reference = Reference {
            shapes: stage.shapes(),
            quads: &quads,
        };
        let theirs = |cast: &CastRay| {
            embree
                .intersect(&cast.ray, cast.t_min, cast.t_max)
                .map(|hit| Answer {
                    object: hit.object,
                    t: hit.t,
                })
        };
        // Ours is the stage's own search: chapter 11's tree when it has one.
        let ours = |cast: &CastRay| {
            stage
                .nearest_hit(&cast.ray, cast.t_min, cast.t_max)
                .map(Answer::from)
        };
        let tally = args
            .overrides
            .in_pool(|| cross_check_with(&reference, &rays, ours, theirs))?;

        print_header(chapter, &settings, &stage, &embree, &quads);
        print_tally(&tally, &stage);
        print_speed(args.timing_runs, &rays, &stage, &embree);
        if tally.clean() {
            println!(
                "result: agree (no difference beyond the tolerance outside the boundary cases)"
            );
            Ok(0)
        } else {
            println!(
                "result: {} DISAGREEMENT(S) beyond the tolerance outside the boundary cases",
                tally.disagreements
            );
            Ok(EXIT_FAILED_CHECK)
        }
    }

    /// The first line: the render compared, and how Embree holds its shapes.
    fn print_header<C: Chapters>(
        chapter: u8,
        settings: &crate::RenderSettings,
        stage: &Stage<C>,
        embree: &EmbreeScene,
        quads: &[Option<PlaneQuad>],
    ) {
        let version = embree.version();
        let quad_side = quads
            .iter()
            .flatten()
            .map(|quad| 2.0 * quad.half_side)
            .next();
        println!(
            "cross-check of chapter {chapter}: {}x{}, {} spp; ours against Embree {}.{}.{} \
             (robust scene, native spheres{}, each run of triangles one mesh; {} geometries, \
             built in {:.1} ms)",
            settings.width,
            settings.height,
            stage.samples(),
            version / 10000,
            version / 100 % 100,
            version % 100,
            quad_side.map_or(String::new(), |side| format!(
                ", planes as quads of side {side}"
            )),
            embree.geometry_count(),
            embree.build_stats().total().as_secs_f64() * 1e3,
        );
    }

    /// Times both searches over the same rays, in the same order, on this
    /// thread only, and prints the median rates of `timing_runs` runs.
    fn print_speed<C: Chapters>(
        timing_runs: u32,
        rays: &[CastRay],
        stage: &Stage<C>,
        embree: &EmbreeScene,
    ) {
        let mut ours_rates = Vec::new();
        let mut embree_rates = Vec::new();
        for _ in 0..timing_runs {
            ours_rates.push(rays_per_second(rays, |cast| {
                stage.nearest_hit(&cast.ray, cast.t_min, cast.t_max)
            }));
            embree_rates.push(rays_per_second(rays, |cast| {
                embree.intersect(&cast.ray, cast.t_min, cast.t_max)
            }));
        }
        let ours_rate = super::super::bench::median(&ours_rates);
        let embree_rate = super::super::bench::median(&embree_rates);
        println!(
            "speed (1 thread, the same {} rays in the same order, median of {}): \
             ours {:.2} M rays/s, Embree {:.2} M rays/s, ratio ours/Embree {:.3}",
            rays.len(),
            timing_runs,
            ours_rate / 1e6,
            embree_rate / 1e6,
            ours_rate / embree_rate
        );
    }

    fn print_tally<C: Chapters>(tally: &Tally, stage: &Stage<C>) {
        let [
            primary,
            shadow,
            reflection,
            refraction,
            bounce,
            light,
            to_camera,
        ] = tally.by_kind;
        // Bounce rays exist only where the stage traces paths (chapter 13),
        // light paths only from chapter 14.
        let mut bounces = String::new();
        if stage.effects.path_tracing {
            bounces += &format!(", {bounce} bounce");
        }
        if stage.effects.light_tracing {
            bounces += &format!(", {light} light, {to_camera} to camera");
        }
        println!(
            "rays compared: {} ({primary} primary, {shadow} shadow, {reflection} reflection, \
             {refraction} refraction{bounces})",
            tally.total()
        );
        let boundary: u64 = tally.boundary.iter().sum();
        println!(
            "hit/miss: {} same object, {} both miss, {boundary} boundary cases, {} disagreements",
            tally.same_hit, tally.both_miss, tally.disagreements
        );
        for (reason, count) in Boundary::ALL.iter().zip(tally.boundary) {
            if count > 0 {
                println!("  {count:>8} {}", reason.describe());
            }
        }
        if tally.edge_misses > 0 {
            println!(
                "  of the disagreements, {} rays Embree hits on a shared triangle edge were \
                 missed by ours (a crack)",
                tally.edge_misses
            );
        }
        match tally.median_and_max() {
            Some((median, max)) => println!(
                "relative difference of t, same object ({} rays, boundary cases aside): \
                 median {median:.3e} ({:.2} eps), max {max:.3e} ({:.1} eps); \
                 largest in a boundary case {:.3e}",
                tally.relative_differences.len(),
                median / f32::EPSILON,
                max / f32::EPSILON,
                tally.boundary_max_relative_difference,
            ),
            None => println!("relative difference of t: no ray hit the same object in both"),
        }
        if let Some(largest) = &tally.largest_difference {
            println!(
                "  the largest, against its tolerance (an absolute one, set by the hit \
                 point's rounding: a tiny t, as for a shadow ray blocked just off its start, \
                 or a grazing ray makes a large relative difference of a small one):\n     {}",
                describe(largest, stage)
            );
        }
        println!(
            "tolerance: {TOLERANCE_EPSILONS} eps x each hit's error scale; silhouette band \
             {SILHOUETTE_EPSILONS} eps, grazing below {GRAZING_EPSILONS} eps, triangle edge band \
             {EDGE_EPSILONS} eps (docs/embree.md)"
        );
        if tally.worst.is_empty() {
            return;
        }
        println!("worst rays (difference / tolerance):");
        for (rank, compared) in tally.worst.iter().enumerate() {
            println!("{:>3}. {}", rank + 1, describe(compared, stage));
        }
    }

    fn describe<C: Chapters>(compared: &Compared, stage: &Stage<C>) -> String {
        let cast = &compared.cast;
        let kind = cast.kind.name();
        let answer = |answer: Option<Answer>| match answer {
            Some(hit) => format!(
                "{} t={:e}",
                crate::text::terminal_safe(&format!("{:?}", stage.name(hit.object).unwrap_or("?"))),
                hit.t
            ),
            None => "miss".into(),
        };
        let verdict = match compared.verdict {
            Verdict::Agree => "agree".to_string(),
            Verdict::Boundary(reason) => format!("boundary: {reason:?}"),
            Verdict::Disagree => "DISAGREE".to_string(),
            Verdict::EdgeMissed => "DISAGREE (shared edge missed by ours)".to_string(),
        };
        format!(
            "{kind}: ours {}, Embree {}; difference/tolerance {:.2}; {verdict}\n       \
             --ray {},{},{},{},{},{} with {} < t < {}",
            answer(compared.ours),
            answer(compared.theirs),
            compared.severity,
            cast.ray.origin.x,
            cast.ray.origin.y,
            cast.ray.origin.z,
            cast.ray.dir.x,
            cast.ray.dir.y,
            cast.ray.dir.z,
            cast.t_min,
            cast.t_max,
        )
    }
}
