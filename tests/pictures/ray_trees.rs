//! `raylab trace`'s ray trees: the pixel a tree ends in is the rendered
//! pixel, for every chapter and every pixel of a small image, and each
//! tree holds the rays the stage casts for that pixel, nested.

use raylab::RayKind;
use raylab::ray_tree::{TracedRay, light_paths_into_pixel, trace_pixel};

fn count(ray: &TracedRay) -> usize {
    1 + ray.children.iter().map(count).sum::<usize>()
}

/// Every bounce carries a share of the pixel no larger than its parent's
/// (a reflectivity, a transparency, a Fresnel split is at most 1), and
/// shadow rays none. A path (`paths`, chapter 13 on) may grow a share:
/// Russian roulette divides a survivor's by its chance of surviving, so
/// there a share need only be positive and finite.
fn shares_shrink(ray: &TracedRay, parent: f32, paths: bool) {
    match ray.kind {
        RayKind::Shadow => assert_eq!(ray.weight, None),
        _ => {
            let weight = ray.weight.expect("a traced ray's share");
            assert!(
                weight > 0.0 && weight.is_finite() && (paths || weight <= parent),
                "{weight} under {parent}"
            );
            for child in &ray.children {
                shares_shrink(child, weight, paths);
            }
        }
    }
}

/// The running sum after the last ray cast (the deepest last bounce).
fn last_running_sum(ray: &TracedRay) -> glam::DVec3 {
    ray.children
        .iter()
        .rev()
        .find(|child| child.running_sum.is_some())
        .map_or_else(
            || ray.running_sum.expect("a camera ray has a running sum"),
            last_running_sum,
        )
}

#[test]
fn every_traced_pixel_is_the_rendered_pixel_in_every_chapter() {
    for chapter in raylab::chapters::CHAPTERS
        .iter()
        .map(|chapter| chapter.number)
    {
        let scene = raylab::builtin::scene(chapter).expect("built-in scene");
        let settings = raylab::RenderSettings {
            width: 24,
            height: 18,
            ..scene.render
        };
        let rendered = raylab::render(&scene, chapter, &settings, None).expect("renders");
        let stage = raylab::Stage::new(&scene, chapter, settings).expect("valid settings");
        let mut rays = 0;
        for y in 0..settings.height {
            for x in 0..settings.width {
                let traced = trace_pixel(&stage, (x, y)).expect("a pixel of the image");
                let at = 3 * (y * settings.width + x) as usize;
                assert_eq!(
                    traced.srgb[..],
                    rendered.rgb[at..at + 3],
                    "chapter {chapter}, pixel {x},{y}"
                );
                assert!(!traced.truncated);
                assert!(
                    traced
                        .samples
                        .iter()
                        .all(|root| root.kind == RayKind::Primary && root.color.is_some())
                );
                rays += traced.samples.iter().map(count).sum::<usize>();
                for root in &traced.samples {
                    assert_eq!(root.weight, Some(1.0));
                    shares_shrink(root, 1.0, stage.effects.path_tracing);
                }
                // Chapter 14's light paths come after the camera rays.
                let sum = last_running_sum(traced.samples.last().expect("a camera ray"))
                    + traced.light_paths.unwrap_or_default().as_dvec3();
                let pixel = traced.color.as_dvec3();
                assert!(
                    (sum - pixel).abs().max_element() <= 1e-5 * (1.0 + pixel.max_element()),
                    "chapter {chapter}, pixel {x},{y}: running sum {sum} for {pixel}"
                );
            }
        }
        // The trees hold every camera path's ray the render cast: no more,
        // no fewer (chapter 14's light paths belong to no pixel).
        let light_rays = rendered.rays.of(RayKind::Light) + rendered.rays.of(RayKind::ToCamera);
        assert_eq!(
            rays as u64,
            rendered.rays.total() - light_rays,
            "chapter {chapter}"
        );
    }
}

#[test]
fn shadow_rays_name_their_light_and_bounces_nest_under_their_point() {
    // Chapter 6's centre pixel meets the mirror ball: a reflection ray
    // under the camera ray, and shadow rays toward the scene's lights.
    let scene = raylab::builtin::scene(6).expect("built-in scene");
    let stage = raylab::Stage::new(&scene, 6, scene.render).expect("valid settings");
    let centre = (scene.render.width / 2, scene.render.height / 2);
    let traced = trace_pixel(&stage, centre).expect("the centre pixel");
    let root = &traced.samples[0];
    let hit = root.hit.as_ref().expect("the camera ray meets something");
    assert!(!hit.name.is_empty());
    let shadows: Vec<&TracedRay> = root
        .children
        .iter()
        .filter(|child| child.kind == RayKind::Shadow)
        .collect();
    assert!(!shadows.is_empty(), "{root:#?}");
    for shadow in &shadows {
        let light = shadow.light.expect("a shadow ray ends at a light");
        assert!(light < scene.lights.len());
        assert!(shadow.color.is_none() && shadow.children.is_empty());
    }
    let bounce = root
        .children
        .iter()
        .find(|child| child.kind == RayKind::Reflection)
        .expect("the mirror reflects");
    assert!(bounce.color.is_some());
    // The bounce leaves from the camera ray's point.
    assert!((bounce.ray.origin - hit.point).length() < 1e-3);
    // Outside the image: no pixel.
    assert!(trace_pixel(&stage, (scene.render.width, 0)).is_none());
}

/// The light paths drawn for a pixel (`raylab figure --draw-light-paths`)
/// are paths that light it: each starts with a ray from a light, and one
/// of its rays toward the camera arrives unblocked from a point the camera
/// sees in that pixel.
#[test]
fn a_pixels_light_paths_start_at_a_light_and_reach_the_camera_through_it() {
    let scene = raylab::builtin::scene(14).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width: 160,
        height: 120,
        ..scene.render
    };
    let stage = raylab::Stage::new(&scene, 14, settings).expect("valid settings");
    // A pixel of the caustic under the glass ball.
    let pixel = (81, 104);
    let paths = light_paths_into_pixel(&stage, pixel, 2);
    assert_eq!(paths.len(), 2);
    for path in &paths {
        assert_eq!(path.kind, RayKind::Light);
        let mut rays = vec![path];
        let mut reaches = false;
        while let Some(ray) = rays.pop() {
            rays.extend(&ray.children);
            let seen = stage.camera().project(ray.ray.origin);
            reaches |= ray.kind == RayKind::ToCamera
                && ray.hit.is_none()
                && seen.map(|(x, y)| (x as u32, y as u32)) == Some(pixel);
        }
        assert!(reaches, "{path:#?}");
    }
    // A stage without light paths has none to draw.
    let scene = raylab::builtin::scene(8).expect("built-in scene");
    let stage = raylab::Stage::new(&scene, 8, scene.render).expect("valid settings");
    assert!(light_paths_into_pixel(&stage, (10, 10), 2).is_empty());
}

/// At a Phong stage, each unblocked shadow ray carries what its light adds
/// at the point: for chapter 5's matte surfaces (no mirror, no glass), the
/// point's colour is the ambient term plus those shares, every pixel.
#[test]
fn the_lights_shares_and_the_ambient_term_make_a_phong_points_colour() {
    let scene = raylab::builtin::scene(5).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width: 32,
        height: 24,
        ..scene.render
    };
    let stage = raylab::Stage::new(&scene, 5, settings).expect("valid settings");
    let mut with_light = 0;
    for y in 0..settings.height {
        for x in 0..settings.width {
            let traced = trace_pixel(&stage, (x, y)).expect("a pixel");
            let root = &traced.samples[0];
            let Some(hit) = &root.hit else { continue };
            let mut sum = hit.albedo * hit.material.ambient * scene.ambient_light;
            for shadow in &root.children {
                assert_eq!(shadow.kind, RayKind::Shadow);
                match (&shadow.hit, shadow.light_share) {
                    (None, Some(share)) => {
                        sum += share.diffuse + share.specular;
                        with_light += 1;
                    }
                    (Some(_), None) => {}
                    other => panic!("pixel {x},{y}: {other:?}"),
                }
            }
            let color = root.color.expect("a colour");
            assert!(
                (color - sum).abs().max_element() <= 1e-5 * (1.0 + color.max_element()),
                "pixel {x},{y}: {color} vs {sum}"
            );
        }
    }
    assert!(with_light > 0);
}
