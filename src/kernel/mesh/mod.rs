//! Certified tessellation: links, chains of links and quadratic spline tubes to closed,
//! consistently oriented triangle meshes whose two-sided Hausdorff distance to the exact
//! sphere sweep is at most a tolerance ε (derivation in `budget.rs`, construction in
//! `rings.rs`).
//!
//! A chain is one closed surface of revolution-like rings: a spherical cap at each end, the
//! tangent circles of every link's cone, and rings over each interior node sphere turning
//! from one link to the next (the joint). A chain is split into several closed components that
//! share a node sphere where a joint would fold deeper than its share of ε, where a link is
//! degenerate (one ball inside the other: that ball is meshed on its own) or where an
//! interior radius is zero. Bifurcations are handled the same way by the caller: each branch
//! is its own chain, and every chain through a node caps itself on that node's sphere, so the
//! union of the closed components has no crack there.

mod budget;
mod rings;
mod spline;

pub use budget::MAX_RING;

use self::budget::{budget, reached};
use self::rings::{ball, fold, tube, Piece};
use crate::error::GeometryError;
use crate::kernel::link::RoundCone;
use crate::kernel::spline::QuadTube;
use crate::real::Scalar;
use crate::vec::V3;

/// A triangle mesh in `f64`: closed components, outward-oriented (counter-clockwise seen
/// from outside), with the certified two-sided Hausdorff distance to the solid it stands for.
///
/// ```
/// use tubecast::{tessellate_link, RoundCone, V3};
/// let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let mesh = tessellate_link(&link, 1e-2)?;
/// assert!(mesh.certified <= 1e-2);
/// assert_eq!(mesh.triangles.len(), 2 * mesh.positions.len() - 4); // closed, genus 0
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<V3<f64>>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: the index of the input link it belongs to (of the chain's links; of the
    /// spline's segments), for colouring and picking. [`Mesh::append`] keeps them as they are.
    pub tags: Vec<u32>,
    /// The closed components and the input nodes each stands for (see [`Part`]).
    pub parts: Vec<Part>,
    /// Certified bound on the two-sided Hausdorff distance between the mesh and the exact
    /// surface (the sum of the terms the construction reached; ≤ the tolerance asked for, up
    /// to the rounding of the vertex coordinates).
    pub certified: f64,
}

/// One closed component of a [`Mesh`]: its triangles and the input nodes (of a chain; of
/// the samples, for a spline) whose links' union it stands for, within the mesh's bound. The
/// mesh stands for the union of its parts; where parts overlap (at a split joint or a
/// bifurcation) each part's surface inside another part is interior to the union, and the
/// union of the parts' solids is within the bound of the union of the exact solids (the
/// Hausdorff distance of unions is at most the largest of the parts').
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Range of [`Mesh::triangles`].
    pub triangles: core::ops::Range<usize>,
    /// First and last node (a single node: a ball).
    pub nodes: core::ops::RangeInclusive<usize>,
}

impl Mesh {
    /// The three corners of triangle `k`.
    pub fn corners(&self, k: usize) -> [V3<f64>; 3] {
        self.triangles[k].map(|i| self.positions[i as usize])
    }
    /// Appends another mesh (indices shifted); the bound becomes the larger of the two.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        let t0 = self.triangles.len();
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
        let shift = |p: &Part| Part { triangles: p.triangles.start + t0..p.triangles.end + t0, nodes: p.nodes.clone() };
        self.parts.extend(other.parts.iter().map(shift));
        self.tags.extend_from_slice(&other.tags);
        self.certified = self.certified.max(other.certified);
    }
    /// Bytes held by the vertex and index arrays.
    pub fn memory_bytes(&self) -> usize {
        self.positions.len() * core::mem::size_of::<V3<f64>>() + self.triangles.len() * 12
    }
}

/// Meshes one link (round cone) within `eps` of its surface, both ways.
///
/// Errors: a tolerance that is not finite and positive, or so small that a ring would need
/// more than [`MAX_RING`] vertices.
///
/// ```
/// use tubecast::{tessellate_link, RoundCone, V3};
/// let tip = RoundCone::new(V3::new(0.0, 0.0, 0.0), 0.0, V3::new(0.0, 0.0, 3.0), 1.0)?;
/// assert!(tessellate_link(&tip, 1e-3)?.certified <= 1e-3);
/// assert!(tessellate_link(&tip, 0.0).is_err());
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
pub fn tessellate_link<T: Scalar>(link: &RoundCone<T>, eps: T) -> Result<Mesh, GeometryError> {
    tessellate_chain(&[(link.a, link.ra), (link.b, link.rb)], eps)
}

/// Meshes the union of the links between consecutive nodes `(centre, radius)` (the sphere
/// sweep of the polyline with linearly interpolated radius) within `eps`, both ways.
///
/// Errors: as [`RoundCone::new`] for each link (non-finite data, negative radii, both radii of
/// a link zero), and as [`tessellate_link`] for the tolerance. An empty slice gives an empty
/// mesh; a single node a sphere.
///
/// ```
/// use tubecast::{tessellate_chain, V3};
/// let v = |x: f64, y: f64| V3::new(x, y, 0.0);
/// let chain = [(v(0.0, 0.0), 0.5), (v(3.0, 0.0), 0.4), (v(5.0, 2.0), 0.3)];
/// let mesh = tessellate_chain(&chain, 1e-3)?;
/// assert!(mesh.certified <= 1e-3 && !mesh.triangles.is_empty());
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
pub fn tessellate_chain<T: Scalar>(nodes: &[(V3<T>, T)], eps: T) -> Result<Mesh, GeometryError> {
    let terms = if nodes.len() > 2 { 3 } else { 2 };
    tessellate_nodes(&validate(nodes)?, eps.to_f64(), 0.0, terms, true)
}

/// [`tessellate_chain`] for renderers: joints are never split for their fold, so a bent chain
/// stays one closed surface (far fewer triangles than split parts with their caps). The
/// surface folds into itself on the inner side of bends. Derived in `budget.rs` (*Joint
/// sweep*, *Solid meshes*), in 3-D: every triangle lies inside the exact solid (its corners are
/// on one ball or one link's round cone), whatever the fold, so a ray never meets the mesh
/// before the exact surface; and every point of the exact surface is within the certified
/// bound (ring and arc terms, ε/2 each; joints spaced to stay within them) of the mesh. Not
/// derived: that a ray cannot slip past the mesh into a fold's pocket deeper than the bound
/// (checked by ray tests, `crates/render/tests/accel/mesh_tracer.rs`). Joints still split where a
/// cone would not emerge from the fold (see `budget.rs`) and at zero radii.
///
/// ```
/// use tubecast::{tessellate_chain, tessellate_chain_solid, V3};
/// let v = |x: f64, y: f64| V3::new(x, y, 0.0);
/// let chain = [(v(0.0, 0.0), 0.5), (v(3.0, 0.0), 0.5), (v(5.0, 2.0), 0.5)];
/// let (surface, solid) = (tessellate_chain(&chain, 1e-3)?, tessellate_chain_solid(&chain, 1e-3)?);
/// assert!(solid.parts.len() == 1 && surface.parts.len() == 2); // the 45° joint splits for its fold
/// assert!(solid.triangles.len() < surface.triangles.len());
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
pub fn tessellate_chain_solid<T: Scalar>(nodes: &[(V3<T>, T)], eps: T) -> Result<Mesh, GeometryError> {
    tessellate_nodes(&validate(nodes)?, eps.to_f64(), 0.0, 2, false)
}

/// Meshes a chain of quadratic sphere-swept segments ([`QuadTube`]; consecutive segments
/// should share their end spheres, as [`crate::HermiteSegment::split`] gives) within `eps`,
/// both ways: each segment is sampled at `t` steps `h` with
/// `h²/4·(|b₀ − 2b₁ + b₂| + |r₀ − 2r₁ + r₂|) ≤ ε/4` and the samples are meshed as a chain.
///
/// ```
/// use tubecast::{tessellate_spline, HermiteSegment, V3};
/// let (p0, p1) = (V3::new(0.0, 0.0, 0.0), V3::new(4.0, 0.0, 0.0));
/// let seg = HermiteSegment::new(p0, V3::new(2.0, 4.0, 0.0), 0.5, 0.0, p1, V3::new(2.0, -4.0, 0.0), 0.3, 0.0);
/// let mesh = tessellate_spline(&seg.split()?, 1e-2)?;
/// assert!(mesh.certified <= 1e-2);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
pub fn tessellate_spline<T: Scalar>(tubes: &[QuadTube<T>], eps: T) -> Result<Mesh, GeometryError> {
    let eps = eps.to_f64();
    check_eps(eps)?;
    let tubes: Vec<QuadTube<f64>> =
        tubes.iter().map(|q| QuadTube { b: q.b.map(|p| p.cast()), r: q.r.map(|x| x.to_f64()) }).collect();
    let mut mesh = Mesh::default();
    // Runs of tubes that share their end spheres are one chain each.
    let mut start = 0;
    for k in 1..=tubes.len() {
        if k == tubes.len() || (tubes[k - 1].b[2], tubes[k - 1].r[2]) != (tubes[k].b[0], tubes[k].r[0]) {
            let sm = spline::samples(&tubes[start..k], eps)?;
            let mut run = tessellate_nodes(&sm.nodes, eps, sm.axial, 4, true)?;
            run.tags.iter_mut().for_each(|t| *t = start as u32 + sm.owner[*t as usize]);
            mesh.append(&run);
            start = k;
        }
    }
    Ok(mesh)
}

fn check_eps(eps: f64) -> Result<(), GeometryError> {
    budget(1.0, eps, 1).map(|_| ())
}

/// Validated nodes in `f64` (each link through [`RoundCone::new`]).
fn validate<T: Scalar>(nodes: &[(V3<T>, T)]) -> Result<Vec<(V3<f64>, f64)>, GeometryError> {
    for w in nodes.windows(2) {
        RoundCone::new(w[0].0, w[0].1, w[1].0, w[1].1)?;
    }
    if let [(c, r)] = nodes {
        RoundCone::new(*c, *r, *c, *r)?;
    }
    Ok(nodes.iter().map(|(c, r)| (c.cast::<f64>(), r.to_f64())).collect())
}

/// Splits the chain into runs (see the module docs) and meshes each; the certified bound is
/// the budget's ring and arc terms, the deepest fold kept, and the axial term.
/// With `folds = false` a fold never splits a joint and is not counted (the enclosed-region
/// bound of [`tessellate_chain_solid`]).
fn tessellate_nodes(
    nodes: &[(V3<f64>, f64)],
    eps: f64,
    axial: f64,
    terms: u32,
    folds: bool,
) -> Result<Mesh, GeometryError> {
    let mut mesh = Mesh::default();
    let Some(&(origin, _)) = nodes.first() else {
        check_eps(eps)?;
        return Ok(mesh);
    };
    let r_max = nodes.iter().fold(0.0f64, |m, n| m.max(n.1));
    let b = budget(r_max, eps, terms)?;
    let rel: Vec<(V3<f64>, f64)> = nodes.iter().map(|&(c, r)| (c - origin, r)).collect();
    let mut folded: f64 = 0.0;
    let (ring_arc, mut joints) = (reached(&b, r_max), 0.0f64);
    let mut covered = vec![false; rel.len()];
    let mut start = 0;
    let mut pieces: Vec<Piece> = Vec::new();
    for k in 0..rel.len() {
        let piece = (k + 1 < rel.len()).then(|| Piece::new(rel[k], rel[k + 1])).flatten();
        let split = match (pieces.last(), piece) {
            (Some(prev), Some(next)) => match fold(prev, &next, rel[k].1) {
                Some(depth) if depth <= b.fold || !folds => {
                    folded = folded.max(if folds { depth } else { 0.0 });
                    false
                }
                _ => true,
            },
            _ => false,
        };
        if split || piece.is_none() {
            if !pieces.is_empty() {
                let t0 = mesh.triangles.len();
                joints = joints.max(tube(&mut mesh, &rel[start..=k], &pieces, &b, origin, start as u32, ring_arc));
                mesh.parts.push(Part { triangles: t0..mesh.triangles.len(), nodes: start..=k });
                covered[start..=k].iter_mut().for_each(|c| *c = true);
            }
            pieces.clear();
            start = if split { k } else { k + 1 };
        }
        if let Some(p) = piece {
            pieces.push(p);
        }
    }
    for (k, &(c, r)) in rel.iter().enumerate() {
        // A ball inside a neighbour's ball adds nothing (ties go to the earlier node).
        let inside = |j: usize| (rel[j].0 - c).length() + r <= rel[j].1 && (j < k || r < rel[j].1);
        let swallowed = (k > 0 && inside(k - 1)) || (k + 1 < rel.len() && inside(k + 1));
        if !covered[k] && r > 0.0 && !swallowed {
            let t0 = mesh.triangles.len();
            ball(&mut mesh, (c, r), &b, origin, k.min(rel.len().saturating_sub(2)) as u32);
            mesh.parts.push(Part { triangles: t0..mesh.triangles.len(), nodes: k..=k });
        }
    }
    // A joint's triangles are within its joint term; every other point within ring + arc.
    mesh.certified = ring_arc.max(joints) + folded + axial;
    Ok(mesh)
}
