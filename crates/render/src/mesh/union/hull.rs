//! The union built with manifold (the pure-Rust port `manifold-rust`): every node sphere an
//! inscribed polyhedron (manifold's subdivided octahedron, vertices on the sphere), every link
//! the convex hull of its two end polyhedra, all links united by halves in space (`tree_union`),
//! with manifold's batch union (disjoint pieces composed, the rest pairwise) for the last few.

use super::piece::Body;
use super::tube::P;
use manifold_rust::csg_tree::CsgNode;
use manifold_rust::linalg::Vec3;
use manifold_rust::manifold::Manifold;
use manifold_rust::types::{Error, MeshGL64, OpType};
use std::collections::HashMap;
use tubecast::V3;

/// Subdivisions per octant edge at most (a sphere of `8·K²` triangles: 2·10⁶ at the cap).
pub(super) const MAX_SUBDIV: u32 = 512;

/// The unit sphere polyhedron with `k` subdivisions per octant edge (`4k` circular segments):
/// its vertices and its sagitta `σ(k)`, the most any point of the unit ball's boundary lies
/// outside the polyhedron (one minus the least distance from the centre to a face's plane,
/// plus any vertex's excess over radius 1), measured on manifold's own triangles.
pub(super) struct UnitSphere {
    pub verts: Vec<P>,
    pub sagitta: f64,
}

/// Unit spheres by subdivision count, measured once each.
#[derive(Default)]
pub(super) struct Spheres {
    by_k: HashMap<u32, UnitSphere>,
}

impl Spheres {
    pub(super) fn get(&mut self, k: u32) -> &UnitSphere {
        self.by_k.entry(k).or_insert_with(|| measure(k))
    }

    /// The least subdivision count whose sphere of radius `r` has sagitta `r·σ(k) ≤ s`
    /// (`MAX_SUBDIV` if none up to it).
    pub(super) fn subdivisions_for(&mut self, r: f64, s: f64) -> u32 {
        // σ(k) ≈ C/k² (a chord's sagitta, chords ∝ 1/k): start from that estimate, then step
        // by the measured value.
        let c = self.get(8).sagitta * 64.0;
        let mut k = ((c * r / s).sqrt().floor() as u32).clamp(1, MAX_SUBDIV);
        while k > 1 && r * self.get(k - 1).sagitta <= s {
            k -= 1;
        }
        while k < MAX_SUBDIV && r * self.get(k).sagitta > s {
            k += 1;
        }
        k
    }
}

fn measure(k: u32) -> UnitSphere {
    let m = Manifold::sphere(1.0, 4 * k as i32).get_mesh_gl64(-1);
    let np = m.num_prop as usize;
    let verts: Vec<P> = m.vert_properties.chunks(np).map(|c| V3::new(c[0], c[1], c[2])).collect();
    let mut face = f64::INFINITY;
    for t in m.tri_verts.chunks(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| verts[i as usize]);
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len > 0.0 {
            face = face.min((n.dot(a) / len).abs());
        }
    }
    let over = verts.iter().map(|v| v.length() - 1.0).fold(0.0, f64::max);
    UnitSphere { verts, sagitta: (1.0 - face) + over }
}

/// The union's triangles, vertices and, per triangle, the link whose hull it lies on.
pub(super) struct Built {
    pub positions: Vec<P>,
    pub triangles: Vec<[u32; 3]>,
    pub link: Vec<u32>,
}

/// Why manifold could not build the union.
#[derive(Debug)]
pub(super) struct BuildError(pub String);

/// The union of the runs' bodies and of the hulls of `links` (tube index, node pair into
/// `centres`/`radii`, with the nodes' subdivision counts `subdiv`); each output triangle names
/// the tube it lies on.
pub(super) fn union(
    centres: &[P],
    radii: &[f64],
    subdiv: &[u32],
    links: &[(u32, [usize; 2])],
    bodies: &[Body],
    spheres: &mut Spheres,
) -> Result<Built, BuildError> {
    for k in subdiv {
        spheres.get(*k);
    }
    let spheres = &*spheres;
    let points = |n: usize, out: &mut Vec<Vec3>| {
        let (c, r) = (centres[n], radii[n]);
        for u in &spheres.by_k[&subdiv[n]].verts {
            out.push(Vec3::new(c.x + r * u.x, c.y + r * u.y, c.z + r * u.z));
        }
    };
    use rayon::prelude::*;
    let hulls: Vec<Result<(i32, Manifold), BuildError>> = links
        .par_iter()
        .map(|&(k, [a, b])| {
            let mut pts = Vec::new();
            points(a, &mut pts);
            points(b, &mut pts);
            let h = Manifold::hull(&pts);
            if h.status() != Error::NoError || h.is_empty() {
                return Err(BuildError(format!("the hull of link {k} failed: {:?}", h.status())));
            }
            Ok((h.original_id(), h))
        })
        .collect();
    // Bodies carry their tubes as face IDs, which manifold keeps on every piece of a face.
    let runs: Vec<Result<Manifold, BuildError>> = bodies
        .par_iter()
        .map(|b| {
            let mesh = MeshGL64 {
                num_prop: 3,
                vert_properties: b.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
                tri_verts: b.triangles.iter().flat_map(|t| t.map(u64::from)).collect(),
                face_id: b.tags.iter().map(|&t| u64::from(t)).collect(),
                run_original_id: vec![Manifold::reserve_ids(1)],
                ..Default::default()
            };
            let m = Manifold::from_mesh_gl64(&mesh);
            if m.status() != Error::NoError || m.is_empty() {
                let l = b.tags.first().copied().unwrap_or(0);
                return Err(BuildError(format!("the body of the run of link {l} was refused: {:?}", m.status())));
            }
            Ok(m)
        })
        .collect();
    let mut ids = HashMap::with_capacity(links.len());
    let mut leaves = Vec::with_capacity(links.len() + bodies.len());
    for (&(k, _), h) in links.iter().zip(hulls) {
        let (id, m) = h?;
        ids.insert(id as u32, k);
        leaves.push(m);
    }
    for m in runs {
        leaves.push(m?);
    }
    let solid = tree_union(leaves);
    if solid.status() != Error::NoError {
        return Err(BuildError(format!("manifold's union failed: {:?}", solid.status())));
    }
    let gl = solid.get_mesh_gl64(-1);
    let np = gl.num_prop as usize;
    // Vertices split for properties are merged back (none are expected: no properties).
    let mut to: Vec<u32> = (0..gl.vert_properties.len() / np.max(1)).map(|i| i as u32).collect();
    for (f, t) in gl.merge_from_vert.iter().zip(&gl.merge_to_vert) {
        to[*f as usize] = *t as u32;
    }
    let positions: Vec<P> = gl.vert_properties.chunks(np).map(|c| V3::new(c[0], c[1], c[2])).collect();
    let triangles: Vec<[u32; 3]> =
        gl.tri_verts.chunks(3).map(|t| [to[t[0] as usize], to[t[1] as usize], to[t[2] as usize]]).collect();
    let mut link = vec![0u32; triangles.len()];
    // Each of manifold's runs (the triangles of one input piece) keyed by its piece: the
    // hull's link, or a body's first tube (a tube lies in one piece only).
    let mut spans: Vec<(u32, usize, usize)> = Vec::with_capacity(gl.run_original_id.len());
    for r in 0..gl.run_original_id.len() {
        let (s, e) = (gl.run_index[r] as usize / 3, gl.run_index[r + 1] as usize / 3);
        match ids.get(&gl.run_original_id[r]) {
            Some(&l) => link[s..e].iter_mut().for_each(|x| *x = l),
            // A run's body: the face ID is the tube.
            None => (s..e).for_each(|t| link[t] = gl.face_id.get(t).map_or(0, |&f| f as u32)),
        }
        if s < e {
            spans.push((link[s], s, e));
        }
    }
    // Manifold orders the runs by the pieces' IDs, which the threads reserve in the order
    // they happen to make the pieces: ordered by piece instead, the triangles come out in the
    // same order on every run.
    if spans.iter().map(|&(_, s, e)| e - s).sum::<usize>() != triangles.len() {
        // The runs do not cover the triangles once each (never seen): keep manifold's order.
        return Ok(Built { positions, triangles, link });
    }
    spans.sort_unstable_by_key(|&(key, s, _)| (key, s));
    let order = spans.iter().flat_map(|&(_, s, e)| s..e);
    let (triangles, link) = order.map(|t| (triangles[t], link[t])).unzip();
    Ok(Built { positions, triangles, link })
}

/// At most this many pieces are united by one call of manifold's batch union.
const TREE_LEAF: usize = 16;

/// The union of `pieces`, by halves: split at the median of their boxes' centres along the
/// widest axis, each half united (the two side by side), then the two halves.
///
/// Manifold's batch union composes pieces whose boxes are disjoint, then unites the rest
/// largest first, so the growing result is carried through nearly every boolean: the work
/// goes as the number of pieces times the result. Halving keeps each boolean's operands
/// near each other and about equal, so every piece takes part in about log₂(n/16) booleans.
fn tree_union(mut pieces: Vec<Manifold>) -> Manifold {
    if pieces.len() <= TREE_LEAF {
        let nodes = pieces.into_iter().map(|m| CsgNode::leaf(m.into_impl())).collect();
        return Manifold::from_impl(CsgNode::op_n(OpType::Add, nodes).evaluate());
    }
    let centre = |m: &Manifold| {
        let b = m.bounding_box();
        [0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), 0.5 * (b.min.z + b.max.z)]
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in pieces.iter().map(centre) {
        for i in 0..3 {
            lo[i] = lo[i].min(c[i]);
            hi[i] = hi[i].max(c[i]);
        }
    }
    let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
    let mid = pieces.len() / 2;
    pieces.select_nth_unstable_by(mid, |a, b| centre(a)[axis].total_cmp(&centre(b)[axis]));
    let right = pieces.split_off(mid);
    let (a, b) = rayon::join(|| tree_union(pieces), || tree_union(right));
    a.boolean(&b, OpType::Add)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The union by halves is the same solid as manifold's batch union of all the pieces: 64
    /// overlapping spheres on a jittered grid (more than `TREE_LEAF`, so the halving runs to
    /// three levels). The two differ only in where the intersection vertices are rounded, a
    /// few ulps of coordinates of at most 4 (≈ 10⁻¹⁵), moving the volume by about the area
    /// (≈ 10²) times that; 10⁻⁹ of the volume allows it a millionfold, while one sphere left
    /// out or counted twice moves it by more than 10⁻³.
    #[test]
    fn union_by_halves_is_manifolds_batch_union() {
        let mut pieces = Vec::new();
        for i in 0..64u32 {
            let (x, y, z) = (f64::from(i % 4), f64::from(i / 4 % 4), f64::from(i / 16));
            let j = 0.1 * f64::from(i.wrapping_mul(2_654_435_761) % 97) / 97.0;
            pieces.push(Manifold::sphere(0.6, 16).translate(Vec3::new(x + j, y - j, z + 0.5 * j)));
        }
        let nodes = pieces.iter().map(|m| CsgNode::leaf(m.clone().into_impl())).collect();
        let batch = Manifold::from_impl(CsgNode::op_n(OpType::Add, nodes).evaluate());
        let halves = tree_union(pieces);
        assert_eq!(halves.status(), Error::NoError);
        let (v, w) = (halves.volume(), batch.volume());
        assert!((v - w).abs() <= 1e-9 * w, "volume {v} by halves, {w} batch");
        let (a, b) = (halves.surface_area(), batch.surface_area());
        assert!((a - b).abs() <= 1e-9 * b, "area {a} by halves, {b} batch");
        // One solid: every sphere overlaps its grid neighbours (spacing 1 + jitter < 1.2).
        assert_eq!(halves.decompose().len(), 1);
    }
}
