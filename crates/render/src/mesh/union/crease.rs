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
        snap(field, raw);
        let n = round(field, raw, &mut out);
        flip(field, raw);
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

/// Where a crease passes within this fraction of an edge of one of its ends, that end is moved
/// onto the crease instead of the edge being split: splitting there would leave a sliver that
/// turns over at the least error in the crease point.
const SNAP: f64 = 0.4;

/// Moves vertices that lie near a crease onto it (to the crease point of one of their crossing
/// edges, the nearest), so that their edges to either tube no longer cross it. A vertex is
/// moved only when none of the triangles around it shares a corner with another moved one's,
/// and kept where it was when a triangle around it would turn over (against its tube's
/// outward direction, or its own former normal) or cross another triangle. Returns how many
/// moved.
fn snap(field: &Field, raw: &mut Raw) -> usize {
    let on: Vec<Vec<u32>> = raw.positions.iter().map(|&x| on_tubes(field, x)).collect();
    let mut want: HashMap<u32, (f64, V3<f64>)> = HashMap::new();
    let mut seen: HashMap<(u32, u32), ()> = HashMap::new();
    let mut ring: Vec<Vec<usize>> = vec![Vec::new(); raw.positions.len()];
    for (k, t) in raw.triangles.iter().enumerate() {
        for e in 0..3 {
            ring[t[e] as usize].push(k);
            let (u, v) = (t[e].min(t[(e + 1) % 3]), t[e].max(t[(e + 1) % 3]));
            if seen.insert((u, v), ()).is_some() || on[u as usize].iter().any(|k| on[v as usize].contains(k)) {
                continue;
            }
            let (xu, xv) = (raw.positions[u as usize], raw.positions[v as usize]);
            let Some((w, _)) = crease_point(field, xu, xv) else { continue };
            let d = xv - xu;
            let s = (w - xu).dot(d) / d.length2();
            for (end, x, near) in [(u, xu, s < SNAP), (v, xv, s > 1.0 - SNAP)] {
                let dist = (w - x).length();
                if near && want.get(&end).map_or(true, |&(d0, _)| dist < d0) {
                    want.insert(end, (dist, w));
                }
            }
        }
    }
    let mut order: Vec<(u32, f64, V3<f64>)> = want.into_iter().map(|(v, (d, w))| (v, d, w)).collect();
    order.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    for _ in 0..4 {
        // An independent set: no two moved vertices on one triangle's corners' rings.
        let mut taken = vec![false; raw.positions.len()];
        let mut moved = Vec::new();
        for &(v, _, w) in &order {
            let touch = ring[v as usize].iter().flat_map(|&k| raw.triangles[k]);
            if touch.clone().any(|c| taken[c as usize]) {
                continue;
            }
            touch.for_each(|c| taken[c as usize] = true);
            moved.push((v, w));
        }
        if moved.is_empty() {
            return 0;
        }
        let mut pos = raw.positions.clone();
        for &(v, w) in &moved {
            pos[v as usize] = w;
        }
        let mut dirty: Vec<usize> = moved.iter().flat_map(|&(v, _)| ring[v as usize].iter().copied()).collect();
        dirty.sort_unstable();
        dirty.dedup();
        let mut bad: Vec<usize> = dirty
            .iter()
            .copied()
            .filter(|&k| {
                let t = raw.triangles[k];
                let p = t.map(|i| pos[i as usize]);
                let n0 = normal(t.map(|i| raw.positions[i as usize]));
                facing(field, p).unwrap_or(n0).dot(normal(p)) <= 0.0
            })
            .collect();
        if bad.is_empty() {
            bad = super::embed::crossing(&raw.triangles, &dirty, &pos, 2.0 * field.h);
        }
        if bad.is_empty() {
            raw.positions = pos;
            return moved.len();
        }
        let drop: std::collections::HashSet<u32> = bad.iter().flat_map(|&k| raw.triangles[k]).collect();
        order.retain(|(v, _, _)| !drop.contains(v) || !moved.iter().any(|m| m.0 == *v));
    }
    0
}

/// Flips crease-crossing edges whose two triangles' far corners are both on each side's tube
/// (typically on the crease itself, split or snapped there): triangles `u v p` and `v u q`,
/// `u` on tube A only and `v` on B, become `u q p` (all on A) and `v p q` (all on B). Where a
/// crease passes through a vertex, the split point of the edge beside it is that vertex to
/// rounding, and the split's pieces would be slivers that turn over; the flip needs no new
/// point. A flip is kept only where the edge `p q` is new (the mesh stays 2-manifold) and
/// neither new triangle turns over or crosses another. Returns how many were made.
fn flip(field: &Field, raw: &mut Raw) -> usize {
    let on: Vec<Vec<u32>> = raw.positions.iter().map(|&x| on_tubes(field, x)).collect();
    let share = |a: &[u32], b: &[u32], c: &[u32]| a.iter().any(|k| b.contains(k) && c.contains(k));
    let mut edge: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, t) in raw.triangles.iter().enumerate() {
        for e in 0..3 {
            edge.insert((t[e], t[(e + 1) % 3]), k);
        }
    }
    let mut plan: Vec<(usize, usize, [u32; 3], [u32; 3])> = Vec::new();
    let mut used = vec![false; raw.triangles.len()];
    for (k, t) in raw.triangles.iter().enumerate() {
        for e in 0..3 {
            let (u, v, p) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            let (ou, ov) = (&on[u as usize], &on[v as usize]);
            if used[k] || ou.iter().any(|x| ov.contains(x)) {
                continue;
            }
            let Some(&k2) = edge.get(&(v, u)) else { continue };
            let t2 = raw.triangles[k2];
            let Some(q) = t2.iter().copied().find(|&x| x != u && x != v) else { continue };
            let (op, oq) = (&on[p as usize], &on[q as usize]);
            if used[k2] || p == q || edge.contains_key(&(p, q)) || edge.contains_key(&(q, p)) {
                continue;
            }
            if !(share(ou, oq, op) && share(ov, op, oq)) {
                continue;
            }
            used[k] = true;
            used[k2] = true;
            plan.push((k, k2, [u, q, p], [v, p, q]));
        }
    }
    for _ in 0..4 {
        if plan.is_empty() {
            return 0;
        }
        let mut tris = raw.triangles.clone();
        let mut dirty = Vec::new();
        for &(k, k2, a, b) in &plan {
            tris[k] = a;
            tris[k2] = b;
            dirty.extend([k, k2]);
        }
        let pos = &raw.positions;
        let mut bad: Vec<usize> = dirty
            .iter()
            .copied()
            .filter(|&k| {
                let p = tris[k].map(|i| pos[i as usize]);
                let n0 = normal(raw.triangles[k].map(|i| pos[i as usize]));
                facing(field, p).unwrap_or(n0).dot(normal(p)) <= 0.0
            })
            .collect();
        if bad.is_empty() {
            bad = super::embed::crossing(&tris, &dirty, pos, 2.0 * field.h);
        }
        if bad.is_empty() {
            let n = plan.len();
            raw.triangles = tris;
            return n;
        }
        plan.retain(|&(k, k2, _, _)| !bad.contains(&k) && !bad.contains(&k2));
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

/// Samples along an edge when looking for the first tube below the start's.
const SCAN: usize = 32;

/// The first tube `k ≠ a` with `f_k < f_a` at one of [`SCAN`] samples along `xu → xv`, with
/// the parameters of the sample before it and of that sample; `None` where none is.
fn first_undercut(field: &Field, a: u32, xu: V3<f64>, xv: V3<f64>) -> Option<(u32, f64, f64)> {
    let ta = &field.tubes[a as usize];
    for j in 1..=SCAN {
        let t = j as f64 / SCAN as f64;
        let x = xu + (xv - xu) * t;
        let fa = ta.sdf(x);
        let below = field.near(x)?.iter().copied().filter(|&k| k != a).map(|k| (field.tubes[k as usize].sdf(x), k));
        if let Some((f, k)) = below.min_by(|p, q| p.0.total_cmp(&q.0)) {
            if f < fa {
                return Some((k, (j - 1) as f64 / SCAN as f64, t));
            }
        }
    }
    None
}

/// How far a crease point may lie from the point of the crossing edge it is found from, for a
/// crease of exterior opening β (`sin_half = sin(β/2)`): a wedge of opening β holds a ball of
/// radius `d·sin(β/2)` centred `d` above its edge, and every ball of radius `√3·h/2` (a grid
/// cube's circumradius) holds a grid vertex, so above `d = √3·h/(2·sin(β/2))` the contour sees
/// the notch; its bridging edges lie within a cube's diagonal `√3·h` of that. A guard against
/// converging on an unrelated crease, not part of the certificate (which measures every
/// triangle as made).
fn reach(h: f64, sin_half: f64) -> f64 {
    3f64.sqrt() * h * (1.0 + 0.5 / sin_half.max(1e-3))
}

/// A point of the crease between the tubes of two vertices, near the segment between them,
/// with `sin(β/2)` there (`β` the exterior opening); `None` where the tubes do not meet
/// near it (Newton leaves [`reach`]), the crease is buried in a third tube and neither its
/// crease with that tube nor the three tubes' common point is near, or the surfaces are too
/// close to parallel to place it.
fn crease_point(field: &Field, xu: V3<f64>, xv: V3<f64>) -> Option<(V3<f64>, f64)> {
    let pick = |x: V3<f64>, other: V3<f64>| {
        on_tubes(field, x).into_iter().min_by(|&i, &j| {
            let (fi, fj) = (field.tubes[i as usize].sdf(other), field.tubes[j as usize].sdf(other));
            fi.total_cmp(&fj)
        })
    };
    let ka = pick(xu, xv)?;
    let kv = pick(xv, xu)?;
    // First the tube that first undercuts A along the edge: where a third tube lies between
    // the ends' tubes the edge crosses two creases, and the crease of the ends' tubes is
    // buried in the third; the first crease is split here, the second in the next round (its
    // piece runs from this point, on A and the third tube, to v). Then v's own tube.
    let first = first_undercut(field, ka, xu, xv).filter(|&(k, _, _)| k != kv);
    first
        .and_then(|(k, lo, hi)| crease_between(field, [ka, k], xu, xv, [lo, hi]))
        .or_else(|| crease_between(field, [ka, kv], xu, xv, [0.0, 1.0]))
}

/// The crease point of tubes `k[0]` (least at `xu`) and `k[1]`, from the root of
/// `f_A − f_B` on the part `[lo, hi]` of the segment `xu → xv`.
fn crease_between(
    field: &Field,
    k: [u32; 2],
    xu: V3<f64>,
    xv: V3<f64>,
    [mut lo, mut hi]: [f64; 2],
) -> Option<(V3<f64>, f64)> {
    let h = field.h;
    let (ta, tb) = (&field.tubes[k[0] as usize], &field.tubes[k[1] as usize]);
    // On [lo, hi], g = f_A − f_B goes from ≤ 0 (A least) to ≥ 0 (B below A): bisect it.
    let g = |t: f64| {
        let x = xu + (xv - xu) * t;
        ta.sdf(x) - tb.sdf(x)
    };
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
    let (x, sin_half) = newton(field, k, start)?;
    let (f, kc) = field.eval(x);
    if f >= -ON * h {
        return Some((x, sin_half));
    }
    if kc == u32::MAX {
        return None;
    }
    // The nearest point of A ∩ B is buried in a third tube C: under the bridging edge the
    // surface runs from A over C to B. Split at the crease of A and C (the next round splits
    // the piece from there to v), else where A, B and C meet, the visible crease's end.
    let visible = |w: &(V3<f64>, f64)| field.eval(w.0).0 >= -ON * h;
    newton(field, [k[0], kc], start).filter(visible).or_else(|| {
        let w = super::triple::meet(field, [k[0], k[1], kc], x)?;
        let s = sin_half_at(field, k, w);
        ((w - start).length() <= reach(h, s)).then_some((w, s))
    })
}

/// `sin(β/2)` of the crease of tubes `k` at `x`, β its exterior opening: the angle between
/// the outward normals is π − β, so `cos(π − β) = g_A·g_B` and `sin²(β/2) = (1 + g_A·g_B)/2`.
fn sin_half_at(field: &Field, k: [u32; 2], x: V3<f64>) -> f64 {
    let c = gradient(&field.tubes[k[0] as usize], x).dot(gradient(&field.tubes[k[1] as usize], x));
    (0.5 * (1.0 + c)).max(0.0).sqrt()
}

/// A point of `A ∩ B` (tubes `k`) near `start` by Newton's least-norm steps on the two exact
/// SDFs, with `sin(β/2)` there; `None` where it leaves [`reach`] or the surfaces are too close
/// to parallel. It may be buried in a third tube (the caller checks).
fn newton(field: &Field, k: [u32; 2], start: V3<f64>) -> Option<(V3<f64>, f64)> {
    let h = field.h;
    let (ta, tb) = (&field.tubes[k[0] as usize], &field.tubes[k[1] as usize]);
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
        if (x - start).length() > reach(h, (0.5 * (1.0 + c)).max(0.0).sqrt()) {
            return None;
        }
        if fa.abs().max(fb.abs()) <= 1e-13 * h && (l0.abs() + l1.abs()) <= 1e-12 * h {
            break;
        }
    }
    let (fa, fb) = (ta.sdf(x), tb.sdf(x));
    (fa.abs().max(fb.abs()) <= ON * h).then_some((x, (0.5 * (1.0 + c)).max(0.0).sqrt()))
}
