//! Owned scene data built from user input: nodes, links, optional spline tangents, and the
//! renderer's primitives ("model no more than a scene needs").
//!
//! A [`Scene`] is a set of nodes `(position, radius, type)` and links `(node a, node b)`.
//! [`Scene::primitives`] turns each link into the cheapest exact primitive: a **cylinder**
//! link when the radii are equal, a **tangent-cone** link when they differ, or a **sphere**
//! when one end sphere contains the other ([`RoundCone::shape`]). Primitives are stored in
//! `f32` relative to a local origin in `f64` (the link's midpoint), so a scene far from the
//! world origin keeps the precision of a scene at the origin ([`Prim`]).

pub mod generate;
mod prim;

pub use prim::{Prim, PrimKind};

use crate::io::{self, IoError, Polyline};
use crate::kernel::link::RoundCone;
use crate::{LinkShape, V3};
use std::fmt;
use std::path::Path;

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
    /// Spline segments (when built with splines).
    pub splines: usize,
    /// Axis-aligned bounds of the surface `(min, max)`.
    pub bounds: ([f64; 3], [f64; 3]),
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
            let (a, b) = l.aabb();
            for (i, (x, y)) in a.to_array().iter().zip(b.to_array()).enumerate() {
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
