//! Creases: where two tubes' surfaces meet, the union has a concave edge, and a triangle with
//! corners on both tubes bridges it, out of the union by up to `(ℓ/2)·sin(φ/2)` for a chord of
//! length `ℓ` across a crease that turns by `φ` — first order in the grid step. Splitting every
//! such mesh edge at a point of the crease itself (`f_A = f_B = 0`, found by Newton's method
//! on the two exact SDFs) leaves each piece with all its corners on one tube, so by that
//! tube's convexity the piece lies inside the union again, and its depth is second order.
//!
//! Splitting an edge splits both triangles that share it, so the mesh stays closed and
//! 2-manifold. A split that would turn a piece over (its normal against the original
//! triangle's) is not made; the certificate then measures that triangle as it is.

use super::field::{gradient, Field};
use super::grid::Raw;
use std::collections::HashMap;
use tubecast::{Primitive, V3};

/// Crease splitting's result: `min_cos_half`, the least `sin(β/2)` over the split points,
/// `β` the crease's exterior opening (1 when none was split).
pub(super) struct Creases {
    pub split: usize,
    pub min_sin_half: f64,
}

/// Per crease-crossing edge (sorted vertex pair): its split point and `sin(β/2)` there, or
/// `None` where it is not split.
type Candidates = HashMap<(u32, u32), Option<(V3<f64>, f64)>>;

/// A vertex is on (or in) tube `i` when `fᵢ ≤ ON·h`.
pub(super) const ON: f64 = 1e-8;

/// The tubes a point is on or in.
pub(super) fn on_tubes(field: &Field, x: V3<f64>) -> Vec<u32> {
    let tol = ON * field.h;
    field.near(x).unwrap_or(&[]).iter().copied().filter(|&k| field.tubes[k as usize].sdf(x) <= tol).collect()
}

/// Splits crease-crossing edges (a few rounds: a split point may leave an edge that crosses
/// a second crease).
pub(super) fn split(field: &Field, raw: &mut Raw) -> Creases {
    let mut out = Creases { split: 0, min_sin_half: 1.0 };
    for _ in 0..3 {
        let n = round(field, raw, &mut out);
        if n == 0 {
            break;
        }
        out.split += n;
    }
    out
}

fn round(field: &Field, raw: &mut Raw, out: &mut Creases) -> usize {
    let on: Vec<Vec<u32>> = raw.positions.iter().map(|&x| on_tubes(field, x)).collect();
    // Candidate split point per crossing edge (sorted vertex pair).
    let mut cand: Candidates = HashMap::new();
    for t in &raw.triangles {
        for e in 0..3 {
            let (u, v) = (t[e], t[(e + 1) % 3]);
            let key = (u.min(v), u.max(v));
            if cand.contains_key(&key) || on[u as usize].iter().any(|k| on[v as usize].contains(k)) {
                continue;
            }
            let w = crease_point(field, raw.positions[key.0 as usize], raw.positions[key.1 as usize]);
            cand.insert(key, w);
        }
    }
    // Refuse splits that would turn a piece over, until none does: a piece must face the way
    // its own tube's surface faces (the gradient at its centroid of a tube holding all its
    // corners), or, with no such tube, the way the original triangle faced.
    for _ in 0..4 {
        let mut refused = Vec::new();
        for t in &raw.triangles {
            let pieces = pieces(t, &raw.positions, &cand);
            if pieces.len() == 1 {
                continue;
            }
            let n0 = normal(t.map(|i| raw.positions[i as usize]));
            if pieces.iter().any(|p| facing(field, *p).unwrap_or(n0).dot(normal(*p)) <= 0.0) {
                for e in 0..3 {
                    let (u, v) = (t[e], t[(e + 1) % 3]);
                    refused.push((u.min(v), u.max(v)));
                }
            }
        }
        let mut changed = false;
        for k in refused {
            if let Some(w @ Some(_)) = cand.get_mut(&k) {
                *w = None;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Make the pieces; where one crosses another triangle, refuse its triangle's splits and
    // make them again (a split point leaves its edge, so the pieces are not confined to the
    // grid's tetrahedra as the contour's triangles are). After a few refusals, no split.
    let n0 = raw.positions.len() as u32;
    for attempt in 0..6 {
        let mut keys: Vec<_> = cand.iter().filter_map(|(k, w)| w.map(|w| (*k, w))).collect();
        keys.sort_by_key(|a| a.0);
        if attempt == 5 {
            keys.clear();
        }
        let index: HashMap<(u32, u32), u32> = keys.iter().enumerate().map(|(i, (k, _))| (*k, n0 + i as u32)).collect();
        let mut pos = raw.positions.clone();
        pos.extend(keys.iter().map(|(_, (w, _))| *w));
        let (mut tris, mut source, mut dirty) =
            (Vec::with_capacity(raw.triangles.len() + 3 * keys.len()), Vec::new(), Vec::new());
        for (s, t) in raw.triangles.iter().enumerate() {
            let mid = |e: usize| {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                index.get(&(u.min(v), u.max(v))).copied()
            };
            let before = tris.len();
            split_triangle(*t, [mid(0), mid(1), mid(2)], &pos, &mut tris);
            source.extend(std::iter::repeat(s).take(tris.len() - before));
            if tris.len() - before > 1 {
                dirty.extend(before..tris.len());
            }
        }
        let bad = super::embed::crossing(&tris, &dirty, &pos, 2.0 * field.h);
        if bad.is_empty() {
            for (_, (w, sin_half)) in &keys {
                raw.owner.push(field.eval(*w).1);
                out.min_sin_half = out.min_sin_half.min(*sin_half);
            }
            raw.positions = pos;
            raw.triangles = tris;
            return keys.len();
        }
        for b in bad {
            let t = raw.triangles[source[b]];
            for e in 0..3 {
                let (u, v) = (t[e], t[(e + 1) % 3]);
                if let Some(w) = cand.get_mut(&(u.min(v), u.max(v))) {
                    *w = None;
                }
            }
        }
    }
    0
}

/// The outward direction of a tube holding all three corners of a piece, at its centroid.
fn facing(field: &Field, p: [V3<f64>; 3]) -> Option<V3<f64>> {
    let c = (p[0] + p[1] + p[2]) * (1.0 / 3.0);
    let tol = ON * field.h;
    let k = field.near(c)?.iter().find(|&&k| p.iter().all(|&v| field.tubes[k as usize].sdf(v) <= tol))?;
    Some(gradient(&field.tubes[*k as usize], c))
}

/// The unnormalised normal of a triangle.
fn normal(p: [V3<f64>; 3]) -> V3<f64> {
    (p[1] - p[0]).cross(p[2] - p[0])
}

/// The pieces a triangle would be split into (positions only), for the turn-over test.
fn pieces(t: &[u32; 3], pos: &[V3<f64>], cand: &Candidates) -> Vec<[V3<f64>; 3]> {
    let mut p: Vec<V3<f64>> = t.iter().map(|&i| pos[i as usize]).collect();
    let mut mids = [None; 3];
    for e in 0..3 {
        let (u, v) = (t[e], t[(e + 1) % 3]);
        if let Some(Some((w, _))) = cand.get(&(u.min(v), u.max(v))) {
            mids[e] = Some(p.len() as u32);
            p.push(*w);
        }
    }
    let mut out = Vec::new();
    split_triangle([0, 1, 2], mids, &p, &mut out);
    out.iter().map(|s| s.map(|i| p[i as usize])).collect()
}

/// Splits triangle `t` at the points `mid[e]` of its edges `e = (t[e], t[e+1])`, keeping its
/// orientation.
fn split_triangle(t: [u32; 3], mid: [Option<u32>; 3], pos: &[V3<f64>], out: &mut Vec<[u32; 3]>) {
    let count = mid.iter().flatten().count();
    // Rotate so that the split edges come first.
    let r = match count {
        1 => (0..3).find(|&e| mid[e].is_some()).unwrap_or(0),
        2 => (0..3).find(|&e| mid[(e + 2) % 3].is_none()).unwrap_or(0),
        _ => 0,
    };
    let [a, b, c] = [t[r], t[(r + 1) % 3], t[(r + 2) % 3]];
    let [m0, m1, m2] = [mid[r], mid[(r + 1) % 3], mid[(r + 2) % 3]];
    let len = |i: u32, j: u32| (pos[i as usize] - pos[j as usize]).length2();
    match (m0, m1, m2) {
        (Some(w), None, None) => out.extend([[a, w, c], [w, b, c]]),
        (Some(w0), Some(w1), None) => {
            out.push([w0, b, w1]);
            // The quad a, w0, w1, c by its shorter diagonal.
            if len(a, w1) <= len(w0, c) {
                out.extend([[a, w0, w1], [a, w1, c]]);
            } else {
                out.extend([[a, w0, c], [w0, w1, c]]);
            }
        }
        (Some(w0), Some(w1), Some(w2)) => out.extend([[a, w0, w2], [w0, b, w1], [w2, w1, c], [w0, w1, w2]]),
        _ => out.push(t),
    }
}

/// A point of the crease between the tubes of two vertices, near the segment between them,
/// with `sin(β/2)` there (`β` the exterior opening); `None` where the tubes do not meet
/// near it (Newton does not converge within a grid step), the crease is buried in a third
/// tube, or the surfaces are too close to parallel to place it.
fn crease_point(field: &Field, xu: V3<f64>, xv: V3<f64>) -> Option<(V3<f64>, f64)> {
    let h = field.h;
    let pick = |x: V3<f64>, other: V3<f64>| {
        on_tubes(field, x).into_iter().min_by(|&i, &j| {
            let (fi, fj) = (field.tubes[i as usize].sdf(other), field.tubes[j as usize].sdf(other));
            fi.total_cmp(&fj)
        })
    };
    let (ka, kb) = (pick(xu, xv)?, pick(xv, xu)?);
    let (ta, tb) = (&field.tubes[ka as usize], &field.tubes[kb as usize]);
    // On the segment, g = f_A − f_B goes from ≤ 0 (u on A) to ≥ 0 (v on B): bisect it.
    let g = |t: f64| {
        let x = xu + (xv - xu) * t;
        ta.sdf(x) - tb.sdf(x)
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    if g(lo) > 0.0 || g(hi) < 0.0 {
        return None;
    }
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if g(m) <= 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    let start = xu + (xv - xu) * lo;
    let mut x = start;
    let mut c = 0.0;
    for _ in 0..30 {
        let (fa, fb) = (ta.sdf(x), tb.sdf(x));
        let (ga, gb) = (gradient(ta, x), gradient(tb, x));
        c = ga.dot(gb);
        let det = 1.0 - c * c;
        if det < 1e-8 {
            return None;
        }
        // Least-norm step to the two tangent planes: x − Jᵀ(JJᵀ)⁻¹F.
        let (l0, l1) = ((fa - c * fb) / det, (fb - c * fa) / det);
        x = x - ga * l0 - gb * l1;
        if (x - start).length() > h {
            return None;
        }
        if fa.abs().max(fb.abs()) <= 1e-13 * h && (l0.abs() + l1.abs()) <= 1e-12 * h {
            break;
        }
    }
    let (fa, fb) = (ta.sdf(x), tb.sdf(x));
    if fa.abs().max(fb.abs()) > ON * h || field.eval(x).0 < -ON * h {
        return None;
    }
    Some((x, (0.5 * (1.0 + c)).max(0.0).sqrt()))
}
