//! The tracer the chapters drive: how a ray is traced and its point
//! handed to the highest chapter of the stage, the state a path carries
//! (its media, how it arrived, its wavelength, its random stream), and
//! chapter 14's light paths. The image loop that makes one tracer a row is
//! the parent module's.

use super::*;

/// A path-traced sample brighter than this many times the brightest light
/// or background a camera ray could see is counted as a firefly: no
/// surface lit by those lights returns that much without an estimate that
/// divided by a tiny density.
pub const FIREFLY_FACTOR: f32 = 10.0;

/// A point chosen on a light, as seen from a point being shaded (chapter
/// 13's next-event estimation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Where a shadow ray aims: the point on the light, moved toward the
    /// shaded point by [`SHADOW_EPSILON`] of the way, so that the light's
    /// own surface is not taken for a blocker.
    pub position: Vec3,
    /// Unit direction from the shaded point toward the light.
    pub direction: Vec3,
    /// The light arriving along `direction`: an emitter's radiance, or a
    /// point light's intensity over the squared distance.
    pub light: Vec3,
    /// The density of having chosen this direction, per unit solid angle
    /// and with the choice of light in it; for a point light, only the
    /// chance of choosing it.
    pub pdf: f32,
    /// A point light: a direction no scattered ray can find.
    pub delta: bool,
}

/// The share of a shadow ray's segment left out at the light's end (pbrt-v4's
/// `ShadowEpsilon`): enough that the light's own surface, where the segment
/// ends, is never found as a blocker after rounding, and small enough
/// (0.09 units over the 900-unit diagonal of the Cornell box) that no real
/// blocker hides in it.
pub const SHADOW_EPSILON: f32 = 1e-4;

/// Past this many bounces [`Tracer::trace`] stops whatever the chapters ask,
/// so that no chapter (a student's without its depth test, say) can recurse
/// until the stack overflows. Chapters 6 and 8 stop at `max_depth`, which is
/// at most this.
pub const DEPTH_LIMIT: u32 = MAX_DEPTH;

/// The renderer's handle, given to the chapters that drive others: through
/// it they cast rays, read the scene and the settings, and reach the other
/// chapters. One per thread; it counts the rays it casts.
pub struct Tracer<'a, C: Chapters = Reference> {
    stage: &'a Stage<'a, C>,
    objects: Objects<'a, C>,
    pub(super) counts: RayCounts,
    recorder: Option<&'a mut dyn RayLog>,
    /// The media the ray being traced travels through (chapter 9): empty
    /// (air) for camera rays, set by [`Tracer::trace_in`] for the others.
    media: MediumStack,
    /// How the ray being traced was cast (chapter 13).
    arrival: Arrival,
    /// Whether the current camera path scattered at random off its first
    /// point (chapter 14: its caustics are the light paths').
    first_point_scatters: bool,
    /// The wavelength of the current path, in nanometres, once it has met
    /// a dispersive surface (chapter 14).
    wavelength: Option<f32>,
    /// Whether the current path started at a light (chapter 14) rather
    /// than at the camera.
    from_light: bool,
    /// What the current light paths brought to which pixel (chapter 14):
    /// the pixel's index and the light, before dividing by the number of
    /// paths.
    pub(super) splats: Vec<(u32, Vec3)>,
    /// The current sample's stream of random numbers (chapter 13): a key
    /// from the seed and the sample's position, and how many were drawn.
    random_key: u64,
    random_index: u32,
    /// Each sample's channels are cut to this (infinite but for the
    /// check's comparison of path-traced images, [`Tracer::with_sample_bound`]).
    sample_bound: f32,
    /// Evaluations spent on implicit normals (a cell: hit points are
    /// made through a shared reference).
    normal_evaluations: std::cell::Cell<u64>,
}

/// What [`Tracer::trace_in`] saw along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traced {
    pub color: Vec3,
    /// How far the ray went before it met something, in the scene's units
    /// (not in units of the direction); infinite when it met nothing.
    pub distance: f32,
}

impl<'a, C: Chapters> Tracer<'a, C> {
    /// A fresh tracer of `stage` (see [`Stage::tracer`]).
    pub(super) fn new(stage: &'a Stage<'a, C>, recorder: Option<&'a mut dyn RayLog>) -> Self {
        Tracer {
            stage,
            objects: stage.objects(),
            counts: RayCounts::default(),
            recorder,
            media: MediumStack::EMPTY,
            arrival: Arrival::Camera,
            first_point_scatters: false,
            wavelength: None,
            from_light: false,
            splats: Vec::new(),
            random_key: 0,
            random_index: 0,
            sample_bound: f32::INFINITY,
            normal_evaluations: std::cell::Cell::new(0),
        }
    }

    /// The rays cast so far, by kind.
    pub fn counts(&self) -> RayCounts {
        RayCounts {
            normal_evaluations: self.normal_evaluations.get(),
            ..self.counts
        }
    }

    /// The objects this stage intersects.
    pub fn objects(&self) -> Objects<'a, C> {
        self.objects
    }

    /// The point where `ray` meets object `object` at parameter `t`, as the
    /// shading chapters receive it.
    #[inline]
    pub fn hit_point(&self, object: usize, ray: &Ray, t: f32) -> HitPoint<'a> {
        let shape = &self.stage.shapes[object];
        let owner = self.stage.owners[object] as usize;
        let material = &self.stage.scene.objects[owner].material;
        let point = HitPoint::new(object, shape, material, ray, t).with_solid(owner);
        if self.stage.effects.smooth_shading && shape.is_triangle() {
            self.smoothed(point, shape)
        } else if self.stage.effects.implicit {
            self.implicit_normal(point, shape)
        } else {
            point
        }
    }

    /// `point` with chapter 12's normal, when `shape` is an implicit
    /// surface; its evaluations are counted apart from the march's.
    #[inline(never)]
    fn implicit_normal(&self, point: HitPoint<'a>, shape: &Shape) -> HitPoint<'a> {
        let Some(surface) = shape.as_implicit() else {
            return point;
        };
        let before = crate::shapes::evaluations();
        let normal = C::implicit_normal(surface, point.surface.point);
        self.normal_evaluations
            .set(self.normal_evaluations.get() + crate::shapes::evaluations() - before);
        point.with_normal(normal)
    }

    /// `point` on `shape` as chapter 10's smooth shading sees it, when the
    /// shape is a triangle with vertex normals. Apart from
    /// [`Tracer::hit_point`] so that stages without smooth meshes do not
    /// carry its code in their hot path.
    #[inline(never)]
    fn smoothed(&self, point: HitPoint<'a>, shape: &Shape) -> HitPoint<'a> {
        let smooth = shape.as_triangle().and_then(|triangle| {
            let normals = self.stage.scene.vertex_normals.get(triangle.normals()?)?;
            Some((triangle, normals))
        });
        match smooth {
            Some((triangle, normals)) => {
                let mut smooth = C::smooth_hit_point(point, triangle, normals);
                // `--terminator flat`: chapter 10's shading without its lift,
                // to show what the lift fixes.
                if self.stage.settings.terminator == TerminatorRule::Flat {
                    smooth.surface.point = point.surface.point;
                }
                smooth
            }
            None => point,
        }
    }

    /// This tracer with every sample's channels cut to at most `bound`:
    /// what `raylab check` compares path-traced images by (fireflies are
    /// rare and huge, so two correct images differ most in them), never
    /// what a render shows.
    pub fn with_sample_bound(mut self, bound: f32) -> Self {
        self.sample_bound = bound;
        self
    }

    /// The effects this stage simulates (chapter 13 reads its switches).
    #[inline]
    pub fn effects(&self) -> Effects {
        self.stage.effects
    }

    /// The next number of the current sample's random stream, uniform in
    /// `[0, 1)` (chapter 13). The stream depends only on the seed and the
    /// sample's position in the image, so a pixel is the same on any
    /// number of threads.
    #[inline]
    pub fn random(&mut self) -> f32 {
        self.random_index += 1;
        let word = mix64(self.random_key ^ u64::from(self.random_index));
        // The top 24 bits: an f32's precision, never rounded up to 1.
        (word >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// How the ray being shaded was cast (chapter 13).
    #[inline]
    pub fn arrival(&self) -> Arrival {
        self.arrival
    }

    /// How many lights next-event estimation and chapter 14's light paths
    /// choose among: the point lights, the beams and every primitive that
    /// emits.
    pub fn light_count(&self) -> usize {
        self.stage.scene.lights.len() + self.stage.scene.beams.len() + self.stage.emitters.len()
    }

    /// A light, and a point on it, chosen at random for the surface point
    /// `from` (chapter 13): each light with the same chance, a point light
    /// as it is, a beam where its light comes from, a point uniformly over
    /// an emitter's area. `None` when the scene has no light, the point
    /// chosen is where `from` is, or a beam chosen does not reach `from`.
    pub fn sample_light(&mut self, from: &HitPoint) -> Option<LightSample> {
        let count = self.light_count();
        if count == 0 {
            return None;
        }
        let choice = ((self.random() * count as f32) as usize).min(count - 1);
        let chosen = 1.0 / count as f32;
        let (u, v) = (self.random(), self.random());
        let origin = from.surface.point;
        let lights = &self.stage.scene.lights;
        if let Some(light) = lights.get(choice) {
            let to_light = light.position - origin;
            let squared = to_light.length_squared();
            if !(squared > 0.0) {
                return None;
            }
            return Some(LightSample {
                position: light.position,
                direction: to_light / squared.sqrt(),
                light: light.radiance() / squared,
                pdf: chosen,
                delta: true,
            });
        }
        let beams = &self.stage.scene.beams;
        if let Some(beam) = beams.get(choice - lights.len()) {
            // The beam's light arrives along its direction, from the point
            // of its disk straight upstream of `origin`.
            let upstream = (origin - beam.position).dot(beam.direction);
            let source = origin - upstream * beam.direction;
            if !(upstream > 0.0)
                || (source - beam.position).length_squared() > beam.radius * beam.radius
            {
                return None;
            }
            return Some(LightSample {
                position: origin - (1.0 - SHADOW_EPSILON) * upstream * beam.direction,
                direction: -beam.direction,
                light: beam.irradiance(),
                pdf: chosen,
                delta: true,
            });
        }
        let object = self.stage.emitters[choice - lights.len() - beams.len()] as usize;
        let shape = &self.stage.shapes[object];
        let (point, normal, area) = point_on(shape, u, v)?;
        let to_light = point - origin;
        let squared = to_light.length_squared();
        let direction = to_light / squared.sqrt();
        let material = &self.stage.scene.objects[self.stage.owners[object] as usize].material;
        let cosine = facing_cosine(material, normal, direction);
        if !(squared > 0.0 && cosine > 0.0) {
            return None;
        }
        Some(LightSample {
            position: point - SHADOW_EPSILON * to_light,
            direction,
            light: material.emission,
            pdf: chosen * squared / (cosine * area),
            delta: false,
        })
    }

    /// The density, per unit solid angle, with which [`Tracer::sample_light`]
    /// would have chosen the direction of `point.ray` toward `point` from
    /// where that ray started: what multiple importance sampling weighs a
    /// scattered ray that found an emitter against. 0 where `point` emits
    /// nothing.
    pub fn light_pdf(&self, point: &HitPoint) -> f32 {
        if point.emitted() == Vec3::ZERO {
            return 0.0;
        }
        let shape = &self.stage.shapes[point.object];
        let Some(area) = area_of(shape) else {
            return 0.0;
        };
        let to_point = point.surface.point - point.ray.origin;
        let squared = to_point.length_squared();
        let cosine = facing_cosine(
            point.material,
            point.surface.normal,
            to_point / squared.sqrt(),
        );
        if !(cosine > 0.0 && area > 0.0) {
            return 0.0;
        }
        squared / (cosine * area * self.light_count() as f32)
    }

    /// [`Tracer::trace_in`] for a ray a path scatters (chapter 13): it
    /// travels inside `media`, and the point it meets knows how it was
    /// cast (`arrival`).
    pub fn trace_path(
        &mut self,
        media: &MediumStack,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
        arrival: Arrival,
    ) -> Traced {
        let arrival = match (self.arrival, arrival) {
            // The ray leaves the camera's first point: whether it scattered
            // there decides who counts the caustics beyond (chapter 14).
            (Arrival::Camera, _) => {
                self.first_point_scatters = matches!(arrival, Arrival::Scattered { .. });
                arrival
            }
            (_, Arrival::Specular)
                if self.first_point_scatters && self.stage.effects.light_tracing =>
            {
                Arrival::Caustic
            }
            _ => arrival,
        };
        let outer = std::mem::replace(&mut self.arrival, arrival);
        let traced = self.trace_in(media, kind, ray, depth, weight);
        self.arrival = outer;
        traced
    }

    /// The camera (chapter 14 joins lit points to it).
    pub fn camera(&self) -> &Camera {
        &self.stage.camera
    }

    /// Whether the current path started at a light (chapter 14's light
    /// paths carry power, not radiance: see `bsdf`'s refraction).
    pub fn from_light(&self) -> bool {
        self.from_light
    }

    /// The wavelength of the current path in nanometres, once it has met a
    /// dispersive surface (chapter 14).
    pub fn wavelength(&self) -> Option<f32> {
        self.wavelength
    }

    /// Fixes the wavelength of the current path (chapter 14): it keeps it
    /// until the path ends.
    pub fn set_wavelength(&mut self, nanometres: f32) {
        self.wavelength = Some(nanometres);
    }

    /// A light chosen at random and a ray of light leaving it (chapter
    /// 14): each light with the same chance; from a point light in a
    /// direction uniform over the sphere, from a beam at a point uniform
    /// over its disk along its direction, from an emitter at a point
    /// uniform over its area, on either face, cosine-distributed about
    /// that face's normal (chapter 13's `cosine_hemisphere`). `power` is
    /// the light it carries: what the light gives off divided by the
    /// density of having chosen this ray, so that the mean over many rays
    /// is the lights' total power. `None` when the scene has no light.
    pub fn emit(&mut self) -> Option<Emitted> {
        use std::f32::consts::PI;
        let count = self.light_count();
        if count == 0 {
            return None;
        }
        let choice = ((self.random() * count as f32) as usize).min(count - 1);
        let count = count as f32;
        let (u, v) = (self.random(), self.random());
        let scene = self.stage.scene;
        // `libm`'s sines: the same bits on every machine and in the browser.
        if let Some(light) = scene.lights.get(choice) {
            let z = 1.0 - 2.0 * u;
            let ring = (1.0 - z * z).max(0.0).sqrt();
            let (sin, cos) = libm::sincosf(2.0 * PI * v);
            return Some(Emitted {
                ray: Ray::new(light.position, Vec3::new(ring * cos, ring * sin, z)),
                power: light.radiance() * (4.0 * PI * count),
            });
        }
        if let Some(beam) = scene.beams.get(choice - scene.lights.len()) {
            let radius = beam.radius * u.sqrt();
            let (sin, cos) = libm::sincosf(2.0 * PI * v);
            let across =
                crate::bsdf::to_world(beam.direction, Vec3::new(radius * cos, radius * sin, 0.0));
            return Some(Emitted {
                ray: Ray::new(beam.position + across, beam.direction),
                power: beam.irradiance() * (PI * beam.radius * beam.radius * count),
            });
        }
        let object = self.stage.emitters[choice - scene.lights.len() - scene.beams.len()] as usize;
        let (point, normal, area) = point_on(&self.stage.shapes[object], u, v)?;
        let material = &scene.objects[self.stage.owners[object] as usize].material;
        // A two-sided emitter sends half its paths from each face.
        let (face, faces) = match material.two_sided {
            true if self.random() < 0.5 => (-normal, 2.0),
            true => (normal, 2.0),
            false => (normal, 1.0),
        };
        let local = C::cosine_hemisphere(self.random(), self.random());
        let direction = crate::bsdf::to_world(face, local);
        let surface = SurfacePoint {
            point,
            normal,
            error: point.abs() * (crate::shapes::SURFACE_ERROR_EPSILONS * f32::EPSILON),
        };
        Some(Emitted {
            ray: Ray::new(self.offset_origin(&surface, direction), direction),
            // Le cos / (cos / pi * 1 / area * 1 / faces * 1 / count).
            power: material.emission * (faces * PI * area * count),
        })
    }

    /// Traces a ray of a light path travelling inside `media` (chapter
    /// 14): the point it meets, as a camera path would see it, and how far
    /// it went. The tracer then knows the media of that ray, for the
    /// surface's scattering (`Lobe::scatter`).
    pub fn trace_light(&mut self, media: &MediumStack, ray: &Ray) -> Option<LightHit<'a>> {
        self.media = *media;
        let Hit { object, t } = self.find(RayKind::Light, ray)?;
        Some(LightHit {
            point: self.hit_point(object, ray, t),
            distance: t * ray.dir.length(),
        })
    }

    /// Whether something lies between `point` and the camera (chapter 14):
    /// a ray toward the camera from chapter 4's offset origin, stopped
    /// short of the camera by [`SHADOW_EPSILON`] of the way.
    pub fn blocked_from_camera(&mut self, point: &HitPoint) -> bool {
        let to_camera = self.stage.camera.origin() - point.surface.point;
        let origin = self.offset_origin(&point.surface, to_camera);
        let ray = Ray::new(origin, self.stage.camera.origin() - origin);
        self.any_blocker(RayKind::ToCamera, &ray, 0.0, 1.0 - SHADOW_EPSILON)
            .is_some()
    }

    /// Adds `light` to the pixel at image point `(x, y)` (in pixels from
    /// the top-left corner, as [`Camera::project`] gives it), for chapter
    /// 14's light paths: the renderer divides it by the number of paths.
    /// A point outside the image, or light that is not finite, adds
    /// nothing (the latter counted as a non-finite sample).
    pub fn splat(&mut self, x: f32, y: f32, light: Vec3) {
        let (width, height) = (self.stage.settings.width, self.stage.settings.height);
        if !(x >= 0.0 && y >= 0.0 && x < width as f32 && y < height as f32) {
            return;
        }
        if !light.is_finite() {
            self.counts.non_finite_samples += 1;
            return;
        }
        let index = (y as u32).min(height - 1) * width + (x as u32).min(width - 1);
        self.counts.splats += 1;
        self.splats.push((index, light));
    }

    /// Starts path number `stream` of a check's own (`raylab check` asks
    /// chapter 14's `dispersive_ior` at the first surface of many paths):
    /// its own stream of random numbers, and no wavelength yet.
    pub fn begin_path(&mut self, stream: u64) {
        self.random_key = mix64(self.stage.settings.seed ^ mix64(stream ^ CHECK_PATH_STREAM));
        self.random_index = 0;
        self.wavelength = None;
    }

    /// Traces light path number `index` of the image (chapter 14), with
    /// its own stream of random numbers, and hands back what it splatted.
    pub(super) fn light_path(&mut self, index: u64) {
        self.random_key = mix64(self.stage.settings.seed ^ mix64(index ^ LIGHT_PATH_STREAM));
        self.random_index = 0;
        self.arrival = Arrival::Camera;
        self.wavelength = None;
        self.from_light = true;
        self.media = MediumStack::EMPTY;
        self.counts.light_paths += 1;
        C::trace_light_path(self);
    }

    /// The scene's point lights.
    #[inline]
    pub fn lights(&self) -> &'a [Light] {
        &self.stage.scene.lights
    }

    /// The scene's ambient light (chapters 4 and 5).
    #[inline]
    pub fn ambient_light(&self) -> Vec3 {
        self.stage.scene.ambient_light
    }

    /// How many bounces chapters 6 and 8 may follow.
    #[inline]
    pub fn max_depth(&self) -> u32 {
        self.stage.settings.max_depth
    }

    /// Samples per pixel (chapter 7).
    pub fn samples(&self) -> u32 {
        self.stage.samples()
    }

    /// Whether a secondary ray that brings `share` of a point whose own
    /// share of the pixel is `weight` is worth casting: the share must be
    /// positive, and the ray's weight in the pixel at least the scene's
    /// `min_contribution`. Skipping the others costs at most that much of
    /// the pixel, and saves every ray they would have spawned.
    #[inline]
    pub fn worth_casting(&self, weight: f32, share: f32) -> bool {
        share > 0.0 && weight * share >= self.stage.settings.min_contribution
    }

    /// Where a secondary ray leaving `surface` in direction `dir` starts:
    /// chapter 4's [`Chapters::offset_origin`], or the fixed epsilon of the
    /// comparison setting `ray_offset = "fixed"`.
    #[inline]
    pub fn offset_origin(&self, surface: &SurfacePoint, dir: Vec3) -> Vec3 {
        self.stage.offset.origin_with::<C>(surface, dir)
    }

    /// Whether shadow rays from `object` leave from a point lifted off its
    /// surface: a triangle with vertex normals, under the lifted terminator
    /// rule.
    fn starts_off_its_surface(&self, object: usize) -> bool {
        self.stage.settings.terminator == TerminatorRule::Lifted
            && self
                .stage
                .shapes
                .get(object)
                .and_then(Shape::as_triangle)
                .is_some_and(|triangle| triangle.normals().is_some())
    }

    /// Casts a shadow ray: whether any object lies on `ray` with
    /// `t_min < t < t_max`. Any blocker will do, so the search stops at the
    /// first in list order. `from` is the point the ray leaves, for the acne
    /// counter of `--stats`.
    #[inline]
    pub fn blocked(&mut self, ray: &Ray, t_min: f32, t_max: f32, from: &HitPoint) -> bool {
        match self.any_blocker(RayKind::Shadow, ray, t_min, t_max) {
            Some(blocker) => {
                // Planes and flat triangles are flat and spheres convex, and
                // lights outside a sphere seen from inside it are skipped
                // before any ray: a shadow ray that leaves a surface and
                // meets it again is acne. Not so from a point lifted off its
                // flat triangle (chapter 10's terminator fix): there the
                // triangle itself may rightly stand between the point and
                // a light, the faceted shadow the lift trades for.
                // An implicit surface may be anything but convex (a torus
                // shadows its own hole), so its self-shadowing is not
                // counted as acne either.
                let own_shadow_possible = self.starts_off_its_surface(from.object)
                    || self.stage.shapes[from.object].as_implicit().is_some();
                if blocker.object == from.object && !own_shadow_possible {
                    self.counts.self_shadow_hits += 1;
                }
                true
            }
            None => false,
        }
    }

    /// The colour seen along `ray`, a ray of `kind` (a reflection or
    /// refraction when chapters 6 and 8 call it). `depth` counts the bounces
    /// so far and `weight` is the ray's share of the pixel.
    pub fn trace(&mut self, kind: RayKind, ray: &Ray, depth: u32, weight: f32) -> Vec3 {
        self.trace_hit(kind, ray, depth, weight).0
    }

    /// The media the ray being shaded travelled through to reach its point
    /// (chapter 9): the solids it is inside, the last entered current.
    #[inline]
    pub fn media(&self) -> &MediumStack {
        &self.media
    }

    /// [`Tracer::trace`] for a ray that travels inside `media` (chapter 9):
    /// the point it meets is shaded knowing them, and the answer says how
    /// far the ray went, for absorption. The tracer's own media are the
    /// same afterwards: each ray carries its own, nothing leaks to the next.
    pub fn trace_in(
        &mut self,
        media: &MediumStack,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
    ) -> Traced {
        let outer = std::mem::replace(&mut self.media, *media);
        let (color, t) = self.trace_hit(kind, ray, depth, weight);
        self.media = outer;
        Traced {
            color,
            // t counts lengths of the direction; a miss went on for ever.
            distance: t.map_or(f32::INFINITY, |t| t * ray.dir.length()),
        }
    }

    /// The colour seen along `ray`, and the `t` of what it met.
    fn trace_hit(
        &mut self,
        kind: RayKind,
        ray: &Ray,
        depth: u32,
        weight: f32,
    ) -> (Vec3, Option<f32>) {
        if depth > DEPTH_LIMIT {
            return (Vec3::ZERO, None);
        }
        let Some(Hit { object, t }) = self.find_weighted(kind, ray, Some(weight)) else {
            self.returned(self.stage.scene.background);
            return (self.stage.scene.background, None);
        };
        let point = self.hit_point(object, ray, t);
        let color = self.shade(&point, depth, weight);
        self.returned(color);
        (color, Some(t))
    }

    /// Any object on `ray`, a ray of `kind`, with `t_min < t < t_max`: the
    /// first the tree or the list order gives, since any blocker will do.
    #[inline]
    fn any_blocker(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        self.log(kind, ray, t_min, t_max);
        let blocker = match &self.stage.wide {
            Some(wide) => C::any_hit_wide(wide, &self.objects, ray, t_min, t_max),
            None => self.objects.first_hit(ray, t_min, t_max),
        };
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.met(blocker);
        }
        blocker
    }

    /// What `ray`, a ray of `kind`, meets first: through chapter 11's tree,
    /// chapter 3's nearest hit, or (before chapter 3) the first in list
    /// order.
    #[inline]
    fn find(&mut self, kind: RayKind, ray: &Ray) -> Option<Hit> {
        self.find_weighted(kind, ray, None)
    }

    /// [`Tracer::find`], telling the recorder the ray's share of the pixel.
    #[inline]
    fn find_weighted(&mut self, kind: RayKind, ray: &Ray, weight: Option<f32>) -> Option<Hit> {
        self.log(kind, ray, 0.0, f32::INFINITY);
        if let (Some(recorder), Some(weight)) = (self.recorder.as_deref_mut(), weight) {
            recorder.weighted(weight);
        }
        let hit = if let Some(wide) = &self.stage.wide {
            C::nearest_hit_wide(wide, &self.objects, ray, 0.0, f32::INFINITY)
        } else if self.stage.effects.nearest_hit {
            C::nearest_hit(&self.objects, ray, 0.0, f32::INFINITY)
        } else {
            self.objects.first_hit(ray, 0.0, f32::INFINITY)
        };
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.met(hit);
        }
        hit
    }

    #[inline]
    fn returned(&mut self, color: Vec3) {
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.returned(color);
        }
    }

    /// The colour of one camera ray through the image point `(x, y)` (in
    /// pixels from the top-left corner), in linear light. A NaN or infinite
    /// colour is counted and becomes black.
    pub fn sample(&mut self, x: f32, y: f32) -> Vec3 {
        let ray = self.stage.camera.ray_through(x, y);
        self.random_key = mix64(
            self.stage.settings.seed
                ^ mix64((u64::from(x.to_bits()) << 32) | u64::from(y.to_bits())),
        );
        self.random_index = 0;
        self.arrival = Arrival::Camera;
        self.first_point_scatters = false;
        self.wavelength = None;
        self.from_light = false;
        let color = self.trace(RayKind::Primary, &ray, 0, 1.0);
        if color.is_finite() {
            if self.stage.effects.path_tracing && color.max_element() > self.stage.firefly_bound {
                self.counts.bright_samples += 1;
            }
            color.min(Vec3::splat(self.sample_bound))
        } else {
            self.counts.non_finite_samples += 1;
            Vec3::ZERO
        }
    }

    /// Where sample `index` of this stage's count falls inside `pixel`, by
    /// chapter 7's [`Chapters::sample_offset`] with the scene's settings.
    #[inline]
    pub fn sample_offset(&self, index: u32, pixel: (u32, u32)) -> (f32, f32) {
        let settings = &self.stage.settings;
        C::sample_offset(
            settings.sampling,
            self.samples(),
            index,
            pixel,
            settings.seed,
        )
    }

    /// The colour of pixel `(x, y)`: one ray through its centre, or chapter
    /// 7's samples when the stage takes more than one.
    pub fn pixel(&mut self, x: u32, y: u32) -> Vec3 {
        if self.samples() == 1 {
            self.sample(x as f32 + 0.5, y as f32 + 0.5)
        } else {
            C::pixel_color(self, x, y)
        }
    }

    #[inline]
    fn log(&mut self, kind: RayKind, ray: &Ray, t_min: f32, t_max: f32) {
        self.counts.count(kind);
        if let Some(recorder) = self.recorder.as_deref_mut() {
            recorder.cast(kind, ray, t_min, t_max);
        }
    }
}

/// Mixed into a light path's number to key its random stream, so that no
/// light path shares its numbers with a camera sample.
const LIGHT_PATH_STREAM: u64 = 0x4C49_4748_545F_5041;

/// Mixed into the seeds of [`Tracer::begin_path`]'s streams: a check's
/// paths draw numbers of their own, not a light path's.
const CHECK_PATH_STREAM: u64 = 0x4348_4543_4B5F_5041;

/// A ray of light leaving a light (chapter 14), and the power it carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emitted {
    pub ray: Ray,
    /// The light's power divided by the density of having chosen this
    /// ray: what the path carries until it meets something.
    pub power: Vec3,
}

/// The point a ray of a light path met (chapter 14), and how far it went
/// in the scene's units (for absorption).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightHit<'a> {
    pub point: HitPoint<'a>,
    pub distance: f32,
}

/// What chapter 14's light paths bring to the image: per pixel, row by row,
/// linear light to add to the camera's estimate; and the rays they cast.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightImage {
    pub pixels: Vec<Vec3>,
    pub counts: RayCounts,
}

/// Light paths traced by one tracer before its splats are handed back.
pub const LIGHT_CHUNK: u64 = 1024;

/// Chunks traced together (in parallel) before their splats are added to
/// the image in chunk order: the memory a batch holds stays bounded, and
/// the sum is the same on any number of threads.
pub(super) const LIGHT_BATCH: u64 = 64;

/// SplitMix64's finaliser: every output bit depends on every input bit.
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The cosine between an emitter's normal and the direction toward it,
/// `direction`, from a point it lights: positive when the point is in
/// front of it; for a two-sided emitter, on either side.
fn facing_cosine(material: &crate::Material, normal: Vec3, direction: Vec3) -> f32 {
    let cosine = -normal.dot(direction);
    if material.two_sided {
        cosine.abs()
    } else {
        cosine
    }
}

/// The area of `shape`, for the shapes a light can be: `None` for a plane
/// (no finite area) and an implicit surface (none known in closed form).
pub(super) fn area_of(shape: &Shape) -> Option<f32> {
    match shape {
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners();
            Some(0.5 * (b - a).cross(c - a).length())
        }
        Shape::Sphere(sphere) => {
            Some(4.0 * std::f32::consts::PI * sphere.radius() * sphere.radius())
        }
        Shape::Plane(_) | Shape::Implicit(_) => None,
    }
}

/// A point uniformly distributed over `shape`'s area for `u, v` uniform in
/// `[0, 1)`, its unit normal, and the area; `None` for a shape with no
/// finite area or a degenerate one.
fn point_on(shape: &Shape, u: f32, v: f32) -> Option<(Vec3, Vec3, f32)> {
    let area = area_of(shape)?;
    match shape {
        Shape::Triangle(triangle) => {
            let [a, b, c] = triangle.corners();
            // Folding the square onto the triangle with the square root
            // keeps the density uniform (pbrt-v4's SampleUniformTriangle
            // gives the same distribution).
            let root = u.sqrt();
            let (first, second) = (1.0 - root, v * root);
            let point = first * a + second * b + (1.0 - first - second) * c;
            let normal = (b - a).cross(c - a).normalize_or_zero();
            (normal != Vec3::ZERO).then_some((point, normal, area))
        }
        Shape::Sphere(sphere) => {
            let z = 1.0 - 2.0 * u;
            let ring = (1.0 - z * z).max(0.0).sqrt();
            let (sin, cos) = libm::sincosf(2.0 * std::f32::consts::PI * v);
            let normal = Vec3::new(ring * cos, ring * sin, z);
            Some((sphere.center() + sphere.radius() * normal, normal, area))
        }
        Shape::Plane(_) | Shape::Implicit(_) => None,
    }
}

/// Makes [`Tracer::shade`] from the registry's `shades` clauses
/// (`chapters/mod.rs`), so that a chapter's shader is its registry line
/// and not a branch here.
macro_rules! shading_chain {
    ($($number:literal $module:ident $folder:literal $title:literal $adds:literal
       |$effects:ident| $switch_on:block [$($function:ident),*] $(kept { $($kept:path),* })?
       $(asks { $($asked:ident($asked_kind:ident)),* $(,)? })?
       $(shades |$when:ident| $condition:expr => $shade:expr)?;)*) => {
        impl<'a, C: Chapters> Tracer<'a, C> {
            /// The colour of `point`, by the shader of the highest chapter
            /// whose condition holds at this stage: chapter 13's paths
            /// over chapter 9's glass over chapter 8's, over chapter 6's
            /// mirror, over chapter 5's Phong or chapter 4's flat light.
            /// Each of those calls the shading of the chapters below it
            /// that it builds on. With none (chapters 1 to 3), the
            /// material's own colour.
            fn shade(&mut self, point: &HitPoint<'a>, depth: u32, weight: f32) -> Vec3 {
                let effects = self.stage.effects;
                let mut highest = 0;
                $($(
                    if (|$when: &Effects| $condition)(&effects) {
                        highest = $number;
                    }
                )?)*
                match highest {
                    $($($number => ($shade)(self, point, depth, weight),)?)*
                    _ => point.albedo,
                }
            }
        }
    };
}

crate::for_each_chapter!(shading_chain);
