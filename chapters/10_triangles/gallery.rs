//! Chapter 10's bug gallery: the classic mistakes of triangle meshes, each
//! planted in one function of the reference, each asserted to fail chapter
//! 10 on the case that names it; and the correct alternatives that must
//! pass, Moller-Trumbore first ("correct, not yet robust").

use raylab::chapters::CHAPTERS;
use raylab::check::{ChapterVerdict, CheckOptions, Level, Status, check_chapter};
use raylab::course::{Chapters, HitPoint, Textbook};
use raylab::shapes::Triangle;
use raylab::{Ray, Reference, Vec3};

const CHAPTER: u8 = 10;

fn options() -> CheckOptions {
    CheckOptions {
        failures_dir: std::env::temp_dir().join("raylab-chapter-10-tests"),
        write_images: false,
        forbid_answer_key: false,
        fresh: None,
    }
}

/// Checks chapter 10 with `C` and asserts that it fails on case `case`,
/// with the earlier chapters (the reference's) not to blame.
fn assert_caught<C: Chapters>(case: &str) -> ChapterVerdict {
    let verdict = check_chapter::<C>(CHAPTER, &options());
    let text = verdict.text();
    assert_eq!(verdict.status, Status::Fail, "{text}");
    assert_eq!(verdict.failing_case(), Some(case), "{text}");
    assert!(
        text.contains(&format!(
            "hint:     read {}/chapters/10_triangles/lesson.md",
            env!("CARGO_MANIFEST_DIR")
        )),
        "{text}"
    );
    assert_eq!(verdict.needs, None, "{text}");
    verdict
}

/// The reference's Moller-Trumbore with the inside test written by the
/// caller: `inside(beta, gamma)`.
fn moller_trumbore(
    triangle: &Triangle,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    cull_back_faces: bool,
    inside: impl Fn(f32, f32) -> bool,
) -> Option<f32> {
    let [a, b, c] = triangle.corners();
    let (edge_1, edge_2) = (b - a, c - a);
    let p = ray.dir.cross(edge_2);
    let determinant = edge_1.dot(p);
    // The textbook's culling test: a negative determinant is a ray
    // travelling along the winding's normal, meeting the back.
    let rejected = if cull_back_faces {
        determinant.is_nan() || determinant <= 1e-8
    } else {
        !(determinant != 0.0)
    };
    if rejected {
        return None;
    }
    let s = ray.origin - a;
    let q = s.cross(edge_1);
    let beta = s.dot(p) / determinant;
    let gamma = ray.dir.dot(q) / determinant;
    if !inside(beta, gamma) {
        return None;
    }
    let t = edge_2.dot(q) / determinant;
    (t > t_min && t < t_max).then_some(t)
}

fn inclusive(beta: f32, gamma: f32) -> bool {
    beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0
}

// ---------------------------------------------------------------------------
// The bug gallery.

/// A one-sided test: Moller-Trumbore with back faces culled, as renderers
/// of closed opaque models do for speed. The lesson's first ray meets its
/// triangle's back.
struct BackFaceCulled;
impl Chapters for BackFaceCulled {
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, true, inclusive)
    }
}

#[test]
fn gallery_one_sided_triangle() {
    assert_caught::<BackFaceCulled>("triangle-hit-from-behind");
}

/// Edges excluded (`beta > 0`, `beta + gamma < 1`): each triangle leaves its
/// boundary to the neighbour, which leaves it too.
struct StrictEdges;
impl Chapters for StrictEdges {
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, false, |beta, gamma| {
            beta > 0.0 && gamma > 0.0 && beta + gamma < 1.0
        })
    }
}

#[test]
fn gallery_edges_belong_to_no_triangle() {
    assert_caught::<StrictEdges>("triangle-shared-edge");
}

/// The interval's lower end ignored (`t > 0` instead of `t > t_min`).
struct IgnoresTMin;
impl Chapters for IgnoresTMin {
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, _: f32, t_max: f32) -> Option<f32> {
        Reference::intersect_triangle(triangle, ray, 0.0, t_max)
    }
}

#[test]
fn gallery_triangle_ignoring_t_min() {
    assert_caught::<IgnoresTMin>("triangle-before-t-min");
}

/// Barycentric coordinates with beta and gamma swapped: symmetric points
/// (the lesson's, the centroid) cannot tell, a corner can.
struct BarycentricSwapped;
impl Chapters for BarycentricSwapped {
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let weights = Reference::barycentric(triangle, point);
        Vec3::new(weights.x, weights.z, weights.y)
    }
}

#[test]
fn gallery_barycentric_beta_and_gamma_swapped() {
    assert_caught::<BarycentricSwapped>("barycentric-corner-b");
}

/// The blend of the vertex normals not made unit again: right at a corner,
/// too short everywhere between.
struct NormalNotRenormalised;
impl Chapters for NormalNotRenormalised {
    fn smooth_normal(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        let w = Self::barycentric(triangle, point);
        w.x * normals[0] + w.y * normals[1] + w.z * normals[2]
    }
}

#[test]
fn gallery_smooth_normal_not_renormalised() {
    assert_caught::<NormalNotRenormalised>("smooth-normal-centroid");
}

/// Hanika's lift with its sign wrong: the point is pushed down, further
/// below the neighbours, instead of up onto the curved surface.
struct TerminatorSignError;
impl Chapters for TerminatorSignError {
    fn terminator_point(triangle: &Triangle, normals: &[Vec3; 3], point: Vec3) -> Vec3 {
        let weights = Self::barycentric(triangle, point).to_array();
        let mut moved = point;
        for ((corner, normal), weight) in triangle.corners().iter().zip(normals).zip(weights) {
            let height = (point - *corner).dot(*normal);
            if height < 0.0 {
                moved += weight * height * *normal;
            }
        }
        moved
    }
}

#[test]
fn gallery_terminator_moves_points_down() {
    assert_caught::<TerminatorSignError>("terminator-convex-lifted");
}

/// `smooth_hit_point` that uses the vertex normals as given, without
/// turning them to the side the ray arrived on.
struct NormalsNotTurned;
impl Chapters for NormalsNotTurned {
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        let mut smooth = point;
        smooth.normal = Self::smooth_normal(triangle, normals, point.surface.point);
        smooth.surface.point = Self::terminator_point(triangle, normals, point.surface.point);
        smooth
    }
}

#[test]
fn gallery_vertex_normals_not_turned_toward_the_ray() {
    assert_caught::<NormalsNotTurned>("smooth-hit-from-below");
}

/// `smooth_hit_point` that lifts the point of a transparent surface too:
/// its refracted ray would start above the surface it has to cross.
struct LiftsGlass;
impl Chapters for LiftsGlass {
    fn smooth_hit_point<'a>(
        point: HitPoint<'a>,
        triangle: &Triangle,
        normals: &[Vec3; 3],
    ) -> HitPoint<'a> {
        let outward = normals[0] + normals[1] + normals[2];
        let side = if outward.dot(point.normal) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let facing = normals.map(|normal| side * normal);
        let mut smooth = point;
        smooth.normal = Self::smooth_normal(triangle, &facing, point.surface.point);
        smooth.surface.point = Self::terminator_point(triangle, &facing, point.surface.point);
        smooth
    }
}

#[test]
fn gallery_transparent_points_lifted() {
    assert_caught::<LiftsGlass>("smooth-hit-transparent");
}

// ---------------------------------------------------------------------------
// Correct alternatives: they must pass.

#[test]
fn alternative_moller_trumbore_is_correct_but_not_robust() {
    let verdict = check_chapter::<Textbook<Reference, false, true>>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    assert!(!verdict.robust(), "{text}");
    assert!(text.contains("correct, not yet robust"), "{text}");
    let failure = verdict
        .robustness
        .as_ref()
        .and_then(|robustness| robustness.first_failure.as_ref())
        .expect("a hard case fails");
    assert_eq!(
        failure.name, "triangle-closed-mesh-nothing-escapes",
        "{text}"
    );
    assert_eq!(failure.level, Level::Robustness, "{text}");
}

/// Cramer's rule with three determinants of their own (not
/// Moller-Trumbore's shared cross products): right to rounding, and not
/// watertight, which the closed mesh, not one formula's known failures,
/// shows.
struct CramersRule;
impl Chapters for CramersRule {
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let [a, b, c] = triangle.corners();
        let (e1, e2, s) = (b - a, c - a, ray.origin - a);
        let back = -ray.dir;
        let determinant = back.dot(e1.cross(e2));
        if determinant == 0.0 || !determinant.is_finite() {
            return None;
        }
        let t = s.dot(e1.cross(e2)) / determinant;
        let beta = back.dot(s.cross(e2)) / determinant;
        let gamma = back.dot(e1.cross(s)) / determinant;
        (beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0 && t > t_min && t < t_max).then_some(t)
    }
}

#[test]
fn alternative_cramers_rule_is_correct_but_lets_rays_out_of_a_closed_mesh() {
    let verdict = check_chapter::<CramersRule>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.passes(), "{text}");
    let failure = verdict
        .robustness
        .as_ref()
        .and_then(|robustness| robustness.first_failure.as_ref())
        .expect("a hard case fails");
    assert_eq!(
        failure.name, "triangle-closed-mesh-nothing-escapes",
        "{text}"
    );
    assert!(
        text.contains("rays hit no triangle and escape the closed mesh"),
        "{text}"
    );
}

/// Moller-Trumbore as raylab keeps it, and as written here (division by
/// the determinant instead of a multiplication by its inverse): both the
/// same "correct, not yet robust" answer to every checkpoint.
struct MollerTrumboreByDivision;
impl Chapters for MollerTrumboreByDivision {
    fn intersect_triangle(triangle: &Triangle, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        moller_trumbore(triangle, ray, t_min, t_max, false, inclusive)
    }
}

#[test]
fn alternative_moller_trumbore_by_division_passes_the_checkpoints() {
    let verdict = check_chapter::<MollerTrumboreByDivision>(CHAPTER, &options());
    assert!(verdict.passes(), "{}", verdict.text());
}

/// Barycentric coordinates as ratios of signed areas (cross products along
/// the normal) instead of the lesson's two-equation solve.
struct BarycentricByAreas;
impl Chapters for BarycentricByAreas {
    fn barycentric(triangle: &Triangle, point: Vec3) -> Vec3 {
        let [a, b, c] = triangle.corners();
        let normal = (b - a).cross(c - a);
        let area = |p: Vec3, q: Vec3, r: Vec3| (q - p).cross(r - p).dot(normal);
        Vec3::new(area(point, b, c), area(a, point, c), area(a, b, point)) / normal.dot(normal)
    }
}

#[test]
fn alternative_barycentric_by_areas() {
    let verdict = check_chapter::<BarycentricByAreas>(CHAPTER, &options());
    assert!(verdict.passes(), "{}", verdict.text());
}

#[test]
fn the_reference_passes_chapter_10_at_both_levels_image_included() {
    let verdict = check_chapter::<Reference>(CHAPTER, &options());
    let text = verdict.text();
    assert!(verdict.robust(), "{text}");
    let image = verdict.image.as_ref().expect("the image was compared");
    assert!(image.passed, "{text}");
}

// ---------------------------------------------------------------------------
// The cases and the lesson agree.

#[test]
fn the_lesson_promises_the_first_two_cases() {
    let info = CHAPTERS
        .iter()
        .find(|info| info.number == CHAPTER)
        .expect("chapter 10 is registered");
    let cases = raylab::check::catalog::checkpoints(info.number);
    let names: Vec<&str> = cases.iter().take(2).map(|case| case.name).collect();
    assert_eq!(
        names,
        ["triangle-hit-from-behind", "barycentric-lesson-point"]
    );
    assert!(
        cases[0].says.contains("expected t = 2"),
        "{}",
        cases[0].says
    );
    assert!(
        cases[1].says.contains("expected (0.5, 0.25, 0.25)"),
        "{}",
        cases[1].says
    );
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("chapters/10_triangles/lesson.md"),
    )
    .expect("the lesson reads");
    // Sentences are compared with their line breaks as spaces.
    let lesson = text.split_whitespace().collect::<Vec<_>>().join(" ");
    for promise in [
        "ray from (0.25, 0.25, 0) along +z at the triangle (0,0,2), (1,0,2), (0,1,2)",
        "hit at `t = 2`",
        "barycentric coordinates (0.5, 0.25, 0.25)",
    ] {
        assert!(
            lesson.contains(promise),
            "the lesson no longer says {promise}"
        );
    }
    // Every case points at a section the lesson has, heading for heading.
    let headings: Vec<&str> = text
        .lines()
        .filter(|line| line.starts_with('#'))
        .map(|line| line.trim_start_matches('#').trim())
        .collect();
    for case in cases
        .iter()
        .chain(&raylab::check::catalog::robustness(info.number))
    {
        assert!(
            headings.contains(&case.section),
            "{}: no section \"{}\" in the lesson",
            case.name,
            case.section
        );
    }
}

/// `--terminator flat` shows what chapter 10's lift fixes: on lesson 10's
/// coarse smooth model lit from the side, rays leaving the flat triangles
/// are shadowed by the neighbouring facets along the terminator, so the
/// picture darkens there; lifted, it is smooth. A renderer that ignored
/// the setting, or a lift that did nothing, would draw the two alike.
#[test]
fn the_flat_terminator_darkens_what_the_lift_lights() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scenes/terminator.toml");
    let scene = raylab::Scene::load(&path).expect("lesson 10's terminator scene");
    let render = |terminator| {
        let settings = raylab::RenderSettings {
            width: 160,
            height: 120,
            samples: 1,
            terminator,
            ..scene.render
        };
        raylab::render::render(&scene, CHAPTER, &settings, None).expect("renders")
    };
    let lifted = render(raylab::scene::TerminatorRule::Lifted);
    let flat = render(raylab::scene::TerminatorRule::Flat);
    let default = render(raylab::RenderSettings::default().terminator);
    assert_eq!(default.rgb, lifted.rgb, "lifted is the default");
    let brightness = |rgb: &[u8]| rgb.iter().map(|&v| u64::from(v)).sum::<u64>();
    let changed = flat
        .rgb
        .chunks(3)
        .zip(lifted.rgb.chunks(3))
        .filter(|(f, l)| f.iter().zip(l.iter()).any(|(f, l)| f.abs_diff(*l) > 2))
        .count();
    // About 3% of the pixels at 320x240 (lesson 10).
    assert!(changed > 400, "only {changed} pixels changed by the lift");
    assert!(
        brightness(&flat.rgb) < brightness(&lifted.rgb),
        "the flat origins should shadow more than they light"
    );
}
