#![doc = include_str!(concat!(env!("OUT_DIR"), "/lessons/README.md"))]

//! # The registry
//!
//! [`for_each_chapter!`](crate::for_each_chapter) below is the one list of
//! chapters. Each line names a chapter's number, module, folder, title,
//! what it adds, the effects its stage switches on and the functions a
//! student writes in it. Everything per chapter is read from it: the
//! modules declared here, [`CHAPTERS`] (the command line's ranges, `raylab
//! chapters`, `raylab scene`, the student workspace, the snapshot and seam
//! tests, the docs tables), [`Effects::for_chapter`], and the checker's
//! table of cases (`check::catalog`). A chapter's folder holds the rest:
//! `chapter.rs` (its code), `lesson.md`, `scene.toml`, `checks.rs` (its
//! checkpoints and hard cases) and `tests.rs`.

use crate::effects::{Effects, Lighting};

/// Calls `$then! { ... }` with one line per chapter:
/// `number module "folder" "title" "adds" |effects| { switch-ons } [functions]`,
/// then, where the chapter had them, `kept { paths }`: names its module
/// re-exports because student workspaces made before name them there;
/// where the chapter asks kinds of question of its own, `asks {
/// Name(Type), ... }`: the types its folder's `kinds.rs` defines, which
/// the judge's enum of kinds names (`check::question`); and, where the
/// chapter colours a hit point its own way,
/// `shades |effects| condition => |tracer, point, depth, weight| colour`:
/// its shader, which the tracer asks (`Tracer::shade`, in
/// src/render/tracer.rs) when the condition holds and no later chapter's
/// does, with `C` the chapters being run.
/// It is the registry: a new chapter is its folder and one line here.
#[doc(hidden)]
#[macro_export]
macro_rules! for_each_chapter {
    ($then:ident) => {
        $then! {
            1 ch01_plane "01_plane" "Ray-plane intersection" "planes"
                |e| { e.planes = true } [intersect_plane];
            2 ch02_sphere "02_sphere" "Ray-sphere intersection" "spheres"
                |e| { e.spheres = true } [intersect_sphere];
            3 ch03_nearest "03_nearest" "Nearest hit" "nearest-hit"
                |e| { e.nearest_hit = true } [nearest_hit];
            4 ch04_shadows "04_shadows" "Hard shadows" "lights, shadow rays"
                |e| { e.lighting = Lighting::Flat; e.shadows = true }
                [offset_origin, in_shadow, shade_flat]
                shades |e| e.lighting == Lighting::Flat
                    => |tracer, point, _depth, _weight| C::shade_flat(tracer, point);
            5 ch05_phong "05_phong" "Phong illumination" "ambient, diffuse, specular"
                |e| { e.lighting = Lighting::Phong; e.specular = true } [phong_terms, shade_phong]
                shades |e| e.lighting == Lighting::Phong => |tracer, point, _depth, _weight| {
                    let light = C::shade_phong(tracer, point);
                    light.diffuse + light.specular
                };
            6 ch06_reflection "06_reflection" "Mirror reflection" "reflection"
                |e| { e.reflection = true } [reflect, shade_mirror]
                shades |e| e.reflection
                    => |tracer, point, depth, weight| C::shade_mirror(tracer, point, depth, weight);
            7 ch07_antialiasing "07_antialiasing" "Anti-aliasing" "supersampling"
                |e| { e.antialiasing = true } [sample_offset, pixel_color]
                kept { $crate::scene::Sampling };
            8 ch08_refraction "08_refraction" "Refraction" "refraction"
                |e| { e.refraction = true } [refract, shade_glass]
                shades |e| e.refraction
                    => |tracer, point, depth, weight| C::shade_glass(tracer, point, depth, weight);
            9 ch09_glass "09_glass" "Glass done right"
                "Fresnel reflectance, nested media, absorption"
                |e| { e.nested_media = true; e.fresnel = true; e.absorption = true }
                [fresnel, schlick, transmittance, crossing, shade_dielectric]
                shades |e| e.nested_media
                    => |tracer, point, depth, weight| C::shade_dielectric(tracer, point, depth, weight);
            10 ch10_triangles "10_triangles" "Triangle meshes"
                "triangles, OBJ meshes, smooth shading"
                |e| { e.triangles = true; e.smooth_shading = true }
                [intersect_triangle, barycentric, smooth_normal, terminator_point, smooth_hit_point];
            11 ch11_bvh "11_bvh" "Bounding volume hierarchy"
                "a tree of boxes: hits among thousands of objects in a few dozen tests"
                |e| { e.bvh = true }
                [hit_box, build_bvh, nearest_hit_bvh, any_hit_bvh, hit_boxes, intersect_triangles,
                 collapse_bvh, nearest_hit_wide, any_hit_wide];
            12 ch12_implicit "12_implicit" "Surfaces without a formula"
                "implicit surfaces: sphere tracing, Newton's method, normals by differences"
                |e| { e.implicit = true }
                [sphere_trace, newton_bracketed, implicit_normal, intersect_implicit]
                asks { March(MarchCase), Newton(NewtonCase), ImplicitNormal(ImplicitNormalCase) };
            13 ch13_path_tracing "13_path_tracing" "Path tracing"
                "global illumination: area lights, random paths, next-event estimation, MIS, Russian roulette"
                |e| { e.path_tracing = true; e.next_event = true; e.mis = true; e.roulette = true }
                [cosine_hemisphere, cosine_pdf, power_heuristic, russian_roulette, next_event, shade_path]
                shades |e| e.path_tracing
                    => |tracer, point, depth, weight| C::shade_path(tracer, point, depth, weight);
            14 ch14_caustics "14_caustics" "Caustics and dispersion"
                "light paths from the lights through glass to the camera: caustics; a wavelength per path: dispersion"
                |e| { e.light_tracing = true; e.dispersion = true }
                [splat_weight, connect_to_camera, trace_light_path, cauchy_ior, dispersive_ior];
        }
    };
}

/// One chapter of the course.
#[derive(Debug, Clone, Copy)]
pub struct ChapterInfo {
    pub number: u8,
    pub title: &'static str,
    /// What this chapter adds to the renderer.
    pub adds: &'static str,
    /// The chapter's folder in `chapters/` (`01_plane`), and the stem of
    /// its module's name (`ch01_plane`, a workspace's `src/chapters/ch01_plane.rs`).
    pub folder: &'static str,
    /// The functions of [`crate::course::Chapters`] a student writes in it.
    pub functions: &'static [&'static str],
    /// The built-in scene, as the TOML a student can print and edit.
    pub scene: &'static str,
    /// The reference image of the built-in scene at
    /// [`REFERENCE_WIDTH`] x [`REFERENCE_HEIGHT`], rendered by raylab's own
    /// chapters and pinned by the snapshot tests: what a student's render is
    /// compared with, never rendered by the code under test. Empty in a
    /// student's build, which holds none of raylab's answers.
    pub reference_png: &'static [u8],
    /// The text of the chapter's reference code (`chapters/NN_name/chapter.rs`):
    /// `raylab new` derives a workspace's skeletons and answer key from it.
    pub source: &'static str,
    /// Switches on, in `effects`, what this chapter adds to the stages
    /// before it.
    pub switch_on: fn(&mut Effects),
}

impl ChapterInfo {
    /// The module name of the chapter's code (`ch01_plane`).
    pub fn module(&self) -> String {
        format!("ch{}", self.folder)
    }

    /// The chapter's code, relative to raylab's folder.
    pub fn code_path(&self) -> String {
        format!("chapters/{}/chapter.rs", self.folder)
    }

    /// The chapter's lesson, relative to raylab's folder.
    pub fn lesson_path(&self) -> String {
        format!("chapters/{}/lesson.md", self.folder)
    }

    /// The chapter's built-in scene, relative to raylab's folder.
    pub fn scene_path(&self) -> String {
        format!("chapters/{}/scene.toml", self.folder)
    }
}

/// Size of the reference images ([`ChapterInfo::reference_png`]).
pub const REFERENCE_WIDTH: u32 = 160;
pub const REFERENCE_HEIGHT: u32 = 120;

macro_rules! declare_chapters {
    ($($number:literal $module:ident $folder:literal $title:literal $adds:literal
       |$effects:ident| $switch_on:block [$($function:ident),*] $(kept { $($kept:path),* })?
       $(asks { $($asked:ident($asked_kind:ident)),* $(,)? })?
       $(shades |$when:ident| $condition:expr => $shade:expr)?;)*) => {
        $(
            // Each chapter's module is its folder: the code a student reads
            // in `chapter.rs`, re-exported. The checker's cases beside it,
            // `checks.rs`, are the judge's (`check::by_chapter`).
            #[path = $folder]
            #[doc = include_str!(concat!(env!("OUT_DIR"), "/lessons/", $folder, ".md"))]
            pub mod $module {
                #[path = "chapter.rs"]
                mod code;
                // A student workspace builds raylab with `student`: its
                // chapters cannot call raylab's answers (crate::answer_key).
                #[cfg(not(feature = "student"))]
                pub use code::*;
                #[cfg(feature = "student")]
                pub(crate) use code::*;
                $($(#[doc(hidden)] pub use $kept;)*)?
            }
        )*

        /// The chapters, in order.
        pub const CHAPTERS: &[ChapterInfo] = &[$(
            ChapterInfo {
                number: $number,
                title: $title,
                adds: $adds,
                folder: $folder,
                functions: &[$(stringify!($function)),*],
                scene: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/chapters/", $folder, "/scene.toml")),
                #[cfg(not(feature = "student"))]
                reference_png: include_bytes!(concat!(
                    env!("CARGO_MANIFEST_DIR"), "/snapshots/chapter-", $number, ".png"
                )),
                // The image a check compares with is an answer too: a
                // student's process that held it could send it back.
                #[cfg(feature = "student")]
                reference_png: &[],
                source: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/chapters/", $folder, "/chapter.rs")),
                switch_on: |$effects: &mut Effects| $switch_on,
            }
        ),*];
    };
}

for_each_chapter!(declare_chapters);

// Beside the registry, because the registry is what it reads: the effects
// know no chapter.
impl Effects {
    /// Everything chapters `1..=chapter` teach: each chapter of the
    /// registry, in order, switches on what it adds.
    pub fn for_chapter(chapter: u8) -> Effects {
        let mut effects = Effects::NONE;
        for info in CHAPTERS.iter().filter(|info| info.number <= chapter) {
            (info.switch_on)(&mut effects);
        }
        effects
    }
}

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

// The chapters' names that the whole crate uses (`raylab::reflect`, ...),
// out of a student workspace's reach like the modules' code.
#[cfg(not(feature = "student"))]
pub use ch06_reflection::reflect;
#[cfg(feature = "student")]
pub(crate) use ch06_reflection::reflect;
#[cfg(not(feature = "student"))]
pub use ch08_refraction::refract;
#[cfg(feature = "student")]
pub(crate) use ch08_refraction::refract;
#[cfg(not(feature = "student"))]
pub use ch09_glass::{fresnel, schlick};
#[cfg(feature = "student")]
pub(crate) use ch09_glass::{fresnel, schlick};

/// raylab's own answer to every chapter: the functions of the modules
/// above, which are the [`crate::course::Chapters`] trait's defaults.
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference;

impl crate::course::Chapters for Reference {}

#[cfg(test)]
mod tests {
    /// A workspace made before the samples' placement became a scene
    /// setting imports it from chapter 7's module: that path still resolves.
    #[test]
    fn kept_names_resolve_where_old_workspaces_look() {
        let kept: super::ch07_antialiasing::Sampling = crate::Sampling::Grid;
        assert_eq!(kept, crate::scene::Sampling::Grid);
    }

    #[test]
    fn each_stage_switches_on_what_its_chapters_add() {
        use crate::effects::{Effects, Lighting};
        assert_eq!(Effects::for_chapter(0), Effects::NONE);
        let four = Effects::for_chapter(4);
        assert!(four.planes && four.spheres && four.nearest_hit && four.shadows);
        assert_eq!(four.lighting, Lighting::Flat);
        assert!(!four.specular && !four.reflection);
        let all = Effects::for_chapter(super::LAST_CHAPTER);
        assert_eq!(all.lighting, Lighting::Phong);
        assert!(all.bvh && all.smooth_shading && all.fresnel && all.antialiasing);
    }
}
