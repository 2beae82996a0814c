//! Chains of links and the spline model along them (see the [module docs](super)).

use super::{Prim, Scene, SceneError};
use std::cmp::Ordering;
use tubecast::HermiteSegment;
use tubecast::V3;

/// Default tolerance of the spline model: certified distance to the cubic Hermite sweep over
/// the local radius (a thousandth of a radius, where Russig's fixed pair of pieces can be off by
/// a whole radius).
pub const SPLINE_TOLERANCE: f64 = 1e-3;
/// Most halvings of one Hermite segment (at most 2⁷ = 128 quadratic pieces; their index is a `u8`).
pub const SPLINE_MAX_DEPTH: u32 = 7;

/// [`Scene::spline_fidelity`]: how far the traced pieces are from the cubic segments.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplineFidelity {
    /// Russig's pair: greatest certified distance (scene units).
    pub pair_distance: f64,
    /// Russig's pair: greatest certified distance over the segment's least node radius.
    pub pair_relative: f64,
    /// The faithful split: greatest certified distance over the local radius.
    pub faithful_relative: f64,
    /// The faithful split: quadratic pieces in all.
    pub faithful_pieces: usize,
    /// Curved segments.
    pub segments: usize,
}

/// A chain of links: a maximal path whose interior nodes have exactly two links.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chain {
    /// Nodes along the chain (`links.len() + 1` of them; a closed chain repeats its first
    /// node at the end).
    pub nodes: Vec<u32>,
    /// Links along the chain: `links[i]` joins `nodes[i]` and `nodes[i + 1]`.
    pub links: Vec<u32>,
    /// A periodic loop (every node has two links).
    pub closed: bool,
}

/// One cubic Hermite segment of a spline tube, modelling scene link `link`, oriented along
/// its chain (`p0` is the node that comes first in the chain).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplineSegment {
    /// Scene link index.
    pub link: u32,
    /// The segment (finite-difference derivatives, see the module docs).
    pub seg: HermiteSegment<f64>,
}

impl SplineSegment {
    /// Greatest defect `Dₖ` of the five control points of the split from the link's straight
    /// round cone (see the module docs): an upper bound on the Hausdorff distance between the
    /// two sweeps; `+∞` when a control point projects outside the chord or the chord is empty.
    pub fn chord_defect(&self) -> f64 {
        let s = &self.seg;
        let v = s.p1 - s.p0;
        let len2 = v.length2();
        if len2.partial_cmp(&0.0) != Some(Ordering::Greater) {
            return f64::INFINITY;
        }
        let ((pa, ra), (pb, rb)) = s.quad_controls();
        let mut worst: f64 = 0.0;
        for (x, rho) in pa.iter().zip(ra).chain(pb.iter().zip(rb)) {
            let w = *x - s.p0;
            let t = w.dot(v) / len2;
            if !(0.0..=1.0).contains(&t) {
                return f64::INFINITY;
            }
            let d = (w - v * t).length() + (rho - (s.r0 + (s.r1 - s.r0) * t)).abs();
            worst = worst.max(d);
        }
        worst
    }

    /// The threshold below which the segment is modelled by its link:
    /// `2⁻²²·(½|p₁ − p₀| + max(r₀, r₁))`.
    pub fn straight_tolerance(&self) -> f64 {
        let s = &self.seg;
        2f64.powi(-22) * (0.5 * (s.p1 - s.p0).length() + s.r0.max(s.r1))
    }

    /// True when the segment is modelled by its link (see the module docs).
    pub fn is_straight(&self) -> bool {
        self.chord_defect() <= self.straight_tolerance()
    }
}

impl Scene {
    /// The link chains (see the module docs): every link except the zero-length links of
    /// isolated nodes belongs to exactly one chain. Open chains run from a node without
    /// exactly two links to the next such node; the remaining links form closed loops.
    pub fn chains(&self) -> Vec<Chain> {
        let n = self.nodes.len();
        let mut adj: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
        for (k, [a, b]) in self.links.iter().enumerate() {
            if a != b {
                adj[a as usize].push((k as u32, b));
                adj[b as usize].push((k as u32, a));
            }
        }
        let mut seen = vec![false; self.links.len()];
        let walk = |seen: &mut Vec<bool>, s: u32, first: (u32, u32)| {
            let (mut l, mut nxt) = first;
            let mut c = Chain { nodes: vec![s], links: Vec::new(), closed: false };
            loop {
                seen[l as usize] = true;
                c.links.push(l);
                c.nodes.push(nxt);
                let a = &adj[nxt as usize];
                if a.len() != 2 {
                    break;
                }
                let next = if a[0].0 == l { a[1] } else { a[0] };
                if seen[next.0 as usize] {
                    break;
                }
                (l, nxt) = next;
            }
            c
        };
        let mut out = Vec::new();
        for (s, es) in adj.iter().enumerate() {
            if es.len() == 2 {
                continue;
            }
            for &e in es {
                if !seen[e.0 as usize] {
                    out.push(walk(&mut seen, s as u32, e));
                }
            }
        }
        for k in 0..self.links.len() {
            let [a, b] = self.links.get(k);
            if a != b && !seen[k] {
                // Every node here has two links: a loop.
                let mut c = walk(&mut seen, a, (k as u32, b));
                c.closed = c.nodes.first() == c.nodes.last();
                out.push(c);
            }
        }
        out
    }

    /// The cubic Hermite segment of every chain link (see the module docs for the
    /// derivatives), in chain order.
    pub fn spline_segments(&self) -> Vec<SplineSegment> {
        let mut out = Vec::with_capacity(self.links.len());
        for c in self.chains() {
            let nn = c.links.len(); // segments; nodes 0..=nn
            let p = |i: usize| V3::from(self.nodes[c.nodes[i] as usize].pos);
            let r = |i: usize| self.radius(c.nodes[i] as usize);
            // Central differences in the interior (wrapping around a closed chain, whose node
            // nn is node 0), one-sided at the ends of an open chain.
            let deriv = |i: usize| {
                let (a, b) =
                    if c.closed { ((i + nn - 1) % nn, (i + 1) % nn) } else { (i.saturating_sub(1), (i + 1).min(nn)) };
                let w = if c.closed { 2.0 } else { (b - a) as f64 };
                let m = (p(b) - p(a)) * (1.0 / w);
                let lim = 2.0 * r(i);
                (m, ((r(b) - r(a)) / w).clamp(-lim, lim))
            };
            let d: Vec<(V3<f64>, f64)> = (0..=nn).map(deriv).collect();
            for j in 0..nn {
                let seg = HermiteSegment::new(p(j), d[j].0, r(j), d[j].1, p(j + 1), d[j + 1].0, r(j + 1), d[j + 1].1);
                out.push(SplineSegment { link: c.links[j], seg });
            }
        }
        out
    }

    /// How faithful the spline models are to the cubic Hermite segments, over the curved
    /// segments (straight ones are their links, exactly): the greatest certified distance
    /// ([`HermiteSegment::pair_distance`]) of Russig's pair ([`Self::pair_spline_primitives`]),
    /// absolute and over the segment's least node radius, and the number of pieces the
    /// faithful split ([`Self::spline_primitives`], [`SPLINE_TOLERANCE`]) needs and the
    /// greatest relative distance it reaches. `info --splines` reports it.
    pub fn spline_fidelity(&self) -> SplineFidelity {
        let mut f = SplineFidelity::default();
        for s in self.spline_segments() {
            if s.is_straight() {
                continue;
            }
            let d = s.seg.pair_distance();
            f.pair_distance = f.pair_distance.max(d);
            f.pair_relative = f.pair_relative.max(d / s.seg.r0.min(s.seg.r1));
            if let Ok(split) = s.seg.split_adaptive(SPLINE_TOLERANCE, SPLINE_MAX_DEPTH) {
                f.faithful_relative = f.faithful_relative.max(split.relative);
                f.faithful_pieces += split.quads.len();
            }
            f.segments += 1;
        }
        f
    }

    /// The same as [`Self::spline_primitives`] (the faithful split is the default; this name is
    /// kept for callers that use it).
    pub fn faithful_spline_primitives(&self) -> Result<Vec<Prim>, SceneError> {
        self.spline_primitives()
    }

    /// Primitives of the spline model (see the module docs), what the renderer, `intersect
    /// --splines` and the reports trace: every curved chain link split adaptively
    /// ([`HermiteSegment::split_adaptive`]) into [`super::PrimKind::Spline`] pieces until the
    /// certified distance to the cubic's sweep is within [`SPLINE_TOLERANCE`] of the local
    /// radius (or [`SPLINE_MAX_DEPTH`] halvings; [`Self::spline_fidelity`] reports what is
    /// reached), the link's own primitive for straight ones and for isolated nodes. Errors (a
    /// guard; see [`Prim::from_quad`]) when a segment cannot be stored as an `f32` spline
    /// primitive.
    pub fn spline_primitives(&self) -> Result<Vec<Prim>, SceneError> {
        self.spline_primitives_with(true)
    }

    /// [`Self::spline_primitives`], optionally keeping straight segments as splines too
    /// (`straight_as_links = false`; for comparing the two models on the same surface).
    pub fn spline_primitives_with(&self, straight_as_links: bool) -> Result<Vec<Prim>, SceneError> {
        self.spline_primitives_impl(straight_as_links, true)
    }

    /// The old model: Russig's C¹ pair of quadratics per curved link ([`HermiteSegment::split`]),
    /// not faithful to the cubic ([`Self::spline_fidelity`] says by how much); for comparisons.
    pub fn pair_spline_primitives(&self) -> Result<Vec<Prim>, SceneError> {
        self.spline_primitives_impl(true, false)
    }

    fn spline_primitives_impl(&self, straight_as_links: bool, faithful: bool) -> Result<Vec<Prim>, SceneError> {
        let mut done = vec![false; self.links.len()];
        let mut out = Vec::with_capacity(2 * self.links.len());
        for s in self.spline_segments() {
            done[s.link as usize] = true;
            if straight_as_links && s.is_straight() {
                out.push(Prim::from_link(&self.link(s.link as usize), s.link));
                continue;
            }
            let [a, b] = self.links.get(s.link as usize);
            let err = |cause| SceneError::Spline { link: s.link, nodes: [a, b], cause };
            let quads = if faithful {
                s.seg.split_adaptive(SPLINE_TOLERANCE, SPLINE_MAX_DEPTH).map_err(err)?.quads
            } else {
                s.seg.split().map_err(err)?.to_vec()
            };
            for (k, q) in quads.iter().enumerate() {
                out.push(Prim::from_quad(q, s.link, k as u8).map_err(err)?);
            }
        }
        for (k, d) in done.iter().enumerate() {
            if !d {
                out.push(Prim::from_link(&self.link(k), k as u32));
            }
        }
        Ok(out)
    }
}
