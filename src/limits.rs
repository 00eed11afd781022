//! The largest scenes, images and values raylab accepts, each with the
//! reason for its size. A leaf: the scene loader checks against them, and
//! the input limits and the mesh reader, which a scene uses, size theirs
//! by them too.

/// Largest accepted width or height, in pixels.
pub const MAX_SIDE: u32 = 16_384;
/// Largest accepted image, in pixels (an 8K frame is 33 million).
pub const MAX_PIXELS: u64 = 40_000_000;
/// Largest accepted samples per pixel.
pub const MAX_SAMPLES: u32 = 4_096;
/// Largest accepted work for one image: width x height x samples per pixel.
/// Each limit above is sensible alone, but together they could ask for
/// 1.6e11 primary rays (hours). 2^30 (about 1.07e9) still allows 4K at 64
/// samples per pixel or 8K at 32, a few minutes on two cores.
pub const MAX_IMAGE_SAMPLES: u64 = 1 << 30;
/// Largest accepted recursion depth.
pub const MAX_DEPTH: u32 = 64;
/// Most objects a scene file may list. Before chapter 11 every ray tests
/// every object, so 100,000 of them at 640x480 are already minutes of
/// rendering; a mesh counts as one object here (its triangles are bounded
/// by [`MAX_PRIMITIVES`]).
pub const MAX_OBJECTS: usize = 100_000;
/// Most point lights a scene may have. Every shaded point casts a shadow
/// ray to each one: 1,024 lights are a thousand times chapter 4's work per
/// pixel. The TOML parser's tables take far more memory than their bytes
/// in the file, so the count is checked in the text first
/// ([`Scene::parse_in`](crate::scene::Scene::parse_in)).
pub const MAX_LIGHTS: usize = 1024;
/// Most primitives (planes, spheres and every triangle of every mesh) a
/// scene may have: 8 million triangles are about 350 MB of shapes, plus
/// their tree in chapter 11.
pub const MAX_PRIMITIVES: usize = 8_000_000;
/// Largest accepted Phong exponent.
pub const MAX_SHININESS: u32 = 100_000;

/// The largest coordinate (and sphere radius) a scene may have, in size.
/// Shading squares distances: `|light - point|^2` for a light at `y = 2e19`
/// is 4e38, past `f32::MAX` (3.4e38), and the light then adds nothing. Within
/// this limit every point of a sphere is within 2e18 of the origin on each
/// axis, any two such points differ by at most 4e18 per axis, and the
/// squared distance, at most 3 x (4e18)^2 = 4.8e37, leaves a factor of 7 to
/// spare. (Precision is another matter: at 1e18 the spacing of `f32` is
/// about 6.9e10, so a scene that far out is coarse, but it is computed as
/// written.)
pub const MAX_COORDINATE: f32 = 1e18;

/// The largest coordinate or radius a shape may have (stricter than
/// [`MAX_COORDINATE`], which keeps squared distances finite). `f32` resolves a
/// coordinate of size `M` to about `M / 1.7e7`: at 1e6 a surface is known
/// to 0.06 units, enough for a ground sphere under a scene of unit-sized
/// objects; a sphere of radius 1e30 is known to 1e23 and renders as noise
/// (lesson 2, "Coordinates f32 can resolve").
pub const MAX_SHAPE_COORDINATE: f32 = 1e6;

/// The brightest light (colour component or intensity) a scene may have.
/// Physics has no such limit, but `f32` does: a light of 1e38 times a
/// colour overflows to infinity and the pixel turns black. A million keeps
/// every product and sum of the shading far from `f32::MAX` (3.4e38) while
/// leaving room for any sensible exposure.
pub const MAX_LIGHT: f32 = 1e6;

/// The largest absorption coefficient, per unit length. `exp(-a d)` is
/// already below the smallest normal `f32` (1.2e-38) once `a d > 87.3`, so
/// at 1e6 any path longer than 1e-4 units is black; larger values would
/// only risk `a d` overflowing to infinity for long paths (harmless, but
/// no scene needs them).
pub const MAX_ABSORPTION: f32 = 1e6;

/// The largest Cauchy `a` a scene may give: diamond's index is 2.42, and no
/// transparent solid reaches 4 in the visible.
pub const MAX_CAUCHY_A: f32 = 4.0;

/// The largest Cauchy `b`, in square micrometres: ten times dense flint's
/// 0.0134, a prism whose spectrum still fits a room.
pub const MAX_CAUCHY_B: f32 = 0.1;
