//! The image loop and the Whitted tracer that ties the chapters together.
//!
//! Each chapter's file holds one idea; this file only decides, for every
//! ray, which of those ideas the current stage switches on, and in which
//! order they combine:
//!
//! ```text
//! colour(ray) = background                                 if nothing is hit
//!             = (1 - kr - kt) (ambient + diffuse) + specular
//!               + kr colour(reflected ray)                 chapter 6
//!               + kt tint colour(refracted ray)            chapter 8
//! ```

use std::time::Instant;

use rayon::prelude::*;

use crate::camera::Camera;
use crate::chapters::ch03_nearest::{first_hit, nearest_hit};
use crate::chapters::ch04_shadows::{RayOffset, SurfacePoint, shadow_ray_from, surface_point};
use crate::chapters::ch05_phong::{ambient, phong_terms};
use crate::chapters::ch06_reflection::reflected_ray;
use crate::chapters::ch07_antialiasing::sample_offset;
use crate::chapters::ch08_refraction::refracted_ray;
use crate::output::linear_to_srgb8;
use crate::scene::{RenderSettings, SphereFormula};
use crate::stage::{Effects, Lighting};
use crate::{Material, Ray, Scene, Shape, Vec3};

/// The kinds of ray a render casts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RayKind {
    Primary,
    Shadow,
    Reflection,
    Refraction,
}

/// What the tracer reports as it works: every ray it casts, and the events
/// worth counting. [`RayCounts`] counts; other logs can record rays.
pub trait RayLog {
    /// A ray of `kind` is about to be traced, looking for hits in `(t_min, t_max)`.
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32);
    /// A shadow ray hit the very primitive it left, which the exact segment
    /// cannot do: shadow acne. Only the first blocker in scene order is
    /// examined, so this may undercount.
    fn self_shadow(&mut self) {}
    /// A sample came out NaN or infinite (it is written as black).
    fn non_finite_sample(&mut self) {}
}

/// How many rays of each kind a render cast, and how many went wrong.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub primary: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Shadow rays that hit the primitive they started on, where the exact
    /// segment does not (acne).
    pub self_shadow_hits: u64,
    /// Pixels with at least one such shadow ray: the acne a student sees.
    /// Only [`render`] fills it in (a log sees rays, not pixels).
    pub self_shadowed_pixels: u64,
    /// Samples whose colour was NaN or infinite.
    pub non_finite_samples: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection + self.refraction
    }

    fn add(mut self, other: RayCounts) -> RayCounts {
        self.primary += other.primary;
        self.shadow += other.shadow;
        self.reflection += other.reflection;
        self.refraction += other.refraction;
        self.self_shadow_hits += other.self_shadow_hits;
        self.self_shadowed_pixels += other.self_shadowed_pixels;
        self.non_finite_samples += other.non_finite_samples;
        self
    }
}

impl RayLog for RayCounts {
    fn cast(&mut self, kind: RayKind, _: &Ray, _: f32, _: f32) {
        match kind {
            RayKind::Primary => self.primary += 1,
            RayKind::Shadow => self.shadow += 1,
            RayKind::Reflection => self.reflection += 1,
            RayKind::Refraction => self.refraction += 1,
        }
    }
    fn self_shadow(&mut self) {
        self.self_shadow_hits += 1;
    }
    fn non_finite_sample(&mut self) {
        self.non_finite_samples += 1;
    }
}

/// One ray as the tracer cast it: what [`RayRecorder`] keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CastRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// The tracer looked for hits with `t_min < t < t_max`.
    pub t_min: f32,
    pub t_max: f32,
}

/// A [`RayLog`] that keeps every ray cast, in order (for `raylab crosscheck`).
#[derive(Debug, Clone, Default)]
pub struct RayRecorder {
    pub rays: Vec<CastRay>,
}

impl RayLog for RayRecorder {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.rays.push(CastRay {
            kind,
            ray: *ray,
            t_min,
            t_max,
        });
    }
}

/// Every ray that rendering the whole image with `tracer` casts, in a fixed
/// order: row by row from the top, pixel by pixel, and within a pixel in the
/// order the tracer casts them. Rows are traced in parallel, each into its
/// own log, and the logs are joined in row order, so the list does not depend
/// on the number of threads.
pub fn record_rays(tracer: &Tracer, camera: &Camera) -> Vec<CastRay> {
    let (width, height) = (tracer.settings.width, tracer.settings.height);
    let rows: Vec<Vec<CastRay>> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut recorder = RayRecorder::default();
            for x in 0..width {
                tracer.pixel(camera, x, y, &mut recorder);
            }
            recorder.rays
        })
        .collect();
    rows.concat()
}

/// A finished render.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub width: u32,
    pub height: u32,
    /// sRGB-encoded pixels, row by row from the top, 3 bytes each.
    pub rgb: Vec<u8>,
    /// The effects that were simulated.
    pub effects: Effects,
    pub rays: RayCounts,
    pub seconds: f64,
}

impl Rendered {
    /// The stable fingerprint of the image (see [`crate::output::image_hash`]).
    pub fn hash(&self) -> u64 {
        crate::output::image_hash(self.width, self.height, &self.rgb)
    }
}

/// Everything needed to trace rays through one scene at one chapter's stage.
pub struct Tracer<'a> {
    scene: &'a Scene,
    /// The shapes this stage can intersect (chapter 1 knows no spheres), with
    /// their materials, index for index.
    shapes: Vec<Shape>,
    materials: Vec<Material>,
    /// For each of `shapes`, its index in the scene (for its name).
    scene_indices: Vec<usize>,
    offset: RayOffset,
    pub effects: Effects,
    pub settings: RenderSettings,
}

impl<'a> Tracer<'a> {
    /// A tracer for `scene` at `chapter`'s stage with `settings`, simulating
    /// only the effects the scene can show.
    pub fn new(scene: &'a Scene, chapter: u8, settings: RenderSettings) -> Tracer<'a> {
        let stage = Effects::for_chapter(chapter);
        let samples = if stage.antialiasing {
            settings.samples
        } else {
            1
        };
        let effects = stage.needed_by(scene, samples);
        let scene_indices: Vec<usize> = (0..scene.shapes.len())
            .filter(|&index| {
                if scene.shapes[index].is_sphere() {
                    effects.spheres
                } else {
                    effects.planes
                }
            })
            .collect();
        let (shapes, materials) = scene_indices
            .iter()
            .map(|&index| (&scene.shapes[index], &scene.materials[index]))
            .map(|(shape, material)| match (shape, settings.sphere_formula) {
                (Shape::Sphere(sphere), SphereFormula::Textbook) => {
                    (Shape::TextbookSphere(*sphere), *material)
                }
                _ => (*shape, *material),
            })
            .unzip();
        Tracer {
            scene,
            shapes,
            materials,
            scene_indices,
            offset: settings.offset(),
            effects,
            settings,
        }
    }

    /// Samples per pixel actually taken (1 before chapter 7).
    pub fn samples(&self) -> u32 {
        if self.effects.antialiasing {
            self.settings.samples
        } else {
            1
        }
    }

    /// The shapes this stage intersects.
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The name of `object` (an index into [`Tracer::shapes`]) in the scene.
    pub fn name(&self, object: usize) -> &str {
        &self.scene.names[self.scene_indices[object]]
    }

    /// The colour of pixel `(x, y)`, in linear light: the mean of its samples,
    /// summed in sample order.
    pub fn pixel(&self, camera: &Camera, x: u32, y: u32, log: &mut impl RayLog) -> Vec3 {
        let samples = self.samples();
        if samples == 1 {
            return self.sample(camera, x as f32 + 0.5, y as f32 + 0.5, log);
        }
        let mut sum = Vec3::ZERO;
        for index in 0..samples {
            let settings = &self.settings;
            let (dx, dy) = sample_offset(settings.sampling, samples, index, (x, y), settings.seed);
            sum += self.sample(camera, x as f32 + dx, y as f32 + dy, log);
        }
        sum / samples as f32
    }

    fn sample(&self, camera: &Camera, x: f32, y: f32, log: &mut impl RayLog) -> Vec3 {
        let ray = camera.ray_through(x, y);
        log.cast(RayKind::Primary, &ray, 0.0, f32::INFINITY);
        let color = self.trace(&ray, 0, 1.0, log);
        if color.is_finite() {
            color
        } else {
            log.non_finite_sample();
            Vec3::ZERO
        }
    }

    /// The colour seen along `ray`. `depth` counts the bounces so far and
    /// `weight` is this ray's share of the pixel.
    pub fn trace(&self, ray: &Ray, depth: u32, weight: f32, log: &mut impl RayLog) -> Vec3 {
        let hit = if self.effects.nearest_hit {
            nearest_hit(&self.shapes, ray, 0.0, f32::INFINITY)
        } else {
            first_hit(&self.shapes, ray, 0.0, f32::INFINITY)
        };
        let Some(hit) = hit else {
            return self.scene.background;
        };
        let shape = &self.shapes[hit.object];
        let material = &self.materials[hit.object];
        let surface = surface_point(shape, ray, hit.t);
        let albedo = material.albedo_at(shape, surface.point);
        if self.effects.lighting == Lighting::Unlit {
            return albedo;
        }
        let (diffuse, specular) =
            self.local_light(hit.object, material, albedo, &surface, ray, log);
        let mirror_share = if self.effects.reflection {
            material.reflectivity
        } else {
            0.0
        };
        let glass_share = if self.effects.refraction {
            material.transparency
        } else {
            0.0
        };
        let mut color = (1.0 - mirror_share - glass_share) * diffuse + specular;
        if depth >= self.settings.max_depth {
            return color;
        }
        let worth_casting =
            |share: f32| share > 0.0 && weight * share >= self.settings.min_contribution;
        // Light that cannot cross the surface (total internal reflection) is
        // reflected instead, so it joins the mirror's share.
        let mut reflected_share = mirror_share;
        if worth_casting(glass_share) {
            match refracted_ray(&surface, ray.dir, material.ior, self.offset) {
                Some(refracted) => {
                    log.cast(RayKind::Refraction, &refracted, 0.0, f32::INFINITY);
                    let through = self.trace(&refracted, depth + 1, weight * glass_share, log);
                    color += glass_share * material.color * through;
                }
                None => reflected_share += glass_share,
            }
        }
        if worth_casting(reflected_share) {
            let reflected = reflected_ray(&surface, ray.dir, self.offset);
            log.cast(RayKind::Reflection, &reflected, 0.0, f32::INFINITY);
            color +=
                reflected_share * self.trace(&reflected, depth + 1, weight * reflected_share, log);
        }
        color
    }

    /// Ambient plus diffuse light, and specular light, at a surface point:
    /// chapter 4's flat lighting or chapter 5's Phong, with a shadow ray to
    /// each light.
    fn local_light(
        &self,
        object: usize,
        material: &Material,
        albedo: Vec3,
        surface: &SurfacePoint,
        ray: &Ray,
        log: &mut impl RayLog,
    ) -> (Vec3, Vec3) {
        let to_eye = -ray.dir.normalize();
        // Light the side of the surface the ray arrived on.
        let normal = if surface.normal.dot(to_eye) >= 0.0 {
            surface.normal
        } else {
            -surface.normal
        };
        // Seen from inside a sphere, a light outside it is hidden by the
        // sphere itself: no need to cast a ray to learn that.
        let inside_sphere = match self.shapes[object] {
            Shape::Sphere(sphere) | Shape::TextbookSphere(sphere) => {
                (surface.normal.dot(to_eye) < 0.0).then_some(sphere)
            }
            Shape::Plane(_) => None,
        };
        let mut diffuse = ambient(albedo, material.ambient, self.scene.ambient_light);
        let mut specular = Vec3::ZERO;
        for light in &self.scene.lights {
            let to_light = light.position - surface.point;
            if normal.dot(to_light) <= 0.0 {
                continue; // the light is behind this side of the surface
            }
            if inside_sphere.is_some_and(|sphere| !sphere.contains(light.position)) {
                continue;
            }
            if self.effects.shadows {
                let shadow_ray = shadow_ray_from(surface, light.position, self.offset);
                log.cast(RayKind::Shadow, &shadow_ray, 0.0, 1.0);
                if let Some(blocker) = first_hit(&self.shapes, &shadow_ray, 0.0, 1.0) {
                    // Planes and spheres are convex, and lights outside a
                    // sphere seen from inside were skipped above: a shadow
                    // ray that meets its own surface is always acne.
                    if blocker.object == object {
                        log.self_shadow();
                    }
                    continue;
                }
            }
            match self.effects.lighting {
                Lighting::Flat => diffuse += albedo * material.diffuse * light.radiance(),
                Lighting::Phong => {
                    let terms = phong_terms(
                        material,
                        albedo,
                        normal,
                        to_light.normalize(),
                        to_eye,
                        light.radiance(),
                    );
                    diffuse += terms.diffuse;
                    if self.effects.specular {
                        specular += terms.specular;
                    }
                }
                Lighting::Unlit => {}
            }
        }
        (diffuse, specular)
    }
}

/// Renders `scene` at `chapter`'s stage with `settings` on the current rayon
/// thread pool. Each pixel depends only on the scene, the settings and its
/// position, so the image is the same on any number of threads.
pub fn render(
    scene: &Scene,
    chapter: u8,
    settings: &RenderSettings,
    progress: Option<&indicatif::ProgressBar>,
) -> Rendered {
    let start = Instant::now();
    let tracer = Tracer::new(scene, chapter, *settings);
    let (width, height) = (settings.width, settings.height);
    let camera = Camera::new(&scene.camera, width, height);
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    let rays = rgb
        .par_chunks_mut(width as usize * 3)
        .enumerate()
        .map(|(y, row)| {
            let mut counts = RayCounts::default();
            for (x, pixel) in row.chunks_exact_mut(3).enumerate() {
                let self_shadowed_before = counts.self_shadow_hits;
                let color = tracer.pixel(&camera, x as u32, y as u32, &mut counts);
                if counts.self_shadow_hits > self_shadowed_before {
                    counts.self_shadowed_pixels += 1;
                }
                pixel.copy_from_slice(&color.to_array().map(linear_to_srgb8));
            }
            if let Some(bar) = progress {
                bar.inc(1);
            }
            counts
        })
        .reduce(RayCounts::default, RayCounts::add);
    Rendered {
        width,
        height,
        rgb,
        effects: tracer.effects,
        rays,
        seconds: start.elapsed().as_secs_f64(),
    }
}
