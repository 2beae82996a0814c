//! The mesh path: a scene tessellated within a certified tolerance ([`tessellate`]: every
//! chain through [`tubecast::tessellate_chain_solid`] (one closed surface per chain; its enclosed region is certified), or through [`tubecast::tessellate_spline`]
//! for the spline model), traced by a triangle BVH ([`MeshTracer`], a [`crate::accel::Tracer`]
//! beside the exact BVH) and written as PLY, OBJ or binary glTF ([`export`]).
//!
//! Bifurcations need nothing special: each chain ends on the node sphere of a bifurcation
//! with a spherical cap, so the branches' closed meshes overlap there and their union has no
//! crack. Those are shells, certified each against its own chain; [`tessellate_union`] meshes
//! the surface of the union itself (one closed surface per component, certified against the
//! union's exact surface; `docs/design/union-mesh.md`), which is what `tubecast mesh` writes.

pub mod export;
mod tracer;
mod union;

pub use tracer::MeshTracer;
pub use union::{
    tessellate_union, tessellate_union_with, Bodies, UnionOptions, UnionReport, UNION_BASE_BYTES,
    UNION_BYTES_PER_BODY_TRIANGLE, UNION_BYTES_PER_HULL_TRIANGLE,
};

use crate::scene::{Model, Scene, SPLINE_MAX_DEPTH, SPLINE_TOLERANCE};
use std::fmt;
use tubecast::{GeometryError, Mesh, V3};

/// A scene's mesh: the kernel's [`Mesh`] (its tags mapped to **scene link** indices) and,
/// per triangle, the closed part it belongs to.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::mesh::tessellate;
/// use tubecast_render::scene::{Model, Scene};
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0], [6.0, 2.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let m = tessellate(&scene, Model::Links, 1e-2).unwrap();
/// assert!(m.mesh.certified <= 1e-2 && m.mesh.tags.iter().all(|&l| l < 2));
/// ```
#[derive(Clone, Debug, Default)]
pub struct SceneMesh {
    /// Vertices, triangles, the certified bound; `tags[k]` is triangle `k`'s scene link.
    pub mesh: Mesh,
    /// Per triangle: the index of its closed part (unique across the scene).
    pub part: Vec<u32>,
}

/// Why a scene could not be tessellated.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// The tolerance is not a positive finite number, or too small for the scene's radii.
    Tolerance {
        /// The tolerance asked for.
        eps: f64,
        /// What the kernel said.
        cause: GeometryError,
    },
    /// A chain's geometry was rejected (its first link named).
    Chain {
        /// Scene link index.
        link: u32,
        /// What the kernel said.
        cause: GeometryError,
    },
    /// The union mesh would need more memory than allowed: refused before it is built.
    Memory {
        /// The tolerance asked for.
        eps: f64,
        /// The estimated peak (bytes).
        estimate: u64,
        /// The limit (bytes).
        limit: u64,
        /// The triangles of the links' hulls the estimate counts.
        hull_triangles: usize,
    },
    /// manifold failed on the union's input (it reports a status, never a partial mesh).
    Union {
        /// The tolerance asked for.
        eps: f64,
        /// What failed.
        what: String,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tolerance { eps, cause } => write!(f, "mesh tolerance {eps}: {cause}"),
            Self::Chain { link, cause } => write!(f, "cannot tessellate the chain of link {link}: {cause}"),
            Self::Memory { eps, estimate, limit, hull_triangles } => write!(
                f,
                "the union mesh at tolerance {eps} needs about {:.2} GB ({hull_triangles} hull triangles), above the limit of {:.2} GB: raise the tolerance (memory goes about as 1/tolerance), mesh a subset, or write --shells",
                *estimate as f64 / 1e9,
                *limit as f64 / 1e9
            ),
            Self::Union { eps, what } => write!(f, "the union mesh at tolerance {eps} failed: {what}"),
        }
    }
}

impl std::error::Error for MeshError {}

/// Tessellates every chain of the scene within `eps` (absolute, scene units), both ways.
/// `Model::Splines` meshes the C¹ spline tubes of the chains (their Hermite segments split into
/// the same certified quadratic sweeps the exact tracer traces), `Model::Links` the links.
pub fn tessellate(scene: &Scene, model: Model, eps: f64) -> Result<SceneMesh, MeshError> {
    if !(eps.is_finite() && eps > 0.0) {
        let cause = GeometryError::TooSmall { what: "mesh tolerance (must be a positive number)" };
        return Err(MeshError::Tolerance { eps, cause });
    }
    let mut out = SceneMesh::default();
    let segs = if model == Model::Splines { scene.spline_segments() } else { Vec::new() };
    let mut seg_at = 0;
    for chain in scene.chains() {
        let Some(&first) = chain.links.first() else { continue };
        let err = |cause| match cause {
            GeometryError::TooSmall { .. } => MeshError::Tolerance { eps, cause },
            _ => MeshError::Chain { link: first, cause },
        };
        let mut m = if model == Model::Splines {
            // spline_segments() lists the chains' segments in the same chain order.
            let chain_segs = &segs[seg_at..seg_at + chain.links.len()];
            seg_at += chain.links.len();
            // The pieces the exact tracer traces (`Scene::spline_primitives`: the certified
            // split within SPLINE_TOLERANCE of the cubic), so the mesh's certified error is
            // measured against the same model; `owner` maps each piece to its segment.
            let (mut tubes, mut owner) = (Vec::with_capacity(2 * chain_segs.len()), Vec::new());
            for (k, s) in chain_segs.iter().enumerate() {
                let quads = s.seg.split_adaptive(SPLINE_TOLERANCE, SPLINE_MAX_DEPTH).map_err(err)?.quads;
                owner.extend(std::iter::repeat(k as u32).take(quads.len()));
                tubes.extend(quads);
            }
            let mut m = tubecast::tessellate_spline(&tubes, eps).map_err(err)?;
            m.tags.iter_mut().for_each(|t| *t = owner[(*t as usize).min(owner.len() - 1)]);
            m
        } else {
            let nodes: Vec<(V3<f64>, f64)> = chain
                .nodes
                .iter()
                .map(|&n| (V3::from(scene.nodes[n as usize].pos), scene.radius(n as usize)))
                .collect();
            tubecast::tessellate_chain_solid(&nodes, eps).map_err(err)?
        };
        m.tags.iter_mut().for_each(|t| *t = chain.links[(*t as usize).min(chain.links.len() - 1)]);
        let base = out.mesh.parts.len() as u32;
        for (i, p) in m.parts.iter().enumerate() {
            out.part.extend(std::iter::repeat(base + i as u32).take(p.triangles.len()));
        }
        out.mesh.append(&m);
    }
    Ok(out)
}
