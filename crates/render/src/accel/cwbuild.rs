//! Building an obvhs CWBVH whose depth its traversal can hold.
//!
//! obvhs walks a [`CwBvh`] with a fixed stack of 32 entries (`TRAVERSAL_STACK_SIZE`, private
//! to obvhs; its debug build asserts the depth is below it, its release build overwrites the
//! last entry when the stack is full, silently dropping subtrees). PLOC builds shallow trees
//! for ordinary scenes, but not where many primitives share one box: nibabel's
//! `multiline_header_field.tck` has 252 zero-length links at one point, and PLOC chains them
//! into a tree 84 wide levels deep. So [`build`] runs obvhs's own PLOC pipeline (the body of
//! `obvhs::cwbvh::builder::build_cwbvh` without its debug validation), measures the depth,
//! and where it reaches [`MAX_DEPTH`] falls back to a median-split binary tree
//! ([`median_bvh2`]), whose depth is `⌈log₂ n⌉` binary levels by construction (at most 32
//! for any `n ≤ 2³²`, and the 8-wide collapse only shortens it), converted by obvhs.

use obvhs::aabb::Aabb;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::CwBvh;
use obvhs::ploc::PlocBuilder;
use obvhs::{Boundable, BvhBuildParams};

/// Deepest wide-node level (root = 0) obvhs's traversal stack of 32 holds: it pushes at most
/// one entry per level below the root.
pub(crate) const MAX_DEPTH: usize = 31;

/// An 8-wide BVH over `aabbs` no deeper than [`MAX_DEPTH`] (see the module docs).
pub(crate) fn build<T: Boundable>(aabbs: &[T]) -> CwBvh {
    build_within(aabbs, MAX_DEPTH)
}

/// [`build`], falling back to the median tree where PLOC's is deeper than `max_depth` (for a
/// tree that goes under other nodes: the `chunked` module). The fallback's depth is at most
/// `⌈log₂ aabbs.len()⌉` whatever `max_depth` is.
pub(crate) fn build_within<T: Boundable>(aabbs: &[T], max_depth: usize) -> CwBvh {
    if aabbs.is_empty() {
        return CwBvh::default();
    }
    let p = BvhBuildParams::medium_build();
    let leaf = p.max_prims_per_leaf.clamp(1, 3);
    let mut bvh2 = PlocBuilder::with_capacity(aabbs.len()).build(
        p.ploc_search_distance,
        aabbs,
        (0..aabbs.len() as u32).collect(),
        p.sort_precision,
        p.search_depth_threshold,
    );
    ReinsertionOptimizer::default().run(&mut bvh2, p.reinsertion_batch_ratio, None);
    let cw = bvh2_to_cwbvh(&bvh2, leaf, true, false);
    if depth(&cw) <= max_depth {
        return cw;
    }
    bvh2_to_cwbvh(&median_bvh2(aabbs), leaf, true, false)
}

/// Depth of the deepest wide node (root = 0).
pub(crate) fn depth(bvh: &CwBvh) -> usize {
    if bvh.nodes.is_empty() {
        return 0;
    }
    let (mut deepest, mut stack) = (0, vec![(0u32, 0usize)]);
    while let Some((i, d)) = stack.pop() {
        deepest = deepest.max(d);
        let node = &bvh.nodes[i as usize];
        for ch in 0..8 {
            if !node.is_child_empty(ch) && !node.is_leaf(ch) {
                stack.push((node.child_node_index(ch), d + 1));
            }
        }
    }
    deepest
}

/// A binary BVH by median splits: each node's primitives are split in two equal halves by
/// their box centres along the widest axis of those centres (ties in any order), one
/// primitive per leaf. Children are stored in pairs after their parent, as obvhs expects.
pub(crate) fn median_bvh2<T: Boundable>(aabbs: &[T]) -> Bvh2 {
    let mut idx: Vec<u32> = (0..aabbs.len() as u32).collect();
    let mut nodes = vec![Bvh2Node::new(Aabb::empty(), 0, 0)];
    let mut stack = vec![(0usize, 0usize, aabbs.len())];
    while let Some((slot, s, e)) = stack.pop() {
        let mut bb = Aabb::empty();
        let mut cb = Aabb::empty();
        for &i in &idx[s..e] {
            let b = aabbs[i as usize].aabb();
            bb = bb.union(&b);
            cb.extend(b.center());
        }
        if e - s == 1 {
            nodes[slot] = Bvh2Node::new(bb, 1, s as u32);
            continue;
        }
        let ext = cb.max - cb.min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let m = s + (e - s) / 2;
        idx[s..e].select_nth_unstable_by(m - s, |&a, &b| {
            aabbs[a as usize].aabb().center_axis(axis).total_cmp(&aabbs[b as usize].aabb().center_axis(axis))
        });
        let left = nodes.len();
        nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
        nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
        nodes[slot] = Bvh2Node::new(bb, 0, left as u32);
        stack.push((left, s, m));
        stack.push((left + 1, m, e));
    }
    Bvh2 { nodes, primitive_indices: idx, children_are_ordered_after_parents: true, ..Bvh2::default() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn unit_at(p: [f32; 3]) -> Aabb {
        let c = Vec3A::from(p);
        Aabb::new(c - 0.5, c + 0.5)
    }

    #[test]
    fn many_equal_boxes_stay_within_the_traversal_stack() {
        // 4096 copies of one box: PLOC has nothing to sort them by.
        let boxes = vec![unit_at([0.0; 3]); 4096];
        let cw = build(&boxes);
        assert!(depth(&cw) <= MAX_DEPTH, "depth {}", depth(&cw));
        let mut seen = cw.primitive_indices.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..4096).collect::<Vec<u32>>());
    }

    #[test]
    fn the_median_tree_is_balanced_and_holds_every_primitive() {
        // 1000 boxes on a line: ⌈log₂ 1000⌉ = 10 binary levels, so ≤ 10 wide levels.
        let boxes: Vec<Aabb> = (0..1000).map(|i| unit_at([i as f32, 0.0, 0.0])).collect();
        let b2 = median_bvh2(&boxes);
        assert_eq!(b2.nodes.len(), 2 * 1000 - 1);
        let cw = bvh2_to_cwbvh(&b2, 3, true, false);
        assert!(depth(&cw) <= 10);
        let mut seen = cw.primitive_indices.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..1000).collect::<Vec<u32>>());
    }
}
