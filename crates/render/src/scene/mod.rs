//! Owned scene data built from user input: nodes, links, optional spline tangents, and the
//! renderer's primitives ("model no more than a scene needs").
//!
//! A [`Scene`] is a set of nodes `(position, radius, type)` and links `(node a, node b)`.
//! [`Scene::primitives`] turns each link into the cheapest exact primitive: a **cylinder**
//! link when the radii are equal, a **tangent-cone** link when they differ, or a **sphere**
//! when one end sphere contains the other ([`RoundCone::shape`]). Primitives are stored in
//! `f32` relative to a local origin in `f64` (the link's midpoint), so a scene far from the
//! world origin keeps the precision of a scene at the origin ([`Prim`]).
//!
//! # Spline tubes ([`Scene::spline_primitives`])
//! The polyline is modelled as a C¹ cubic Hermite spline tube, positions and radii alike:
//!
//! * **Chains.** The links are split into *chains*: maximal paths whose interior nodes have
//!   exactly two links ([`Scene::chains`]). A bifurcation (a node with three or more links)
//!   or an end ends every chain through it, so each branch is its own spline and the branches
//!   meet in the node's sphere, which every one of them contains (each spline passes through
//!   the node with the node's radius); the tube is C¹ along each chain and only connected
//!   (like the link model) at bifurcations. A closed loop of two-link nodes is one periodic
//!   chain.
//! * **Derivatives** at chain node `i` (per unit of the segment parameter, each segment's
//!   parameter running over `[0, 1]`): uniform Catmull–Rom, i.e. central differences
//!   `mᵢ = (pᵢ₊₁ − pᵢ₋₁)/2`, `r'ᵢ = (rᵢ₊₁ − rᵢ₋₁)/2` in the interior (wrapping around on a
//!   closed chain) and one-sided differences `m₀ = p₁ − p₀`, `m_N = p_N − p_{N−1}` (likewise
//!   `r'`) at the chain ends. Both segments at a node use the same derivatives, so the tube is
//!   C¹ in the chain parameter. Radius derivatives are then limited to `|r'ᵢ| ≤ 2rᵢ`: every
//!   control radius of the split (below) is then `≥ rᵢ/3 ≥ 0`, so no sub-segment gets a
//!   negative or identically zero radius (a tapering tip stays a tip). Uniform Catmull–Rom
//!   assumes roughly even node spacing (streamlines and most reconstructions): very uneven
//!   spacing can overshoot, as any interpolating cubic does.
//! * **Split.** Each segment is split by [`HermiteSegment::split`] into two quadratic
//!   sphere-swept sub-segments ([`QuadTube`]), each one [`Prim`] of kind
//!   [`PrimKind::Spline`], stored in `f32` relative to its midpoint like the links.
//! * **Straight runs stay links** ("model no more than a scene needs"): a segment whose
//!   five control points `(bₖ, ρₖ)` lie on the chord with the link's affine radius — defect
//!   `Dₖ = dist(bₖ, chord line) + |ρₖ − r(sₖ)|` with the projection parameter `sₖ ∈ [0, 1]`
//!   — within `max Dₖ ≤ 2⁻²²·(½|p₁ − p₀| + max(r₀, r₁))` is modelled by its link. Why that is
//!   safe: `D` is convex in `(x, ρ)` and the sweep's `(p(t), r(t))` are convex combinations of
//!   the controls, so every sphere of the spline is within `max Dₖ` of a sphere of the link
//!   and vice versa (Hausdorff distance ≤ `max Dₖ`); the threshold is 4× the rounding of
//!   storing the primitive in `f32` relative to its midpoint, so the two models are
//!   indistinguishable at storage precision. In practice this keeps exactly straight,
//!   evenly sampled runs (and single-link chains, whose one-sided derivatives are the chord)
//!   as links.

pub mod generate;
mod prim;

pub use prim::{Prim, PrimKind};

use crate::io::{self, IoError, Polyline};
use std::fmt;
use std::path::Path;
use tubecast::HermiteSegment;
#[allow(unused_imports)] // documentation links
use tubecast::QuadTube;
use tubecast::RoundCone;
use tubecast::{LinkShape, Primitive, V3};

/// Largest coordinate or radius magnitude a scene may hold: squares of lengths must stay
/// finite in `f32` (`(2·1e18)² ≈ 4e36 < 3.4e38`), since primitives are stored in `f32`.
pub const MAX_COORD: f64 = 1e18;

/// One node of a tube.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Position.
    pub pos: [f64; 3],
    /// Radius (≥ 0).
    pub radius: f64,
    /// SWC structure type (0 when the input has none).
    pub kind: i32,
}

/// Nodes and links.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Nodes.
    pub nodes: Vec<Node>,
    /// Links as node index pairs. A node that no link uses is stored as the zero-length link
    /// `[i, i]` (a sphere), so every primitive has a link index.
    pub links: Vec<[u32; 2]>,
}

/// Why a scene could not be built or loaded.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// A reader failed.
    Io(IoError),
    /// The input holds geometry that cannot be modelled.
    Geometry(String),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => e.fmt(f),
            Self::Geometry(s) => f.write_str(s),
        }
    }
}
impl std::error::Error for SceneError {}
impl From<IoError> for SceneError {
    fn from(e: IoError) -> Self {
        Self::Io(e)
    }
}

/// Counts and extents of a scene's primitives (what `tubecast info` prints).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Nodes.
    pub nodes: usize,
    /// Links (including zero-length links of isolated nodes).
    pub links: usize,
    /// Cylinder links (equal radii).
    pub cylinders: usize,
    /// Tangent-cone links (different radii).
    pub cones: usize,
    /// Links that are a sphere (one end inside the other, or an isolated node).
    pub spheres: usize,
    /// Spline segments: cubic Hermite segments, each two [`PrimKind::Spline`] primitives
    /// (zero for the link model, [`Scene::stats`]).
    pub splines: usize,
    /// Axis-aligned bounds of the surface `(min, max)`.
    pub bounds: ([f64; 3], [f64; 3]),
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
        if !(len2 > 0.0) {
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
    /// A scene from SWC rows (links child → parent; ids mapped to indices).
    pub fn from_swc(rows: &[io::swc::SwcNode], name: &str) -> Result<Self, SceneError> {
        let mut index = std::collections::HashMap::new();
        for (i, r) in rows.iter().enumerate() {
            index.insert(r.id, i as u32);
        }
        let nodes = rows.iter().map(|r| Node { pos: r.pos, radius: r.radius, kind: r.kind }).collect();
        let mut links = Vec::new();
        for (i, r) in rows.iter().enumerate() {
            if r.parent >= 0 {
                let p = *index.get(&r.parent).ok_or_else(|| {
                    SceneError::Geometry(format!("{name}: parent {} of node {} does not exist", r.parent, r.id))
                })?;
                links.push([p, i as u32]);
            }
        }
        Self::finish(nodes, links, name)
    }

    /// A scene from polylines; points without a radius get `default_radius`.
    pub fn from_polylines(lines: &[Polyline], default_radius: f64, name: &str) -> Result<Self, SceneError> {
        if !(default_radius.is_finite() && default_radius > 0.0) {
            return Err(SceneError::Geometry(format!("radius {default_radius} must be a positive number")));
        }
        let mut nodes = Vec::new();
        let mut links = Vec::new();
        for l in lines {
            let base = nodes.len() as u32;
            for (k, p) in l.points.iter().enumerate() {
                let radius = l.radii.get(k).copied().unwrap_or(default_radius);
                nodes.push(Node { pos: *p, radius, kind: 0 });
                if k > 0 {
                    links.push([base + k as u32 - 1, base + k as u32]);
                }
            }
        }
        Self::finish(nodes, links, name)
    }

    fn finish(nodes: Vec<Node>, mut links: Vec<[u32; 2]>, name: &str) -> Result<Self, SceneError> {
        if nodes.is_empty() {
            return Err(SceneError::Geometry(format!("{name}: no nodes")));
        }
        if nodes.len() > u32::MAX as usize - 1 {
            return Err(SceneError::Geometry(format!("{name}: too many nodes")));
        }
        for (i, n) in nodes.iter().enumerate() {
            if n.pos.iter().chain([&n.radius]).any(|v| !v.is_finite() || v.abs() > MAX_COORD) {
                return Err(SceneError::Geometry(format!(
                    "{name}: node {i} has a coordinate or radius that is not finite or exceeds {MAX_COORD:e}"
                )));
            }
            if n.radius < 0.0 {
                return Err(SceneError::Geometry(format!("{name}: node {i} has negative radius {}", n.radius)));
            }
        }
        let mut used = vec![false; nodes.len()];
        for l in &links {
            used[l[0] as usize] = true;
            used[l[1] as usize] = true;
        }
        for (i, u) in used.iter().enumerate() {
            if !u {
                links.push([i as u32, i as u32]);
            }
        }
        let s = Self { nodes, links };
        for (k, l) in s.links.iter().enumerate() {
            if s.nodes[l[0] as usize].radius == 0.0 && s.nodes[l[1] as usize].radius == 0.0 {
                return Err(SceneError::Geometry(format!(
                    "{name}: link {k} (nodes {} and {}) has zero radius at both ends, so no volume",
                    l[0], l[1]
                )));
            }
        }
        Ok(s)
    }

    /// Load a scene from a file, by extension: `.swc`, `.trk`, `.tck`, `.obj`. Formats without
    /// radii (and OBJ vertices without one) use `default_radius`.
    pub fn load(path: &Path, default_radius: f64) -> Result<Self, SceneError> {
        let name = path.display().to_string();
        let data = io::read_bytes(path)?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "swc" => Self::from_swc(&io::swc::read(&data, &name)?, &name),
            "trk" => Self::from_polylines(&io::trk::read(&data, &name)?.1, default_radius, &name),
            "tck" => Self::from_polylines(&io::tck::read(&data, &name)?, default_radius, &name),
            "obj" => Self::from_polylines(&io::obj::read(&data, &name)?, default_radius, &name),
            _ => Err(SceneError::Io(IoError::file(
                &name,
                format!("unknown extension {ext:?} (expected .swc, .trk, .tck or .obj)"),
            ))),
        }
    }

    /// Link `k` as a validated `f64` round cone.
    pub fn link(&self, k: usize) -> RoundCone<f64> {
        let [a, b] = self.links[k];
        let (a, b) = (&self.nodes[a as usize], &self.nodes[b as usize]);
        RoundCone::new(V3::from(a.pos), a.radius, V3::from(b.pos), b.radius)
            .expect("scene links are validated when the scene is built")
    }

    /// One primitive per link, each the cheapest exact shape (see the module docs).
    pub fn primitives(&self) -> Vec<Prim> {
        (0..self.links.len()).map(|k| Prim::from_link(&self.link(k), k as u32)).collect()
    }

    /// The link chains (see the module docs): every link except the zero-length links of
    /// isolated nodes belongs to exactly one chain. Open chains run from a node without
    /// exactly two links to the next such node; the remaining links form closed loops.
    pub fn chains(&self) -> Vec<Chain> {
        let n = self.nodes.len();
        let mut adj: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
        for (k, &[a, b]) in self.links.iter().enumerate() {
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
            let [a, b] = self.links[k];
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
            let r = |i: usize| self.nodes[c.nodes[i] as usize].radius;
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

    /// Primitives of the spline model (see the module docs): two [`PrimKind::Spline`]
    /// sub-segments per curved chain link, the link's own primitive for straight ones and for
    /// isolated nodes. Errors (a guard; see [`Prim::from_quad`]) when a segment cannot be stored
    /// as an `f32` spline primitive.
    pub fn spline_primitives(&self) -> Result<Vec<Prim>, SceneError> {
        self.spline_primitives_with(true)
    }

    /// [`Self::spline_primitives`], optionally keeping straight segments as splines too
    /// (`straight_as_links = false`; for comparing the two models on the same surface).
    pub fn spline_primitives_with(&self, straight_as_links: bool) -> Result<Vec<Prim>, SceneError> {
        let mut done = vec![false; self.links.len()];
        let mut out = Vec::with_capacity(2 * self.links.len());
        for s in self.spline_segments() {
            done[s.link as usize] = true;
            if straight_as_links && s.is_straight() {
                out.push(Prim::from_link(&self.link(s.link as usize), s.link));
                continue;
            }
            let [a, b] = self.links[s.link as usize];
            let err = |e: tubecast::GeometryError| {
                SceneError::Geometry(format!("link {} (nodes {a} and {b}): cannot model it as a spline: {e}", s.link))
            };
            let [q0, q1] = s.seg.split().map_err(err)?;
            out.push(Prim::from_quad(&q0, s.link, 0).map_err(err)?);
            out.push(Prim::from_quad(&q1, s.link, 1).map_err(err)?);
        }
        for (k, d) in done.iter().enumerate() {
            if !d {
                out.push(Prim::from_link(&self.link(k), k as u32));
            }
        }
        Ok(out)
    }

    /// Counts and bounds of a primitive list built from this scene ([`Self::primitives`] or
    /// [`Self::spline_primitives`]): link primitives by kind, spline segments (pairs of
    /// sub-segments), and the union of the primitives' boxes.
    pub fn stats_of(&self, prims: &[Prim]) -> Stats {
        let mut s = Stats { nodes: self.nodes.len(), links: self.links.len(), ..Default::default() };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in prims {
            match p.kind {
                PrimKind::Cylinder => s.cylinders += 1,
                PrimKind::Cone => s.cones += 1,
                PrimKind::Sphere => s.spheres += 1,
                PrimKind::Spline => s.splines += (p.half == 0) as usize,
            }
            let (a, b) = p.aabb();
            for i in 0..3 {
                lo[i] = lo[i].min(a[i]);
                hi[i] = hi[i].max(b[i]);
            }
        }
        s.bounds = (lo, hi);
        s
    }

    /// Counts and bounds.
    pub fn stats(&self) -> Stats {
        let mut s = Stats { nodes: self.nodes.len(), links: self.links.len(), ..Default::default() };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for k in 0..self.links.len() {
            let l = self.link(k);
            match l.shape() {
                LinkShape::Cylinder => s.cylinders += 1,
                LinkShape::Cone => s.cones += 1,
                LinkShape::Sphere => s.spheres += 1,
            }
            let bx = l.aabb();
            for (i, (x, y)) in bx.min.to_array().iter().zip(bx.max.to_array()).enumerate() {
                lo[i] = lo[i].min(*x);
                hi[i] = hi[i].max(y);
            }
        }
        s.bounds = (lo, hi);
        s
    }

    /// Unit direction of link `k` (zero for a zero-length link).
    pub fn link_direction(&self, k: usize) -> [f64; 3] {
        let [a, b] = self.links[k];
        let v = V3::from(self.nodes[b as usize].pos) - V3::from(self.nodes[a as usize].pos);
        v.normalize_or_zero().to_array()
    }
}
