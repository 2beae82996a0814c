//! The tree every tracer walks: obvhs's PLOC build collapsed to eight children per node, with
//! each child's box stored as plain `f32` planes, structure of arrays ([`Node`]), and a
//! traversal that visits children nearest-first by their true entry distance, keeps
//! `(child, entry)` pairs on its stack and drops every pair whose entry lies beyond the current
//! hit when it is popped.
//!
//! Why not obvhs's own CWBVH traversal over the same tree: it dequantises the 8-bit child planes
//! on every visit, orders children by a fixed octant instead of their distance, and its stack
//! keeps no entry distance, so a pushed child is tested again after a closer hit was found.
//! Storing exact `f32` planes costs memory (256 bytes a node instead of 80) and nothing else;
//! the eight slab tests of a node run as one eight-lane computation.
//!
//! # Conservative planes
//! The walk's trees ([`Tree::from_cwbvh`]) store each child's **exact** box: the union
//! (`f32` min and max, exact) of the padded `f32` boxes of the items under it, the boxes the
//! build was given. So every plane contains what it stands for with no rounding of its own,
//! and the traversal's slab arithmetic is the one the parent module's bound covers (the box
//! padding `pad`): one subtraction and one product per plane, with `1/dᵢ` clamped to `±2²³`
//! as obvhs clamps it. (obvhs's 8-bit quantised planes, `p + q·2ᵏ`, are looser, and were
//! measured up to one `f32` step *inside* the padded boxes they stand for: the padding, not the
//! quantisation, is what made them safe.)
//!
//! The layout is `#[repr(C)]` and plain data so that another backend (a GPU) can take the
//! nodes as they are ([`Tree::nodes`]).

use obvhs::cwbvh::CwBvh;
use wide::f32x8;

/// Children per node.
pub const WIDTH: usize = 8;

/// [`Node::child`] of an empty slot (its box is empty too: `lo = +∞`, `hi = −∞`).
pub const EMPTY: u32 = u32::MAX;

/// One node: the boxes of its up to eight children, by axis, in the tree's `f32` frame, and
/// what each child is.
///
/// A child with `count[i] == 0` is an inner node, `child[i]` its index in [`Tree::nodes`]; one
/// with `count[i] > 0` is a leaf of the `count[i]` items `child[i] .. child[i] + count[i]`
/// (indices into the tracer's leaf-order item list); an empty slot has `child[i] == EMPTY`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Lower planes, `lo[axis][child]`.
    pub lo: [[f32; WIDTH]; 3],
    /// Upper planes, `hi[axis][child]`.
    pub hi: [[f32; WIDTH]; 3],
    /// Inner node index, first item of a leaf, or [`EMPTY`].
    pub child: [u32; WIDTH],
    /// Items of a leaf; 0 for an inner node or an empty slot.
    pub count: [u32; WIDTH],
}

impl Node {
    const VOID: Node = Node {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [EMPTY; WIDTH],
        count: [0; WIDTH],
    };
}

/// A ray in the tree's frame, ready for the slab tests.
#[derive(Clone, Copy, Debug)]
pub struct TreeRay {
    /// Origin.
    pub o: [f32; 3],
    /// Clamped inverse direction (`±2²³` where `|dᵢ| ≤ 2⁻²³`).
    pub inv: [f32; 3],
    /// Far end of the parameter range (entry `t` beyond it is culled).
    pub t_max: f32,
}

impl TreeRay {
    /// The ray `o + t·d`, `t ∈ [0, t_max]`.
    pub fn new(o: [f32; 3], d: [f32; 3], t_max: f32) -> Self {
        let inv = d.map(|x| if x.abs() <= f32::EPSILON { (1.0f32).copysign(x) / f32::EPSILON } else { 1.0 / x });
        Self { o, inv, t_max }
    }
}

/// Stack entries of a walk: seven per level of a tree of depth at most
/// `cwbuild::MAX_DEPTH + 1`, rounded up.
const STACK: usize = 7 * (super::cwbuild::MAX_DEPTH + 2);

thread_local! {
    /// Each thread's walk stack ([`Tree::walk`]).
    static STACKS: std::cell::Cell<Option<Box<[u64; STACK]>>> = const { std::cell::Cell::new(None) };
}

/// A stack entry: a child (`count` ≤ 3 items of a leaf, 0 for an inner node) and its entry.
#[inline(always)]
fn pack(child: u32, count: u32, t: f32) -> u64 {
    u64::from(t.to_bits()) << 32 | u64::from(child | count << 30)
}

#[inline(always)]
fn unpack(e: u64) -> (u32, u32, f32) {
    let lo = e as u32;
    (lo & ((1 << 30) - 1), lo >> 30, f32::from_bits((e >> 32) as u32))
}

/// The eight-wide tree. An empty tree has no nodes and every ray misses.
#[derive(Clone, Debug, Default)]
pub struct Tree {
    nodes: Vec<Node>,
}

/// What the traversal hands to the caller for each leaf it enters: the item range and the
/// ray's current `t_max`, which the caller lowers when it finds a closer hit.
pub struct Leaf {
    /// First item (leaf-order index).
    pub first: u32,
    /// Number of items.
    pub count: u32,
}

impl Tree {
    /// The tree of obvhs's `bvh` (its nodes and leaf ranges) with every child's planes set to
    /// its exact box: the union of the boxes `item_box(k)` of its leaf-order items `k` (for an
    /// inner child, of everything under it), the boxes the build was given (module docs).
    /// obvhs's quantised planes are not used.
    pub fn from_cwbvh(bvh: &CwBvh, item_box: impl Fn(u32) -> ([f32; 3], [f32; 3])) -> Self {
        let nodes = bvh
            .nodes
            .iter()
            .map(|n| {
                let mut out = Node::VOID;
                for ch in (0..WIDTH).filter(|&ch| !n.is_child_empty(ch)) {
                    if n.is_leaf(ch) {
                        let (first, count) = n.child_primitives(ch);
                        (out.child[ch], out.count[ch]) = (first, count);
                    } else {
                        out.child[ch] = n.child_node_index(ch);
                    }
                }
                out
            })
            .collect();
        let mut tree = Self { nodes };
        if !tree.nodes.is_empty() {
            tree.tighten(0, &item_box);
        }
        tree
    }

    /// Set node `ni`'s child planes to the exact boxes (see [`Self::from_cwbvh`]) and
    /// return the node's own box.
    fn tighten(&mut self, ni: usize, item_box: &impl Fn(u32) -> ([f32; 3], [f32; 3])) -> ([f32; 3], [f32; 3]) {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for ch in 0..WIDTH {
            let (child, count) = (self.nodes[ni].child[ch], self.nodes[ni].count[ch]);
            if child == EMPTY {
                continue;
            }
            let (l, h) = if count > 0 {
                (child..child + count)
                    .map(item_box)
                    .fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(l, h), (a, b)| {
                        (std::array::from_fn(|i| l[i].min(a[i])), std::array::from_fn(|i| h[i].max(b[i])))
                    })
            } else {
                self.tighten(child as usize, item_box)
            };
            let n = &mut self.nodes[ni];
            for a in 0..3 {
                (n.lo[a][ch], n.hi[a][ch]) = (l[a], h[a]);
                (lo[a], hi[a]) = (lo[a].min(l[a]), hi[a].max(h[a]));
            }
        }
        (lo, hi)
    }

    /// The nodes; the root is node 0.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>()
    }

    /// The children of `n` whose boxes the ray enters before `t_max` (bit `i` for child `i`)
    /// and their entry distances, eight lanes at once. The arithmetic is the slab test the
    /// module docs bound: `(plane − o)·inv` per plane, entry the largest near distance (from
    /// 0), exit the least far one (to `t_max`). No lane is NaN: `o` and `inv` are finite and a
    /// plane is finite or an empty slot's `±∞`.
    #[inline(always)]
    fn entries(n: &Node, r: &TreeRay, neg: [bool; 3]) -> (u32, [f32; WIDTH]) {
        let mut near = f32x8::splat(0.0);
        let mut far = f32x8::splat(r.t_max);
        for (a, &flip) in neg.iter().enumerate() {
            let (lo, hi) = if flip { (n.hi[a], n.lo[a]) } else { (n.lo[a], n.hi[a]) };
            let (o, inv) = (f32x8::splat(r.o[a]), f32x8::splat(r.inv[a]));
            near = ((f32x8::new(lo) - o) * inv).fast_max(near);
            far = ((f32x8::new(hi) - o) * inv).fast_min(far);
        }
        (near.simd_le(far).to_bitmask(), near.to_array())
    }

    /// Walk the tree along `r`, nearest child first, calling `leaf` for each leaf entered
    /// before `t_max` with the ray's `t_max` (the caller lowers it as hits are found; entries
    /// beyond it are dropped). `leaf` returns false to stop the walk.
    #[inline]
    pub fn walk(&self, r: &mut TreeRay, leaf: impl FnMut(Leaf, &mut f32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        // One stack per thread, reused: a fresh array would be zeroed (1.8 kB) for every ray.
        // A walk started from inside another's leaf callback finds the slot empty and takes a
        // stack of its own.
        let mut stack = STACKS.with(|s| s.take()).unwrap_or_else(|| Box::new([0u64; STACK]));
        self.walk_with(r, leaf, &mut stack);
        STACKS.with(|s| s.set(Some(stack)));
    }

    #[inline(always)]
    fn walk_with(&self, r: &mut TreeRay, mut leaf: impl FnMut(Leaf, &mut f32) -> bool, stack: &mut [u64; STACK]) {
        let neg = [r.inv[0] < 0.0, r.inv[1] < 0.0, r.inv[2] < 0.0];
        // Pushed children as `entry bits << 32 | child | count << 30`: at most seven a level,
        // and the build bounds the depth (`cwbuild::MAX_DEPTH`).
        let mut top = 0usize;
        let mut node = 0u32;
        loop {
            let n = &self.nodes[node as usize];
            let (mut hit, t) = Self::entries(n, r, neg);
            // The children hit, as stack entries: entries are `≥ +0.0`, so their bits (the high
            // half of an entry) order them as the floats do, and whole entries sort by distance.
            let mut keys = [0u64; WIDTH];
            let k = hit.count_ones() as usize;
            for key in keys.iter_mut().take(k) {
                let i = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                *key = pack(n.child[i], n.count[i], t[i]);
            }
            let mut next = None;
            if k == 1 {
                next = Some(keys[0]);
            } else if k == 2 {
                let (a, b) = (keys[0].min(keys[1]), keys[0].max(keys[1]));
                stack[top] = b;
                top += 1;
                next = Some(a);
            } else if k > 2 {
                // Nearest first (insertion sort of at most eight); push all but the nearest,
                // farthest first; go on with the nearest.
                let keys = &mut keys[..k];
                for i in 1..k {
                    let x = keys[i];
                    let mut j = i;
                    while j > 0 && keys[j - 1] > x {
                        keys[j] = keys[j - 1];
                        j -= 1;
                    }
                    keys[j] = x;
                }
                for &e in keys[1..].iter().rev() {
                    stack[top] = e;
                    top += 1;
                }
                next = Some(keys[0]);
            }
            loop {
                let e = match next.take() {
                    Some(x) => x,
                    None if top > 0 => {
                        top -= 1;
                        stack[top]
                    }
                    None => return,
                };
                let (c, cnt, te) = unpack(e);
                if te > r.t_max {
                    continue;
                }
                if cnt == 0 {
                    node = c;
                    break;
                }
                if !leaf(Leaf { first: c, count: cnt }, &mut r.t_max) {
                    return;
                }
            }
        }
    }
}
