//! Compact link storage for [`WideBvh::from_scene`](super::WideBvh::from_scene): runs of up to
//! [`MAX_LINKS`] consecutive links of one chain (link `k + 1` starts at the node where link `k`
//! ends) share **one** `f64` local origin and store each of their nodes **once**, as `f32`
//! `(x, y, z, r)` relative to that origin — 16 bytes per node plus a 32-byte head per cluster,
//! instead of a [`Prim`] (88 bytes) per link. A traversal moves the ray to the cluster's origin
//! once (one `f64` shift per cluster, not per link) and runs each link's filter and kernel on the
//! shared local ray.
//!
//! # The primitives are the stored ones
//! Link `i` of a cluster *is* the [`Prim`] `{ origin: cluster origin, shape: Cylinder or Cone
//! (RoundCone { a: node i, ra, b: node i + 1, rb }) }` ([`Clusters::prim`]): the traversal runs
//! exactly that primitive's arithmetic ([`local_origin`], then [`link_interval`]), so its
//! answers equal [`Prim::intersect`] of the reconstructed primitives bit for bit, and brute
//! force over [`Tracer::prim`](super::Tracer::prim) is the reference (`fuzz/checks/accel.rs`).
//!
//! # Precision
//! A coordinate stored in `f32` relative to an `f64` origin errs by at most `u·|x|` (`u = 2⁻²⁴`,
//! round to nearest; the origin itself and the `f64` subtraction add `≤ 2⁻⁵³` relative, nothing
//! at this scale). A per-link [`Prim::from_link`] stores offsets from the link's own midpoint,
//! `|x|∞ ≤ ℓ/2` with `ℓ = |b − a|∞`, so its error is `≤ u·ℓ/2`. A cluster's origin is the centre
//! of its nodes' bounding box and a link joins only while the box's half-extent `h` (∞-norm)
//! stays `≤ SPREAD·(ℓₖ + Rₖ)` for **every** link `k` of the cluster (`Rₖ = max(raₖ, rbₖ)`), so
//! each stored coordinate errs by `≤ u·h ≤ SPREAD·u·(ℓₖ + Rₖ)`: with [`SPREAD`] `= 4`, at most
//! `8u·(ℓ + R)` — eight times the per-link figure `u·ℓ/2` for thin links, still relative to the
//! link's **own size** and independent of where the scene lies (the property the local origin
//! exists for; world `f32` coordinates would err by `u·|position|`). Radii are stored as
//! `r as f32` exactly as [`Prim::from_link`] stores them. A straight run of equal links has
//! `h = n·ℓ/2`, so it fills [`MAX_LINKS`] `= 2·SPREAD` links; a bent or uneven run stops sooner.
//! The kernel's own rounding grows with the size of its local frame in the same way (its local
//! centre and ray origin are formed in `f32` at distance `≤ √3·h` from the origin), which the
//! static filter's margin accounts for (`link_surely_misses` in `scene/prim.rs`).
//!
//! # Tree items
//! The tree is built over **pieces** of [`super::wide`]'s `PIECE` links of a cluster (one link:
//! the same boxes as one item per link), not over whole clusters: a cluster's box is far
//! looser than its links' boxes (a run of eight diagonal links has about 16 times their
//! volume), and in a dense bundle a ray enters so many of them that tracing slows several-fold
//! (the peers report, `tubecast-lab peers`, measures the trade on Bundle 10⁵).

use crate::scene::{link_interval, local_origin, stored_as_sphere, Best, PendingHit, Prim, Scene, Shape};
use tubecast::{Interval, Ray, RoundCone, V3};

mod pending;
pub(crate) use pending::Pending;

/// Most links per cluster (one lane group of eight).
pub(crate) const MAX_LINKS: usize = 8;
/// A cluster's half-extent may be at most this many times each of its links' `ℓ + R`.
pub(crate) const SPREAD: f64 = 4.0;

/// One cluster: its `f64` origin, the index of its first node in [`Clusters::nodes`] and the
/// scene index of its first link (its links are consecutive in the scene).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Head {
    origin: [f64; 3],
    node: u32,
    link: u32,
}

/// Clusters of links, their nodes stored once (see the module docs).
#[derive(Debug, Default)]
pub(crate) struct Clusters {
    /// One head per cluster plus a sentinel whose `node` is `nodes.len()` (so cluster `c` has
    /// `heads[c + 1].node − heads[c].node − 1` links).
    heads: Vec<Head>,
    /// `(x, y, z, r)` of each cluster's nodes, relative to its origin.
    nodes: Vec<[f32; 4]>,
}

/// A run of `n` scene links starting at link `first`, grouped into one cluster.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Run {
    pub first: u32,
    pub n: u32,
}

impl Clusters {
    /// Split the scene's links into runs (see the module docs) and the primitives of the links
    /// that join none (spheres: a link whose larger end sphere contains the other, or one shorter
    /// than [`crate::scene::SHORT_LINK`]). One pass over
    /// [`crate::scene::Links::iter`] (each link read once, whatever the streamline lengths).
    pub fn group(scene: &Scene) -> (Vec<Run>, Vec<Prim>) {
        let mut runs: Vec<Run> = Vec::new();
        let mut single = Vec::new();
        let node = |i: u32| (V3::from(scene.nodes[i as usize].pos), scene.radius(i as usize));
        let mut cur: Option<(Run, [f64; 3], [f64; 3], f64)> = None; // run, node box, min(ℓ + R)
        let mut prev_end = None; // the end node of link k − 1
        for (k, [na, nb]) in scene.links.iter().enumerate() {
            let joins_chain = prev_end == Some(na);
            prev_end = Some(nb);
            let ((pa, ra), (pb, rb)) = (node(na), node(nb));
            let l = RoundCone::new(pa, ra, pb, rb).expect("scene links are validated when the scene is built");
            if stored_as_sphere(&l) {
                single.push(Prim::from_link(&l, k as u32));
                runs.extend(cur.take().map(|c| c.0));
                continue;
            }
            let size = (l.b - l.a).max_abs() + l.ra.max(l.rb);
            let (pa, pb) = (pa.to_array(), pb.to_array());
            if let Some((run, lo, hi, m)) = cur.as_mut() {
                let joins = run.n < MAX_LINKS as u32 && joins_chain;
                let (lo2, hi2) = (min3(*lo, pb), max3(*hi, pb));
                let h = (0..3).map(|i| 0.5 * (hi2[i] - lo2[i])).fold(0.0, f64::max);
                if joins && h <= SPREAD * m.min(size) {
                    (run.n, *lo, *hi, *m) = (run.n + 1, lo2, hi2, m.min(size));
                    continue;
                }
            }
            runs.extend(cur.take().map(|c| c.0));
            cur = Some((Run { first: k as u32, n: 1 }, min3(pa, pb), max3(pa, pb), size));
        }
        runs.extend(cur.map(|c| c.0));
        (runs, single)
    }

    /// The clusters of `runs`, in that order (the scene's links walked once when `runs` are in
    /// link order, as [`Self::group`] gives them).
    pub fn from_runs(scene: &Scene, runs: &[Run]) -> Self {
        let pending = Pending::new(scene, runs);
        let n = pending.len();
        pending.into_clusters(0..n)
    }

    /// The same clusters in the order `order` (each cluster once).
    #[cfg(test)]
    pub fn reordered(&self, order: impl Iterator<Item = usize>) -> Self {
        let mut heads = Vec::with_capacity(self.heads.len());
        let mut nodes = Vec::with_capacity(self.nodes.len());
        for c in order {
            let h = self.heads[c];
            heads.push(Head { node: nodes.len() as u32, ..h });
            nodes.extend_from_slice(&self.nodes[h.node as usize..self.heads[c + 1].node as usize]);
        }
        heads.push(Head { origin: [0.0; 3], node: nodes.len() as u32, link: 0 });
        Self { heads, nodes }
    }

    /// Number of clusters.
    pub fn len(&self) -> usize {
        self.heads.len().saturating_sub(1)
    }

    /// Number of links in all clusters.
    pub fn link_count(&self) -> usize {
        self.nodes.len() - self.len()
    }

    /// Number of links of cluster `c`.
    #[inline(always)]
    pub fn links(&self, c: usize) -> usize {
        (self.heads[c + 1].node - self.heads[c].node - 1) as usize
    }

    /// Position of cluster `c`'s first link among all clusters' links (the links of cluster
    /// `c` are numbered `first(c)..first(c) + links(c)`).
    #[inline(always)]
    pub fn first(&self, c: usize) -> u32 {
        self.heads[c].node - c as u32
    }

    /// Link `i` of cluster `c` relative to the cluster's origin.
    #[inline(always)]
    fn cone(&self, c: usize, i: usize) -> RoundCone<f32> {
        let n = self.heads[c].node as usize + i;
        cone(self.nodes[n], self.nodes[n + 1])
    }

    /// Scene link index of link `i` of cluster `c`.
    #[inline(always)]
    pub fn link(&self, c: usize, i: usize) -> u32 {
        self.heads[c].link + i as u32
    }

    /// Link `i` of cluster `c` as the primitive it is (see the module docs). Its kind is a
    /// cylinder where the stored radii are equal.
    pub fn prim(&self, c: usize, i: usize) -> Prim {
        prim(self.heads[c].origin, self.link(c, i), self.cone(c, i))
    }

    /// The cluster and position in it of the link numbered `k` (see [`Self::first`]; `k` below
    /// [`Self::link_count`]), by bisection (`first` increases with `c`).
    pub fn locate(&self, k: u32) -> (usize, usize) {
        let (mut lo, mut hi) = (0, self.len());
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.first(mid) <= k {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (lo, (k - self.first(lo)) as usize)
    }

    /// World box of links `i0..i1` of cluster `c`: the union of their stored boxes
    /// ([`Prim::aabb`]; the tree's build takes them from [`Pending::aabb`]).
    #[cfg(test)]
    pub fn aabb(&self, c: usize, i0: usize, i1: usize) -> ([f64; 3], [f64; 3]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for i in i0..i1 {
            let (a, b) = self.prim(c, i).aabb();
            (lo, hi) = (min3(lo, a), max3(hi, b));
        }
        (lo, hi)
    }

    /// Each of the links `i0..i1` of cluster `c` whose line interval is a hit
    /// ([`Prim::intersect`] of [`Self::prim`], bit for bit): `f(i, interval)` in link order, with
    /// one local ray for them all. Stops and returns false as soon as `f` does.
    #[inline(always)]
    pub fn hits(
        &self,
        (c, i0, i1): (usize, usize, usize),
        ray: &Ray<f64>,
        dn: V3<f64>,
        len: f64,
        mut f: impl FnMut(usize, Interval<f64>) -> bool,
    ) -> bool {
        let (rl, tc) = self.local_ray(c, ray, dn);
        for i in i0..i1 {
            let iv = link_interval(&self.cone(c, i), &rl, tc, len, ray);
            if iv.hit && !f(i, iv) {
                return false;
            }
        }
        true
    }

    /// Keep in `best` the closest first crossing of the links `i0..i1` of cluster `c` (as
    /// [`Self::hits`] then [`Interval::first_hit`] find them, bit for bit), left pending;
    /// `id(i)` is link `i`'s hit id.
    #[inline(always)]
    pub fn closest(
        &self,
        (c, i0, i1): (usize, usize, usize),
        ray: &Ray<f64>,
        dn: V3<f64>,
        len: f64,
        id: impl Fn(usize) -> u32,
        best: &mut Best,
    ) {
        let (rl, tc) = self.local_ray(c, ray, dn);
        for i in i0..i1 {
            if let Some(p) = PendingHit::of_link(&self.cone(c, i), &rl, tc, len, ray, id(i)) {
                best.keep(Best::Pending(p));
            }
        }
    }

    /// The local ray of cluster `c` (its origin moved to the line's point nearest the
    /// cluster's origin, unit direction, unbounded) and that point's distance `tc` along `dn`.
    #[inline(always)]
    fn local_ray(&self, c: usize, ray: &Ray<f64>, dn: V3<f64>) -> (Ray<f32>, f64) {
        let (o, tc) = local_origin(self.heads[c].origin, ray.o, dn);
        (Ray::with_range(o, dn.cast::<f32>(), f32::NEG_INFINITY, f32::INFINITY), tc)
    }

    /// Bytes held (allocated capacity).
    pub fn bytes(&self) -> usize {
        self.heads.capacity() * std::mem::size_of::<Head>() + self.nodes.capacity() * std::mem::size_of::<[f32; 4]>()
    }
}

/// The link between stored nodes `a` and `b`.
#[inline(always)]
fn cone([ax, ay, az, ra]: [f32; 4], [bx, by, bz, rb]: [f32; 4]) -> RoundCone<f32> {
    RoundCone { a: V3::new(ax, ay, az), ra, b: V3::new(bx, by, bz), rb }
}

/// Scene link `link`, stored as `cone` relative to `origin`, as the primitive it is (a cylinder
/// where the stored radii are equal).
#[inline(always)]
fn prim(origin: [f64; 3], link: u32, cone: RoundCone<f32>) -> Prim {
    let shape = if cone.ra == cone.rb { Shape::Cylinder(cone) } else { Shape::Cone(cone) };
    Prim { origin, link, shape }
}

/// Scene node `i` as a cluster with origin `origin` stores it: `(x, y, z, r)` in `f32`, the
/// position relative to the origin.
#[inline(always)]
fn stored(scene: &Scene, origin: [f64; 3], i: u32) -> [f32; 4] {
    let p = (V3::from(scene.nodes[i as usize].pos) - V3::from(origin)).cast::<f32>();
    [p.x, p.y, p.z, scene.radius(i as usize) as f32]
}

fn min3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i].min(b[i]))
}

fn max3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i].max(b[i]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::generate;
    use tubecast::LinkShape;

    /// Scenes with chains, bifurcations, tapering and far origins (a bundle moved 10⁶ away),
    /// and SWC trees whose soma links are spheres.
    fn scenes() -> Vec<Scene> {
        let mut far = generate::bundle(20, 40, 3);
        for l in &mut far {
            for p in &mut l.points {
                *p = p.map(|x| x * 1e-3 + 1e6);
            }
        }
        let neuron = generate::neurons(2, &[generate::base_neuron(4)], 5);
        vec![
            Scene::from_polylines(&generate::bundle(30, 84, 1), 0.12, "bundle").unwrap(),
            Scene::from_polylines(&generate::furball(40, 78, 2), 0.05, "furball").unwrap(),
            Scene::from_polylines(&generate::helix(60), 0.3, "helix").unwrap(),
            Scene::from_polylines(&far, 1e-4, "far").unwrap(),
            Scene::from_swc(&neuron, "neurons").unwrap(),
        ]
    }

    /// Every link is stored exactly once (in a cluster or whole), a cluster's links are
    /// consecutive links of a chain, and each stored coordinate is within the module docs'
    /// bound of the scene's `f64` node: `|s − (p − O)|∞ ≤ u·h` with the half-extent
    /// `h ≤ SPREAD·(ℓₖ + Rₖ)` for every link `k` of its cluster; radii are `r as f32`.
    #[test]
    fn clusters_store_every_link_within_the_bound() {
        let u = 2f64.powi(-24);
        for scene in scenes() {
            let (runs, single) = Clusters::group(&scene);
            let cl = Clusters::from_runs(&scene, &runs);
            let mut seen = vec![0u32; scene.links.len()];
            single.iter().for_each(|p| seen[p.link as usize] += 1);
            for c in 0..cl.len() {
                let o = V3::from(cl.heads[c].origin);
                let n = cl.links(c);
                assert!((1..=MAX_LINKS).contains(&n));
                let ids: Vec<u32> = (0..=n)
                    .map(|i| {
                        if i < n {
                            scene.links.get(cl.link(c, i) as usize)[0]
                        } else {
                            scene.links.get(cl.link(c, n - 1) as usize)[1]
                        }
                    })
                    .collect();
                let h = ids.iter().map(|&i| (V3::from(scene.nodes[i as usize].pos) - o).max_abs()).fold(0.0, f64::max);
                for i in 0..n {
                    let k = cl.link(c, i) as usize;
                    seen[k] += 1;
                    assert!(i == 0 || scene.links.get(k - 1)[1] == scene.links.get(k)[0], "a chain");
                    let l = scene.link(k);
                    assert!(h <= SPREAD * ((l.b - l.a).max_abs() + l.ra.max(l.rb)) * (1.0 + 1e-12), "spread");
                }
                for (j, &i) in ids.iter().enumerate() {
                    let nd = &scene.nodes[i as usize];
                    let [x, y, z, r] = cl.nodes[cl.heads[c].node as usize + j];
                    let exact = V3::from(nd.pos) - o;
                    let err = (V3::new(x as f64, y as f64, z as f64) - exact).max_abs();
                    assert!(err <= u * h * (1.0 + 1e-9), "error {err:e} > u·h = {:e}", u * h);
                    assert_eq!(r, scene.radius(i as usize) as f32);
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "every link once");
        }
    }

    /// On straight, evenly sampled chains (the bundle) clusters fill up: the mean is at least
    /// six links, so nodes cost at most 16·7/6 + 32/6 ≈ 24 bytes per link.
    #[test]
    fn bundle_clusters_fill_up() {
        let scene = Scene::from_polylines(&generate::bundle(30, 84, 1), 0.12, "bundle").unwrap();
        let (runs, single) = Clusters::group(&scene);
        assert!(single.is_empty());
        let mean = scene.links.len() as f64 / runs.len() as f64;
        assert!(mean >= 6.0, "mean {mean} links per cluster");
        let cl = Clusters::from_runs(&scene, &runs);
        let per = cl.bytes() as f64 / scene.links.len() as f64;
        assert!(per <= 16.0 * 7.0 / 6.0 + 32.0 / 6.0 + 0.5, "{per} B per link");
    }

    /// Reordering keeps each cluster's data, and `locate` inverts `first`.
    #[test]
    fn reorder_and_locate() {
        let scene = Scene::from_polylines(&generate::furball(10, 30, 7), 0.05, "furball").unwrap();
        let (runs, _) = Clusters::group(&scene);
        let cl = Clusters::from_runs(&scene, &runs);
        let order: Vec<usize> = (0..cl.len()).rev().collect();
        let re = cl.reordered(order.iter().copied());
        for (new, &old) in order.iter().enumerate() {
            assert_eq!(re.links(new), cl.links(old));
            for i in 0..cl.links(old) {
                assert_eq!(re.prim(new, i), cl.prim(old, i));
                assert_eq!(re.locate(re.first(new) + i as u32), (new, i));
            }
        }
        assert_eq!(re.link_count(), scene.links.len());
    }

    /// Streamlines of unequal lengths (2 to 24 points) with, after every tenth, generated SWC
    /// neurons (explicit branch pairs) and a soma-like sphere link: the scene, its links as a plain
    /// list of pairs, and its radii.
    pub(super) fn mixed_links() -> (Scene, Vec<[u32; 2]>, Vec<f64>) {
        let lines = generate::furball(40, 24, 11);
        let swc = generate::neurons(2, &[generate::base_neuron(4)], 5);
        let tree = Scene::from_swc(&swc, "tree").unwrap();
        let (mut nodes, mut radii, mut pairs) = (Vec::new(), Vec::new(), Vec::<[u32; 2]>::new());
        for (j, l) in lines.iter().enumerate() {
            let base = nodes.len() as u32;
            let len = 2 + (j * 7) % 23; // 2..24 points
            nodes.extend(l.points[..len].iter().map(|&pos| crate::scene::Node { pos }));
            radii.extend((0..len).map(|i| 0.02 + 0.001 * i as f64));
            pairs.extend((0..len as u32 - 1).map(|i| [base + i, base + i + 1]));
            if j % 10 == 9 {
                let base = nodes.len() as u32;
                nodes.extend(tree.nodes.iter().copied());
                radii.extend((0..tree.nodes.len()).map(|i| tree.radius(i)));
                pairs.extend(tree.links.iter().map(|[a, b]| [base + a, base + b]));
                // A soma-like link: the larger end sphere contains the other (a sphere).
                let (b2, p) = (nodes.len() as u32, l.points[0]);
                nodes.extend([p, [p[0] + 0.1, p[1], p[2]]].map(|pos| crate::scene::Node { pos }));
                radii.extend([1.0, 0.2]);
                pairs.push([b2, b2 + 1]);
            }
        }
        let mut scene = Scene { nodes, links: pairs.clone().into(), ..Scene::default() };
        radii.iter().enumerate().for_each(|(i, &r)| scene.set_radius(i, r));
        (scene, pairs, radii)
    }

    /// Streamlines of unequal lengths (1 to 23 links, so [`Links::get`](crate::scene::Links::get)
    /// must bisect) interleaved with SWC trees (explicit branch pairs, soma links that are
    /// spheres): the one-pass grouping equals a reference written here over a plain list of
    /// pairs, straight from the module docs' rule (a link joins the run before it when it starts
    /// where the previous link ends, the run has fewer than `MAX_LINKS` links and the joined
    /// node box's half-extent is ≤ `SPREAD·min(ℓ + R)` over the run; spheres join nothing).
    #[test]
    fn grouping_matches_a_plain_list_reference_on_mixed_links() {
        let (scene, pairs, radii) = mixed_links();
        // The reference, over `pairs` only.
        let shape = |[a, b]: [u32; 2]| {
            let p = |i: u32| V3::from(scene.nodes[i as usize].pos);
            RoundCone::new(p(a), radii[a as usize], p(b), radii[b as usize]).unwrap()
        };
        let (mut want_runs, mut want_single) = (Vec::<(u32, u32)>::new(), Vec::new());
        let mut open = false; // whether the last run may still grow
        for (k, &pair) in pairs.iter().enumerate() {
            let l = shape(pair);
            if l.shape() == LinkShape::Sphere {
                want_single.push(k as u32);
                open = false;
                continue;
            }
            if let (true, Some(&(first, n))) = (open, want_runs.last()) {
                let ks = first as usize..=k;
                let ids: Vec<u32> = ks.clone().flat_map(|i| pairs[i]).collect();
                let h = (0..3)
                    .map(|c| {
                        let v = ids.iter().map(|&i| scene.nodes[i as usize].pos[c]);
                        0.5 * (v.clone().fold(f64::NEG_INFINITY, f64::max) - v.fold(f64::INFINITY, f64::min))
                    })
                    .fold(0.0, f64::max);
                let m = ks
                    .map(|i| shape(pairs[i]))
                    .map(|l| (l.b - l.a).max_abs() + l.ra.max(l.rb))
                    .fold(f64::MAX, f64::min);
                if pairs[k - 1][1] == pair[0] && (n as usize) < MAX_LINKS && h <= SPREAD * m {
                    want_runs.last_mut().unwrap().1 += 1;
                    continue;
                }
            }
            want_runs.push((k as u32, 1));
            open = true;
        }
        let (runs, single) = Clusters::group(&scene);
        let got: Vec<(u32, u32)> = runs.iter().map(|r| (r.first, r.n)).collect();
        assert_eq!(got, want_runs);
        assert_eq!(single.iter().map(|p| p.link).collect::<Vec<_>>(), want_single);
        assert!(!want_single.is_empty() && want_runs.iter().any(|r| r.1 > 1) && want_runs.iter().any(|r| r.1 == 1));
        for p in &single {
            assert_eq!(*p, Prim::from_link(&shape(pairs[p.link as usize]), p.link));
        }
    }
}
