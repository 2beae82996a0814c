//! Owned scene data built from user input: nodes, links, optional spline tangents, and the
//! renderer's primitives ("model no more than a scene needs").
//!
//! A [`Scene`] is a set of nodes `(position, radius, type)` and links `(node a, node b)`.
//! It keeps per link only what it needs: a 24-byte [`Node`] (`f64` position), the radius once
//! while every node has the same one ([`Scene::radii`]), the type only where some node has one
//! ([`Scene::kinds`]), and chains of links as runs ([`Links`]): about 24.4 bytes per link for a
//! tractogram's streamlines of 84 links.
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
//! * **Split.** Each segment is split by [`HermiteSegment::split_adaptive`] into quadratic
//!   sphere-swept pieces ([`QuadTube`]) until the certified distance to the cubic's sweep is
//!   ≤ [`SPLINE_TOLERANCE`] of the local radius ([`Scene::spline_fidelity`]), each one [`Prim`] of kind
//!   [`Shape::Spline`], stored in `f32` relative to its midpoint like the links.
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

mod build;
mod chains;
pub mod choice;
mod error;
pub mod fit;
pub mod generate;
mod links;
mod load;
mod prim;
mod radii;
pub mod simplify;
mod stats;

pub use chains::{Chain, SplineFidelity, SplineSegment, SPLINE_MAX_DEPTH, SPLINE_TOLERANCE};
pub use error::SceneError;
pub use links::{Iter as LinkIter, Links};
pub use load::{LoadOptions, LoadReport};
pub(crate) use prim::{link_interval, local_origin};
pub use prim::{Prim, PrimKind, Shape};
pub use radii::Radii;
pub use stats::Stats;

use tubecast::RoundCone;
use tubecast::V3;
#[allow(unused_imports)] // documentation links
use tubecast::{HermiteSegment, QuadTube};

/// Largest coordinate or radius magnitude a scene may hold: squares of lengths must stay
/// finite in `f32` (`(2·1e18)² ≈ 4e36 < 3.4e38`), since primitives are stored in `f32`.
pub const MAX_COORD: f64 = 1e18;

/// One node of a tube: 24 bytes (its radius is in [`Scene::radii`], its SWC structure type,
/// when it has one, in [`Scene::kinds`]).
///
/// ```
/// use tubecast_render::scene::Node;
/// let n = Node { pos: [1.0, 2.0, 3.0] };
/// assert_eq!(std::mem::size_of::<Node>(), 24); // 3 × 8 (position)
/// assert_eq!(n.pos[2], 3.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Position.
    pub pos: [f64; 3],
}

/// Nodes and links. A scene may be empty (a file without streamlines or nodes): it has no
/// primitives, every ray misses it, and its [`Stats`] are zeros.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Nodes.
    pub nodes: Vec<Node>,
    /// Links as node index pairs ([`Links`]: chains of consecutive nodes stored implicitly).
    /// A node that no link uses is stored as the zero-length link `[i, i]` (a sphere), so
    /// every primitive has a link index.
    pub links: Links,
    /// Radius (≥ 0) of each node ([`Scene::radius`]), stored once while they are all equal.
    pub radii: Radii,
    /// SWC structure type of each node ([`Scene::kind`]), or empty when every node's is 0
    /// (tractography, polylines).
    pub kinds: Vec<i32>,
    /// One data value per node for colouring ([`crate::render::ColorBy::Values`]), or empty;
    /// set by [`Scene::select_values`] from the fields [`Scene::load_fields`] returns.
    pub values: Vec<f64>,
    /// Per-node coverage in `[0, 1]` of tubes widened to a minimum pixel footprint
    /// ([`crate::render::clamp_thin`]); empty when none was.
    pub coverage: Vec<f32>,
}

/// Which model of the tubes a renderer uses ([`Scene::model_primitives`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Model {
    /// One exact primitive per link ([`Scene::primitives`]).
    #[default]
    Links,
    /// C¹ spline tubes along the chains ([`Scene::spline_primitives`]).
    Splines,
}

impl Scene {
    /// Link `k` as a validated `f64` round cone.
    pub fn link(&self, k: usize) -> RoundCone<f64> {
        let [a, b] = self.links.get(k);
        let (a, b) = (a as usize, b as usize);
        let (pa, pb) = (V3::from(self.nodes[a].pos), V3::from(self.nodes[b].pos));
        RoundCone::new(pa, self.radius(a), pb, self.radius(b))
            .expect("scene links are validated when the scene is built")
    }

    /// One primitive per link, each the cheapest exact shape (see the module docs).
    pub fn primitives(&self) -> Vec<Prim> {
        (0..self.links.len()).map(|k| Prim::from_link(&self.link(k), k as u32)).collect()
    }

    /// The primitives of `model`: [`Self::primitives`] or [`Self::spline_primitives`].
    pub fn model_primitives(&self, model: Model) -> Result<Vec<Prim>, SceneError> {
        match model {
            Model::Links => Ok(self.primitives()),
            Model::Splines => self.spline_primitives(),
        }
    }

    /// Bytes held by the nodes, links and per-node data (capacities): 24 per node
    /// ([`Node`]), the links' [`Links::memory_bytes`], 8 per node for [`Self::radii`] where
    /// they differ, 4 per node for [`Self::kinds`], 8 for [`Self::values`] and 4 for
    /// [`Self::coverage`] where they are not empty.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.links.memory_bytes()
            + self.radii.memory_bytes()
            + self.kinds.capacity() * 4
            + self.values.capacity() * 8
            + self.coverage.capacity() * 4
    }

    /// Radius of node `i`.
    #[inline]
    pub fn radius(&self, i: usize) -> f64 {
        self.radii.get(i)
    }

    /// Set the radius of node `i` (the scene then keeps one radius per node if it differs).
    pub fn set_radius(&mut self, i: usize, r: f64) {
        self.radii.set(i, r, self.nodes.len());
    }

    /// SWC structure type of node `i` (0 when the input has none).
    pub fn kind(&self, i: usize) -> i32 {
        self.kinds.get(i).copied().unwrap_or(0)
    }

    /// Unit direction of link `k` (zero for a zero-length link).
    pub fn link_direction(&self, k: usize) -> [f64; 3] {
        let [a, b] = self.links.get(k);
        let v = V3::from(self.nodes[b as usize].pos) - V3::from(self.nodes[a as usize].pos);
        v.normalize_or_zero().to_array()
    }
}
