//! Seeded link cases aimed at every failure region, the error bound the judges use, and what
//! the oracle says about a case. These are the report's case generators (the report's committed
//! numbers were made with them).

use crate::link::{line_gap, line_interval, sweep_dist, sweep_normal, Link};
use crate::rng::{splitmix, FloatRng, SplitMix64};
use crate::vec::{Line, Vec3};

/// Failure regions of the link kernels (the case mix of `tests/kernels/link/properties.rs`).
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
    /// Both centres equal (the link is one sphere). Not in [`LINK_REGIONS`] (the reports'
    /// regions); the tests draw it.
    ZeroLength,
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
            Self::ZeroLength => "zero-length",
        }
    }
}

/// One link test case. The inputs are `f32`-representable (rounded from the generated `f64`
/// values), so every precision and Embree see exactly the same problem, and the `f64` oracle
/// solves that problem exactly.
#[derive(Clone, Copy, Debug)]
pub struct LinkCase {
    /// The link.
    pub link: Link,
    /// The ray (range `[0, ∞)`).
    pub ray: Line,
    /// Its region.
    pub region: LinkRegion,
    /// Characteristic size `max(L, ra, rb)`.
    pub size: f64,
}

/// A uniformly distributed unit vector.
pub(crate) fn unit(rng: &mut SplitMix64) -> Vec3 {
    Vec3::from(rng.unit())
}

/// A random unit vector perpendicular to the unit `v` (rejecting near-parallel draws).
pub(crate) fn perp(v: Vec3, rng: &mut SplitMix64) -> Vec3 {
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

/// A deterministic link case for `seed`, aimed at `region`. Scales range over 1e-4 … 1e4.
pub fn link_case(seed: u64, region: LinkRegion) -> LinkCase {
    let mut rng = splitmix(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5DEE_CE66);
    let scale = 10f64.powf(rng.range(-4.0, 4.0));
    let centre = Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)) * scale;
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
            if rng.coin() {
                (ra, rb) = (big, small);
            } else {
                (ra, rb) = (small, big);
            }
        }
        LinkRegion::SphereInside => {
            ra = rng.range(0.5, 1.0) * scale;
            rb = ra * rng.range(0.05, 0.5);
            len = (ra - rb) * rng.range(0.0, 0.999);
            if rng.coin() {
                core::mem::swap(&mut ra, &mut rb);
            }
        }
        LinkRegion::LongThin => {
            ra = len * 1e-4 * rng.range(0.5, 1.5);
            rb = len * 1e-4 * rng.range(0.5, 1.5);
        }
        LinkRegion::ZeroRadiusEnd => {
            if rng.coin() {
                ra = 0.0
            } else {
                rb = 0.0
            }
        }
        LinkRegion::ZeroLength => len = 0.0,
        _ => {}
    }
    let a = (centre - axis * (len / 2.0)).round_f32();
    let b = (centre + axis * (len / 2.0)).round_f32();
    let (ra, rb) = (r32(ra), r32(rb));
    let link = Link { a, ra, b, rb };
    let size = (b - a).length().max(ra).max(rb);
    let u = rng.range(-0.2, 1.2).clamp(0.0, 1.0);
    let (ref_pt, ref_r) = (link.p_at(u), link.r_at(u));
    let ax = (b - a).normalize_or_zero();
    let ax = if ax.length() > 0.0 { ax } else { axis };
    let mut dir = unit(&mut rng);
    let target = match region {
        LinkRegion::Grazing => {
            let probe = ref_pt + perp(ax, &mut rng) * (ref_r + size);
            let (dist, _) = sweep_dist(&link, probe);
            let n = sweep_normal(&link, probe);
            let on = probe - n * dist;
            let sign = if rng.coin() { 1.0 } else { -1.0 };
            let off = 10f64.powf(rng.range(-12.0, -2.0)) * size * sign;
            dir = perp(n, &mut rng);
            on + n * off
        }
        LinkRegion::AxisParallel => {
            dir = if rng.coin() { ax } else { -ax };
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
    let mut ray = Line { o: (target - dir * dist).round_f32(), d: (dir * dlen).round_f32() };
    if region == LinkRegion::AxisParallel {
        // Keep the direction exactly the (rounded) axis so the ray stays parallel after rounding.
        let along = if dir.dot(ax) > 0.0 { b - a } else { a - b };
        ray.d = (along * (dlen / (b - a).length())).round_f32();
    }
    LinkCase { link, ray, region, size }
}

/// The distance bound `E` of `tests/kernels/link/properties.rs` (derived in that file's module docs) for a
/// stable-link hit point, for a kernel of unit roundoff `eps`: `64·ε·(S + D)` with `S = size`
/// and `D = |o − m|` (`m` the link's midpoint), plus the nearly-flat-stump term
/// `8·ε·S′/max(c², 32ε)` with `c² = 1 − sin²θ`, `sin θ = (ra − rb)/L` and `S′ = max(L, ra, rb)`
/// (zero for `L = 0` or `c² ≤ 0`).
///
/// The stump term: for a nearly flat stump (one sphere almost inside the other, `c = cos θ → 0`)
/// the quadratic's coefficients `A = c²|d×â|² − s²(d·â)²` and `C = c²|P|² − e²` are differences
/// of terms whose sum is O(1)·|·|² while the difference is O(c²)·|·|²: they carry a relative
/// error of ≈ 4ε/c², which moves the crossing by that fraction of the local scale (≤ S):
/// 4ε·S/c², ×2 for safety. (With c² < 64ε the kernel drops the stump, costing ≤ 64ε·L, already
/// in E; so this term is at most S/8.)
pub fn link_error_bound(l: &Link, origin: Vec3, size: f64, eps: f64) -> f64 {
    let m = (l.a + l.b) * 0.5;
    let len = (l.b - l.a).length();
    let mut cone = 0.0;
    if len > 0.0 {
        let s = (l.ra - l.rb) / len;
        let c2 = (1.0 - s) * (1.0 + s);
        if c2 > 0.0 {
            cone = 8.0 * eps * len.max(l.ra).max(l.rb) / c2.max(32.0 * eps);
        }
    }
    64.0 * eps * (size + (origin - m).length()) + cone
}

/// The tip term of a `t` tolerance for a link with a pointed end (radius < `e`, a distance
/// bound such as [`link_error_bound`]): the solid there is a spike thinner than `e` over an axial
/// length `e/tan θ` from the tip, every point of which is within `e` of the surface, so where a
/// line crosses it is undetermined along the line by up to `e·(1 + 1/|s|)·2` (`s = sin θ`,
/// `tan θ ≥ |s|`). Zero for links without such an end (and for NaN input).
pub fn link_tip_term(l: &Link, e: f64) -> f64 {
    let len = (l.b - l.a).length();
    let r_min = l.ra.min(l.rb);
    if r_min.is_nan() || e.is_nan() || r_min >= e || len.is_nan() || len <= 0.0 {
        return 0.0;
    }
    let s = ((l.ra - l.rb) / len).abs().max(1e-300);
    2.0 * e * (1.0 + 1.0 / s)
}

/// The `t` tolerance of `tests/kernels/link/properties.rs` for a kernel of unit roundoff `eps`:
/// the hit-point distance bound `E` ([`link_error_bound`]) plus the same for the `f64` oracle,
/// converted to `t` through the incidence cosine `γ`: `(E + E₆₄)/(γ·|d|)`. Also returns `E`
/// itself (the classification band).
pub fn link_bound(c: &LinkCase, eps: f64, gamma: f64) -> (f64, f64) {
    let e = |eps: f64| link_error_bound(&c.link, c.ray.o, c.size, eps);
    let (e1, e64) = (e(eps), e(f64::EPSILON));
    ((e1 + e64) / (gamma * c.ray.d.length()) + 1e-12, e1)
}

/// What the oracle says about a link case.
#[derive(Clone, Copy, Debug)]
pub struct LinkTruth {
    /// Signed gap of the line to the solid.
    pub gap: f64,
    /// Line interval `(t_in, t_out)`, if any.
    pub iv: Option<(f64, f64)>,
    /// Incidence cosines `|n·d̂|` at entry and exit (NaN where the surface has no normal).
    pub gamma: (f64, f64),
}

/// Run the link oracle on a case.
pub fn link_truth(c: &LinkCase) -> LinkTruth {
    let (gap, _) = line_gap(&c.link, &c.ray);
    let iv = line_interval(&c.link, &c.ray).map(|x| (x.t_in, x.t_out));
    let dl = c.ray.d.length();
    let g = |t: f64| sweep_normal(&c.link, c.ray.at(t)).dot(c.ray.d).abs() / dl;
    let gamma = iv.map_or((f64::NAN, f64::NAN), |(a, b)| (g(a), g(b)));
    LinkTruth { gap, iv, gamma }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_are_f32_representable_and_aimed_at_their_region() {
        let f32ok = |x: f64| x as f32 as f64 == x;
        for &region in &LINK_REGIONS {
            for seed in 0..50 {
                let c = link_case(seed, region);
                let l = &c.link;
                for x in [l.a.x, l.a.y, l.a.z, l.ra, l.b.x, l.b.y, l.b.z, l.rb, c.ray.o.x, c.ray.d.z] {
                    assert!(f32ok(x), "{region:?} {seed}: {x} is not an f32");
                }
                assert!(l.ra >= 0.0 && l.rb >= 0.0 && c.size > 0.0, "{c:?}");
                match region {
                    LinkRegion::ZeroRadiusEnd => assert!(l.ra == 0.0 || l.rb == 0.0),
                    // The origin is inside: its distance to the sweep is negative.
                    LinkRegion::Inside => assert!(sweep_dist(l, c.ray.o).0 < 0.0, "{c:?}"),
                    LinkRegion::AxisParallel => {
                        let (v, d) = (l.b - l.a, c.ray.d);
                        let sin = (v.y * d.z - v.z * d.y).hypot(v.z * d.x - v.x * d.z).hypot(v.x * d.y - v.y * d.x)
                            / (v.length() * d.length());
                        assert!(sin < 1e-6, "{c:?}");
                    }
                    _ => {}
                }
            }
        }
        for seed in 0..20 {
            let c = link_case(seed, LinkRegion::ZeroLength);
            assert!(c.link.a == c.link.b && c.size == c.link.ra.max(c.link.rb), "{c:?}");
        }
    }

    #[test]
    fn link_error_bound_is_the_formula_of_link_props() {
        let l = Link { a: Vec3::new(0.0, 0.0, 0.0), ra: 1.0, b: Vec3::new(2.0, 0.0, 0.0), rb: 1.0 };
        // Cylinder: D = |o − m| = 3 → 64ε(2 + 3), plus the stump term at c² = 1: 8ε·2.
        let o = Vec3::new(1.0, 3.0, 0.0);
        assert_eq!(link_error_bound(&l, o, 2.0, f64::EPSILON), 64.0 * f64::EPSILON * 5.0 + 16.0 * f64::EPSILON);
        // A stump, sin θ = (1 − 0.02)/2 = 0.49: plus 8ε·max(L, ra, rb)/c², c² = (1 − s)(1 + s).
        let l = Link { rb: 0.02, ..l };
        let s: f64 = (1.0 - 0.02) / 2.0;
        let want = 64.0 * f64::EPSILON * 5.0 + 8.0 * f64::EPSILON * 2.0 / ((1.0 - s) * (1.0 + s));
        assert_eq!(link_error_bound(&l, o, 2.0, f64::EPSILON), want);
        // A single point-like link (L = 0): no cone term.
        let l = Link { b: l.a, ..l };
        assert_eq!(link_error_bound(&l, Vec3::new(0.0, 3.0, 4.0), 1.0, 0.5), 64.0 * 0.5 * 6.0);
    }
}
