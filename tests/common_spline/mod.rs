//! Shared helpers of the spline tests: random segments and rays, and an independent
//! dense-sampling oracle of the quadratic sphere sweep (f64).
#![allow(dead_code)]

use proptest::prelude::*;
use tubecast::QuadTube;
use tubecast::V3;

/// `p(t)`, `r(t)` of a quadratic Bézier tube written out directly (independent of the crate).
pub fn eval(b: &[[f64; 3]; 3], r: &[f64; 3], t: f64) -> ([f64; 3], f64) {
    let s = 1.0 - t;
    let w = [s * s, 2.0 * s * t, t * t];
    let mut p = [0.0; 3];
    for k in 0..3 {
        p[k] = w[0] * b[0][k] + w[1] * b[1][k] + w[2] * b[2][k];
    }
    (p, w[0] * r[0] + w[1] * r[1] + w[2] * r[2])
}

/// Ray–sphere entry and exit along a ray `o + s·d` (any `d ≠ 0`), plain textbook quadratic.
pub fn sphere_hit(o: [f64; 3], d: [f64; 3], c: [f64; 3], r: f64) -> Option<(f64, f64)> {
    let f = [o[0] - c[0], o[1] - c[1], o[2] - c[2]];
    let a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    let cc = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
    let disc = b * b - a * cc;
    if disc < 0.0 || r <= 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    Some(((-b - sq) / a, (-b + sq) / a))
}

/// The oracle: entry = min over t of the sphere entry, exit = max of the sphere exit, by
/// `n` uniform samples and golden-section refinement (to 1e-13 in t) around the best
/// sample. Returns `(t_in, u_in, t_out, u_out, depth)` where `depth` is the largest
/// `√(disc)/|d|` (half chord) seen: how robust the hit is.
pub fn oracle(
    b: &[[f64; 3]; 3],
    r: &[f64; 3],
    o: [f64; 3],
    d: [f64; 3],
    n: usize,
) -> Option<(f64, f64, f64, f64, f64)> {
    let ent = |t: f64| {
        let (p, rr) = eval(b, r, t);
        sphere_hit(o, d, p, rr).map(|x| x.0).unwrap_or(f64::INFINITY)
    };
    let ext = |t: f64| {
        let (p, rr) = eval(b, r, t);
        sphere_hit(o, d, p, rr).map(|x| -x.1).unwrap_or(f64::INFINITY)
    };
    let mut depth: f64 = -1.0;
    let (mut bi, mut ki, mut bo, mut ko) = (f64::INFINITY, 0, f64::INFINITY, 0);
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (p, rr) = eval(b, r, t);
        if let Some((a, c)) = sphere_hit(o, d, p, rr) {
            depth = depth.max((c - a) * 0.5);
            if a < bi {
                bi = a;
                ki = k;
            }
            if -c < bo {
                bo = -c;
                ko = k;
            }
        }
    }
    if depth < 0.0 {
        return None;
    }
    let refine = |f: &dyn Fn(f64) -> f64, k: usize| {
        let h = 1.0 / n as f64;
        let (mut a, mut c) = (((k as f64) - 1.0) * h, ((k as f64) + 1.0) * h);
        a = a.max(0.0);
        c = c.min(1.0);
        let gr = 0.5 * (5f64.sqrt() - 1.0);
        let mut x1 = c - gr * (c - a);
        let mut x2 = a + gr * (c - a);
        let (mut f1, mut f2) = (f(x1), f(x2));
        while c - a > 1e-13 {
            if f1 < f2 {
                c = x2;
                x2 = x1;
                f2 = f1;
                x1 = c - gr * (c - a);
                f1 = f(x1);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + gr * (c - a);
                f2 = f(x2);
            }
        }
        let cands = [a, c, 0.5 * (a + c), k as f64 * h];
        let mut best = (f(cands[3]), cands[3]);
        for &x in &cands {
            if f(x) < best.0 {
                best = (f(x), x);
            }
        }
        best
    };
    let (vi, ui) = refine(&ent, ki);
    let (vo, uo) = refine(&ext, ko);
    Some((vi, ui, -vo, uo, depth))
}

/// A random, validated quadratic tube of size ~1 near `centre`, radii in `[rmin, rmax]`.
pub fn tube_strategy(rmin: f64, rmax: f64) -> impl Strategy<Value = ([[f64; 3]; 3], [f64; 3])> {
    let p = || prop::array::uniform3(-1.0f64..1.0);
    (p(), p(), p(), prop::array::uniform3(rmin..rmax)).prop_map(|(a, b, c, r)| ([a, b, c], r))
}

/// A ray aimed at a random point near the segment, from distance ~5.
pub fn ray_strategy() -> impl Strategy<Value = ([f64; 3], [f64; 3])> {
    (prop::array::uniform3(-1.5f64..1.5), prop::array::uniform3(-1.0f64..1.0)).prop_filter_map(
        "direction",
        |(target, dir)| {
            let l = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
            if l < 0.2 {
                return None;
            }
            let o = [target[0] - 5.0 * dir[0] / l, target[1] - 5.0 * dir[1] / l, target[2] - 5.0 * dir[2] / l];
            Some((o, dir))
        },
    )
}

/// Crate tube from arrays.
pub fn tube(b: &[[f64; 3]; 3], r: &[f64; 3]) -> QuadTube<f64> {
    QuadTube::new([V3::from(b[0]), V3::from(b[1]), V3::from(b[2])], *r).expect("valid tube")
}

/// Scale of a tube query: max control-point distance from b₀ plus max radius plus the
/// ray's distance to b₀ — the magnitude the ray-space coordinates can reach.
pub fn scale(b: &[[f64; 3]; 3], r: &[f64; 3]) -> f64 {
    let mut s: f64 = 0.0;
    for p in b {
        for k in 0..3 {
            s = s.max((p[k] - b[0][k]).abs());
        }
    }
    s * 3f64.sqrt() + r.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Proptest config: `PROPTEST_CASES` (read by proptest itself) overrides `default`; the
/// defaults are small so that `cargo test` stays fast.
pub fn config(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(default);
    ProptestConfig {
        cases,
        max_global_rejects: 20 * cases + 1024,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Measure (in t) of the set of spheres the ray's line meets, by `n` uniform samples.
pub fn hit_measure(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], d: [f64; 3], n: usize) -> f64 {
    let hits = (0..=n)
        .filter(|&k| {
            let (p, rr) = eval(b, r, k as f64 / n as f64);
            sphere_hit(o, d, p, rr).is_some()
        })
        .count();
    hits as f64 / (n + 1) as f64
}
