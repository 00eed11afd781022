//! Every ray of one pixel, as a tree: what `raylab trace` prints. The
//! tracer tells a [`RayLog`] each ray it casts, what the ray met and the
//! colour it brought back, in the order it computes them; [`TreeLog`]
//! nests them (the rays a point's shading casts are its children), and
//! [`trace_pixel`] adds what each hit was: the object, the point, its
//! normals and material. The pixel it returns is the one the render
//! writes, since the tracer computes it the same way with or without a
//! log.

use crate::course::{Chapters, Hit};
use crate::effects::Lighting;
use crate::render::{RayKind, RayLog, Stage};
use crate::{Ray, Vec3};

/// One ray of a pixel, with the rays its point's shading cast.
#[derive(Debug, Clone, PartialEq)]
pub struct TracedRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// The tracer looked for hits with `t_min < t < t_max`.
    pub t_min: f32,
    pub t_max: f32,
    /// Its share of the pixel (`None` for shadow rays): 1 for a camera
    /// ray; a bounce's is its parent's times the share the chapter gave it
    /// (reflectivity, transparency, the Fresnel split).
    pub weight: Option<f32>,
    /// What it met: the nearest hit, or a shadow ray's blocker.
    pub hit: Option<RayHit>,
    /// The colour it brought back, in linear light; `None` for shadow rays,
    /// which bring back only whether they were blocked.
    pub color: Option<Vec3>,
    /// For a shadow ray, the light its range ends at (an index into the
    /// scene's lights).
    pub light: Option<usize>,
    /// For a shadow ray that reached its light at a stage with Phong
    /// lighting (chapter 5 on): what that light adds at the point, by the
    /// chapters' `phong_terms`, its share of the point's colour.
    pub light_share: Option<crate::course::PhongTerms>,
    /// What this ray adds to the pixel beyond what its bounces bring:
    /// its colour times its share of the pixel, less each bounce's colour
    /// times the bounce's share (`None` for shadow rays). A point's own
    /// light (ambient, diffuse, specular) is this; a perfect mirror adds
    /// nothing of its own. Summed over every ray of every sample it is
    /// the mean of the samples' colours, whatever a chapter does with
    /// them: each bounce's colour times its share is counted once with a
    /// plus (its own) and once with a minus (its parent's).
    pub contribution: Option<glam::DVec3>,
    /// The sum of the contributions of the rays cast up to this one, in
    /// the order they were cast: after the last ray, the pixel.
    pub running_sum: Option<glam::DVec3>,
    pub children: Vec<TracedRay>,
}

/// What a ray met.
#[derive(Debug, Clone, PartialEq)]
pub struct RayHit {
    /// The primitive hit (an index into the stage's shapes), and the name
    /// of its object in the scene.
    pub shape: usize,
    pub name: String,
    pub t: f32,
    pub point: Vec3,
    /// The geometric normal, and the one the chapter shades with (turned
    /// toward the ray, smoothed on a mesh, from the function on an implicit
    /// surface).
    pub geometric_normal: Vec3,
    pub shading_normal: Vec3,
    pub material: crate::scene::Material,
    /// The material's colour there (its checker applied).
    pub albedo: Vec3,
}

/// One pixel's rays and its colour.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelTrace {
    pub pixel: (u32, u32),
    /// The camera rays of the pixel, one a sample, each the root of its tree.
    pub samples: Vec<TracedRay>,
    /// What chapter 14's light paths brought to the pixel, in linear
    /// light: added after the camera rays' running sum, which ends at the
    /// camera's estimate. `None` where the stage traces no light paths.
    pub light_paths: Option<Vec3>,
    /// The pixel's colour in linear light, as the chapters computed it.
    pub color: Vec3,
    /// The same as the image stores it: 8-bit sRGB.
    pub srgb: [u8; 3],
    /// Whether the pixel cast more than [`MAX_TRACED_RAYS`], of which only
    /// the first are kept.
    pub truncated: bool,
}

/// The most rays one trace keeps: far more than any pixel casts at the
/// depth and sample limits a scene may set, so that a chapter that casts
/// without end (a student's, say) cannot exhaust memory.
pub const MAX_TRACED_RAYS: usize = 1_000_000;

/// A [`RayLog`] that nests the rays it is told about.
#[derive(Debug, Default)]
pub struct TreeLog {
    /// The rays still being shaded, outermost first.
    open: Vec<TracedRay>,
    /// The camera rays done, in order.
    roots: Vec<TracedRay>,
    /// A shadow ray cast and not yet told what it met.
    shadow: Option<TracedRay>,
    kept: usize,
    /// Rays past [`MAX_TRACED_RAYS`] still being shaded (all inside the
    /// kept ones), and whether the shadow ray just cast is one of them.
    dropped_open: usize,
    dropped_shadow: bool,
    /// Whether [`MAX_TRACED_RAYS`] was reached (the rest were not kept).
    pub truncated: bool,
}

impl TreeLog {
    fn attach(&mut self, ray: TracedRay) {
        match self.open.last_mut() {
            Some(parent) => parent.children.push(ray),
            None => self.roots.push(ray),
        }
    }

    /// The camera rays, each with its tree; rays still open (a chapter
    /// that panicked mid-shading) are closed as they are.
    pub fn into_roots(mut self) -> Vec<TracedRay> {
        if let Some(shadow) = self.shadow.take() {
            self.attach(shadow);
        }
        while let Some(ray) = self.open.pop() {
            self.attach(ray);
        }
        self.roots
    }
}

impl RayLog for TreeLog {
    fn cast(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        if self.kept >= MAX_TRACED_RAYS {
            self.truncated = true;
            if kind == RayKind::Shadow {
                self.dropped_shadow = true;
            } else {
                self.dropped_open += 1;
            }
            return;
        }
        self.kept += 1;
        let node = TracedRay {
            kind,
            ray: *ray,
            t_min,
            t_max,
            weight: None,
            hit: None,
            color: None,
            light: None,
            light_share: None,
            contribution: None,
            running_sum: None,
            children: Vec::new(),
        };
        if kind == RayKind::Shadow {
            self.shadow = Some(node);
        } else {
            self.open.push(node);
        }
    }

    fn weighted(&mut self, weight: f32) {
        if self.dropped_open == 0
            && let Some(open) = self.open.last_mut()
        {
            open.weight = Some(weight);
        }
    }

    fn met(&mut self, hit: Option<Hit>) {
        let found = hit.map(|hit| RayHit {
            shape: hit.object,
            name: String::new(),
            t: hit.t,
            point: Vec3::ZERO,
            geometric_normal: Vec3::ZERO,
            shading_normal: Vec3::ZERO,
            material: crate::scene::Material::default(),
            albedo: Vec3::ZERO,
        });
        // A shadow ray is told what it met at once, before anything else
        // is cast: it is done.
        if std::mem::take(&mut self.dropped_shadow) {
            return;
        }
        if let Some(mut shadow) = self.shadow.take() {
            shadow.hit = found;
            self.attach(shadow);
        } else if self.dropped_open == 0
            && let Some(open) = self.open.last_mut()
        {
            open.hit = found;
        }
    }

    fn returned(&mut self, color: Vec3) {
        if self.dropped_open > 0 {
            self.dropped_open -= 1;
        } else if let Some(mut ray) = self.open.pop() {
            ray.color = Some(color);
            self.attach(ray);
        }
    }
}

/// Pixel `(x, y)` of `stage` traced ray by ray: every sample's tree, and
/// the pixel's colour exactly as the render computes it. `None` when the
/// pixel is outside the image.
pub fn trace_pixel<C: Chapters>(stage: &Stage<'_, C>, (x, y): (u32, u32)) -> Option<PixelTrace> {
    if x >= stage.settings.width || y >= stage.settings.height {
        return None;
    }
    let mut log = TreeLog::default();
    let light_paths = stage
        .light_image()
        .map(|light| light.pixels[(y * stage.settings.width + x) as usize]);
    let color = {
        let mut tracer = stage.tracer(Some(&mut log));
        tracer.pixel(x, y)
    } + light_paths.unwrap_or(Vec3::ZERO);
    let truncated = log.truncated;
    let mut samples = log.into_roots();
    let describer = stage.tracer(None);
    for sample in &mut samples {
        describe(stage, &describer, sample);
    }
    let per_sample = 1.0 / samples.len().max(1) as f64;
    let mut running_sum = glam::DVec3::ZERO;
    for sample in &mut samples {
        add_contributions(sample, per_sample, &mut running_sum);
    }
    Some(PixelTrace {
        pixel: (x, y),
        samples,
        light_paths,
        color,
        srgb: color.to_array().map(crate::output::linear_to_srgb8),
        truncated,
    })
}

/// Up to `most` of chapter 14's light paths that light pixel `(x, y)`, in
/// path order, each ray by ray: the first leaves a light, the last goes
/// toward the camera. Empty where the stage traces no light paths or the
/// pixel is outside the image.
pub fn light_paths_into_pixel<C: Chapters>(
    stage: &Stage<'_, C>,
    (x, y): (u32, u32),
    most: usize,
) -> Vec<TracedRay> {
    let (width, height) = (stage.settings.width, stage.settings.height);
    if most == 0 || x >= width || y >= height {
        return Vec::new();
    }
    let describer = stage.tracer(None);
    let mut paths = Vec::new();
    for index in stage.light_paths_lighting(y * width + x, most) {
        let mut log = TreeLog::default();
        stage.record_light_paths(index..index + 1, &mut log);
        for mut root in log.into_roots() {
            describe(stage, &describer, &mut root);
            paths.push(root);
        }
    }
    paths
}

/// Sets each ray's [`TracedRay::contribution`] (its colour and shares
/// scaled by `per_sample`, the share of one sample in the pixel) and its
/// running sum, in the order the rays were cast.
fn add_contributions(traced: &mut TracedRay, per_sample: f64, running_sum: &mut glam::DVec3) {
    let weighted = |ray: &TracedRay| match (ray.weight, ray.color) {
        (Some(weight), Some(color)) => Some(color.as_dvec3() * f64::from(weight) * per_sample),
        _ => None,
    };
    let Some(own) = weighted(traced) else {
        return;
    };
    let bounces: glam::DVec3 = traced.children.iter().filter_map(weighted).sum();
    let contribution = own - bounces;
    *running_sum += contribution;
    traced.contribution = Some(contribution);
    traced.running_sum = Some(*running_sum);
    for child in &mut traced.children {
        add_contributions(child, per_sample, running_sum);
    }
}

/// Fills in each hit's object, point, normals and material, and each
/// shadow ray's light.
fn describe<C: Chapters>(
    stage: &Stage<'_, C>,
    tracer: &crate::render::Tracer<'_, C>,
    traced: &mut TracedRay,
) {
    let mut shaded = None;
    if let Some(hit) = traced.hit.as_mut() {
        let point = tracer.hit_point(hit.shape, &traced.ray, hit.t);
        hit.name = stage.name(hit.shape).unwrap_or("?").to_string();
        hit.point = point.surface.point;
        hit.geometric_normal = point.surface.normal;
        hit.shading_normal = point.normal;
        hit.material = *point.material;
        hit.albedo = point.albedo;
        if traced.kind != RayKind::Shadow {
            shaded = Some(point);
        }
    }
    if traced.kind == RayKind::Shadow {
        let end = traced.ray.at(traced.t_max);
        traced.light = tracer.lights().iter().position(|light| {
            (light.position - end).length() <= 1e-3 * (1.0 + light.position.length())
        });
    }
    for child in &mut traced.children {
        describe(stage, tracer, child);
        // What each light that reached the point adds there: the terms the
        // chapter's Phong shading sums for it.
        if let Some(point) = &shaded
            && stage.effects.lighting == Lighting::Phong
            && child.kind == RayKind::Shadow
            && child.hit.is_none()
            && let Some(light) = child.light.and_then(|index| tracer.lights().get(index))
        {
            let to_light = (light.position - point.surface.point).normalize();
            child.light_share = Some(C::phong_terms(
                point.material,
                point.albedo,
                point.normal,
                to_light,
                point.to_eye,
                light.radiance(),
            ));
        }
    }
}

impl PixelTrace {
    /// The camera rays to show: every sample, or only sample `only`.
    pub fn chosen(&self, only: Option<usize>) -> impl Iterator<Item = (usize, &TracedRay)> {
        self.samples
            .iter()
            .enumerate()
            .filter(move |(index, _)| only.is_none_or(|only| only == *index))
    }

    /// The trace as `raylab trace --json` prints it and the browser page
    /// draws it. JSON has no infinity: a `t_max` of `null` is an unbounded
    /// range.
    pub fn to_json(&self, chapter: u8, only: Option<usize>) -> serde_json::Value {
        let (x, y) = self.pixel;
        let samples: Vec<serde_json::Value> = self
            .chosen(only)
            .map(|(index, root)| serde_json::json!({ "sample": index, "ray": ray_json(root) }))
            .collect();
        serde_json::json!({
            "chapter": chapter,
            "pixel": [x, y],
            "samples": samples,
            "sample_count": self.samples.len(),
            "light_paths": self.light_paths.map(|light| light.to_array()),
            "color": self.color.to_array(),
            "srgb": self.srgb,
            "truncated": self.truncated,
        })
    }
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
        "kind": ray.kind.name(),
        "origin": ray.ray.origin.to_array(),
        "direction": ray.ray.dir.to_array(),
        "t_min": ray.t_min,
        "t_max": ray.t_max.is_finite().then_some(ray.t_max),
        "weight": ray.weight,
        "hit": hit,
        "light": ray.light,
        "light_share": ray.light_share.map(|share| serde_json::json!({
            "diffuse": share.diffuse.to_array(),
            "specular": share.specular.to_array(),
        })),
        "color": ray.color.map(|color| color.to_array()),
        "contribution": ray.contribution.map(|sum| sum.to_array()),
        "running_sum": ray.running_sum.map(|sum| sum.to_array()),
        "children": ray.children.iter().map(ray_json).collect::<Vec<_>>(),
    })
}
