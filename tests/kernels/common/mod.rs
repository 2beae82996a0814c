//! Case generators for the link kernels, and thin adapters to the independent oracle of
//! `tubecast-oracle` (`crates/oracle`, which shares no code with the kernels).
//!
//! The oracle works on the *sphere-sweep* definition of a link, `⋃_{u∈[0,1]} B(p(u), r(u))`
//! with `p`, `r` linear, in f64 (see `tubecast_oracle::link` for the method):
//!
//! * `sweep_dist(x)`: `min_u |x − p(u)| − r(u)`, the exact distance outside the solid; its
//!   gradient is the outward normal (`sweep_normal`).
//! * `line_gap(ray)`: the signed distance of the line to the solid (< 0: the line enters it).
//! * `line_interval(ray)`: `t_in = min_u t_in(u)`, `t_out = max_u t_out(u)` over the spheres the
//!   line meets.
//!
//! The generator here draws full-`f64` cases (the report's generator, `tubecast_oracle::link_case`,
//! draws `f32`-representable ones) and adds a zero-length region, so the tests keep their own.
#![allow(dead_code)]

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tubecast::{Ray, RoundCone, V3};
use tubecast_oracle as oracle;
pub use tubecast_oracle::Crossing;

pub mod check;

pub type V = V3<f64>;

/// tubecast's vector as the oracle's, and back.
pub fn ov(v: V) -> oracle::Vec3 {
    oracle::Vec3::new(v.x, v.y, v.z)
}
pub fn tv(v: oracle::Vec3) -> V {
    V::new(v.x, v.y, v.z)
}
/// The link and the ray's line as the oracle's types.
pub fn olink(l: &RoundCone<f64>) -> oracle::Link {
    oracle::Link { a: ov(l.a), ra: l.ra, b: ov(l.b), rb: l.rb }
}
pub fn oline(ray: &Ray<f64>) -> oracle::Line {
    oracle::Line { o: ov(ray.o), d: ov(ray.d) }
}

pub fn p_at(l: &RoundCone<f64>, u: f64) -> V {
    l.a + (l.b - l.a) * u
}
pub fn r_at(l: &RoundCone<f64>, u: f64) -> f64 {
    l.ra + (l.rb - l.ra) * u
}

/// (min_u |x − p(u)| − r(u), argmin u).
pub fn sweep_dist(l: &RoundCone<f64>, x: V) -> (f64, f64) {
    oracle::sweep_dist(&olink(l), ov(x))
}

/// Outward unit normal of the sweep at (or near) x.
pub fn sweep_normal(l: &RoundCone<f64>, x: V) -> V {
    tv(oracle::sweep_normal(&olink(l), ov(x)))
}

/// The sweep's signed distance from the ray's line, and its argmin u.
pub fn line_gap(l: &RoundCone<f64>, ray: &Ray<f64>) -> (f64, f64) {
    oracle::line_gap(&olink(l), &oline(ray))
}

/// Oracle line interval (entry and exit `t` and `u`), if the line meets the sweep.
pub fn line_interval(l: &RoundCone<f64>, ray: &Ray<f64>) -> Option<Crossing> {
    oracle::line_interval(&olink(l), &oline(ray))
}

/// The hard regions the generators aim at: the reports' link regions plus a zero-length link.
pub use tubecast_oracle::LinkRegion as Region;

pub const REGIONS: [Region; 11] = {
    let mut r = [Region::ZeroLength; 11];
    let mut i = 0;
    while i < oracle::LINK_REGIONS.len() {
        r[i] = oracle::LINK_REGIONS[i];
        i += 1;
    }
    r
};

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
