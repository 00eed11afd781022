//! The effects a render simulates: what each chapter's stage switches on,
//! and which of those a given scene can show. What each stage switches on
//! is the registry's (`Effects::for_chapter`, in `chapters/mod.rs`).

use crate::Scene;
use crate::scene::{FresnelModel, Switch};

/// How a hit point is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lighting {
    /// Chapters 1 to 3: the material's colour, no light at all.
    Unlit,
    /// Chapter 4: ambient, plus a constant share from each visible light.
    Flat,
    /// Chapter 5 on: Phong's ambient, diffuse and specular terms.
    Phong,
}

/// The effects a render simulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Effects {
    pub planes: bool,
    pub spheres: bool,
    /// Nearest hit (chapter 3) rather than first hit in list order.
    pub nearest_hit: bool,
    pub lighting: Lighting,
    pub shadows: bool,
    pub specular: bool,
    pub reflection: bool,
    pub antialiasing: bool,
    pub refraction: bool,
    /// Chapter 9: each ray knows the media it travels through, so every
    /// crossing has the right pair of indices.
    pub nested_media: bool,
    /// Chapter 9: reflection and transmission weighted by Fresnel (exact
    /// or Schlick) rather than chapter 8's constants.
    pub fresnel: bool,
    /// Chapter 9: Beer-Lambert absorption inside solids.
    pub absorption: bool,
    /// Chapter 10: triangles (meshes).
    pub triangles: bool,
    /// Chapter 10: vertex normals blended across smooth triangles, and
    /// their shadow rays lifted off the terminator.
    pub smooth_shading: bool,
    /// Chapter 11: rays find their hits through a bounding volume
    /// hierarchy instead of testing every object.
    pub bvh: bool,
    /// Chapter 12: implicit surfaces, marched by sphere tracing.
    pub implicit: bool,
    /// Chapter 13: every hit scatters one random ray (Monte Carlo
    /// estimation of the rendering equation) in place of the Whitted mix.
    pub path_tracing: bool,
    /// Chapter 13: at each diffuse or glossy point, a shadow ray toward a
    /// point chosen on a light (next-event estimation).
    pub next_event: bool,
    /// Chapter 13: light sampling and BSDF sampling weighed by Veach's
    /// power heuristic (multiple importance sampling).
    pub mis: bool,
    /// Chapter 13: paths ended at random, the survivors' weight divided by
    /// their chance of surviving (Russian roulette).
    pub roulette: bool,
    /// Chapter 14: paths traced from the lights through mirrors and glass
    /// to the diffuse points they light, each joined to the camera: the
    /// caustics a camera path finds only by chance, or never.
    pub light_tracing: bool,
    /// Chapter 14: glass whose index depends on the wavelength (Cauchy), a
    /// wavelength drawn for each path that meets it.
    pub dispersion: bool,
}

/// From how many objects with a box (spheres, triangles) chapter 11 builds
/// a tree. Below, the loop of chapter 3 is faster: a tree costs a build, and
/// each ray pays for its box tests before it reaches the objects.
///
/// Measured, not guessed: `raylab cost --chapter 11 --knob bvh --repeats 5`
/// times the loop against building and tracing a tree, with the same 4096
/// rays, on scenes of 1 to 64 spheres and a floor, and reports the smallest
/// count from which the tree wins at every larger count (its "loop or
/// tree" table; lesson 11 quotes a run). On the development machine that
/// count came out at 6 in two runs; 8 is that, rounded up. (Each ray
/// clears its walk's stack before its first box test: a fixed cost that
/// small scenes feel most.) Near the crossover the two differ by a few
/// per cent, so a count one or two off costs little either way. (A render
/// traces more rays per build than the 4096 measured, which moves the
/// crossover down, not up.)
pub const BVH_MIN_OBJECTS: usize = 8;

impl Effects {
    /// Nothing at all: no shape is drawn.
    pub const NONE: Effects = Effects {
        planes: false,
        spheres: false,
        nearest_hit: false,
        lighting: Lighting::Unlit,
        shadows: false,
        specular: false,
        reflection: false,
        antialiasing: false,
        refraction: false,
        nested_media: false,
        fresnel: false,
        absorption: false,
        triangles: false,
        smooth_shading: false,
        bvh: false,
        implicit: false,
        path_tracing: false,
        next_event: false,
        mis: false,
        roulette: false,
        light_tracing: false,
        dispersion: false,
    };

    /// Drops the effects that `scene`, rendered with `samples` per pixel,
    /// cannot show: shadow rays need a light, the specular term a light and
    /// a material with `specular > 0`, refraction rays a transparent
    /// material, reflection rays a material that reflects or (total internal
    /// reflection) one that is transparent while refraction is on, extra
    /// samples a count above one. What is dropped would only have cost time:
    /// the image is the same, bit for bit, because every dropped term is a
    /// product with a zero coefficient that the tracer no longer computes.
    ///
    /// Extra samples are never skipped pixel by pixel. The only pixels where
    /// more samples provably cannot change the result are those whose whole
    /// square sees one constant colour, and in a Whitted scene that can only
    /// be the background (lit surfaces vary across every pixel). Proving
    /// that no ray through a pixel's square hits any shape needs a
    /// conservative pyramid-versus-shape test that accounts for the rounding
    /// of every camera ray; checking a few samples instead (adaptive
    /// sampling) is a guess, since a thin object can pass between them.
    /// raylab does neither: with `samples = N`, every pixel takes N samples.
    pub fn needed_by(self, scene: &Scene, samples: u32) -> Effects {
        let any = |test: &dyn Fn(&crate::Material) -> bool| scene.materials().any(test);
        let lit = !scene.lights.is_empty();
        // Beams light only the stages that trace paths (chapter 13 on).
        let beams = !scene.beams.is_empty();
        let emits = any(&|m| m.emission != crate::Vec3::ZERO);
        let refraction = self.refraction && any(&|m| m.transparency > 0.0);
        Effects {
            shadows: self.shadows && lit,
            specular: self.specular && lit && any(&|m| m.specular > 0.0),
            // A refracted ray that meets the surface past the critical angle
            // is reflected instead: glass casts reflection rays even when
            // its `reflectivity` is 0.
            reflection: self.reflection
                && any(&|m| m.reflectivity > 0.0 || (refraction && m.transparency > 0.0)),
            refraction,
            antialiasing: self.antialiasing && samples > 1,
            // Media only matter to rays that cross surfaces; Fresnel only
            // splits the light of transparent materials (an opaque one has
            // no transmitted share to weigh), and absorption only happens
            // inside a transparent solid that absorbs.
            nested_media: self.nested_media && refraction,
            fresnel: self.fresnel
                && refraction
                && any(&|m| m.transparency > 0.0 && m.fresnel != FresnelModel::None),
            absorption: self.absorption
                && refraction
                && any(&|m| m.transparency > 0.0 && m.absorption != crate::Vec3::ZERO),
            // Only triangles that carry vertex normals are shaded smooth.
            smooth_shading: self.smooth_shading
                && self.triangles
                && scene
                    .shapes
                    .iter()
                    .any(|shape| shape.as_triangle().is_some_and(|t| t.normals().is_some())),
            bvh: self.bvh
                && scene
                    .shapes
                    .iter()
                    .filter(|shape| shape.bounds().is_some())
                    .count()
                    >= BVH_MIN_OBJECTS,
            implicit: self.implicit
                && scene
                    .shapes
                    .iter()
                    .any(|shape| shape.as_implicit().is_some()),
            // A point light or a surface that glows is something to aim
            // shadow rays at; only a glowing surface can also be found by a
            // scattered ray, so only it has two strategies to weigh.
            next_event: self.next_event && (lit || beams || emits),
            mis: self.mis && self.next_event && emits,
            // Light paths end at the first diffuse point unless a mirror or
            // glass came before it: with neither, none would reach the
            // camera. Dispersion needs glass that disperses.
            light_tracing: self.light_tracing
                && (lit || beams || emits)
                && any(&|m| m.transparency > 0.0 || (m.reflectivity > 0.0 && m.roughness == 0.0)),
            dispersion: self.dispersion
                && any(&|m| m.transparency > 0.0 && m.cauchy.is_some_and(|c| c.b > 0.0)),
            ..self
        }
    }

    /// These effects less the ones `off` names, and less those built on
    /// them. Without `phong`, lighting is chapter 4's flat lighting (no
    /// specular term); without `lighting`, surfaces show their colour,
    /// unlit, as in chapter 3 (and cast no shadow rays). Shading is a stack,
    /// each chapter's on the one before: chapter 6's mirror shades its point
    /// with chapter 5's Phong terms, chapter 8's glass casts chapter 6's
    /// reflection rays, chapter 9's media refine chapter 8's glass. So
    /// leaving out one layer leaves out every layer above it (without
    /// reflection, chapter 8's stage shades as chapter 5's).
    pub fn without(self, off: crate::scene::SwitchedOff) -> Effects {
        let lit = self.lighting != Lighting::Unlit && !off.contains(Switch::Lighting);
        let phong = lit && self.lighting == Lighting::Phong && !off.contains(Switch::Phong);
        let all_lighting = lit && (self.lighting != Lighting::Phong || phong);
        let reflection = self.reflection && all_lighting && !off.contains(Switch::Reflection);
        let refraction = self.refraction
            && all_lighting
            && (reflection || !self.reflection)
            && !off.contains(Switch::Refraction);
        let nested_media = self.nested_media && refraction && !off.contains(Switch::NestedMedia);
        let triangles = self.triangles && !off.contains(Switch::Triangles);
        // Path tracing lights with the lights, mirrors with chapter 6's
        // reflection and bends light with chapters 8 and 9's glass: it is
        // the top of the stack.
        let path_tracing = self.path_tracing
            && all_lighting
            && (reflection || !self.reflection)
            && (refraction || !self.refraction)
            && (nested_media || !self.nested_media)
            && !off.contains(Switch::PathTracing);
        let next_event = path_tracing && self.next_event && !off.contains(Switch::NextEvent);
        Effects {
            planes: self.planes && !off.contains(Switch::Planes),
            spheres: self.spheres && !off.contains(Switch::Spheres),
            nearest_hit: self.nearest_hit && !off.contains(Switch::NearestHit),
            lighting: match self.lighting {
                _ if !lit => Lighting::Unlit,
                Lighting::Phong if !phong => Lighting::Flat,
                lighting => lighting,
            },
            shadows: self.shadows && lit,
            specular: self.specular && phong,
            reflection,
            antialiasing: self.antialiasing && !off.contains(Switch::Antialiasing),
            refraction,
            nested_media,
            // Fresnel's split and absorption are chapter 9's glass, which
            // only a stage with media shades.
            fresnel: self.fresnel && nested_media,
            absorption: self.absorption && nested_media,
            triangles,
            smooth_shading: self.smooth_shading
                && triangles
                && !off.contains(Switch::SmoothShading),
            bvh: self.bvh && !off.contains(Switch::Bvh),
            implicit: self.implicit && !off.contains(Switch::Implicit),
            path_tracing,
            next_event,
            mis: next_event && self.mis && !off.contains(Switch::Mis),
            roulette: path_tracing && self.roulette && !off.contains(Switch::RussianRoulette),
            light_tracing: path_tracing
                && self.light_tracing
                && !off.contains(Switch::LightTracing),
            // Dispersion bends light through chapter 9's glass.
            dispersion: path_tracing
                && nested_media
                && self.dispersion
                && !off.contains(Switch::Dispersion),
        }
    }

    /// The effects on that a stage can be asked to leave out, by their
    /// names in [`crate::scene::SwitchedOff::NAMES`].
    pub fn switchable(&self) -> Vec<&'static str> {
        crate::scene::SwitchedOff::NAMES
            .into_iter()
            .filter(|name| {
                let off = crate::scene::SwitchedOff::parse([*name]).unwrap_or_default();
                self.without(off) != *self
            })
            .collect()
    }

    /// The names of the effects switched on, in chapter order.
    pub fn names(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        let mut add = |on: bool, name| {
            if on {
                names.push(name)
            }
        };
        add(self.planes, "planes");
        add(self.spheres, "spheres");
        add(self.nearest_hit, "nearest-hit");
        add(self.lighting == Lighting::Flat, "flat-lighting");
        add(self.lighting == Lighting::Phong, "phong-diffuse");
        add(self.shadows, "shadows");
        add(self.specular, "phong-specular");
        add(self.reflection, "reflection");
        add(self.antialiasing, "antialiasing");
        add(self.refraction, "refraction");
        add(self.nested_media, "nested-media");
        add(self.fresnel, "fresnel");
        add(self.absorption, "absorption");
        add(self.triangles, "triangles");
        add(self.smooth_shading, "smooth-shading");
        add(self.bvh, "bvh");
        add(self.implicit, "implicit");
        add(self.path_tracing, "path-tracing");
        add(self.next_event, "next-event");
        add(self.mis, "mis");
        add(self.roulette, "russian-roulette");
        add(self.light_tracing, "light-tracing");
        add(self.dispersion, "dispersion");
        names
    }
}
