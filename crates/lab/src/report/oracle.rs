//! The report's reference: independent `f64` oracles of the sphere sweep and seeded case
//! generators aimed at every hard region.
//!
//! Nothing here calls the kernels being measured. The link oracle follows the test oracle of
//! `tests/common` (same method, re-written against the crate's seeded [`Rng`]): a link is the
//! sweep `⋃_{u∈[0,1]} B(p(u), r(u))` with `p`, `r` linear; `min_u (dist(line, p(u)) − r(u))` is
//! convex in `u` (golden-section search) and is the line's signed gap to the solid; the line
//! interval is `[min_u t_in(u), max_u t_out(u)]` over the `u` whose sphere the line meets, by
//! bisection for that `u` range, dense sampling and golden-section refinement. The spline oracle
//! (after `tests/common_spline`) samples the quadratic sweep densely and refines by golden section.

use tubecast::QuadTube;
use tubecast::{Ray, RoundCone, V3};
use tubecast_render::scene::generate::Rng;

type V = V3<f64>;

fn p_at(l: &RoundCone<f64>, u: f64) -> V {
    l.a + (l.b - l.a) * u
}
fn r_at(l: &RoundCone<f64>, u: f64) -> f64 {
    l.ra + (l.rb - l.ra) * u
}

/// Golden-section minimisation of a unimodal function on `[lo, hi]`: `(argmin, min)`.
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

/// Minimiser of a convex function on `[0, 1]` by bisection on the sign of its derivative.
fn convex_argmin(df: impl Fn(f64) -> f64) -> f64 {
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

/// `(min_u |x − p(u)| − r(u), argmin u)`: the exact distance outside the link.
pub fn sweep_dist(l: &RoundCone<f64>, x: V) -> (f64, f64) {
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

/// Outward unit normal of the link's surface at (or near) `x`.
pub fn sweep_normal(l: &RoundCone<f64>, x: V) -> V {
    let (_, u) = sweep_dist(l, x);
    let g = x - p_at(l, u);
    g * (1.0 / g.length())
}

fn line_dist(o: V, d: V, c: V) -> f64 {
    let f = o - c;
    let tc = -f.dot(d) / d.length2();
    (f + d * tc).length()
}

/// The link's signed distance from the ray's line (negative: the line enters the solid).
pub fn line_gap(l: &RoundCone<f64>, ray: &Ray<f64>) -> f64 {
    golden_min(|u| line_dist(ray.o, ray.d, p_at(l, u)) - r_at(l, u), 0.0, 1.0).1
}

fn sphere_ts(o: V, d: V, c: V, r: f64) -> Option<(f64, f64)> {
    let d2 = d.length2();
    let f = o - c;
    let tc = -f.dot(d) / d2;
    let q = f + d * tc;
    let h2 = (r * r - q.length2()) / d2;
    if h2 < 0.0 || r <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some((tc - h, tc + h))
}

/// Oracle line interval `(t_in, t_out)` of a link, if the line meets it.
pub fn link_interval(l: &RoundCone<f64>, ray: &Ray<f64>) -> Option<(f64, f64)> {
    let (us, gap) = golden_min(|u| line_dist(ray.o, ray.d, p_at(l, u)) - r_at(l, u), 0.0, 1.0);
    if gap > 0.0 {
        return None;
    }
    let inside = |u: f64| line_dist(ray.o, ray.d, p_at(l, u)) - r_at(l, u) <= 0.0;
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
    let ts = |u: f64| sphere_ts(ray.o, ray.d, p_at(l, u.clamp(u0, u1)), r_at(l, u.clamp(u0, u1)));
    let tin = |u: f64| ts(u).map(|s| s.0).unwrap_or(f64::INFINITY);
    let tout = |u: f64| ts(u).map(|s| -s.1).unwrap_or(f64::INFINITY);
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
    let (_, ti) = refine(&tin);
    let (_, to) = refine(&tout);
    if !(ti.is_finite() && to.is_finite()) {
        return None;
    }
    Some((ti, -to))
}

/// Failure regions of the link kernels (the case mix of `tests/link_props.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LinkRegion {
    /// Rays aimed near a random link.
    Random,
    /// Rays tangent to the surface, offset by ±(1e-12 … 1e-2)·size along the normal.
    Grazing,
    /// Radii equal to a relative 1e-7 (the apex of Han's cone goes to infinity).
    NearEqualRadii,
    /// One sphere almost inside the other (a nearly flat stump, cos θ → 0).
    AlmostInside,
    /// One sphere inside the other (the link is the larger sphere).
    SphereInside,
    /// Radii 1e-4 of the length.
    LongThin,
    /// Ray origins 10⁴ sizes away.
    FarOrigin,
    /// Rays starting inside the link.
    Inside,
    /// Rays parallel to the link's axis.
    AxisParallel,
    /// One radius exactly zero (a cone tip).
    ZeroRadiusEnd,
}

/// Every link region, in chart order.
pub const LINK_REGIONS: [LinkRegion; 10] = [
    LinkRegion::Random,
    LinkRegion::Grazing,
    LinkRegion::NearEqualRadii,
    LinkRegion::AlmostInside,
    LinkRegion::SphereInside,
    LinkRegion::LongThin,
    LinkRegion::FarOrigin,
    LinkRegion::Inside,
    LinkRegion::AxisParallel,
    LinkRegion::ZeroRadiusEnd,
];

impl LinkRegion {
    /// Short name used in tables and charts.
    pub fn name(self) -> &'static str {
        match self {
            Self::Random => "random",
            Self::Grazing => "grazing",
            Self::NearEqualRadii => "near-equal-radii",
            Self::AlmostInside => "almost-inside",
            Self::SphereInside => "sphere-inside-sphere",
            Self::LongThin => "long-thin",
            Self::FarOrigin => "far-origin",
            Self::Inside => "ray-starts-inside",
            Self::AxisParallel => "axis-parallel",
            Self::ZeroRadiusEnd => "zero-radius-end",
        }
    }
}

/// One link test case. The inputs are `f32`-representable (rounded from the generated `f64`
/// values), so every precision and Embree see exactly the same problem, and the `f64` oracle
/// solves that problem exactly.
#[derive(Clone, Copy, Debug)]
pub struct LinkCase {
    /// The link.
    pub link: RoundCone<f64>,
    /// The ray (range `[0, ∞)`).
    pub ray: Ray<f64>,
    /// Its region.
    pub region: LinkRegion,
    /// Characteristic size `max(L, ra, rb)`.
    pub size: f64,
}

fn unit(rng: &mut Rng) -> V {
    V::from(rng.unit())
}

fn perp(v: V, rng: &mut Rng) -> V {
    loop {
        let w = unit(rng);
        let p = w - v * w.dot(v);
        if p.length() > 0.1 {
            return p * (1.0 / p.length());
        }
    }
}

fn r32(x: f64) -> f64 {
    x as f32 as f64
}
fn v32(p: V) -> V {
    V::new(r32(p.x), r32(p.y), r32(p.z))
}

/// A deterministic link case for `seed`, aimed at `region`. Scales range over 1e-4 … 1e4.
pub fn link_case(seed: u64, region: LinkRegion) -> LinkCase {
    let mut rng = Rng::new(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5DEE_CE66);
    let coin = |rng: &mut Rng| rng.uniform() < 0.5;
    let scale = 10f64.powf(rng.range(-4.0, 4.0));
    let centre = V::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)) * scale;
    let axis = unit(&mut rng);
    let mut len = rng.range(0.2, 4.0) * scale;
    let mut ra = rng.range(0.05, 1.0) * scale;
    let mut rb = rng.range(0.05, 1.0) * scale;
    match region {
        LinkRegion::NearEqualRadii => rb = ra * (1.0 + rng.range(-1e-7, 1e-7)),
        LinkRegion::AlmostInside => {
            let big = ra.max(rb);
            let frac = 1.0 - 10f64.powf(rng.range(-9.0, -3.0));
            len = big * rng.range(0.3, 0.9);
            let small = big - len * frac;
            if coin(&mut rng) {
                (ra, rb) = (big, small);
            } else {
                (ra, rb) = (small, big);
            }
        }
        LinkRegion::SphereInside => {
            ra = rng.range(0.5, 1.0) * scale;
            rb = ra * rng.range(0.05, 0.5);
            len = (ra - rb) * rng.range(0.0, 0.999);
            if coin(&mut rng) {
                core::mem::swap(&mut ra, &mut rb);
            }
        }
        LinkRegion::LongThin => {
            ra = len * 1e-4 * rng.range(0.5, 1.5);
            rb = len * 1e-4 * rng.range(0.5, 1.5);
        }
        LinkRegion::ZeroRadiusEnd => {
            if coin(&mut rng) {
                ra = 0.0
            } else {
                rb = 0.0
            }
        }
        _ => {}
    }
    let a = v32(centre - axis * (len / 2.0));
    let b = v32(centre + axis * (len / 2.0));
    let (ra, rb) = (r32(ra), r32(rb));
    let link = RoundCone { a, ra, b, rb };
    let size = (b - a).length().max(ra).max(rb);
    let u = rng.range(-0.2, 1.2).clamp(0.0, 1.0);
    let (ref_pt, ref_r) = (p_at(&link, u), r_at(&link, u));
    let ax = (b - a).normalize_or_zero();
    let ax = if ax.length() > 0.0 { ax } else { axis };
    let mut dir = unit(&mut rng);
    let target = match region {
        LinkRegion::Grazing => {
            let probe = ref_pt + perp(ax, &mut rng) * (ref_r + size);
            let (dist, _) = sweep_dist(&link, probe);
            let n = sweep_normal(&link, probe);
            let on = probe - n * dist;
            let sign = if coin(&mut rng) { 1.0 } else { -1.0 };
            let off = 10f64.powf(rng.range(-12.0, -2.0)) * size * sign;
            dir = perp(n, &mut rng);
            on + n * off
        }
        LinkRegion::AxisParallel => {
            dir = if coin(&mut rng) { ax } else { -ax };
            ref_pt + perp(ax, &mut rng) * (ref_r * rng.range(0.0, 1.3))
        }
        LinkRegion::Inside => ref_pt + perp(ax, &mut rng) * (ref_r * rng.range(0.0, 0.9)),
        _ => ref_pt + unit(&mut rng) * (ref_r * rng.range(0.0, 1.5)),
    };
    let dist = match region {
        LinkRegion::FarOrigin => 1e4 * size * rng.range(1.0, 3.0),
        LinkRegion::Inside => 0.0,
        _ => size * rng.range(2.0, 10.0),
    };
    let dlen = 10f64.powf(rng.range(-2.0, 2.0));
    let mut ray = Ray::new(v32(target - dir * dist), v32(dir * dlen));
    if region == LinkRegion::AxisParallel {
        // Keep the direction exactly the (rounded) axis so the ray stays parallel after rounding.
        ray.d = v32(if dir.dot(ax) > 0.0 { b - a } else { a - b } * (dlen / (b - a).length()));
    }
    LinkCase { link, ray, region, size }
}

/// The `t` tolerance of `tests/link_props.rs` for a kernel of unit roundoff `eps`:
/// the hit-point distance bound `E = 64·ε·(S + D) + cone term` (see that file's module docs),
/// plus the same for the `f64` oracle, converted to `t` through the incidence cosine `γ`:
/// `(E + E₆₄)/(γ·|d|)`. Also returns `E` itself (the classification band).
pub fn link_bound(c: &LinkCase, eps: f64, gamma: f64) -> (f64, f64) {
    let e = |eps: f64| {
        let m = (c.link.a + c.link.b) * 0.5;
        let len = (c.link.b - c.link.a).length();
        let mut cone = 0.0;
        if len > 0.0 {
            let s = (c.link.ra - c.link.rb) / len;
            let c2 = (1.0 - s) * (1.0 + s);
            if c2 > 0.0 {
                cone = 8.0 * eps * c.size / c2.max(32.0 * eps);
            }
        }
        64.0 * eps * (c.size + (c.ray.o - m).length()) + cone
    };
    let (e1, e64) = (e(eps), e(f64::EPSILON));
    ((e1 + e64) / (gamma * c.ray.d.length()) + 1e-12, e1)
}

/// What the oracle says about a link case.
#[derive(Clone, Copy, Debug)]
pub struct LinkTruth {
    /// Signed gap of the line to the solid.
    pub gap: f64,
    /// Line interval, if any.
    pub iv: Option<(f64, f64)>,
    /// Incidence cosines `|n·d̂|` at entry and exit (NaN where the surface has no normal).
    pub gamma: (f64, f64),
}

/// Run the link oracle on a case.
pub fn link_truth(c: &LinkCase) -> LinkTruth {
    let gap = line_gap(&c.link, &c.ray);
    let iv = link_interval(&c.link, &c.ray);
    let dl = c.ray.d.length();
    let g = |t: f64| sweep_normal(&c.link, c.ray.at(t)).dot(c.ray.d).abs() / dl;
    let gamma = iv.map_or((f64::NAN, f64::NAN), |(a, b)| (g(a), g(b)));
    LinkTruth { gap, iv, gamma }
}

// ---------------------------------------------------------------------------------------------
// Splines

/// Failure regions of the spline kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplineRegion {
    /// A random bent segment, radii well below the curvature radius.
    Random,
    /// Radius larger than the centre line's curvature radius (the sweep folds onto itself).
    RadiusOverCurvature,
    /// A cusp: the centre line reverses (`b₂ ≈ b₀`, so `p′(½) ≈ 0`).
    Cusp,
    /// Rays tangent to the surface (offset ±(1e-9 … 1e-3)·size along the normal).
    Grazing,
    /// Rays starting inside the tube.
    Inside,
}

/// Every spline region, in chart order.
pub const SPLINE_REGIONS: [SplineRegion; 5] = [
    SplineRegion::Random,
    SplineRegion::RadiusOverCurvature,
    SplineRegion::Cusp,
    SplineRegion::Grazing,
    SplineRegion::Inside,
];

impl SplineRegion {
    /// Short name used in tables and charts.
    pub fn name(self) -> &'static str {
        match self {
            Self::Random => "random",
            Self::RadiusOverCurvature => "radius>curvature",
            Self::Cusp => "cusp",
            Self::Grazing => "grazing",
            Self::Inside => "ray-starts-inside",
        }
    }
}

/// One spline test case (inputs `f32`-representable, like [`LinkCase`]).
#[derive(Clone, Copy, Debug)]
pub struct SplineCase {
    /// The segment.
    pub tube: QuadTube<f64>,
    /// The ray.
    pub ray: Ray<f64>,
    /// Its region.
    pub region: SplineRegion,
    /// Largest control radius (the unit of the error).
    pub radius: f64,
}

/// What the dense oracle says about a spline case.
#[derive(Clone, Copy, Debug)]
pub struct SplineTruth {
    /// Signed gap of the line to the sweep (sampled minimum of `dist(line, p(t)) − r(t)`).
    pub gap: f64,
    /// Hull `(t_in, t_out)` of the line with the sweep.
    pub iv: Option<(f64, f64)>,
}

const SPLINE_SAMPLES: usize = 1024;

/// Dense-sampling oracle of a quadratic sweep: entry `min_t` of the sphere entries, exit
/// `max_t` of the exits, each refined by golden section around the best sample; the gap is
/// refined the same way.
pub fn spline_truth(c: &SplineCase) -> SplineTruth {
    let (o, d) = (c.ray.o, c.ray.d);
    let tube = &c.tube;
    let sph = |t: f64| sphere_ts(o, d, tube.point(t), tube.radius(t));
    let n = SPLINE_SAMPLES;
    let h = 1.0 / n as f64;
    let gapf = |t: f64| line_dist(o, d, tube.point(t)) - tube.radius(t);
    let tin = |t: f64| sph(t.clamp(0.0, 1.0)).map_or(f64::INFINITY, |s| s.0);
    let tout = |t: f64| sph(t.clamp(0.0, 1.0)).map_or(f64::INFINITY, |s| -s.1);
    let (mut bg, mut bi, mut bo) = ((0usize, f64::INFINITY), (0usize, f64::INFINITY), (0usize, f64::INFINITY));
    for k in 0..=n {
        let t = k as f64 * h;
        let g = gapf(t);
        if g < bg.1 {
            bg = (k, g);
        }
        if let Some((a, b)) = sph(t) {
            if a < bi.1 {
                bi = (k, a);
            }
            if -b < bo.1 {
                bo = (k, -b);
            }
        }
    }
    let refine = |f: &dyn Fn(f64) -> f64, k: usize, v: f64| {
        let lo = (k as f64 - 1.0) * h;
        let hi = (k as f64 + 1.0) * h;
        let (_, w) = golden_min(f, lo.max(0.0), hi.min(1.0));
        w.min(v)
    };
    let gap = refine(&gapf, bg.0, bg.1);
    let iv = if bi.1.is_finite() && bo.1.is_finite() {
        Some((refine(&tin, bi.0, bi.1), -refine(&tout, bo.0, bo.1)))
    } else {
        None
    };
    SplineTruth { gap, iv }
}

/// A deterministic spline case for `seed`, aimed at `region`. Sizes ~1 around the origin.
pub fn spline_case(seed: u64, region: SplineRegion) -> SplineCase {
    let mut rng = Rng::new(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xC0FF_EE00);
    loop {
        let pt = |rng: &mut Rng| V::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let b0 = pt(&mut rng);
        let mut b1 = pt(&mut rng);
        let mut b2 = pt(&mut rng);
        let mut rr = [rng.range(0.02, 0.15), rng.range(0.02, 0.15), rng.range(0.02, 0.15)];
        match region {
            SplineRegion::RadiusOverCurvature => {
                // A tight bend: b₁ far from the chord, b₂ near b₀; curvature radius at the apex
                // is |p′|²/|p′ × p″| ≪ the radii chosen here.
                b2 = b0 + V::from(rng.unit()) * rng.range(0.05, 0.3);
                b1 = b0 + V::from(rng.unit()) * rng.range(0.5, 1.0);
                rr = [rng.range(0.2, 0.5), rng.range(0.2, 0.5), rng.range(0.2, 0.5)];
            }
            SplineRegion::Cusp => {
                b2 = b0 + V::from(rng.unit()) * 10f64.powf(rng.range(-6.0, -2.0));
            }
            _ => {}
        }
        let b = [v32(b0), v32(b1), v32(b2)];
        let r = rr.map(r32);
        let Ok(tube) = QuadTube::new(b, r) else { continue };
        let radius = r[0].max(r[1]).max(r[2]);
        let tt = rng.range(0.0, 1.0);
        let (pc, rc) = (tube.point(tt), tube.radius(tt));
        let mut dir = unit(&mut rng);
        let dist = rng.range(3.0, 6.0);
        let (o, d) = match region {
            SplineRegion::Inside => (pc + unit(&mut rng) * (0.5 * rc * rng.uniform()), dir),
            SplineRegion::Grazing => {
                // A hit point of a random ray (from the oracle) and the sweep normal there.
                let probe = Ray::new(v32(pc - dir * dist), v32(dir));
                let c0 = SplineCase { tube, ray: probe, region, radius };
                let Some((t0, _)) = spline_truth(&c0).iv else { continue };
                let x = probe.at(t0);
                let (tb, _) = golden_min(|t| (x - tube.point(t)).length() - tube.radius(t), 0.0, 1.0);
                let nrm = (x - tube.point(tb)).normalize_or_zero();
                if nrm.length() == 0.0 {
                    continue;
                }
                let sign = if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
                let off = 10f64.powf(rng.range(-9.0, -3.0)) * radius * sign;
                dir = perp(nrm, &mut rng);
                (x + nrm * off - dir * dist, dir)
            }
            _ => (pc + unit(&mut rng) * (rc * rng.range(0.0, 1.5)) - dir * dist, dir),
        };
        let ray = Ray::new(v32(o), v32(d));
        return SplineCase { tube, ray, region, radius };
    }
}
