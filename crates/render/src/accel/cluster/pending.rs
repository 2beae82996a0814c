//! The clusters before their nodes are stored ([`Pending`]): the tree's build needs only the
//! boxes of their links, so the nodes are stored once, in the tree's leaf order, after it.

use super::{cone, max3, min3, prim, stored, Clusters, Head, Run};
use crate::scene::{LinkIter as Iter, Scene};

/// Runs of links with their clusters' origins, the nodes not stored yet (32 bytes per run).
/// [`Self::aabb`] computes a link's box from the scene, bit for bit the box of the link
/// [`Clusters`] stores, and [`Self::into_clusters`] stores the nodes in the order the tree
/// wants them. Storing the clusters in run order and then copying them into leaf order held
/// two copies at once (16 bytes per node each: 1.8 GB at 10⁸ links, the peak of `info`).
#[derive(Default)]
pub(crate) struct Pending<'a> {
    /// The scene the runs are of (`None`: no runs).
    scene: Option<&'a Scene>,
    /// One head per run (its `node` counts the nodes of the runs before it) and a sentinel.
    heads: Vec<Head>,
}

impl<'a> Pending<'a> {
    /// The runs `runs` of `scene`, each with its cluster's origin: the centre of its nodes'
    /// bounding box (see [`Clusters`]' module docs).
    pub fn new(scene: &'a Scene, runs: &[Run]) -> Self {
        let mut heads = Vec::with_capacity(runs.len() + 1);
        let (mut walk, mut node) = (Walk::new(scene), 0u32);
        for &r in runs {
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            walk.nodes(r, |i| {
                let p = scene.nodes[i as usize].pos;
                (lo, hi) = (min3(lo, p), max3(hi, p));
            });
            let origin = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
            heads.push(Head { origin, node, link: r.first });
            node += r.n + 1;
        }
        heads.push(Head { origin: [0.0; 3], node, link: 0 });
        Self { scene: Some(scene), heads }
    }

    /// Number of runs.
    pub fn len(&self) -> usize {
        self.heads.len().saturating_sub(1)
    }

    /// Links of run `c`.
    pub fn links(&self, c: usize) -> usize {
        (self.heads[c + 1].node - self.heads[c].node - 1) as usize
    }

    /// World box of links `i0..i1` of run `c` as its cluster will store them: bit for bit
    /// [`Clusters::aabb`] of the stored clusters.
    pub fn aabb(&self, c: usize, i0: usize, i1: usize) -> ([f64; 3], [f64; 3]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let Some(scene) = self.scene else { return (lo, hi) };
        let h = self.heads[c];
        let first = h.link as usize + i0;
        for (k, [a, b]) in (first..).zip(scene.links.iter_from(first).take(i1 - i0)) {
            let link = cone(stored(scene, h.origin, a), stored(scene, h.origin, b));
            let (a, b) = prim(h.origin, k as u32, link).aabb();
            (lo, hi) = (min3(lo, a), max3(hi, b));
        }
        (lo, hi)
    }

    /// The clusters of the runs in the order `order` (each run once), their nodes stored
    /// (walking the scene's links once when `order` is increasing).
    pub fn into_clusters(self, order: impl Iterator<Item = usize>) -> Clusters {
        let Some(scene) = self.scene else { return Clusters::default() };
        let mut heads = Vec::with_capacity(self.heads.len());
        let mut nodes = Vec::with_capacity(self.heads.last().map_or(0, |h| h.node as usize));
        let mut walk = Walk::new(scene);
        for c in order {
            let h = self.heads[c];
            heads.push(Head { node: nodes.len() as u32, ..h });
            walk.nodes(Run { first: h.link, n: self.links(c) as u32 }, |i| nodes.push(stored(scene, h.origin, i)));
        }
        heads.push(Head { origin: [0.0; 3], node: nodes.len() as u32, link: 0 });
        Clusters { heads, nodes }
    }
}

/// A walk over a scene's links that reads the nodes of runs: forward from where it is when a
/// run starts at or after it, from a new start ([`crate::scene::Links::iter_from`]) otherwise.
struct Walk<'a> {
    scene: &'a Scene,
    links: Iter<'a>,
    /// The index of the link `links` yields next.
    next: usize,
}

impl<'a> Walk<'a> {
    fn new(scene: &'a Scene) -> Self {
        Self { scene, links: scene.links.iter(), next: 0 }
    }

    /// `f(node)` for each node of run `r` (a chain): the start of each link, then the end of
    /// the last.
    fn nodes(&mut self, r: Run, mut f: impl FnMut(u32)) {
        let first = r.first as usize;
        match first.checked_sub(self.next) {
            Some(0) => {}
            Some(d) if d <= 64 => {
                self.links.nth(d - 1);
            }
            _ => self.links = self.scene.links.iter_from(first),
        }
        let mut end = None;
        for [a, b] in self.links.by_ref().take(r.n as usize) {
            f(a);
            end = Some(b);
        }
        end.into_iter().for_each(f);
        self.next = first + r.n as usize;
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::mixed_links;
    use super::*;
    use tubecast::V3;

    /// On unequal streamlines (so [`crate::scene::Links::get`] bisects), SWC branches and sphere
    /// links, the clusters stored from the runs equal a reference written here over the plain
    /// list of pairs, straight from the module docs of [`Clusters`]: a run's nodes are the start
    /// of each link and the end of the last, its origin the centre of their bounding box, each
    /// node stored as `f32` of its position less the origin and `f32` of its radius. In any
    /// order of the runs (reversed; every third first), and the boxes of [`Pending::aabb`] are
    /// bit for bit those of the stored clusters.
    #[test]
    fn clusters_match_a_plain_list_reference_on_mixed_links() {
        let (scene, pairs, radii) = mixed_links();
        let (runs, _) = Clusters::group(&scene);
        assert!(runs.iter().any(|r| r.n > 1) && runs.len() > 100);
        let reference = |r: &Run| {
            let ks = r.first as usize..(r.first + r.n) as usize;
            let ids: Vec<u32> = ks.clone().map(|k| pairs[k][0]).chain([pairs[ks.end - 1][1]]).collect();
            let pos = |i: u32| scene.nodes[i as usize].pos;
            let lo: [f64; 3] = std::array::from_fn(|c| ids.iter().map(|&i| pos(i)[c]).fold(f64::INFINITY, f64::min));
            let hi: [f64; 3] =
                std::array::from_fn(|c| ids.iter().map(|&i| pos(i)[c]).fold(f64::NEG_INFINITY, f64::max));
            let origin: [f64; 3] = std::array::from_fn(|c| 0.5 * (lo[c] + hi[c]));
            let nodes: Vec<[f32; 4]> = ids
                .iter()
                .map(|&i| {
                    let d = V3::from(pos(i)) - V3::from(origin);
                    [d.x as f32, d.y as f32, d.z as f32, radii[i as usize] as f32]
                })
                .collect();
            (origin, nodes)
        };
        let n = runs.len();
        let orders: [Vec<usize>; 3] = [
            (0..n).collect(),
            (0..n).rev().collect(),
            (0..n).step_by(3).chain((0..n).filter(|c| c % 3 != 0)).collect(),
        ];
        for order in orders {
            let pending = Pending::new(&scene, &runs);
            let boxes: Vec<_> = order.iter().map(|&c| pending.aabb(c, 0, pending.links(c))).collect();
            let last: Vec<_> = order.iter().map(|&c| pending.aabb(c, pending.links(c) - 1, pending.links(c))).collect();
            let cl = pending.into_clusters(order.iter().copied());
            assert_eq!(cl.len(), n);
            for (new, &old) in order.iter().enumerate() {
                let (origin, nodes) = reference(&runs[old]);
                let h = cl.heads[new];
                assert_eq!((h.origin, h.link), (origin, runs[old].first), "run {old}");
                assert_eq!(&cl.nodes[h.node as usize..cl.heads[new + 1].node as usize], &nodes[..], "run {old}");
                assert_eq!(boxes[new], cl.aabb(new, 0, cl.links(new)), "run {old}");
                assert_eq!(last[new], cl.aabb(new, cl.links(new) - 1, cl.links(new)), "run {old}");
            }
        }
    }
}
