//! A local embedding check for the crease splits: a split point leaves its edge, and the
//! pieces around it must not cross any other triangle. Only triangles near changed pieces
//! are tested (a hash of cells of two grid steps).

use super::field::{pack, CellMap};
use tubecast::V3;

type P = V3<f64>;

/// Whether segment `a–b` crosses the interior of triangle `t` (Möller–Trumbore; touching
/// within a relative `1e-12` does not count: shared corners and edges touch by design).
fn seg_tri(a: P, b: P, t: [P; 3]) -> bool {
    let d = b - a;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    // A segment in the triangle's plane (to rounding) is not a crossing: pieces of adjacent
    // tetrahedra can be coplanar where the surface is a plane or a ruled surface's line.
    if det.abs() <= 1e-12 * d.length() * e1.length() * e2.length() {
        return false;
    }
    let inv = 1.0 / det;
    let s = a - t[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    let w = e2.dot(q) * inv;
    let eps = 1e-12;
    u > eps && v > eps && u + v < 1.0 - eps && w > eps && w < 1.0 - eps
}

/// Whether triangles `i` and `j` (vertex indices) cross: an edge of one through the other,
/// edges at a shared corner excluded; triangles sharing an edge are not tested.
fn cross(ti: [u32; 3], tj: [u32; 3], pos: &[P]) -> bool {
    let shared = ti.iter().filter(|v| tj.contains(v)).count();
    if shared >= 2 {
        return false;
    }
    let (ci, cj) = (ti.map(|k| pos[k as usize]), tj.map(|k| pos[k as usize]));
    let edges = |t: [u32; 3], other: [u32; 3]| {
        (0..3).filter(move |&e| !other.contains(&t[e]) && !other.contains(&t[(e + 1) % 3]))
    };
    edges(ti, tj).any(|e| seg_tri(ci[e], ci[(e + 1) % 3], cj))
        || edges(tj, ti).any(|e| seg_tri(cj[e], cj[(e + 1) % 3], ci))
}

/// The indices (into `tris`) of the `dirty` triangles that cross some other triangle.
pub(super) fn crossing(tris: &[[u32; 3]], dirty: &[usize], pos: &[P], cell: f64) -> Vec<usize> {
    let key = |p: P| [(p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64];
    let range = |t: [u32; 3]| {
        let c = t.map(|k| pos[k as usize]);
        let lo = key(V3::new(
            c[0].x.min(c[1].x).min(c[2].x),
            c[0].y.min(c[1].y).min(c[2].y),
            c[0].z.min(c[1].z).min(c[2].z),
        ));
        let hi = key(V3::new(
            c[0].x.max(c[1].x).max(c[2].x),
            c[0].y.max(c[1].y).max(c[2].y),
            c[0].z.max(c[1].z).max(c[2].z),
        ));
        (lo, hi)
    };
    let cells_of = |t: [u32; 3]| {
        let (lo, hi) = range(t);
        (lo[0]..=hi[0]).flat_map(move |i| (lo[1]..=hi[1]).flat_map(move |j| (lo[2]..=hi[2]).map(move |k| [i, j, k])))
    };
    // Cells the dirty triangles touch, then every triangle in those cells.
    let mut wanted: CellMap<Vec<usize>> = CellMap::default();
    for &d in dirty {
        for c in cells_of(tris[d]) {
            wanted.entry(pack(c)).or_default();
        }
    }
    for (k, &t) in tris.iter().enumerate() {
        for c in cells_of(t) {
            if let Some(v) = wanted.get_mut(&pack(c)) {
                v.push(k);
            }
        }
    }
    let mut bad = Vec::new();
    for &d in dirty {
        let hit = cells_of(tris[d]).any(|c| wanted[&pack(c)].iter().any(|&o| o != d && cross(tris[d], tris[o], pos)));
        if hit {
            bad.push(d);
        }
    }
    bad
}
