//! Triple points: where three tubes meet, three creases meet, and the triangle between their
//! split points has no tube holding all its corners (each corner is on two of the three). The
//! point where all three surfaces meet (`f_A = f_B = f_C = 0`, Newton's method on the three
//! exact SDFs) fans it into three triangles, each with its corners on one tube.

use super::crease::{on_tubes, ON};
use super::field::{gradient, Field};
use super::grid::Raw;
use tubecast::{Primitive, V3};

/// Fans every triangle whose corners span exactly three tubes and share none around the
/// three tubes' common point; returns how many. Fans that would cross another triangle are
/// not made.
pub(super) fn fan(field: &Field, raw: &mut Raw) -> usize {
    let mut plan: Vec<(usize, V3<f64>)> = Vec::new();
    for (k, t) in raw.triangles.iter().enumerate() {
        let sets: Vec<Vec<u32>> = t.iter().map(|&i| on_tubes(field, raw.positions[i as usize])).collect();
        if sets[0].iter().any(|a| sets[1].contains(a) && sets[2].contains(a)) {
            continue;
        }
        let mut all: Vec<u32> = sets.concat();
        all.sort_unstable();
        all.dedup();
        if all.len() != 3 {
            continue;
        }
        let c = t.iter().fold(V3::zero(), |s, &i| s + raw.positions[i as usize]) * (1.0 / 3.0);
        if let Some(x) = meet(field, [all[0], all[1], all[2]], c) {
            plan.push((k, x));
        }
    }
    for _ in 0..4 {
        let n0 = raw.positions.len() as u32;
        let mut pos = raw.positions.clone();
        let mut tris = raw.triangles.clone();
        let mut dirty = Vec::new();
        let mut of = Vec::new();
        for (j, &(k, x)) in plan.iter().enumerate() {
            pos.push(x);
            let [a, b, c] = raw.triangles[k];
            let m = n0 + j as u32;
            tris[k] = [a, b, m];
            tris.push([b, c, m]);
            tris.push([c, a, m]);
            dirty.extend([k, tris.len() - 2, tris.len() - 1]);
            of.extend([j, j, j]);
        }
        let bad = super::embed::crossing(&tris, &dirty, &pos, 2.0 * field.h);
        if bad.is_empty() {
            let n = plan.len();
            raw.owner.extend(plan.iter().map(|&(_, x)| field.eval(x).1));
            raw.positions = pos;
            raw.triangles = tris;
            return n;
        }
        let drop: std::collections::HashSet<usize> =
            bad.iter().map(|&b| of[dirty.iter().position(|&d| d == b).unwrap_or(0)]).collect();
        plan = plan.into_iter().enumerate().filter(|(j, _)| !drop.contains(j)).map(|(_, p)| p).collect();
    }
    0
}

/// The point near `start` where the three tubes' surfaces meet, on the union's surface.
pub(super) fn meet(field: &Field, k: [u32; 3], start: V3<f64>) -> Option<V3<f64>> {
    let t = k.map(|i| &field.tubes[i as usize]);
    let mut x = start;
    for _ in 0..30 {
        let f = t.map(|t| t.sdf(x));
        let g = [gradient(t[0], x), gradient(t[1], x), gradient(t[2], x)];
        // Solve G·dx = f with the gradients as rows (Cramer's rule).
        let det = g[0].dot(g[1].cross(g[2]));
        if det.abs() < 1e-6 {
            return None;
        }
        let (c0, c1, c2) = (g[1].cross(g[2]), g[2].cross(g[0]), g[0].cross(g[1]));
        let dx = (c0 * f[0] + c1 * f[1] + c2 * f[2]) * (1.0 / det);
        x -= dx;
        if (x - start).length() > 2.0 * field.h {
            return None;
        }
        if dx.length() <= 1e-13 * field.h {
            break;
        }
    }
    let tol = ON * field.h;
    (t.iter().all(|t| t.sdf(x).abs() <= tol) && field.eval(x).0 >= -tol).then_some(x)
}
