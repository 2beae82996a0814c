//! Marching tetrahedra over the band cells of a [`Field`]: each grid cube split into the six
//! Kuhn tetrahedra around its main diagonal (the same split in every cube, so neighbouring
//! cubes cut their shared face along the same diagonal), one vertex per grid edge whose ends
//! differ in sign (shared by every tetrahedron around the edge), placed at the root of the
//! exact union SDF on that edge.
//!
//! Why the result is a closed, embedded, oriented 2-manifold (derivation in
//! `docs/design/union-mesh.md`): in a tetrahedron whose corners are not all of one sign, the
//! piece is a triangle (one corner apart) or a quadrilateral split in two (two and two), with
//! its corners on the tetrahedron's edges, so it lies in the tetrahedron and meets a face only
//! along the segment between that face's two crossing points — which the neighbour across the
//! face shares. Every piece edge is then either inside a tetrahedron (a quad's diagonal, two
//! triangles) or on a face (the two tetrahedra of the face, one triangle each). Pieces of
//! different tetrahedra meet only there. Zero counts as positive, so no corner is on the surface.

use super::field::{EdgeMap, Field};
use tubecast::V3;

/// A contoured surface: vertices on the exact surface (to the root tolerance), the tube each
/// vertex lies on, and outward-oriented triangles.
#[derive(Default)]
pub(super) struct Raw {
    pub positions: Vec<V3<f64>>,
    pub owner: Vec<u32>,
    pub triangles: Vec<[u32; 3]>,
}

/// The six Kuhn tetrahedra of a cube as corner bit masks (bit 0: +x, 1: +y, 2: +z).
const TETS: [[u8; 4]; 6] = [[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]];

/// Contours `f = 0` over every band cell.
pub(super) fn contour(field: &Field) -> Raw {
    let n = field.n;
    let m = (n + 1) as usize;
    let mut raw = Raw::default();
    let mut edges = EdgeMap::default();
    let mut vals = vec![0.0; m * m * m];
    for cell in field.band_cells() {
        let base = cell.map(|c| c * n);
        for a in 0..m {
            for b in 0..m {
                for c in 0..m {
                    let i = [base[0] + a as i64, base[1] + b as i64, base[2] + c as i64];
                    vals[(a * m + b) * m + c] = field.at_vertex(i);
                }
            }
        }
        let mut corners = [[0i64; 3]; 8];
        let mut cv = [0.0; 8];
        for a in 0..n as usize {
            for b in 0..n as usize {
                for c in 0..n as usize {
                    for bits in 0..8usize {
                        let (x, y, z) = (bits & 1, (bits >> 1) & 1, (bits >> 2) & 1);
                        cv[bits] = vals[((a + x) * m + b + y) * m + c + z];
                        corners[bits] = [base[0] + (a + x) as i64, base[1] + (b + y) as i64, base[2] + (c + z) as i64];
                    }
                    let neg = cv.iter().filter(|&&v| v < 0.0).count();
                    if neg == 0 || neg == 8 {
                        continue;
                    }
                    for t in TETS {
                        let p = t.map(|k| corners[k as usize]);
                        let v = t.map(|k| cv[k as usize]);
                        tet(field, &mut raw, &mut edges, p, v);
                    }
                }
            }
        }
    }
    raw
}

type I3 = [i64; 3];

fn sub(a: I3, b: I3) -> I3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: I3, b: I3) -> I3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn cross(a: I3, b: I3) -> I3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn dot(a: I3, b: I3) -> i64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Whether the triangle on edges `e` (as corner pairs; twice their midpoints in integers, so
/// exact) turns its normal along `d`. The construction's orientation is decided here, on the
/// midpoints, where it cannot round; the roots move each corner along its own edge only,
/// which keeps it (see the module docs).
fn faces(e: [(I3, I3); 3], d: I3) -> bool {
    let m = e.map(|(a, b)| add(a, b));
    dot(cross(sub(m[1], m[0]), sub(m[2], m[0])), d) > 0
}

/// Emits the piece of one tetrahedron.
fn tet(field: &Field, raw: &mut Raw, edges: &mut EdgeMap, p: [I3; 4], v: [f64; 4]) {
    let neg: Vec<usize> = (0..4).filter(|&k| v[k] < 0.0).collect();
    let pos: Vec<usize> = (0..4).filter(|&k| v[k] >= 0.0).collect();
    let mut vert = |a: usize, b: usize| edge_vertex(field, raw, edges, (p[a], v[a]), (p[b], v[b]));
    match (neg.len(), pos.len()) {
        (1, 3) | (3, 1) => {
            let (lone, others, lone_neg) = if neg.len() == 1 {
                (neg[0], [pos[0], pos[1], pos[2]], true)
            } else {
                (pos[0], [neg[0], neg[1], neg[2]], false)
            };
            let mut d = sub(add(add(p[others[0]], p[others[1]]), p[others[2]]), p[lone].map(|x| 3 * x));
            if !lone_neg {
                d = d.map(|x| -x);
            }
            let mut o = others;
            if !faces(o.map(|k| (p[lone], p[k])), d) {
                o.swap(1, 2);
            }
            let t = o.map(|k| vert(lone, k));
            raw.triangles.push(t);
        }
        (2, 2) => {
            let (n0, n1, q0, q1) = (neg[0], neg[1], pos[0], pos[1]);
            let mut cycle = [(n0, q0), (n0, q1), (n1, q1), (n1, q0)];
            let d = sub(add(p[q0], p[q1]), add(p[n0], p[n1]));
            if !faces([0, 1, 2].map(|k| (p[cycle[k].0], p[cycle[k].1])), d) {
                cycle.reverse();
            }
            let e = cycle.map(|(a, b)| vert(a, b));
            let x = |k: usize| raw.positions[e[k] as usize];
            if (x(0) - x(2)).length2() <= (x(1) - x(3)).length2() {
                raw.triangles.push([e[0], e[1], e[2]]);
                raw.triangles.push([e[0], e[2], e[3]]);
            } else {
                raw.triangles.push([e[0], e[1], e[3]]);
                raw.triangles.push([e[1], e[2], e[3]]);
            }
        }
        _ => {}
    }
}

/// The vertex on the grid edge between two corners of opposite sign (created once).
fn edge_vertex(field: &Field, raw: &mut Raw, edges: &mut EdgeMap, a: (I3, f64), b: (I3, f64)) -> u32 {
    // In a Kuhn tetrahedron one corner's offset bits contain the other's: order by the sum.
    let (lo, hi) = if a.0.iter().sum::<i64>() <= b.0.iter().sum::<i64>() { (a, b) } else { (b, a) };
    let d = sub(hi.0, lo.0);
    let key = (super::field::pack(lo.0), (d[0] | d[1] << 1 | d[2] << 2) as u8);
    if let Some(&i) = edges.get(&key) {
        return i;
    }
    let (x, owner) = root(field, (field.at(lo.0), lo.1), (field.at(hi.0), hi.1));
    let i = raw.positions.len() as u32;
    raw.positions.push(x);
    raw.owner.push(owner);
    edges.insert(key, i);
    i
}

/// The fraction of an edge kept between a root and the edge's ends: a vertex never sits on a
/// grid corner, so the pieces of neighbouring tetrahedra never touch at a point of zero area.
pub(super) const END_GAP: f64 = 1e-10;

/// The root of `f` on the segment between two points of opposite sign (Illinois false
/// position on the exact SDF, bracketed, to a step of `1e-12` of the edge), and the tube it
/// lies on.
fn root(field: &Field, a: (V3<f64>, f64), b: (V3<f64>, f64)) -> (V3<f64>, u32) {
    let at = |t: f64| a.0 + (b.0 - a.0) * t;
    let (mut t0, mut f0, mut t1, mut f1) = (0.0, a.1, 1.0, b.1);
    let mut side = 0;
    let mut best = (0.5, u32::MAX);
    for _ in 0..200 {
        let t = ((t0 * f1 - t1 * f0) / (f1 - f0)).clamp(t0, t1);
        let t = if t.is_finite() && t > t0 && t < t1 { t } else { 0.5 * (t0 + t1) };
        let (f, k) = field.eval(at(t));
        best = (t, k);
        if f.abs() <= 1e-12 * field.h || t1 - t0 <= 1e-12 {
            break;
        }
        if (f < 0.0) == (f0 < 0.0) {
            (t0, f0) = (t, f);
            if side == -1 {
                f1 *= 0.5;
            }
            side = -1;
        } else {
            (t1, f1) = (t, f);
            if side == 1 {
                f0 *= 0.5;
            }
            side = 1;
        }
        if (t1 - t0) <= 1e-12 {
            best = (if f0.abs() < f1.abs() { t0 } else { t1 }, k);
            break;
        }
    }
    let t = best.0.clamp(END_GAP, 1.0 - END_GAP);
    let x = at(t);
    (x, field.eval(x).1)
}
