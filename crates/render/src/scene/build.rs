//! Building a [`Scene`] from reader output, with validation.

use super::{Links, Node, Scene, SceneError, MAX_COORD};
use crate::io::{self, Polyline};

/// Nodes, links and node kinds (empty: all 0) before validation.
pub(super) type Parts = (Vec<Node>, Links, Vec<i32>);

impl Scene {
    /// A scene from SWC rows (links child → parent; ids mapped to indices). No rows give the
    /// empty scene.
    pub fn from_swc(rows: &[io::swc::SwcNode], name: &str) -> Result<Self, SceneError> {
        let (nodes, links, kinds) = Self::swc_parts(rows, name)?;
        Self::finish(nodes, links, kinds, name)
    }

    /// The nodes and links of SWC rows.
    pub(super) fn swc_parts(rows: &[io::swc::SwcNode], name: &str) -> Result<Parts, SceneError> {
        let mut index = std::collections::HashMap::new();
        for (i, r) in rows.iter().enumerate() {
            index.insert(r.id, i as u32);
        }
        let nodes = rows.iter().map(|r| Node { pos: r.pos, radius: r.radius }).collect();
        let kinds = rows.iter().map(|r| r.kind).collect();
        let mut links = Links::default();
        for (i, r) in rows.iter().enumerate() {
            if r.parent >= 0 {
                let p = *index.get(&r.parent).ok_or_else(|| SceneError::MissingParent {
                    file: name.to_string(),
                    parent: r.parent,
                    node: r.id,
                })?;
                links.push([p, i as u32]);
            }
        }
        Ok((nodes, links, kinds))
    }

    /// A scene from polylines; points without a radius get `default_radius`. No polylines
    /// (or only empty ones) give the empty scene.
    pub fn from_polylines(lines: &[Polyline], default_radius: f64, name: &str) -> Result<Self, SceneError> {
        let (nodes, links, kinds) = Self::polyline_parts(lines, default_radius)?;
        Self::finish(nodes, links, kinds, name)
    }

    /// The nodes and links of polylines.
    pub(super) fn polyline_parts(lines: &[Polyline], default_radius: f64) -> Result<Parts, SceneError> {
        if !(default_radius.is_finite() && default_radius > 0.0) {
            return Err(SceneError::DefaultRadius(default_radius));
        }
        let mut nodes = Vec::new();
        let mut links = Links::default();
        for l in lines {
            let base = nodes.len() as u32;
            for (k, p) in l.points.iter().enumerate() {
                let radius = l.radii.get(k).copied().unwrap_or(default_radius);
                nodes.push(Node { pos: *p, radius });
                if k > 0 {
                    links.push([base + k as u32 - 1, base + k as u32]);
                }
            }
        }
        Ok((nodes, links, Vec::new()))
    }

    /// Validate nodes and links into a scene (no nodes: the empty scene); `kinds` is dropped
    /// when every kind is 0.
    pub(super) fn finish(
        mut nodes: Vec<Node>,
        mut links: Links,
        mut kinds: Vec<i32>,
        name: &str,
    ) -> Result<Self, SceneError> {
        if nodes.len() > u32::MAX as usize - 1 {
            return Err(SceneError::TooManyNodes { file: name.to_string() });
        }
        for (i, n) in nodes.iter().enumerate() {
            if n.pos.iter().chain([&n.radius]).any(|v| !v.is_finite() || v.abs() > MAX_COORD) {
                return Err(SceneError::OutOfRange { file: name.to_string(), node: i });
            }
            if n.radius < 0.0 {
                return Err(SceneError::NegativeRadius { file: name.to_string(), node: i, radius: n.radius });
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
        if kinds.iter().all(|&k| k == 0) {
            kinds = Vec::new();
        }
        nodes.shrink_to_fit();
        links.shrink_to_fit();
        kinds.shrink_to_fit();
        let s = Self { nodes, links, kinds, values: Vec::new(), coverage: Vec::new() };
        for (k, l) in s.links.iter().enumerate() {
            if s.nodes[l[0] as usize].radius == 0.0 && s.nodes[l[1] as usize].radius == 0.0 {
                return Err(SceneError::NoVolume { file: name.to_string(), link: k, nodes: l });
            }
        }
        Ok(s)
    }
}
