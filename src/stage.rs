//! The course's chapters as data, and the effects each stage switches on.
//!
//! [`CHAPTERS`] is the one list of chapters: the command line's ranges,
//! `raylab chapters` and `raylab scene`, the student workspace, the checks,
//! the snapshot tests and the docs all read it. A new chapter is one entry
//! here plus its files.

use crate::Scene;
use crate::check::catalog;
use crate::scene::FresnelModel;

/// One chapter of the course.
#[derive(Debug, Clone, Copy)]
pub struct ChapterInfo {
    pub number: u8,
    pub title: &'static str,
    /// What this chapter adds to the renderer.
    pub adds: &'static str,
    /// The chapter's file stem in `chapters/`: `NN_name.rs` holds its code,
    /// `NN_name.md` its lesson, and a workspace's `src/chapters/` the same.
    pub file: &'static str,
    /// The functions of [`crate::course::Chapters`] a student writes in it.
    pub functions: &'static [&'static str],
    /// The built-in scene, as the TOML a student can print and edit.
    pub scene: &'static str,
    /// The reference image of the built-in scene at
    /// [`REFERENCE_WIDTH`] x [`REFERENCE_HEIGHT`], rendered by raylab's own
    /// chapters and pinned by the snapshot tests: what a student's render is
    /// compared with, never rendered by the code under test.
    pub reference_png: &'static [u8],
    /// The checkpoint cases of `raylab check` (level 1): questions to this
    /// chapter's functions that every correct implementation answers.
    pub checkpoints: fn() -> Vec<crate::check::Case>,
    /// Its hard cases (level 2, reported apart): only a numerically robust
    /// implementation answers them.
    pub robustness: fn() -> Vec<crate::check::Case>,
    /// The text of the chapter's reference file (`chapters/NN_name.rs`):
    /// `raylab new` derives a workspace's skeletons and answer key from it.
    pub source: &'static str,
}

impl ChapterInfo {
    /// The module name of the chapter's file (`ch01_plane`).
    pub fn module(&self) -> String {
        format!("ch{}", self.file)
    }
}

/// Size of the reference images ([`ChapterInfo::reference_png`]).
pub const REFERENCE_WIDTH: u32 = 160;
pub const REFERENCE_HEIGHT: u32 = 120;

macro_rules! chapter {
    ($number:literal, $file:literal, $title:literal, $adds:literal, [$($function:literal),*],
     $checkpoints:path, $robustness:path) => {
        ChapterInfo {
            number: $number,
            title: $title,
            adds: $adds,
            file: $file,
            functions: &[$($function),*],
            scene: include_str!(concat!("../chapters/scenes/chapter-", $number, ".toml")),
            reference_png: include_bytes!(concat!("../snapshots/chapter-", $number, ".png")),
            checkpoints: $checkpoints,
            robustness: $robustness,
            source: include_str!(concat!("../chapters/", $file, ".rs")),
        }
    };
}

/// The chapters, in order.
pub const CHAPTERS: &[ChapterInfo] = &[
    chapter!(
        1,
        "01_plane",
        "Ray-plane intersection",
        "planes",
        ["intersect_plane"],
        catalog::chapter_1,
        catalog::chapter_1_robustness
    ),
    chapter!(
        2,
        "02_sphere",
        "Ray-sphere intersection",
        "spheres",
        ["intersect_sphere"],
        catalog::chapter_2,
        catalog::chapter_2_robustness
    ),
    chapter!(
        3,
        "03_nearest",
        "Nearest hit",
        "nearest-hit",
        ["nearest_hit"],
        catalog::chapter_3,
        catalog::chapter_3_robustness
    ),
    chapter!(
        4,
        "04_shadows",
        "Hard shadows",
        "lights, shadow rays",
        ["offset_origin", "in_shadow", "shade_flat"],
        catalog::chapter_4,
        catalog::chapter_4_robustness
    ),
    chapter!(
        5,
        "05_phong",
        "Phong illumination",
        "ambient, diffuse, specular",
        ["phong_terms", "shade_phong"],
        catalog::chapter_5,
        catalog::chapter_5_robustness
    ),
    chapter!(
        6,
        "06_reflection",
        "Mirror reflection",
        "reflection",
        ["reflect", "shade_mirror"],
        catalog::chapter_6,
        catalog::chapter_6_robustness
    ),
    chapter!(
        7,
        "07_antialiasing",
        "Anti-aliasing",
        "supersampling",
        ["sample_offset", "pixel_color"],
        catalog::chapter_7,
        catalog::chapter_7_robustness
    ),
    chapter!(
        8,
        "08_refraction",
        "Refraction",
        "refraction",
        ["refract", "shade_glass"],
        catalog::chapter_8,
        catalog::chapter_8_robustness
    ),
    chapter!(
        9,
        "09_glass",
        "Glass done right",
        "Fresnel reflectance, nested media, absorption",
        [
            "fresnel",
            "schlick",
            "transmittance",
            "crossing",
            "shade_dielectric"
        ],
        catalog::chapter_9,
        catalog::chapter_9_robustness
    ),
    chapter!(
        10,
        "10_triangles",
        "Triangle meshes",
        "triangles, OBJ meshes, smooth shading",
        [
            "intersect_triangle",
            "barycentric",
            "smooth_normal",
            "terminator_point",
            "smooth_hit_point"
        ],
        catalog::chapter_10,
        catalog::chapter_10_robustness
    ),
    chapter!(
        11,
        "11_bvh",
        "Bounding volume hierarchy",
        "a tree of boxes: hits among thousands of objects in a few dozen tests",
        ["hit_box", "build_bvh", "nearest_hit_bvh", "any_hit_bvh"],
        catalog::chapter_11,
        catalog::chapter_11_robustness
    ),
];

/// The last chapter: rendering "with everything".
pub const LAST_CHAPTER: u8 = CHAPTERS.len() as u8;

/// Chapter `number`, if there is one.
pub fn chapter(number: u8) -> Option<&'static ChapterInfo> {
    CHAPTERS.iter().find(|info| info.number == number)
}

/// Parses a chapter number given on the command line (for clap).
pub fn parse_chapter(text: &str) -> Result<u8, String> {
    text.parse::<u8>()
        .ok()
        .filter(|&n| chapter(n).is_some())
        .ok_or_else(|| format!("there is no chapter {text}; chapters are 1 to {LAST_CHAPTER}"))
}

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
/// count came out at 6 in two runs; 8 is that, rounded up. (It was 14 and
/// 15, and this constant 16, until the walk's stack took 8-byte entries:
/// each ray then cleared a kilobyte before its first box test, a fixed cost
/// that small scenes felt most.) Near the crossover the two differ by a few
/// per cent, so a count one or two off costs little either way. (A render
/// traces more rays per build than the 4096 measured, which moves the
/// crossover down, not up.)
pub const BVH_MIN_OBJECTS: usize = 8;

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
            nested_media: chapter >= 9,
            fresnel: chapter >= 9,
            absorption: chapter >= 9,
            triangles: chapter >= 10,
            smooth_shading: chapter >= 10,
            bvh: chapter >= 11,
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
        let any = |test: &dyn Fn(&crate::Material) -> bool| scene.materials().any(test);
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
        add(self.nested_media, "nested-media");
        add(self.fresnel, "fresnel");
        add(self.absorption, "absorption");
        add(self.triangles, "triangles");
        add(self.smooth_shading, "smooth-shading");
        add(self.bvh, "bvh");
        names
    }
}
