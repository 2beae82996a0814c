//! Building the 8-wide tree of a large scene chunk by chunk, so that the builder's buffers
//! (obvhs's PLOC arrays, its binary tree and the 8-wide conversion's cost table: about 300
//! bytes per item) are held for a few chunks at a time instead of for every item at once.
//!
//! - **Chunks.** Items are sorted by the Morton code of their box centres (10 bits per axis over
//!   the centres' box, ties by item index: deterministic) and cut into `⌈n / chunk⌉` runs of
//!   equal size (±1). Each run is built by [`cwbuild::build_within`] (PLOC, medium quality) over
//!   its items' own boxes, at most [`CHUNKS_AT_ONCE`] runs at a time.
//! - **Top.** The runs' roots are grouped, in Morton order, into nodes of at most eight
//!   children, level by level, until one node is left: the root. A top node's children are
//!   placed in obvhs's slots by its own rule (the child whose centre lies farthest along a
//!   slot's octant direction goes last for it), so the traversal's front-to-back order holds.
//! - **Boxes.** A top node quantises the exact `f32` boxes of its children (a run's: the union of
//!   its items' boxes) outward, checked in `f32`: `p + q·e ≤ min` and `p + q·e ≥ max` for the
//!   planes it stores, so every child box contains what it stands for, as obvhs's own nodes do.
//! - **Depth.** With `L` top levels (`8^L ≥` runs) each run's tree may be `31 − L` deep; PLOC's
//!   deeper trees fall back to the median tree, at most `⌈log₂ chunk⌉` deep. With `chunk ≤ 2^k`,
//!   `k ≤ 24` ([`MAX_CHUNK`]) and under `2³²` items, `L ≤ ⌈(32 − k)/3⌉`, so the whole tree is at
//!   most `k + ⌈(32 − k)/3⌉ ≤ 27` levels: within obvhs's traversal stack ([`cwbuild::MAX_DEPTH`]).
//! - **One tree.** The result is one obvhs [`CwBvh`] (top nodes, then the runs' roots, then each
//!   run's other nodes with `child_base_idx` and `primitive_base_idx` moved), walked by the same
//!   traversal code. At most `chunk` items it is exactly [`cwbuild::build`]'s tree.

use super::cwbuild;
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::cwbvh::CwBvh;
use rayon::prelude::*;

/// Items per chunk of [`crate::accel::WideBvh::from_scene`]: the builder's buffers for one
/// chunk are about 300 MiB.
pub const CHUNK: usize = 1 << 20;

/// The largest chunk size used (larger requests are lowered to it; see the depth bound).
pub(crate) const MAX_CHUNK: usize = 1 << 24;

/// Chunks built at the same time at most (each holds its builder's buffers).
pub const CHUNKS_AT_ONCE: usize = 2;

/// An 8-wide tree over `n` items, item `j` with the `f32` box `aabb(j)`: [`cwbuild::build`] when
/// `n ≤ chunk`, otherwise built in chunks of at most `chunk` items (see the module docs).
pub(crate) fn build(n: usize, aabb: impl Fn(usize) -> Aabb + Sync, chunk: usize) -> CwBvh {
    let chunk = chunk.clamp(1, MAX_CHUNK);
    if n <= chunk {
        return cwbuild::build(&(0..n).map(&aabb).collect::<Vec<_>>());
    }
    let keys = morton_order(n, &aabb);
    let count = n.div_ceil(chunk);
    let levels = top_levels(count);
    let range = |c: usize| &keys[c * n / count..(c + 1) * n / count];
    let par = rayon::current_num_threads().clamp(1, CHUNKS_AT_ONCE);
    let mut runs = Vec::with_capacity(count);
    for first in (0..count).step_by(par) {
        let batch = first..(first + par).min(count);
        runs.par_extend(batch.into_par_iter().map(|c| run(range(c), &aabb, cwbuild::MAX_DEPTH - levels)));
    }
    drop(keys);
    let bvh = merge(runs);
    debug_assert!(cwbuild::depth(&bvh) <= cwbuild::MAX_DEPTH);
    bvh
}

/// Top levels over `count` runs: groups of at most eight until one is left.
fn top_levels(mut count: usize) -> usize {
    let mut levels = 0;
    while count > 1 {
        count = count.div_ceil(8);
        levels += 1;
    }
    levels
}

/// Item indices sorted by the Morton code of their box centres (in the high 30 bits of each
/// key; the index in the low 32, which also breaks ties).
fn morton_order(n: usize, aabb: &(impl Fn(usize) -> Aabb + Sync)) -> Vec<u64> {
    let centres = (0..n).into_par_iter().map(|j| aabb(j).center());
    let (lo, hi) = centres
        .fold_with((Vec3A::INFINITY, Vec3A::NEG_INFINITY), |(l, h), c| (l.min(c), h.max(c)))
        .reduce(|| (Vec3A::INFINITY, Vec3A::NEG_INFINITY), |(l1, h1), (l2, h2)| (l1.min(l2), h1.max(h2)));
    let ext = (hi - lo).max(Vec3A::splat(f32::MIN_POSITIVE));
    let mut keys: Vec<u64> = (0..n)
        .into_par_iter()
        .map(|j| {
            let q = ((aabb(j).center() - lo) / ext * 1024.0).clamp(Vec3A::ZERO, Vec3A::splat(1023.0));
            let code = spread(q.x as u64) << 2 | spread(q.y as u64) << 1 | spread(q.z as u64);
            code << 32 | j as u64
        })
        .collect();
    keys.par_sort_unstable();
    keys
}

/// The 10 low bits of `v` moved to every third bit (bit `i` to bit `3i`).
fn spread(v: u64) -> u64 {
    (0..10).fold(0, |acc, i| acc | ((v >> i) & 1) << (3 * i))
}

/// The tree of one run (its keys), with global item indices, and the union of its boxes.
fn run(keys: &[u64], aabb: &(impl Fn(usize) -> Aabb + Sync), max_depth: usize) -> (CwBvh, Aabb) {
    let boxes: Vec<Aabb> = keys.iter().map(|&k| aabb(k as u32 as usize)).collect();
    let bb = boxes.iter().fold(Aabb::empty(), |u, b| u.union(b));
    let mut bvh = cwbuild::build_within(&boxes, max_depth);
    drop(boxes);
    bvh.nodes.shrink_to_fit();
    bvh.primitive_indices.iter_mut().for_each(|p| *p = keys[*p as usize] as u32);
    bvh.primitive_indices.shrink_to_fit();
    (bvh, bb)
}

/// A node of the top: its exact box and its children (indices into the same list; the first
/// entries, without children, are the runs).
struct Top {
    bb: Aabb,
    kids: Vec<usize>,
}

/// One tree over the runs (see the module docs for the layout).
fn merge(runs: Vec<(CwBvh, Aabb)>) -> CwBvh {
    let count = runs.len();
    let mut tops: Vec<Top> = runs.iter().map(|r| Top { bb: r.1, kids: Vec::new() }).collect();
    let mut level: Vec<usize> = (0..count).collect();
    while level.len() > 1 {
        let groups = level.len().div_ceil(8);
        level = (0..groups)
            .map(|g| {
                let kids = level[g * level.len() / groups..(g + 1) * level.len() / groups].to_vec();
                let bb = kids.iter().fold(Aabb::empty(), |u, &k| u.union(&tops[k].bb));
                tops.push(Top { bb, kids });
                tops.len() - 1
            })
            .collect();
    }
    // Breadth first from the root, each node's children in its slot order: positions.
    let (mut pos, mut queue, mut slots) = (vec![0u32; tops.len()], vec![level[0]], vec![[usize::MAX; 8]; tops.len()]);
    let mut head = 0;
    while head < queue.len() {
        let x = queue[head];
        head += 1;
        if x < count {
            continue;
        }
        slots[x] = slot_order(&tops[x].bb, &tops[x].kids.iter().map(|&k| tops[k].bb).collect::<Vec<_>>());
        for &k in slots[x].iter().filter(|&&k| k != usize::MAX) {
            let kid = tops[x].kids[k];
            pos[kid] = queue.len() as u32;
            queue.push(kid);
        }
    }
    let fixed = queue.len();
    let total = fixed + runs.iter().map(|r| r.0.nodes.len() - 1).sum::<usize>();
    let items = runs.iter().map(|r| r.0.primitive_indices.len()).sum::<usize>();
    let mut nodes = vec![CwBvhNode::default(); fixed];
    nodes.reserve_exact(total - fixed);
    for (x, top) in tops.iter().enumerate().skip(count) {
        let kids: Vec<Option<Aabb>> =
            slots[x].iter().map(|&k| (k != usize::MAX).then(|| tops[top.kids[k]].bb)).collect();
        let first = slots[x].iter().find(|&&k| k != usize::MAX).map_or(0, |&k| pos[top.kids[k]]);
        nodes[pos[x] as usize] = top_node(&top.bb, &kids, first);
    }
    let mut primitive_indices = Vec::with_capacity(items);
    let total_aabb = tops[level[0]].bb;
    for (c, (mut bvh, _)) in runs.into_iter().enumerate() {
        // This run's nodes 1.. go to `base`.., its leaves' items to `shift`..
        let (base, shift) = (nodes.len() as u32, primitive_indices.len() as u32);
        nodes[pos[c] as usize] = moved(&bvh.nodes[0], base, shift);
        nodes.extend(bvh.nodes[1..].iter().map(|n| moved(n, base, shift)));
        primitive_indices.append(&mut bvh.primitive_indices);
    }
    CwBvh { nodes, primitive_indices, total_aabb, exact_node_aabbs: None, uses_spatial_splits: false }
}

/// Node `n` of a run whose nodes `1..` go to `base..` and whose leaves' items go to `shift..`.
fn moved(n: &CwBvhNode, base: u32, shift: u32) -> CwBvhNode {
    CwBvhNode {
        child_base_idx: (base + n.child_base_idx).saturating_sub(1),
        primitive_base_idx: n.primitive_base_idx + shift,
        ..*n
    }
}

/// Slot of each child (`slots[s]`: the child in slot `s`, or `usize::MAX`), by obvhs's rule: slot
/// `s` goes to the child whose centre lies least along direction `s` (signs of x, y, z from its
/// bits 2, 1, 0: minus where set), greedily, cheapest pair first.
fn slot_order(bb: &Aabb, kids: &[Aabb]) -> [usize; 8] {
    let dir = |s: usize| Vec3A::new(sign(s & 4), sign(s & 2), sign(s & 1));
    let cost = |c: usize, s: usize| dir(s).dot(kids[c].center() - bb.center());
    let mut slots = [usize::MAX; 8];
    let mut placed = vec![false; kids.len()];
    for _ in 0..kids.len() {
        let free = |s: &usize| slots[*s] == usize::MAX;
        let (c, s) = (0..kids.len())
            .filter(|&c| !placed[c])
            .flat_map(|c| (0..8).filter(free).map(move |s| (c, s)))
            .min_by(|a, b| cost(a.0, a.1).total_cmp(&cost(b.0, b.1)))
            .expect("a free slot for each of at most eight children");
        slots[s] = c;
        placed[c] = true;
    }
    slots
}

fn sign(bit: usize) -> f32 {
    if bit != 0 {
        -1.0
    } else {
        1.0
    }
}

/// A top node over box `bb` whose slot `s` holds the internal node with box `kids[s]` (none
/// where `None`), the first of which is node `first` (the others follow in slot order).
fn top_node(bb: &Aabb, kids: &[Option<Aabb>], first: u32) -> CwBvhNode {
    let p = bb.min;
    let mut node = CwBvhNode { p: p.into(), child_base_idx: first, ..CwBvhNode::default() };
    for axis in 0..3 {
        let (lo, hi) = (p[axis], bb.max[axis]);
        // The smallest power of two e with p + 255·e ≥ hi in f32 (at least 2⁻¹²⁶).
        let need = ((hi - lo) / 255.0).max(f32::MIN_POSITIVE);
        let mut e = f32::from_bits(((need.to_bits() + 0x7f_ffff) >> 23) << 23);
        while lo + 255.0 * e < hi {
            e *= 2.0;
        }
        node.e[axis] = (e.to_bits() >> 23) as u8;
        for (s, kid) in kids.iter().enumerate() {
            let Some(k) = kid else { continue };
            let mut qmin = ((k.min[axis] - lo) / e).floor().clamp(0.0, 255.0);
            while qmin > 0.0 && lo + qmin * e > k.min[axis] {
                qmin -= 1.0;
            }
            let mut qmax = ((k.max[axis] - lo) / e).ceil().clamp(0.0, 255.0);
            while qmax < 255.0 && lo + qmax * e < k.max[axis] {
                qmax += 1.0;
            }
            let (qmin, qmax) = (qmin as u8, qmax as u8);
            match axis {
                0 => (node.child_min_x[s], node.child_max_x[s]) = (qmin, qmax),
                1 => (node.child_min_y[s], node.child_max_y[s]) = (qmin, qmax),
                _ => (node.child_min_z[s], node.child_max_z[s]) = (qmin, qmax),
            }
        }
    }
    for (s, kid) in kids.iter().enumerate() {
        if kid.is_some() {
            node.imask |= 1 << s;
            node.child_meta[s] = (24 + s as u8) | 0b0010_0000;
        }
    }
    node
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::wide::tests::aim;
    use crate::accel::{Tracer, WideBvh};
    use crate::scene::generate::{self, Rng};
    use crate::scene::{Model, Prim, Scene};
    use tubecast::csg::{union, Tagged};
    use tubecast::Ray;

    fn unit_at(p: [f32; 3]) -> Aabb {
        let c = Vec3A::from(p);
        Aabb::new(c - 0.5, c + 0.5)
    }

    /// Every item exactly once in the leaves, and a depth obvhs's traversal stack holds.
    fn check_items_and_depth(bvh: &CwBvh, n: usize) {
        let mut seen = bvh.primitive_indices.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n as u32).collect::<Vec<_>>());
        assert!(cwbuild::depth(bvh) <= cwbuild::MAX_DEPTH, "depth {}", cwbuild::depth(bvh));
    }

    #[test]
    fn at_most_one_chunk_is_the_unchunked_tree() {
        let boxes: Vec<Aabb> = (0..300).map(|i| unit_at([(i % 7) as f32, (i / 7) as f32 * 0.3, 0.0])).collect();
        for chunk in [300, 301, 1 << 30] {
            assert_eq!(build(300, |j| boxes[j], chunk), cwbuild::build(&boxes), "chunk {chunk}");
        }
    }

    /// Degenerate chunks: one item each (4096 runs: four top levels), three, and 4096 copies
    /// of one box (the Morton order is the index order; PLOC has nothing to sort by).
    #[test]
    fn merged_trees_hold_every_item_once_within_the_stack() {
        let line: Vec<Aabb> = (0..4096).map(|i| unit_at([i as f32, (i % 3) as f32, 0.0])).collect();
        let same = vec![unit_at([1.0; 3]); 4096];
        for boxes in [&line, &same] {
            for chunk in [1, 3, 1000, 4095] {
                let bvh = build(boxes.len(), |j| boxes[j], chunk);
                check_items_and_depth(&bvh, boxes.len());
            }
        }
        assert_eq!((top_levels(1), top_levels(8), top_levels(9), top_levels(4096), top_levels(4097)), (0, 1, 2, 4, 5));
    }

    /// A top node's quantised child boxes contain the exact ones, evaluated in `f32` the way
    /// obvhs decodes them, over boxes from 2⁻²⁰ to 2²⁰ across at offsets up to 2²⁰ of their size;
    /// each child gets its own slot, and the slots hold the children's node indices in order.
    #[test]
    fn top_nodes_are_conservative() {
        let mut rng = Rng::new(5);
        for case in 0..2000 {
            let scale = 2f32.powi(rng.range(-20.0, 20.0) as i32);
            let off = scale * 2f32.powi(rng.range(0.0, 20.0) as i32) * rng.range(-1.0, 1.0) as f32;
            let kids: Vec<Aabb> = (0..1 + case % 8)
                .map(|_| {
                    let c = Vec3A::from(rng.unit().map(|x| x as f32)) * scale + off;
                    let h = Vec3A::from(rng.unit().map(|x| x.abs() as f32)) * scale * rng.uniform() as f32;
                    Aabb::new(c - h, c + h)
                })
                .collect();
            let bb = kids.iter().fold(Aabb::empty(), |u, k| u.union(k));
            let slots = slot_order(&bb, &kids);
            let mut used: Vec<usize> = slots.iter().copied().filter(|&k| k != usize::MAX).collect();
            used.sort_unstable();
            assert_eq!(used, (0..kids.len()).collect::<Vec<_>>());
            let by_slot: Vec<Option<Aabb>> = slots.iter().map(|&k| (k != usize::MAX).then(|| kids[k])).collect();
            let node = top_node(&bb, &by_slot, 7);
            let mut next = 7;
            for (s, kid) in by_slot.iter().enumerate() {
                let Some(k) = kid else {
                    assert!(node.is_child_empty(s));
                    continue;
                };
                let q = node.child_aabb(s);
                assert!(q.min.cmple(k.min).all() && q.max.cmpge(k.max).all(), "case {case} slot {s}: {q:?} ⊉ {k:?}");
                assert_eq!(node.child_node_index(s), next);
                next += 1;
            }
        }
    }

    fn translated(lines: &[crate::io::Polyline], by: [f64; 3]) -> Vec<crate::io::Polyline> {
        let mut out = lines.to_vec();
        out.iter_mut().flat_map(|l| l.points.iter_mut()).for_each(|p| *p = std::array::from_fn(|i| p[i] + by[i]));
        out
    }

    /// The union boundaries `(t, entering)` of a ray's line intervals (as in the wide tree's
    /// tests: where two links start at the same `t` the normal depends on the order).
    fn bounds(ivs: &mut [Tagged<f64>]) -> Vec<(u64, bool)> {
        let mut b = Vec::new();
        union(ivs, f64::NEG_INFINITY, f64::INFINITY, |x| b.push((x.t.to_bits(), x.entering)));
        b
    }

    /// With tiny chunks forced (one link, five, 64: the merge path), the tree answers as
    /// brute force over its primitives and as the unchunked tree, bit for bit: closest `t`,
    /// any-hit, the union of the line intervals. Bundle, furball, and a bundle 10⁶ away from
    /// the world origin; rays from outside and inside the tubes.
    #[test]
    fn chunked_trees_equal_brute_force_and_the_whole_tree() {
        let bundle = generate::bundle(20, 30, 3);
        let scenes = [
            Scene::from_polylines(&bundle, 0.12, "bundle").unwrap(),
            Scene::from_polylines(&generate::furball(60, 10, 4), 0.05, "fur").unwrap(),
            Scene::from_polylines(&translated(&bundle, [1e6, -2e6, 5e5]), 0.12, "far").unwrap(),
        ];
        let mut rng = Rng::new(11);
        for scene in &scenes {
            let whole = WideBvh::from_scene(scene, Model::Links).unwrap();
            let prims: Vec<Prim> = (0..whole.prim_count() as u32).map(|i| whole.prim(i)).collect();
            let trees: Vec<WideBvh> =
                [1, 5, 64].iter().map(|&c| WideBvh::from_scene_chunked(scene, Model::Links, c).unwrap()).collect();
            for t in &trees {
                // (The leaves' items are the tree's own table now: `prim` covers them below.)
                assert!(t.depth() <= cwbuild::MAX_DEPTH);
                let mut links: Vec<u32> = (0..t.prim_count() as u32).map(|i| t.prim(i).link).collect();
                links.sort_unstable();
                assert!(links.iter().enumerate().all(|(k, &l)| l == k as u32), "every link once");
                assert!(t.node_count() > whole.node_count(), "the merge ran");
            }
            let mut hits = 0;
            for k in 0..300 {
                let ray = aim(&mut rng, scene, k);
                let brute = prims.iter().filter_map(|p| p.first_hit(&ray)).map(|h| h.t).reduce(f64::min);
                let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
                let mut all = Vec::new();
                for (i, p) in prims.iter().enumerate() {
                    p.pieces(&line, |iv| all.push(Tagged { iv, id: i as u32 }));
                }
                let all = bounds(&mut all);
                let any = prims.iter().any(|p| p.meets(&ray));
                assert_eq!(whole.closest_hit(&ray).map(|h| h.t.to_bits()), brute.map(f64::to_bits));
                hits += usize::from(brute.is_some());
                for t in &trees {
                    let got = t.closest_hit(&ray);
                    assert_eq!(got.map(|h| h.t.to_bits()), brute.map(f64::to_bits), "ray {k}: {ray:?}");
                    if let Some(h) = got {
                        assert_eq!(t.prim(h.id).first_hit(&ray).map(|x| x.t.to_bits()), Some(h.t.to_bits()));
                    }
                    assert_eq!(t.any_hit(&ray), any, "ray {k}");
                    let mut mine = Vec::new();
                    t.line_intervals(&ray, &mut mine);
                    assert_eq!(bounds(&mut mine), all, "ray {k}");
                }
            }
            assert!(hits > 30, "{hits} hits of 300");
        }
    }
}
