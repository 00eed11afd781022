//! The eight chapters as stages: which effects each one switches on.

use crate::Scene;

/// One chapter of the course.
#[derive(Debug, Clone, Copy)]
pub struct ChapterInfo {
    pub number: u8,
    pub title: &'static str,
    /// What this chapter adds to the renderer.
    pub adds: &'static str,
}

/// The chapters, in order.
pub const CHAPTERS: [ChapterInfo; 8] = [
    ChapterInfo {
        number: 1,
        title: "Ray-plane intersection",
        adds: "planes",
    },
    ChapterInfo {
        number: 2,
        title: "Ray-sphere intersection",
        adds: "spheres",
    },
    ChapterInfo {
        number: 3,
        title: "Nearest hit",
        adds: "nearest-hit",
    },
    ChapterInfo {
        number: 4,
        title: "Hard shadows",
        adds: "lights, shadow rays",
    },
    ChapterInfo {
        number: 5,
        title: "Phong illumination",
        adds: "ambient, diffuse, specular",
    },
    ChapterInfo {
        number: 6,
        title: "Mirror reflection",
        adds: "reflection",
    },
    ChapterInfo {
        number: 7,
        title: "Anti-aliasing",
        adds: "supersampling",
    },
    ChapterInfo {
        number: 8,
        title: "Refraction",
        adds: "refraction",
    },
];

/// The last chapter: rendering "with everything".
pub const LAST_CHAPTER: u8 = 8;

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
}

impl Effects {
    /// Everything chapters `1..=chapter` teach.
    pub fn for_chapter(chapter: u8) -> Effects {
        Effects {
            planes: chapter >= 1,
            spheres: chapter >= 2,
            nearest_hit: chapter >= 3,
            lighting: match chapter {
                0..=3 => Lighting::Unlit,
                4 => Lighting::Flat,
                _ => Lighting::Phong,
            },
            shadows: chapter >= 4,
            specular: chapter >= 5,
            reflection: chapter >= 6,
            antialiasing: chapter >= 7,
            refraction: chapter >= 8,
        }
    }

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
        let any = |test: &dyn Fn(&crate::Material) -> bool| scene.materials.iter().any(test);
        let lit = !scene.lights.is_empty();
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
            ..self
        }
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
        names
    }
}
