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
pub(crate) use prim::{link_interval, local_origin, stored_as_sphere, Best, PendingHit};
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

/// Smallest non-zero radius a scene may hold, `2⁻⁴⁴ ≈ 5.7·10⁻¹⁴`: the counterpart of
/// [`MAX_COORD`] at small scales. Radius 0 stays allowed at one end of a link (a pointed tip;
/// both ends 0 is [`SceneError::NoVolume`]).
///
/// **Why a limit** (fuzz finding `regression-underflow-touch`): the renderer stores its
/// primitives in `f32` ([`Prim`]), and the `f32` sphere kernel decides hit or miss by
/// `disc = r² − |l|²` (`l`: the centre's perpendicular to the line). A sphere of radius
/// `5.8·10⁻³¹` missed by `4.8·10⁻²⁷` squares both to 0 (`f32`'s smallest subnormal is
/// `2⁻¹⁴⁹ ≈ 1.4·10⁻⁴⁵`), so `disc = 0` and it reported a touch 8,000 radii away. The kernels'
/// own constructors ([`tubecast::Sphere::new`], [`RoundCone::new`]) refuse a non-zero `f32`
/// radius below `2⁻⁵¹·⁵` (square below `MIN_POSITIVE/EPS = 2⁻¹⁰³`); the renderer's primitives
/// do not go through them, so the scene applies a limit itself, and a stricter one (below).
/// A radius `r ≥ 2⁻⁴⁴` in `f64` stays `≥ 2⁻⁴⁴` when rounded to `f32` (rounding is monotone and
/// `2⁻⁴⁴` is an `f32`).
///
/// **Radii** (`u = 2⁻²⁴`, `f32`'s unit roundoff): every `f32` product or sum errs by `≤ u·|x|`
/// where the result is normal and by `≤ 2⁻¹⁵⁰` (half the subnormal spacing, gradual underflow)
/// where it is subnormal; with `r ≥ 2⁻⁴⁴`, `2⁻¹⁵⁰ ≤ 2⁻⁶²·r²`. So the computed
/// `disc = r²(1 + δ₀) − |l|²(1 + δ₁) + η` with `|δ₀| ≤ u`, `|δ₁| ≤ 3u` (three squares, two
/// sums) and `|η| ≤ 4·2⁻¹⁵⁰ ≤ 2⁻⁶⁰·r²` (squares of components below `2⁻⁶³`), for **every**
/// `|l|`, subnormal `|l|²` included (there `|l| < 2⁻⁶³ < r` and `disc > 0`: a hit, which is
/// right); `l`'s components err by `≤ u·|l| + 2⁻¹⁵⁰`, and the final subtraction keeps the sign.
/// So the sign is the exact one unless `|r² − |l|²| ≤ u·r² + 3u·|l|² + 2⁻⁶⁰r²`: for `|l| ≥ 2r`
/// never (`r² − |l|² ≤ −3r²`), otherwise only where `||l| − r| ≤ (13u + 2⁻⁶⁰)·r`, a line
/// within `≈ 13u·r` of the surface (`≈ 2u·r` where `|l| ≈ r`). Underflow adds `2⁻⁶⁰·r`, nothing
/// against the link kernels' band `E = 64ε·S ≥ 2⁻¹⁷·r` (`ε = 2⁻²³`; the kernel crate's
/// `tests/kernels/link/properties.rs`).
///
/// **Link lengths.** The link kernel normalises its axis by `L = √|b − a|²`, formed in `f32`; for
/// `L < 2⁻⁶³` that square is subnormal, `L` loses up to all its digits, and the stump's sine
/// `(ra − rb)/L` and unit axis go wrong by a share of the radius: measured, hit points up to
/// `1,400·E` off for links `2⁻⁷⁵…2⁻⁷¹` long with radii `2⁻⁵¹…2⁻³⁰` (this crate's
/// `tests/scene/min_radius.rs`). So [`Prim::from_link`] (and the compact tree's clusters) store
/// a link shorter than [`SHORT_LINK`] `= 2⁻⁶²` as its larger end sphere. That is within
/// `L` of the link (the hull lies in `B(a, ra + L)` for `ra ≥ rb`, since `B(b, rb) ⊂ B(a, ra + L)`,
/// and contains `B(a, ra)`), and a short link has a non-zero radius at both ends (one 0 needs
/// `L > ra − 0`), so `r ≥ 2⁻⁴⁴` gives `L < 2⁻⁶² ≤ 2⁻¹⁸·r`: half the band `E`. That is the reason
/// for `2⁻⁴⁴` rather than the kernels' `2⁻⁵¹·⁵`. A link `≥ 2⁻⁶²` long has a normal `f32` squared
/// length (its stored offsets round by `≤ u` relative), accurate to `≈ 4u` like any other.
///
/// `tests/scene/min_radius.rs` checks the `f32` primitives (spheres, cylinders, cones, zero
/// tips, links `2⁻⁹⁰` to `2⁶` of their radius long, far ray origins; per link and the compact
/// tree's) against the `f64` kernels within that band over scenes scaled by `2ᵏ` down to this
/// limit, and shows them leaving it below.
///
/// ```
/// use tubecast::{RoundCone, V3};
/// use tubecast_render::scene::MIN_RADIUS;
/// assert_eq!(MIN_RADIUS, 2f64.powi(-44));
/// // Stricter than the f32 kernels' own rule: that accepts down to 2⁻⁵¹ = MIN_RADIUS/2⁷.
/// let link = |r: f32| RoundCone::new(V3::zero(), r, V3::new(1.0, 0.0, 0.0), r);
/// assert!(link(MIN_RADIUS as f32 / 128.0).is_ok() && link(MIN_RADIUS as f32 / 256.0).is_err());
/// ```
pub const MIN_RADIUS: f64 = 1.0 / (1u64 << 44) as f64;

/// Links shorter than this, `2⁻⁶²`, are stored as their larger end sphere ([`Prim::from_link`]):
/// their `f32` squared length would be subnormal (derivation at [`MIN_RADIUS`]). (Where such a
/// link is not also shorter than `2⁻¹⁸` of its radius — only beyond the scene's radius limit —
/// it is left a link.)
pub const SHORT_LINK: f64 = 1.0 / (1u64 << 62) as f64;

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
    /// Radius (0, or in [`MIN_RADIUS`]…[`MAX_COORD`]) of each node ([`Scene::radius`]), stored
    /// once while they are all equal.
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
