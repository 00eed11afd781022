//! The media a ray travels through (chapter 9): a small stack of the solids
//! it is inside, carried by the tracer with each ray.
//!
//! The rule, stated once for nested, touching and overlapping solids:
//!
//! - a ray is inside every transparent solid whose surface it has crossed
//!   inward and not yet crossed outward since (the camera's rays start in
//!   air, inside nothing);
//! - among those, the medium it travels in is the one it entered last.
//!
//! Nested solids (water in glass, a bubble in the water) need nothing more:
//! the inner one is always entered last. In the region two overlapping
//! solids share, the one entered last wins, so the same region can be
//! different media for different rays: a scene should not rely on it
//! (priorities per material would settle it; raylab has none). Touching
//! solids (a glass wall and the water against it) share a surface, and the
//! ray meets it twice at the same point: the second crossing is within the
//! secondary ray's offset and is skipped, so the stack would miss it. Model
//! them nested instead: the water a hair inside the glass, by more than the
//! offset (a few ulps of the coordinates) and less than a pixel.
//!
//! The stack holds at most [`MediumStack::CAPACITY`] solids. When it is
//! full, entering one more does not record it: the ray goes on as if in the
//! innermost recorded medium, and leaving that unrecorded solid later finds
//! nothing to remove. The image is then wrong inside that deepest solid
//! only, the same way on every run, and never panics.

use crate::Vec3;

/// A medium: the solid it fills, its index of refraction and absorption.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    /// The solid it fills (a [`crate::HitPoint::solid`]: the scene's
    /// object, so a whole mesh is one solid), or [`Medium::OUTSIDE`].
    pub object: usize,
    pub ior: f32,
    /// Beer-Lambert absorption per unit length, per channel.
    pub absorption: Vec3,
}

impl Medium {
    /// The object number of the space outside every solid.
    pub const OUTSIDE: usize = usize::MAX;

    /// The space outside every solid: air, index 1, clear. (Air's index is
    /// 1.0003; raylab, like chapter 8, takes it to be exactly 1.)
    pub const AIR: Medium = Medium {
        object: Medium::OUTSIDE,
        ior: 1.0,
        absorption: Vec3::ZERO,
    };
}

/// The solids a ray is inside, in the order it entered them (see the
/// module's rule). Fixed size and `Copy`: a recursive trace copies it, it
/// never allocates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MediumStack {
    entries: [Medium; MediumStack::CAPACITY],
    len: usize,
}

impl Default for MediumStack {
    fn default() -> Self {
        MediumStack::EMPTY
    }
}

impl MediumStack {
    /// How many nested solids a ray can be inside. Eight covers any scene a
    /// lesson builds (glass, water, bubble use three); the stack is copied
    /// at each refraction, so it stays small.
    pub const CAPACITY: usize = 8;

    /// In air, inside nothing: where the camera's rays start.
    pub const EMPTY: MediumStack = MediumStack {
        entries: [Medium::AIR; MediumStack::CAPACITY],
        len: 0,
    };

    /// The medium the ray travels in: the solid entered last, or air.
    #[inline]
    pub fn current(&self) -> Medium {
        match self.len {
            0 => Medium::AIR,
            len => self.entries[len - 1],
        }
    }

    /// How many solids the ray is inside.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The solids, outermost (entered first) to innermost.
    pub fn media(&self) -> &[Medium] {
        &self.entries[..self.len]
    }

    /// Whether the ray is inside `object`.
    #[inline]
    pub fn contains(&self, object: usize) -> bool {
        self.media().iter().any(|medium| medium.object == object)
    }

    /// The stack after entering `medium`: it becomes the current one. Full
    /// stacks come back unchanged (see the module's rule).
    #[inline]
    pub fn entering(&self, medium: Medium) -> MediumStack {
        let mut after = *self;
        if after.len < MediumStack::CAPACITY {
            after.entries[after.len] = medium;
            after.len += 1;
        }
        after
    }

    /// The stack after leaving `object`: its last entry is removed and the
    /// others keep their order. A solid not on the stack changes nothing.
    #[inline]
    pub fn leaving(&self, object: usize) -> MediumStack {
        let mut after = *self;
        if let Some(at) = self.media().iter().rposition(|m| m.object == object) {
            after.entries.copy_within(at + 1..self.len, at);
            after.len -= 1;
            after.entries[after.len] = Medium::AIR;
        }
        after
    }
}

/// The two sides of a surface a ray meets (chapter 9's
/// [`crate::Chapters::crossing`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// Whether the ray enters the solid (travels against its outward normal).
    pub entering: bool,
    /// Index of the medium the ray arrives in, and of the one beyond.
    pub n1: f32,
    pub n2: f32,
    /// The media on the side the ray arrives on: where the reflected ray
    /// travels.
    pub before: MediumStack,
    /// The media beyond the surface: where the refracted ray travels.
    pub beyond: MediumStack,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn medium(object: usize, ior: f32) -> Medium {
        Medium {
            object,
            ior,
            absorption: Vec3::ZERO,
        }
    }

    #[test]
    fn empty_is_air() {
        assert_eq!(MediumStack::EMPTY.current(), Medium::AIR);
        assert!(MediumStack::default().is_empty());
    }

    #[test]
    fn nested_solids_are_entered_and_left_in_order() {
        let glass = medium(0, 1.5);
        let water = medium(1, 1.33);
        let in_glass = MediumStack::EMPTY.entering(glass);
        let in_water = in_glass.entering(water);
        assert_eq!(in_water.current(), water);
        assert_eq!(in_water.leaving(1), in_glass);
        assert_eq!(in_water.leaving(1).leaving(0), MediumStack::EMPTY);
    }

    #[test]
    fn overlapping_solids_can_be_left_out_of_order() {
        let a = medium(0, 1.5);
        let b = medium(1, 1.33);
        let both = MediumStack::EMPTY.entering(a).entering(b);
        // Leaving A first, inside B: B stays current.
        let only_b = both.leaving(0);
        assert_eq!(only_b.media(), &[b]);
        assert_eq!(both.current(), only_b.current());
        // Leaving something never entered changes nothing.
        assert_eq!(both.leaving(7), both);
    }

    #[test]
    fn a_full_stack_ignores_one_more_solid() {
        let mut stack = MediumStack::EMPTY;
        for object in 0..MediumStack::CAPACITY {
            stack = stack.entering(medium(object, 1.0 + object as f32 / 10.0));
        }
        assert_eq!(stack.len(), MediumStack::CAPACITY);
        let more = stack.entering(medium(99, 2.0));
        assert_eq!(more, stack);
        assert_eq!(more.leaving(99), stack);
    }
}
