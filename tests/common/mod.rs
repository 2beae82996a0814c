//! Independent oracles and case generators for the link kernels.
//!
//! Nothing here calls the kernels under test. The oracle works on the *sphere-sweep*
//! definition of a link, `⋃_{u∈[0,1]} B(p(u), r(u))` with `p`, `r` linear, in f64:
//!
//! * `sweep_dist(x)`: `min_u |x − p(u)| − r(u)`. The function of `u` is convex (a norm of an
//!   affine map minus a linear one), so golden-section search finds the global minimum. Outside
//!   the solid it is the exact Euclidean distance; its zero set is the surface; its gradient is
//!   `(x − p(u*))/|x − p(u*)|` (envelope theorem), the outward normal.
//! * `line_gap(ray)`: `min_u dist(line, p(u)) − r(u)`, also convex in `u`: the signed distance
//!   of the line to the solid (< 0: the line enters it).
//! * `line_interval(ray)`: the line enters the union when it enters one of its spheres, so
//!   `t_in = min_u t_in(u)` and `t_out = max_u t_out(u)` over the `u` where the line meets
//!   `B(p(u), r(u))` — an interval `[u0, u1]` (a sublevel set of the convex `line_gap` integrand),
//!   found by bisection; the min/max over it by dense sampling plus golden-section refinement.
#![allow(dead_code)]

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tubecast::{Ray, RoundCone, V3};

pub type V = V3<f64>;

pub fn p_at(l: &RoundCone<f64>, u: f64) -> V {
    l.a + (l.b - l.a) * u
}
pub fn r_at(l: &RoundCone<f64>, u: f64) -> f64 {
    l.ra + (l.rb - l.ra) * u
}

/// Golden-section minimisation of a unimodal function on [lo, hi]; returns (argmin, min),
/// comparing with both end points.
pub fn golden_min(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo, hi);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= 1e-17 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let mut best = ((a + b) / 2.0, f((a + b) / 2.0));
    for x in [lo, hi, c, d] {
        let v = f(x);
        if v < best.1 {
            best = (x, v);
        }
    }
    best
}

/// Minimiser of a convex differentiable function on [0, 1] by bisection on the sign of its
/// derivative `df` (monotone): resolves the argmin to ~1 ulp, where golden-section search on
/// values only resolves it to ~√ε (the function is flat to second order there).
pub fn convex_argmin(df: impl Fn(f64) -> f64) -> f64 {
    if df(0.0) >= 0.0 {
        return 0.0;
    }
    if df(1.0) <= 0.0 {
        return 1.0;
    }
    let (mut a, mut b) = (0.0f64, 1.0f64);
    for _ in 0..1100 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if df(m) < 0.0 {
            a = m
        } else {
            b = m
        }
    }
    0.5 * (a + b)
}

/// (min_u |x − p(u)| − r(u), argmin u).
pub fn sweep_dist(l: &RoundCone<f64>, x: V) -> (f64, f64) {
    // f(u) = |x − p(u)| − r(u); f'(u) = −(x − p(u))·v/|x − p(u)| − (rb − ra).
    let v = l.b - l.a;
    let dr = l.rb - l.ra;
    let u = convex_argmin(|u| {
        let w = x - p_at(l, u);
        let n = w.length();
        if n == 0.0 {
            return 0.0;
        }
        -w.dot(v) / n - dr
    });
    ((x - p_at(l, u)).length() - r_at(l, u), u)
}

/// Outward unit normal of the sweep at (or near) x.
pub fn sweep_normal(l: &RoundCone<f64>, x: V) -> V {
    let (_, u) = sweep_dist(l, x);
    let g = x - p_at(l, u);
    g * (1.0 / g.length())
}

fn line_dist(ray: &Ray<f64>, c: V) -> f64 {
    let d2 = ray.d.length2();
    let f = ray.o - c;
    let tc = -f.dot(ray.d) / d2;
    (f + ray.d * tc).length()
}

/// The sweep's signed distance from the ray's line, and its argmin u.
pub fn line_gap(l: &RoundCone<f64>, ray: &Ray<f64>) -> (f64, f64) {
    let (u, v) = golden_min(|u| line_dist(ray, p_at(l, u)) - r_at(l, u), 0.0, 1.0);
    (v, u)
}

/// Line–sphere (t_in, t_out) for sphere u, if the line meets it.
fn sphere_ts(l: &RoundCone<f64>, ray: &Ray<f64>, u: f64) -> Option<(f64, f64)> {
    let c = p_at(l, u);
    let r = r_at(l, u);
    let d2 = ray.d.length2();
    let f = ray.o - c;
    let tc = -f.dot(ray.d) / d2;
    let q = f + ray.d * tc;
    let h2 = (r * r - q.length2()) / d2;
    if h2 < 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some((tc - h, tc + h))
}

/// Oracle line interval: Some((t_in, u_in, t_out, u_out)) if the line meets the sweep.
pub fn line_interval(l: &RoundCone<f64>, ray: &Ray<f64>) -> Option<(f64, f64, f64, f64)> {
    let (gap, us) = line_gap(l, ray);
    if gap > 0.0 {
        return None;
    }
    // [u0, u1] = {u : line_dist(p(u)) ≤ r(u)} by bisection from the argmin outwards.
    let inside = |u: f64| line_dist(ray, p_at(l, u)) - r_at(l, u) <= 0.0;
    let edge = |from: f64, to: f64| {
        if inside(to) {
            return to;
        }
        let (mut a, mut b) = (from, to);
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if inside(m) {
                a = m
            } else {
                b = m
            }
        }
        a
    };
    let (u0, u1) = (edge(us, 0.0), edge(us, 1.0));
    let tin = |u: f64| sphere_ts(l, ray, u.clamp(u0, u1)).map(|s| s.0).unwrap_or(f64::INFINITY);
    let tout = |u: f64| sphere_ts(l, ray, u.clamp(u0, u1)).map(|s| -s.1).unwrap_or(f64::INFINITY);
    let refine = |f: &dyn Fn(f64) -> f64| {
        let n = 64;
        let mut best = (us, f(us));
        for i in 0..=n {
            let u = u0 + (u1 - u0) * i as f64 / n as f64;
            let v = f(u);
            if v < best.1 {
                best = (u, v);
            }
        }
        let w = (u1 - u0) / n as f64;
        let (u, v) = golden_min(f, (best.0 - w).max(u0), (best.0 + w).min(u1));
        if v < best.1 {
            (u, v)
        } else {
            best
        }
    };
    let (ui, ti) = refine(&tin);
    let (uo, to) = refine(&tout);
    Some((ti, ui, -to, uo))
}

/// The hard regions the generators aim at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    Random,
    Grazing,
    NearEqualRadii,
    AlmostInside,
    SphereInside,
    LongThin,
    FarOrigin,
    Inside,
    AxisParallel,
    ZeroRadiusEnd,
    ZeroLength,
}

pub const REGIONS: [Region; 11] = [
    Region::Random,
    Region::Grazing,
    Region::NearEqualRadii,
    Region::AlmostInside,
    Region::SphereInside,
    Region::LongThin,
    Region::FarOrigin,
    Region::Inside,
    Region::AxisParallel,
    Region::ZeroRadiusEnd,
    Region::ZeroLength,
];

#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub link: RoundCone<f64>,
    pub ray: Ray<f64>,
    pub region: Region,
    /// Characteristic size: max(L, ra, rb).
    pub size: f64,
}

fn unit(rng: &mut StdRng) -> V {
    loop {
        let v = V::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v * (1.0 / l);
        }
    }
}

fn perp(v: V, rng: &mut StdRng) -> V {
    let w = unit(rng);
    let p = w - v * w.dot(v);
    p * (1.0 / p.length())
}

/// A deterministic case from a seed, aimed at `region`. Scales range over 1e-4 … 1e4.
pub fn make_case(seed: u64, region: Region) -> Case {
    let mut rng = StdRng::seed_from_u64(seed);
    let scale = 10f64.powf(rng.gen_range(-4.0..4.0));
    let centre = V::new(rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0)) * scale;
    let axis = unit(&mut rng);
    let mut len = rng.gen_range(0.2..4.0) * scale;
    let mut ra = rng.gen_range(0.05..1.0) * scale;
    let mut rb = rng.gen_range(0.05..1.0) * scale;
    match region {
        Region::NearEqualRadii => rb = ra * (1.0 + rng.gen_range(-1e-7..1e-7)),
        Region::AlmostInside => {
            let big = ra.max(rb);
            let frac = 1.0 - 10f64.powf(rng.gen_range(-9.0..-3.0));
            len = big * rng.gen_range(0.3..0.9);
            let small = big - len * frac;
            if rng.gen_bool(0.5) {
                ra = big;
                rb = small;
            } else {
                rb = big;
                ra = small;
            }
        }
        Region::SphereInside => {
            ra = rng.gen_range(0.5..1.0) * scale;
            rb = ra * rng.gen_range(0.05..0.5);
            len = (ra - rb) * rng.gen_range(0.0..0.999);
            if rng.gen_bool(0.5) {
                core::mem::swap(&mut ra, &mut rb);
            }
        }
        Region::LongThin => {
            ra = len * 1e-4 * rng.gen_range(0.5..1.5);
            rb = len * 1e-4 * rng.gen_range(0.5..1.5);
        }
        Region::ZeroRadiusEnd => {
            if rng.gen_bool(0.5) {
                ra = 0.0
            } else {
                rb = 0.0
            }
        }
        Region::ZeroLength => len = 0.0,
        _ => {}
    }
    let a = centre - axis * (len / 2.0);
    let b = centre + axis * (len / 2.0);
    let link = RoundCone::new(a, ra, b, rb).expect("generated link is valid");
    let size = len.max(ra).max(rb);
    // Ray target: near the link.
    let u: f64 = rng.gen_range(-0.2..1.2);
    let (ref_pt, ref_r) = (link.a + (link.b - link.a) * u.clamp(0.0, 1.0), ra + (rb - ra) * u.clamp(0.0, 1.0));
    let mut dir = unit(&mut rng);
    let target;
    match region {
        Region::Grazing => {
            // A surface point with its outward normal (from the independent oracle), then a
            // tangent direction through a point offset along the normal by ±(1e-12 … 1e-2)·size.
            let probe = ref_pt + perp(axis, &mut rng) * (ref_r + size);
            let (dist, _) = sweep_dist(&link, probe);
            let n = sweep_normal(&link, probe);
            let on = probe - n * dist;
            let off = 10f64.powf(rng.gen_range(-12.0..-2.0)) * size * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
            target = on + n * off;
            dir = perp(n, &mut rng);
        }
        Region::AxisParallel => {
            target = ref_pt + perp(axis, &mut rng) * (ref_r * rng.gen_range(0.0..1.3));
            dir = if rng.gen_bool(0.5) { axis } else { -axis };
        }
        Region::Inside => {
            target = ref_pt + perp(axis, &mut rng) * (ref_r * rng.gen_range(0.0..0.9));
        }
        _ => {
            target = ref_pt + unit(&mut rng) * (ref_r * rng.gen_range(0.0..1.5));
        }
    }
    let dist = match region {
        Region::FarOrigin => 1e4 * size * rng.gen_range(1.0..3.0),
        Region::Inside => 0.0,
        _ => size * rng.gen_range(2.0..10.0),
    };
    let dlen = 10f64.powf(rng.gen_range(-2.0..2.0));
    let ray = Ray::new(target - dir * dist, dir * dlen);
    Case { link, ray, region, size }
}

/// Rounding each input coordinate to f32 and back: the f32 problem, exactly, in f64.
pub fn round_case_f32(c: &Case) -> Case {
    let r = |x: f64| x as f32 as f64;
    let v = |p: V| V::new(r(p.x), r(p.y), r(p.z));
    Case {
        link: RoundCone { a: v(c.link.a), ra: r(c.link.ra), b: v(c.link.b), rb: r(c.link.rb) },
        ray: Ray { o: v(c.ray.o), d: v(c.ray.d), t_min: r(c.ray.t_min), t_max: c.ray.t_max },
        ..*c
    }
}
