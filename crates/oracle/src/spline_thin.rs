//! Seeded quadratic-tube cases across length/radius ratios `L/r = 1 … 10⁵` in the families
//! where spline kernels fail (thin tubes in `f32`, extreme scales and direction ratios), judged by
//! [`crate::quad_crossing_offset`]. Every number is `f32`-representable, so the `f32` and `f64`
//! kernels answer the same question.

use crate::link_cases::{perp, unit};
use crate::rng::{splitmix, FloatRng, RngCore, SplitMix64};
use crate::spline::Quad;
use crate::vec::{Line, Vec3};

/// Families of the length/radius sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ThinFamily {
    /// A random bent segment of length ~2, radii `L/ratio·[0.5, 1.5]`.
    Unit,
    /// A tight bend: the radius exceeds the apex's curvature radius.
    Bulge,
    /// A cusp: `b₂ ≈ b₀`, so `p′(½) ≈ 0`.
    Cusp,
    /// A radius tapering to `≈ 0` (`r₀ = 0` or `10⁻⁶ r`), the ray aimed near the thin end.
    Taper,
    /// The line within `10⁻⁶ … 10⁻²` radii of the surface (either side).
    Grazing,
    /// The origin `10³ … 10⁴` lengths away.
    FarOrigin,
    /// The origin inside the tube.
    Inside,
    /// A straight segment along a coordinate axis, the origin on its axis one end radius from
    /// an end (to `10⁻¹²…10⁻²`), the line exactly at right angles to the axis: `h` is
    /// constant, so `P = 4h'²g − g'² = −g'²` has only double roots, and the entry and exit lie
    /// at `g`'s maximum beside the end (the differential fuzz finding
    /// `regression-spline-f32-exit-at-end`).
    InsideEnd,
    /// A zero-radius middle: `r = [a, −a, a]` (`r(½) = 0`), aimed within `t ∈ [0.3, 0.7]`.
    Pinched,
    /// Everything scaled by `2^k`, `k ∈ [−50, 50]` (in f32 the kernel rejects extents whose
    /// square times 64 overflows, from ~2⁶¹).
    Scale,
    /// A near-axis direction with components spanning `2⁻⁴⁰` of the largest, `|d| = 2^k`.
    DirRatio,
}

/// Every family, in report order.
pub const THIN_FAMILIES: [ThinFamily; 11] = [
    ThinFamily::Unit,
    ThinFamily::Bulge,
    ThinFamily::Cusp,
    ThinFamily::Taper,
    ThinFamily::Grazing,
    ThinFamily::FarOrigin,
    ThinFamily::Inside,
    ThinFamily::InsideEnd,
    ThinFamily::Pinched,
    ThinFamily::Scale,
    ThinFamily::DirRatio,
];

/// One case of the sweep.
#[derive(Clone, Copy, Debug)]
pub struct ThinCase {
    /// The segment (`f32`-representable).
    pub tube: Quad,
    /// The ray (`f32`-representable; range `[0, ∞)`).
    pub ray: Line,
    /// `R = max |bᵢ − p(½)| + max rᵢ`: the scale of the kernel's rounding.
    pub extent: f64,
    /// `|o − p(½)|`: the scale of the origin's rounding.
    pub origin_dist: f64,
}

impl From<&crate::SplineCase> for ThinCase {
    /// The same segment and ray with the sweep's rounding scales, so the stability report's
    /// cases are judged by the band the thin-tube cases are.
    fn from(s: &crate::SplineCase) -> Self {
        let m = s.tube.point(0.5);
        let extent = s.tube.b.iter().map(|&p| (p - m).length()).fold(0.0, f64::max) + s.radius;
        ThinCase { tube: s.tube, ray: s.ray, extent, origin_dist: (s.ray.o - m).length() }
    }
}

fn pt(rng: &mut SplitMix64) -> Vec3 {
    Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
}

/// The segment of a family at `L/r = ratio` (unrounded).
fn segment(rng: &mut SplitMix64, ratio: f64, family: ThinFamily) -> (Quad, f64) {
    let b0 = pt(rng);
    let axis = unit(rng);
    let len = 2.0;
    let r = len / ratio;
    let mut rr = [r * rng.range(0.5, 1.5), r * rng.range(0.5, 1.5), r * rng.range(0.5, 1.5)];
    let k = (rng.next_u64() % 3) as usize;
    let (b1, b2) = match family {
        ThinFamily::InsideEnd => {
            let mut e = [0.0; 3];
            e[k] = if rng.coin() { len } else { -len };
            let b2 = b0 + Vec3::from(e);
            ((b0 + b2) * 0.5, b2)
        }
        ThinFamily::Bulge => (b0 + unit(rng) * len, b0 + unit(rng) * (len * rng.range(1e-3, 0.05))),
        ThinFamily::Cusp => (b0 + unit(rng) * len, b0 + unit(rng) * (len * 10f64.powf(rng.range(-6.0, -2.0)))),
        _ => {
            let b2 = b0 + axis * len;
            let bend = rng.range(0.0, 0.6) * len;
            ((b0 + b2) * 0.5 + perp(axis, rng) * bend, b2)
        }
    };
    let mut t0 = rng.uniform();
    match family {
        ThinFamily::Taper => {
            rr[0] = if rng.coin() { 0.0 } else { 1e-6 * r };
            t0 = rng.range(0.0, 0.2);
        }
        ThinFamily::Pinched => {
            let a = rr[0] as f32 as f64;
            rr = [a, -a, a];
            t0 = rng.range(0.3, 0.7);
        }
        ThinFamily::InsideEnd => {
            // The line crosses the axis at a distance a = r_end·(1 ± 10⁻¹²…10⁻²) from the end's
            // centre: it touches the end sphere to within rounding in f32, where g(end) ≈ 0
            // ties the end with the real interval's other end as the exit candidate.
            let s = if rng.coin() { 1.0 } else { -1.0 };
            let rel = 1.0 + s * 10f64.powf(rng.range(-12.0, -2.0));
            let at_end = rng.coin();
            rr = [rr[0], rr[0], rr[0] * (1.0 + rng.range(-1e-3, 1e-3))];
            let a = if at_end { rr[2] } else { rr[0] } * rel;
            let near = (a / len).min(0.5);
            t0 = if at_end { 1.0 - near } else { near };
        }
        _ => {}
    }
    (Quad { b: [b0, b1, b2], r: rr }, t0)
}

/// The case `seed` of `family` at `L/r = ratio`.
pub fn thin_case(seed: u64, ratio: f64, family: ThinFamily) -> ThinCase {
    let mut rng = splitmix(seed.wrapping_mul(0xD1B5_4A32_D192_ED03) ^ ratio.to_bits() ^ (family as u64) << 56);
    let (q, t0) = segment(&mut rng, ratio, family);
    let q = Quad { b: q.b.map(Vec3::round_f32), r: q.r.map(|x| x as f32 as f64) };
    let (pc, rc) = (q.point(t0), q.radius(t0));
    let mut dir = unit(&mut rng);
    // Offset of the aim point from the centre, in local radii (|off| < 1: the line hits).
    let off = match family {
        ThinFamily::Grazing => {
            let s = if rng.coin() { 1.0 } else { -1.0 };
            1.0 + s * 10f64.powf(rng.range(-6.0, -2.0))
        }
        ThinFamily::Inside => rng.range(0.0, 0.5),
        ThinFamily::InsideEnd => 0.0,
        _ => rng.range(0.0, 2.5),
    };
    // Aim perpendicular to the tangent, `off` local radii from the centre.
    let tan = (q.b[1] - q.b[0]) * (1.0 - t0) + (q.b[2] - q.b[1]) * t0;
    let tan = if tan.length() > 0.0 { tan * (1.0 / tan.length()) } else { unit(&mut rng) };
    let target = pc + perp(tan, &mut rng) * (off * rc);
    if family == ThinFamily::Grazing {
        // Graze: the direction perpendicular to the offset, so the line's distance is `off·r`.
        let n = (target - pc) * (1.0 / (target - pc).length().max(f64::MIN_POSITIVE));
        dir = perp(n, &mut rng);
    }
    if family == ThinFamily::InsideEnd {
        // Exactly ⊥ the axis (the coordinate axis the segment runs along, after rounding).
        let ta = [tan.x.abs(), tan.y.abs(), tan.z.abs()];
        let k = (0..3).fold(0, |k, i| if ta[i] > ta[k] { i } else { k });
        let mut d = [dir.x, dir.y, dir.z];
        d[k] = 0.0;
        let d = Vec3::from(d);
        dir = d * (1.0 / d.length().max(f64::MIN_POSITIVE));
    }
    if family == ThinFamily::DirRatio {
        let mut d = [0.0; 3];
        let j = (rng.next_u64() % 3) as usize;
        for (i, x) in d.iter_mut().enumerate() {
            *x = if i == j { 1.0 } else { rng.range(-1.0, 1.0) * 2f64.powi(-((rng.next_u64() % 41) as i32)) };
        }
        dir = Vec3::from(d);
        dir = dir * (1.0 / dir.length());
    }
    let dist = match family {
        ThinFamily::FarOrigin => 10f64.powf(rng.range(3.0, 4.0)) * 2.0,
        ThinFamily::Inside | ThinFamily::InsideEnd => 0.0,
        _ => rng.range(3.0, 6.0),
    };
    let mut o = target - dir * dist;
    let mut d = dir * 2f64.powi((rng.next_u64() % 5) as i32 - 2);
    let mut tube = q;
    if family == ThinFamily::Scale || family == ThinFamily::DirRatio {
        let k = 2f64.powi((rng.next_u64() % 101) as i32 - 50);
        if family == ThinFamily::Scale {
            tube = Quad { b: q.b.map(|p| p * k), r: q.r.map(|x| x * k) };
            o = o * k;
        } else {
            d = d * k;
        }
    }
    let ray = Line { o: o.round_f32(), d: d.round_f32() };
    let m = tube.point(0.5);
    let extent =
        tube.b.iter().map(|&p| (p - m).length()).fold(0.0, f64::max) + tube.r.iter().fold(0.0f64, |a, &x| a.max(x));
    ThinCase { tube, ray, extent, origin_dist: (ray.o - m).length() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_are_f32_representable_and_valid() {
        let f32ok = |x: f64| x as f32 as f64 == x;
        for &family in &THIN_FAMILIES {
            for ratio in [1.0, 1e5] {
                for seed in 0..10 {
                    let c = thin_case(seed, ratio, family);
                    for p in c.tube.b.iter().chain([&c.ray.o, &c.ray.d]) {
                        assert!(f32ok(p.x) && f32ok(p.y) && f32ok(p.z), "{family:?} {c:?}");
                    }
                    assert!(c.tube.r.iter().all(|&r| f32ok(r)), "{c:?}");
                    // r(t) ≥ 0 on [0, 1] (the pinch is exactly 0 at ½) and the ray is not null.
                    assert!((0..=100).all(|k| c.tube.radius(k as f64 / 100.0) >= 0.0), "{c:?}");
                    assert!(c.ray.d.length() > 0.0 && c.extent > 0.0, "{c:?}");
                }
            }
        }
    }
}
