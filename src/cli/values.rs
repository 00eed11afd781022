//! The words the command line takes for raylab's settings (`--sampling
//! jittered`, `--knob bvh`): clap's `ValueEnum` for types defined below the
//! command line, which know nothing of clap.

use clap::ValueEnum;
use clap::builder::PossibleValue;

use crate::cost::Knob;
use crate::scene::{OffsetRule, Sampling, SphereFormula, TerminatorRule, TriangleTest};

/// `impl ValueEnum` for `$type`: each variant, its word and its help.
macro_rules! words {
    ($type:ty { $($variant:ident = $word:literal $(: $help:literal)?),+ $(,)? }) => {
        impl ValueEnum for $type {
            fn value_variants<'a>() -> &'a [Self] {
                &[$(Self::$variant),+]
            }

            fn to_possible_value(&self) -> Option<PossibleValue> {
                Some(match self {
                    $(Self::$variant => PossibleValue::new($word)$(.help($help))?,)+
                })
            }
        }
    };
}

words!(Sampling {
    Grid = "grid": "A regular `k x k` grid of cell centres (supersampling)",
    Jittered = "jittered": "One random point in each cell of a `k x k` grid (stratified)",
    Random = "random": "Independent random points anywhere in the pixel",
});

words!(SphereFormula {
    Stable = "stable",
    Textbook = "textbook",
});

words!(TriangleTest {
    Watertight = "watertight",
    MollerTrumbore = "moller-trumbore",
});

words!(TerminatorRule {
    Lifted = "lifted": "Lifted towards the curved surface the vertex normals describe (`terminator_point`)",
    Flat = "flat": "On the flat triangle, where the hit is: the shadow terminator shows as facet-shaped shadows",
});

words!(OffsetRule {
    Scaled = "scaled",
    Fixed = "fixed",
});

words!(Knob {
    Samples = "samples": "Samples per pixel, 1 to 64, for grid, jittered and random sampling (chapter 7)",
    Neighbours = "neighbours": "Not a sweep: the lab report's anti-aliasing (each pixel averaged with its four neighbours) against supersampling, on the chapter's scene and a checker of one-pixel squares (chapter 7)",
    Depth = "depth": "Reflection and refraction depth, 0 to 8 (chapter 6)",
    Offset = "offset": "Where secondary rays start: global epsilons against the scaled offset (chapter 4)",
    SphereFormula = "sphere-formula": "The textbook against the stable ray-sphere formula, on a far small sphere (chapter 2)",
    Fresnel = "fresnel": "Fresnel on every transparent material: none (chapter 8's constants), Schlick, exact (chapter 9)",
    TriangleTest = "triangle-test": "Moller-Trumbore against the watertight triangle test (chapter 10)",
    Bvh = "bvh": "Not an image knob (the tree changes no pixel): the BVH report, build and trace time against triangles, split rule, leaf size, and from how many objects a tree pays (chapter 11)",
    March = "march": "The march of implicit surfaces: hit tolerance, step budget, over-relaxation, the Lipschitz factor, Newton (chapter 12)",
    Normals = "normals": "Implicit surfaces' normals: analytic, central differences and the tetrahedron at steps 1e-1 to 1e-7 (chapter 12)",
    Paths = "paths": "Path tracing: 1 to 256 samples per pixel with every switch, without MIS, without next-event estimation, without Russian roulette (chapter 13)",
    Caustics = "caustics": "Light paths: camera paths alone against camera and light paths together, 1 to 256 of each per pixel (chapter 14)",
});

#[cfg(test)]
mod tests {
    use super::*;

    /// The command line's words are the scene file's (serde's names).
    #[test]
    fn the_words_are_the_scene_files() {
        for sampling in Sampling::value_variants() {
            let word = sampling.to_possible_value().expect("a word");
            let from_toml: Sampling =
                serde_json::from_str(&format!("\"{}\"", word.get_name())).expect("serde knows it");
            assert_eq!(&from_toml, sampling);
        }
        assert_eq!(Knob::value_variants().len(), Knob::ALL.len());
    }
}
