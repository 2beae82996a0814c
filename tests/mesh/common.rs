//! Independent checks on meshes for the `mesh_*` tests: topology by counting directed edges,
//! point–triangle distance, samples on the
//! triangles and on the exact surfaces (built here from the geometry, not by the mesher).
#![allow(dead_code)]

use std::collections::HashMap;
use tubecast::{Mesh, V3};

pub type P = V3<f64>;

/// Every directed edge appears once and its reverse once (closed, consistently oriented,
/// every edge shared by exactly two faces); no triangle repeats a vertex. Returns the number
/// of undirected edges.
pub fn assert_watertight(m: &Mesh) -> usize {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &m.triangles {
        assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "degenerate triangle {t:?}");
        for k in 0..3 {
            *count.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &c) in &count {
        assert_eq!(c, 1, "directed edge {a}->{b} used {c} times");
        assert_eq!(count.get(&(b, a)), Some(&1), "edge {a}->{b} has no opposite (open or flipped)");
    }
    count.len() / 2
}

/// Signed volume (positive for outward orientation), relative to the first triangle's first
/// corner so that far origins do not cancel.
pub fn volume(m: &Mesh) -> f64 {
    let Some(&o) = m.triangles.first().map(|t| &m.positions[t[0] as usize]) else { return 0.0 };
    (0..m.triangles.len())
        .map(|k| {
            let [a, b, c] = m.corners(k).map(|x| x - o);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Distance from `p` to the segment `ab`.
fn segment_dist(p: P, a: P, b: P) -> f64 {
    let e = b - a;
    let t = ((p - a).dot(e) / e.length2()).clamp(0.0, 1.0);
    (a + e.scale(t) - p).length()
}

/// Distance from `p` to triangle `abc`: to the plane when the projection falls inside (signs
/// of the edge cross products against the normal), else to the nearest edge. Written this way
/// rather than with Ericson's barycentric products, which cancel catastrophically on the
/// needle triangles of long thin links.
pub fn triangle_dist(p: P, a: P, b: P, c: P) -> f64 {
    let n = (b - a).cross(c - a);
    let nl = n.length();
    if nl > 0.0 {
        let n = n.scale(1.0 / nl);
        let h = n.dot(p - a);
        let q = p - n.scale(h);
        let side = |u: P, v: P| n.dot((v - u).cross(q - u)) >= 0.0;
        if side(a, b) && side(b, c) && side(c, a) {
            return h.abs();
        }
    }
    segment_dist(p, a, b).min(segment_dist(p, b, c)).min(segment_dist(p, c, a))
}

/// Distance from points to a mesh, brute force with a bounding-ball cull.
pub struct MeshDist {
    tris: Vec<([P; 3], P, f64)>,
}

impl MeshDist {
    pub fn new(m: &Mesh) -> Self {
        let tris = (0..m.triangles.len())
            .map(|k| {
                let t = m.corners(k);
                let c = (t[0] + t[1] + t[2]).scale(1.0 / 3.0);
                let r = t.iter().map(|&v| (v - c).length()).fold(0.0, f64::max);
                (t, c, r)
            })
            .collect();
        Self { tris }
    }
    pub fn dist(&self, p: P) -> f64 {
        let mut best = f64::INFINITY;
        for (t, c, r) in &self.tris {
            if (p - *c).length() - r < best {
                best = best.min(triangle_dist(p, t[0], t[1], t[2]));
            }
        }
        best
    }
}

/// Points on every triangle: the corners, edge points and interior points of a barycentric
/// grid with `k` steps.
pub fn triangle_samples(m: &Mesh, k: usize) -> Vec<P> {
    let mut out = Vec::new();
    for t in 0..m.triangles.len() {
        let [a, b, c] = m.corners(t);
        for i in 0..=k {
            for j in 0..=(k - i) {
                let (u, v) = (i as f64 / k as f64, j as f64 / k as f64);
                out.push(a.scale(1.0 - u - v) + b.scale(u) + c.scale(v));
            }
        }
    }
    out
}

/// A unit vector perpendicular to `w` at angle `phi` around it.
pub fn perp(w: P, phi: f64) -> P {
    let h = if w.x.abs() < 0.9 { V3::new(1.0, 0.0, 0.0) } else { V3::new(0.0, 1.0, 0.0) };
    let e1 = w.cross(h).normalize_or_zero();
    let e2 = w.cross(e1);
    e1.scale(phi.cos()) + e2.scale(phi.sin())
}

/// Points on the exact surface of the round cone `(a, ra)`–`(b, rb)` (built from its closed
/// form: the two caps beyond the tangent circles and the straight cone between them), `k`
/// per family. Empty families when one ball contains the other (then: the larger sphere).
pub fn link_surface(a: P, ra: f64, b: P, rb: f64, k: usize) -> Vec<P> {
    let d = b - a;
    let l = d.length();
    let mut out = Vec::new();
    let golden = 2.399_963_229_728_653;
    if l <= (ra - rb).abs() {
        let (c, r) = if ra >= rb { (a, ra) } else { (b, rb) };
        for i in 0..3 * k {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / (3 * k) as f64;
            let e = perp(V3::new(0.0, 0.0, 1.0), golden * i as f64);
            out.push(c + (V3::new(0.0, 0.0, z) + e.scale((1.0 - z * z).sqrt())).scale(r));
        }
        return out;
    }
    let w = d.scale(1.0 / l);
    let alpha = std::f64::consts::FRAC_PI_2 - ((ra - rb) / l).asin(); // the cone normal leans to the small end
    let dir = |pol: f64, phi: f64| w.scale(pol.cos()) + perp(w, phi).scale(pol.sin());
    for i in 0..k {
        let f = (i as f64 + 0.5) / k as f64;
        let phi = golden * i as f64;
        out.push(a + dir(alpha + (std::f64::consts::PI - alpha) * f, phi).scale(ra));
        out.push(b + dir(alpha * f, phi).scale(rb));
        let s = (i as f64 * 0.618_033_988_749_895) % 1.0;
        out.push((a + dir(alpha, phi).scale(ra)).scale(1.0 - s) + (b + dir(alpha, phi).scale(rb)).scale(s));
    }
    out
}
