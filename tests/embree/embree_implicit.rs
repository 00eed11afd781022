//! Chapter 12's march against Embree, which has no implicit surfaces: the
//! built-in scene's torus and sphere, tessellated into triangles whose
//! corners lie on the surface, meet every camera ray where raylab's march
//! (and Newton) does, within the tessellation's own error.

use std::f32::consts::PI;

use raylab::check::exact;
use raylab::crosscheck::Primitive;
use raylab::embree::EmbreeScene;
use raylab::shapes::{Implicit, Sdf};
use raylab::{Ray, Shape, Vec3};

/// A grid of `rows x columns` quads over a surface given by its angles,
/// two triangles each.
fn grid(rows: usize, columns: usize, point: impl Fn(usize, usize) -> Vec3) -> Vec<Primitive> {
    let mut triangles = Vec::with_capacity(rows * columns * 2);
    for row in 0..rows {
        for column in 0..columns {
            let (a, b) = (point(row, column), point(row + 1, column));
            let (c, d) = (point(row + 1, column + 1), point(row, column + 1));
            triangles.push(Primitive::Triangle([a, b, c]));
            triangles.push(Primitive::Triangle([a, c, d]));
        }
    }
    triangles
}

/// The surface and its tessellation, with the bound on how far the flat
/// triangles stray from it: each is spanned by two arcs of the grid (one
/// around the axis, one around the tube or from pole to pole), and a chord
/// of angle `a` on a circle of radius `rho` is at most the sagitta
/// `rho (1 - cos(a / 2))` from it. A triangle strays by at most the sum of
/// its two arcs' sagittas, to second order; the bound is twice that.
struct Tessellated {
    tree: Sdf,
    triangles: Vec<Primitive>,
    bound: f64,
}

fn sagitta(radius: f32, pieces: usize, of_angle: f32) -> f64 {
    f64::from(radius) * (1.0 - f64::from(of_angle / pieces as f32 / 2.0).cos())
}

fn torus(center: Vec3, major: f32, minor: f32) -> Tessellated {
    let (around, tube) = (512, 128);
    let point = |i: usize, j: usize| {
        let phi = 2.0 * PI * (i % around) as f32 / around as f32;
        let theta = 2.0 * PI * (j % tube) as f32 / tube as f32;
        let radial = Vec3::new(phi.cos(), 0.0, phi.sin());
        center + radial * (major + minor * theta.cos()) + Vec3::Y * (minor * theta.sin())
    };
    Tessellated {
        tree: Sdf::Torus {
            center,
            major,
            minor,
        },
        triangles: grid(around, tube, point),
        bound: 2.0 * (sagitta(major + minor, around, 2.0 * PI) + sagitta(minor, tube, 2.0 * PI)),
    }
}

fn sphere(center: Vec3, radius: f32) -> Tessellated {
    let (around, poles) = (512, 256);
    let point = |i: usize, j: usize| {
        let phi = 2.0 * PI * (i % around) as f32 / around as f32;
        let theta = PI * j as f32 / poles as f32;
        center
            + radius
                * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                )
    };
    Tessellated {
        tree: Sdf::Sphere { center, radius },
        triangles: grid(around, poles, point),
        bound: 2.0 * (sagitta(radius, around, 2.0 * PI) + sagitta(radius, poles, PI)),
    }
}

/// The first crossing of the exact surface grown by `grow`.
fn exact_hit(tree: &Sdf, ray: &Ray, grow: f64) -> Option<f64> {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    match tree {
        Sdf::Sphere { center, radius } => exact::sphere(
            center.as_dvec3(),
            f64::from(*radius) + grow,
            o,
            d,
            0.0,
            f64::INFINITY,
        ),
        Sdf::Torus {
            center,
            major,
            minor,
        } => exact::torus(
            center.as_dvec3(),
            f64::from(*major),
            f64::from(*minor) + grow,
            o,
            d,
            0.0,
            f64::INFINITY,
        ),
        _ => None,
    }
}

#[test]
fn the_scenes_torus_and_sphere_agree_with_their_tessellations_in_embree() {
    let eye = Vec3::new(0.0, 2.2, -5.5);
    for surface in [
        torus(Vec3::new(-1.75, 0.3, 0.4), 0.75, 0.3),
        sphere(Vec3::new(0.55, 0.35, -1.3), 0.35),
    ] {
        let shape: Shape = Implicit::new(surface.tree.clone())
            .expect("a valid tree")
            .into();
        let embree = EmbreeScene::new(&surface.triangles).expect("Embree scene");
        let bounds = shape.bounds().expect("a box");
        let (mut same, mut boundary, mut worst) = (0u64, 0u64, 0.0f64);
        let side = 240;
        for row in 0..side {
            for column in 0..side {
                // Rays through a grid over the box, as seen from the eye.
                let target = bounds.min
                    + (bounds.max - bounds.min)
                        * Vec3::new(
                            (column as f32 + 0.5) / side as f32,
                            (row as f32 + 0.5) / side as f32,
                            0.5,
                        );
                let ray = Ray::new(eye, target - eye);
                let ours = shape.intersect(&ray, 0.0, f32::INFINITY).map(f64::from);
                let theirs = embree
                    .intersect(&ray, 0.0, f32::INFINITY)
                    .map(|hit| f64::from(hit.t));
                let speed = ray.dir.as_dvec3().length();
                match (ours, theirs) {
                    (Some(ours), Some(theirs)) => {
                        let exact = exact_hit(&surface.tree, &ray, 0.0);
                        let normal = exact::difference_normal(
                            &surface.tree,
                            ray.origin.as_dvec3() + ours * ray.dir.as_dvec3(),
                            raylab::shapes::NormalMethod::Analytic,
                            0.0,
                        );
                        let cosine = normal.dot(ray.dir.as_dvec3() / speed).abs();
                        // Near the silhouette a sub-bound shift of the
                        // surface moves t without bound: a boundary case.
                        // A ray the exact surface does not cross skims it
                        // within the march's cone.
                        if cosine < 0.05 || exact.is_none() {
                            boundary += 1;
                            continue;
                        }
                        let apart = (ours - theirs).abs() * speed;
                        let allowed = surface.bound / cosine + 1e-5 * ours * speed;
                        // The march may stop where the ray skims the
                        // surface within its cone before crossing it
                        // farther on: the surface shrunk by the cone is not
                        // crossed before that point.
                        let cone = 2.0
                            * f64::from(raylab::shapes::March::default().tolerance)
                            * ours
                            * speed;
                        let at = exact::sdf_distance(
                            &surface.tree,
                            ray.origin.as_dvec3() + ours * ray.dir.as_dvec3(),
                        );
                        let shrunk = exact_hit(&surface.tree, &ray, -cone);
                        if apart > allowed
                            && at.abs() <= cone
                            && shrunk.is_none_or(|root| root > ours)
                        {
                            boundary += 1;
                            continue;
                        }
                        assert!(
                            apart <= allowed,
                            "{ray:?}: ours {ours}, Embree {theirs}, {apart} apart, allowed {allowed}"
                        );
                        worst = worst.max(apart * cosine / surface.bound);
                        same += 1;
                    }
                    (None, None) => same += 1,
                    (ours, theirs) => {
                        // Hit or miss may differ only where the surface
                        // grown and shrunk by the bound and the march's
                        // cone (a march may stop on a ray that skims the
                        // surface within it) disagree.
                        let t = ours.or(theirs).unwrap_or(0.0);
                        let cone =
                            2.0 * f64::from(raylab::shapes::March::default().tolerance) * t * speed;
                        let grown = exact_hit(&surface.tree, &ray, surface.bound + cone);
                        let shrunk = exact_hit(&surface.tree, &ray, -surface.bound - cone);
                        assert!(
                            grown.is_some() != shrunk.is_some(),
                            "{ray:?}: ours {ours:?}, Embree {theirs:?}, away from the silhouette \
                             (exact {:?}, grown {grown:?}, shrunk {shrunk:?})",
                            exact_hit(&surface.tree, &ray, 0.0)
                        );
                        boundary += 1;
                    }
                }
            }
        }
        let total = (side * side) as u64;
        println!(
            "{:?}: {same} of {total} rays agree, {boundary} at the silhouette; tessellation bound {:e}, \
             largest gap {worst:.3} of it",
            surface.tree, surface.bound
        );
        assert!(
            boundary * 50 < total,
            "{boundary} of {total} at the silhouette"
        );
        assert!(same > total / 4);
    }
}
