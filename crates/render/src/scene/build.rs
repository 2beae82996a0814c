//! Building a [`Scene`] from reader output, with validation.

use super::{Links, Node, Radii, Scene, SceneError, MAX_COORD, MIN_RADIUS};
use crate::io::{self, Polyline};

/// Nodes, links, node kinds (empty: all 0) and radii before validation.
pub(super) type Parts = (Vec<Node>, Links, Vec<i32>, Radii);

impl Scene {
    /// A scene from SWC rows (links child → parent; ids mapped to indices). No rows give the
    /// empty scene. Errors: two rows with one id ([`SceneError::DuplicateId`]), a parent id no
    /// row has, and whatever [`Scene::from_polylines`]' checks refuse.
    pub fn from_swc(rows: &[io::swc::SwcNode], name: &str) -> Result<Self, SceneError> {
        let (nodes, links, kinds, radii) = Self::swc_parts(rows, name)?;
        Self::finish((nodes, links, kinds, radii), name)
    }

    /// The nodes and links of SWC rows.
    pub(super) fn swc_parts(rows: &[io::swc::SwcNode], name: &str) -> Result<Parts, SceneError> {
        let ids: Vec<i64> = rows.iter().map(|r| r.id).collect();
        let index = io::swc::IdIndex::new(&ids)
            .map_err(|(_, second)| SceneError::DuplicateId { file: name.to_string(), id: ids[second] })?;
        let nodes = rows.iter().map(|r| Node { pos: r.pos }).collect();
        let radii = Radii::from_vec(rows.iter().map(|r| r.radius).collect());
        let kinds = rows.iter().map(|r| r.kind).collect();
        let mut links = Links::default();
        for (i, r) in rows.iter().enumerate() {
            if r.parent >= 0 {
                let p = index.get(r.parent).map(|p| p as u32).ok_or_else(|| SceneError::MissingParent {
                    file: name.to_string(),
                    parent: r.parent,
                    node: r.id,
                })?;
                links.push([p, i as u32]);
            }
        }
        Ok((nodes, links, kinds, radii))
    }

    /// A scene from polylines; points without a radius get `default_radius`. No polylines
    /// (or only empty ones) give the empty scene.
    pub fn from_polylines(lines: &[Polyline], default_radius: f64, name: &str) -> Result<Self, SceneError> {
        let parts = Self::polyline_parts(lines, default_radius)?;
        Self::finish(parts, name)
    }

    /// The nodes and links of polylines.
    pub(super) fn polyline_parts(lines: &[Polyline], default_radius: f64) -> Result<Parts, SceneError> {
        if !(default_radius.is_finite() && default_radius > 0.0) {
            return Err(SceneError::DefaultRadius(default_radius));
        }
        let (mut nodes, mut links, mut radii) = (Vec::new(), Links::default(), Radii::default());
        for l in lines {
            let base = nodes.len() as u32;
            for (k, p) in l.points.iter().enumerate() {
                let radius = l.radii.get(k).copied().unwrap_or(default_radius);
                radii.push(radius, nodes.len());
                nodes.push(Node { pos: *p });
                if k > 0 {
                    links.push([base + k as u32 - 1, base + k as u32]);
                }
            }
        }
        Ok((nodes, links, Vec::new(), radii))
    }

    /// Validate nodes and links into a scene (no nodes: the empty scene); `kinds` is dropped
    /// when every kind is 0. Coordinates and radii must be finite and within [`MAX_COORD`],
    /// radii `≥ 0`, non-zero radii `≥` [`MIN_RADIUS`], and no link may have radius 0 at both ends.
    pub(super) fn finish(parts: Parts, name: &str) -> Result<Self, SceneError> {
        let (mut nodes, mut links, mut kinds, mut radii) = parts;
        if nodes.len() > u32::MAX as usize - 1 {
            return Err(SceneError::TooManyNodes { file: name.to_string() });
        }
        for (i, n) in nodes.iter().enumerate() {
            let radius = radii.get(i);
            if n.pos.iter().chain([&radius]).any(|v| !v.is_finite() || v.abs() > MAX_COORD) {
                return Err(SceneError::OutOfRange { file: name.to_string(), node: i });
            }
            if radius < 0.0 {
                return Err(SceneError::NegativeRadius { file: name.to_string(), node: i, radius });
            }
            if radius > 0.0 && radius < MIN_RADIUS {
                return Err(SceneError::RadiusTooSmall { file: name.to_string(), node: i, radius });
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
        radii.shrink_to_fit();
        let s = Self { nodes, links, radii, kinds, values: Vec::new(), coverage: Vec::new() };
        for (k, l) in s.links.iter().enumerate() {
            if s.radius(l[0] as usize) == 0.0 && s.radius(l[1] as usize) == 0.0 {
                return Err(SceneError::NoVolume { file: name.to_string(), link: k, nodes: l });
            }
        }
        Ok(s)
    }
}
