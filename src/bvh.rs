//! The data of a bounding volume hierarchy: boxes, nodes, the tree.
//!
//! How a ray meets a box, how the tree is built and how a ray walks it is
//! chapter 11's lesson; this module only
//! holds the shapes of the data those functions share with the renderer.

// A shape gives its own bounds, so the box is the shapes' (which then
// need nothing of the tree); the tree's code names it here too.
pub use crate::shapes::Aabb;
use crate::shapes::Triangle;
use crate::{Vec3, Vec4};

/// One node of a [`Bvh`], in a flat array.
///
/// `count == 0` marks an inner node: its children are nodes `first` and
/// `first + 1` (always allocated side by side, so one index names both).
/// `count > 0` marks a leaf: its objects are
/// `Bvh::primitives[first..first + count]`. No node is both, and a leaf is
/// never empty.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BvhNode {
    /// Holds every object below this node.
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

impl BvhNode {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// The indices of the two children of an inner node, `None` for a leaf.
    pub fn children(&self) -> Option<(usize, usize)> {
        (!self.is_leaf()).then(|| (self.first as usize, self.first as usize + 1))
    }

    /// The range of [`Bvh::primitives`] a leaf holds (empty for an inner node).
    pub fn primitive_range(&self) -> std::ops::Range<usize> {
        if self.is_leaf() {
            self.first as usize..self.first as usize + self.count as usize
        } else {
            0..0
        }
    }
}

/// A bounding volume hierarchy over a list of objects, by index.
///
/// The root is `nodes[0]`; `nodes` is empty when no object has a box.
/// Every object index appears exactly once, in `primitives` (under a leaf)
/// or in `unbounded` (no box could hold it: planes, and anything whose box
/// is not finite). Indices are `u32` to halve the tree's memory: a scene of
/// more than four billion objects would not fit in memory anyway.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    /// Object indices, grouped so that each leaf's objects are contiguous.
    pub primitives: Vec<u32>,
    /// Object indices that are tested by a plain loop, outside the tree.
    pub unbounded: Vec<u32>,
}

impl Bvh {
    /// How many nodes, inner and leaves.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|node| node.is_leaf()).count()
    }

    /// The number of nodes on the longest path from the root to a leaf (1
    /// for a tree that is a single leaf, 0 for an empty tree).
    ///
    /// Walks with an explicit stack: a tree built from degenerate input can
    /// be as deep as it has objects.
    pub fn depth(&self) -> usize {
        if self.nodes.is_empty() {
            return 0;
        }
        let mut deepest = 0;
        let mut stack = vec![(0usize, 1usize)];
        while let Some((index, depth)) = stack.pop() {
            deepest = deepest.max(depth);
            let Some(node) = self.nodes.get(index) else {
                continue;
            };
            if let Some((left, right)) = node.children() {
                stack.push((left, depth + 1));
                stack.push((right, depth + 1));
            }
        }
        deepest
    }

    /// The bytes the tree's arrays hold (their lengths, not capacities).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<BvhNode>()
            + (self.primitives.len() + self.unbounded.len()) * std::mem::size_of::<u32>()
    }
}

/// How [`Chapters::build_bvh`](crate::Chapters::build_bvh) chooses where to
/// cut a node in two.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum SplitRule {
    /// The surface-area heuristic, evaluated at the bin boundaries.
    #[default]
    Sah,
    /// The middle of the node's centroids along their widest axis.
    Midpoint,
}

/// The knobs of the build.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct BvhOptions {
    pub split: SplitRule,
    /// How many bins the centroids are sorted into along the split axis
    /// (values below 2 count as 2).
    pub bins: u32,
    /// A node with this many objects or fewer becomes a leaf without trying
    /// a split (values below 1 count as 1). A larger node can still become
    /// a leaf when no split is cheaper (SAH) or none is possible (every
    /// centroid in the same place).
    pub max_leaf: u32,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions {
            split: SplitRule::Sah,
            bins: 16,
            max_leaf: 4,
        }
    }
}

/// How many children a node of a [`WideBvh`] has room for, and how many
/// triangles a [`Leaf4`] tests at once: the lanes of a [`Vec4`].
pub const WIDTH: usize = 4;

/// Four boxes side by side, coordinate by coordinate: box `lane` runs from
/// `min[axis][lane]` to `max[axis][lane]` on each axis. A [`Vec4`] holds
/// one coordinate of all four, and its arithmetic works on the four at
/// once (one SSE instruction each on x86-64): a ray is tested against four
/// boxes for about the price of one.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Boxes4 {
    pub min: [Vec4; 3],
    pub max: [Vec4; 3],
}

impl Boxes4 {
    /// Four empty boxes.
    pub const EMPTY: Boxes4 = Boxes4 {
        min: [Vec4::INFINITY; 3],
        max: [Vec4::NEG_INFINITY; 3],
    };

    /// Box `lane`.
    pub fn get(&self, lane: usize) -> Aabb {
        Aabb::new(
            Vec3::new(self.min[0][lane], self.min[1][lane], self.min[2][lane]),
            Vec3::new(self.max[0][lane], self.max[1][lane], self.max[2][lane]),
        )
    }

    /// Puts `bounds` in lane `lane`.
    pub fn set(&mut self, lane: usize, bounds: Aabb) {
        for axis in 0..3 {
            self.min[axis][lane] = bounds.min[axis];
            self.max[axis][lane] = bounds.max[axis];
        }
    }
}

/// Lane by lane `if a > b { a } else { b }`: `b` wherever `a` is NaN, as a
/// comparison decides (chapter 11's slab test folds its crossings so).
///
/// On x86-64 that is exactly what the `maxps` instruction computes, in one
/// step. `Vec4::max` promises nothing about NaN (on ARM it returns the
/// NaN), and `Vec4::select` on a comparison takes four instructions.
#[inline(always)]
pub fn greater_of(a: Vec4, b: Vec4) -> Vec4 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    {
        // SAFETY: `_mm_max_ps` needs SSE, which the `cfg` above says this
        // build has (every x86-64 target does).
        Vec4::from(unsafe { std::arch::x86_64::_mm_max_ps(a.into(), b.into()) })
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    {
        Vec4::select(a.cmpgt(b), a, b)
    }
}

/// Lane by lane `if a < b { a } else { b }`: `b` wherever `a` is NaN
/// (`minps` on x86-64; see [`greater_of`]).
#[inline(always)]
pub fn lesser_of(a: Vec4, b: Vec4) -> Vec4 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    {
        // SAFETY: as in `greater_of`.
        Vec4::from(unsafe { std::arch::x86_64::_mm_min_ps(a.into(), b.into()) })
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    {
        Vec4::select(a.cmplt(b), a, b)
    }
}

/// Asks the processor to start loading `item`'s cache lines now, without
/// waiting for them: a walk that knows which nodes it will open next can
/// have their loads under way while it works on the current one, instead
/// of waiting for each in turn. A hint only: it changes no value, and
/// where the target has no such instruction it does nothing.
#[inline(always)]
pub fn prefetch<T>(item: *const T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let first = item.cast::<i8>();
        for line in (0..std::mem::size_of::<T>()).step_by(CACHE_LINE) {
            // SAFETY: a prefetch reads nothing the program sees and never
            // faults, whatever the address (`wrapping_add` makes none).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(first.wrapping_add(line)) };
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = item;
}

/// An empty `Vec` with room for `capacity` items, whose memory Linux is
/// asked to map in huge pages (2 MB on x86-64) rather than 4 KB ones.
///
/// The processor translates each address through a small cache of page
/// mappings (the TLB): about two thousand entries, 8 MB of 4 KB pages. A
/// walk through a tree of a hundred megabytes jumps to a new page at
/// nearly every node, and each miss in that cache costs a walk of the page
/// tables, on top of the wait for the node itself. In 2 MB pages the same
/// entries map 4 GB. The advice is given before anything is written, so
/// the pages are huge from their first use; it is only advice, and where
/// it is refused (or on other systems) the `Vec` is an ordinary one.
pub fn vec_on_huge_pages<T>(capacity: usize) -> Vec<T> {
    let items = Vec::with_capacity(capacity);
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = items.as_ptr() as usize;
        let end = start + capacity * std::mem::size_of::<T>();
        // `madvise` takes whole pages: those inside the allocation.
        let first_page = start.next_multiple_of(PAGE);
        if end > first_page {
            // SAFETY: the range lies inside the `Vec`'s own allocation, and
            // this advice changes how its pages are mapped, not their
            // contents (there are none yet).
            unsafe {
                libc::madvise(
                    first_page as *mut libc::c_void,
                    end - first_page,
                    libc::MADV_HUGEPAGE,
                );
            }
        }
    }
    items
}

/// The bytes the processor loads from memory at once.
pub const CACHE_LINE: usize = 64;

/// One node of a [`WideBvh`]: up to [`WIDTH`] children, each with its box
/// in `boxes` and, lane by lane, what a [`BvhNode`] says of itself:
/// `count[lane] == 0`, the inner node `nodes[first[lane]]`;
/// `count[lane] > 0`, a leaf of `count` [`Leaf4`]s from `leaves[first]`.
/// A lane whose box is empty ([`Aabb::EMPTY`]) holds nothing.
///
/// 96 bytes of boxes and 32 of indices: aligned to 64, a node is exactly
/// two cache lines.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub struct WideNode {
    pub boxes: Boxes4,
    pub first: [u32; WIDTH],
    pub count: [u32; WIDTH],
}

impl WideNode {
    /// A node whose every lane holds nothing.
    pub const UNUSED: WideNode = WideNode {
        boxes: Boxes4::EMPTY,
        first: [0; WIDTH],
        count: [0; WIDTH],
    };

    /// The lanes that hold a child: those whose box is not empty.
    #[inline(always)]
    pub fn used_lanes(&self) -> glam::BVec4A {
        self.boxes.min[0].cmple(self.boxes.max[0])
    }
}

/// Four triangles side by side: `corners[k][axis]` holds coordinate `axis`
/// of corner `k` (`a`, `b`, `c`) of the four, lane by lane.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Triangles4 {
    pub corners: [[Vec4; 3]; 3],
}

impl Triangles4 {
    /// Four triangles with NaN corners, which no ray hits.
    pub const NAN: Triangles4 = Triangles4 {
        corners: [[Vec4::NAN; 3]; 3],
    };

    /// Puts `triangle`'s corners in lane `lane`.
    pub fn set(&mut self, lane: usize, triangle: &Triangle) {
        for (corner, point) in triangle.corners().into_iter().enumerate() {
            for axis in 0..3 {
                self.corners[corner][axis][lane] = point[axis];
            }
        }
    }

    /// The triangle in lane `lane`.
    pub fn get(&self, lane: usize) -> Triangle {
        let corner = |k: usize| {
            Vec3::new(
                self.corners[k][0][lane],
                self.corners[k][1][lane],
                self.corners[k][2][lane],
            )
        };
        Triangle::new(corner(0), corner(1), corner(2))
    }
}

/// Up to four objects of a leaf of a [`WideBvh`], object `objects[lane]`
/// in lane `lane`. The triangles among them are copied into `triangles`,
/// to be tested together; the lanes set in `one_by_one` (bit `lane`) hold
/// objects of other kinds, asked by their own test. Those lanes' corners,
/// and the unused lanes' (object `u32::MAX`), are NaN.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Leaf4 {
    pub triangles: Triangles4,
    pub objects: [u32; WIDTH],
    pub one_by_one: u32,
}

/// A bounding volume hierarchy whose nodes have up to [`WIDTH`] children,
/// each leaf's objects in [`Leaf4`]s. The root is `nodes[0]`; `nodes` is
/// empty when no object has a box. `unbounded` is as in [`Bvh`].
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct WideBvh {
    pub nodes: Vec<WideNode>,
    pub leaves: Vec<Leaf4>,
    pub unbounded: Vec<u32>,
}

impl WideBvh {
    /// The bytes the tree's arrays hold (their lengths, not capacities).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<WideNode>()
            + self.leaves.len() * std::mem::size_of::<Leaf4>()
            + self.unbounded.len() * std::mem::size_of::<u32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lane_folds_keep_the_other_operand_where_one_is_nan() {
        let a = Vec4::new(1.0, f32::NAN, 3.0, f32::NEG_INFINITY);
        let b = Vec4::new(2.0, 5.0, f32::NAN, 0.0);
        let greater = greater_of(a, b).to_array();
        // 1 > 2 false: 2; NaN > 5 false: 5; 3 > NaN false: NaN; -inf > 0: 0.
        assert_eq!(&greater[..2], &[2.0, 5.0]);
        assert!(greater[2].is_nan());
        assert_eq!(greater[3], 0.0);
        let lesser = lesser_of(a, b).to_array();
        assert_eq!(&lesser[..2], &[1.0, 5.0]);
        assert!(lesser[2].is_nan());
        assert_eq!(lesser[3], f32::NEG_INFINITY);
    }

    #[test]
    fn lanes_hold_what_is_put_in_them() {
        let mut boxes = Boxes4::EMPTY;
        let bounds = Aabb::new(Vec3::new(-1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0));
        boxes.set(2, bounds);
        assert_eq!(boxes.get(2), bounds);
        assert_eq!(boxes.get(0), Aabb::EMPTY);
        let node = WideNode {
            boxes,
            ..WideNode::UNUSED
        };
        assert_eq!(node.used_lanes().bitmask(), 0b100);
        let triangle = Triangle::new(Vec3::X, Vec3::Y, Vec3::Z);
        let mut triangles = Triangles4::NAN;
        triangles.set(1, &triangle);
        assert_eq!(triangles.get(1), triangle);
        assert!(triangles.get(0).a().is_nan());
    }
}
