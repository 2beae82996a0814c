//! The certified count (`RaySpace::certified`) against `P`'s cascade, on the same queries.

use super::{Path, QuadTube, RaySpace};
use crate::ray::Ray;
use crate::real::Scalar;
use crate::vec::V3;
use crate::Primitive;
use rand::rngs::StdRng;
use rand::{Rng as _, SeedableRng};

/// Seeded uniform draws (rand's `StdRng`, a dev-dependency; also the capsule filter's tests).
pub(super) struct Rng(pub(super) StdRng);
impl Rng {
    pub(super) fn range(&mut self, a: f64, b: f64) -> f64 {
        self.0.gen_range(a..b)
    }
    pub(super) fn unit(&mut self) -> V3<f64> {
        loop {
            let v = V3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            if v.length2() > 1e-3 && v.length2() <= 1.0 {
                return v.normalize_or_zero();
            }
        }
    }
}

/// `(hit, t_in, t_out)` of a line interval, in f64.
type Line = (bool, f64, f64);

/// One query in precision `T`: the `Auto` and `Cascade` line intervals and whether the
/// certified count answered it.
fn both<T: Scalar>(t: &QuadTube<f64>, ray: &Ray<f64>) -> Option<(Line, Line, bool)> {
    let tt: QuadTube<T> = QuadTube::new(
        [t.b[0].cast(), t.b[1].cast(), t.b[2].cast()],
        [T::from_f64(t.r[0]), T::from_f64(t.r[1]), T::from_f64(t.r[2])],
    )
    .ok()?;
    let rr = Ray::new(ray.o.cast::<T>(), ray.d.cast::<T>());
    let rs = RaySpace::new(&tt, &rr)?;
    let (a, cert) = tt.polynomial_line(&rs, &rr, Path::Auto);
    let (c, _) = tt.polynomial_line(&rs, &rr, Path::Cascade);
    let f = |iv: crate::ray::Interval<T>| (iv.hit, iv.entry.t.to_f64(), iv.exit.t.to_f64());
    Some((f(a), f(c), cert))
}

/// Where the count certifies, its interval is the cascade's, in f32 and f64, across unit,
/// fat, thin (L/r to 10³), tapered-to-zero, pinched and strongly bent segments with rays
/// aimed within 1.5 radii of a random centre-line point (so many graze) from any direction,
/// and symmetric arcs crossed in their plane of symmetry.
///
/// *Tolerance.* Both are within the kernel's band of the exact interval (parent module,
/// "Conditioning": a shift `≤ E` and a radius within `E`, [`crate::spline_error_band`]). A radius
/// change `E` moves an entry by `E/cos θ`, and `cos θ ≥ c/r_max` for a chord of half length
/// `c` through a sphere of radius `≤ r_max`; so the two entries (and exits) differ by at most
/// `2E(1 + r_max/c)`, and the hit flags may differ only where `c ≤ √(2E·r_max)` (the chord of
/// a ray within `E` of grazing) — the comparison takes `4E(1 + r_max/c)` and `c ≤ 2√(E·r_max)`.
/// A hull may also hold a grazing contact within `E` that the other leaves out; where the
/// entries (exits) differ by more, the line between them must stay within `2E` of outside.
///
/// The count must also answer most queries on fat tubes (else the fast path is not what
/// these tests exercise) and leave some to the cascade (its fallback is exercised too).
#[test]
fn certified_count_agrees_with_the_cascade() {
    let mut rng = Rng(StdRng::seed_from_u64(11));
    // [queries, certified] per family, f32 then f64.
    let mut tally = [[[0usize; 2]; 7]; 2];
    for k in 0..24_000 {
        let fam = if k % 7 == 6 { 6 } else { k % 6 };
        let len = 2.0;
        let r = match fam {
            0 => 0.3,
            1 => len * rng.range(0.05, 0.5),
            2 => len / 10f64.powf(rng.range(1.0, 3.0)),
            _ => len * rng.range(0.01, 0.2),
        };
        let axis = rng.unit();
        let b0 = rng.unit() * rng.range(0.0, 2.0);
        let b2 = b0 + axis * len;
        let bend = if fam == 5 { rng.range(1.0, 3.0) } else { rng.range(0.0, 0.7) };
        let b1 = (b0 + b2) * 0.5 + rng.unit() * (len * bend);
        let radii = match fam {
            3 => [r, r * rng.range(0.2, 1.0), 0.0],
            // r(½) = (r₀ + 2r₁ + r₂)/4 = r·10⁻³: pinched near zero mid-segment.
            4 => [r, -r + r * 2e-3, r],
            _ => [r, r * rng.range(0.5, 1.5), r * rng.range(0.5, 1.5)],
        };
        let Ok(tube) = QuadTube::new([b0, b1, b2], radii) else { continue };
        let u = rng.range(0.0, 1.0);
        let aim = tube.point(u) + rng.unit() * (tube.radius(u).max(1e-3 * r) * rng.range(0.0, 1.5));
        let dir = rng.unit();
        let ray = Ray::new(aim - dir * rng.range(3.0, 8.0), dir);
        // Mirror-symmetric arcs crossed in their plane of symmetry (fuzz seed `seed-arc-5`):
        // the entry's and the exit's critical points coincide at t = ½, the midpoint of the
        // real interval, where both sign functions are exactly 0.
        let (tube, ray) = if k % 7 == 6 {
            let (w, h) = (rng.range(0.5, 2.0), rng.range(0.2, 2.0));
            let rr = rng.range(0.05, 0.5);
            let Ok(t) = QuadTube::new([V3::new(-w, 0.0, 0.0), V3::new(0.0, h, 0.0), V3::new(w, 0.0, 0.0)], [rr; 3])
            else {
                continue;
            };
            (t, Ray::new(V3::new(0.0, -3.0, rr * rng.range(-0.9, 0.9)), V3::new(0.0, 1.0, 0.0)))
        } else {
            (tube, ray)
        };
        let radii = tube.r;
        let rmax = radii.iter().fold(0.0f64, |a, &x| a.max(x));
        for (p, res) in [(0, both::<f32>(&tube, &ray)), (1, both::<f64>(&tube, &ray))] {
            let Some((a, c, cert)) = res else { continue };
            tally[p][fam][0] += 1;
            if !cert {
                continue;
            }
            tally[p][fam][1] += 1;
            let eps = if p == 0 { f32::EPSILON as f64 } else { f64::EPSILON };
            let e = tube.error_band(ray.o, eps);
            // Half chords along the line (|d| = 1).
            let half = |x: (bool, f64, f64)| if x.0 { 0.5 * (x.2 - x.1) } else { 0.0 };
            let ch = half(a).max(half(c));
            if a.0 != c.0 {
                assert!(
                    ch <= 2.0 * (e * rmax).sqrt(),
                    "fam {fam} p {p}: hit {} vs {}: {a:?} {c:?} {tube:?} {ray:?}",
                    a.0,
                    c.0
                );
                continue;
            }
            if a.0 {
                let tol = 4.0 * e * (1.0 + rmax / half(a).min(half(c)).max(1e-300));
                // The hulls may differ by a grazing contact that one includes (both are
                // right within the band): then the line between the two entries (exits)
                // must not enter the tube deeper than 2E (the exact sweep's depth, sampled:
                // sampling can only miss a violation, never invent one).
                for (x, y, entry) in [(a.1, c.1, true), (a.2, c.2, false)] {
                    if (x - y).abs() <= tol {
                        continue;
                    }
                    let (lo, hi) = if entry { (x.min(y), x.max(y) - tol) } else { (x.min(y) + tol, x.max(y)) };
                    let depth = (0..=2000)
                        .map(|i| -tube.sdf(ray.at(lo + (hi - lo) * i as f64 / 2000.0)))
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(
                        depth <= 2.0 * e,
                        "fam {fam} p {p}: {a:?} vs cascade {c:?} (tol {tol:e}) crosses {depth:e} deep: {tube:?} {ray:?}"
                    );
                }
            }
        }
    }
    println!(
        "[queries, certified] per family (unit, fat, thin, taper, pinched, bent, symmetric), f32 / f64: {tally:?}"
    );
    for (p, fams) in tally.iter().enumerate() {
        let [n, c] = fams[1];
        assert!(c as f64 >= 0.8 * n as f64, "fat tubes: only {c} of {n} certified (precision {p})");
        let fallback: usize = fams.iter().map(|[n, c]| n - c).sum();
        assert!(fallback > 0, "no query left to the cascade (precision {p})");
    }
}

/// `Direct::p_monotone`'s claims hold for the `P` of the stored coefficients: where it says
/// monotone, `P` sampled on 1,001 points of `[a, b]` never moves both up and down, and where it
/// says of one sign, the samples never take both signs — each beyond the f64 rounding of the
/// oracle's `P` (`32ε₆₄` times its magnitude formula), which is independent code: `P =
/// 4h'²g − g'²` from the stored power-basis vectors in f64 (exact: the f32 coefficients are
/// f64 numbers). In f32 the oracle is 2²⁹ times finer than the claim; in f64 it is as fine
/// as the claim, so there only gross errors can show. Intervals of width 10⁻⁵ … 1 about
/// random points and about the roots of `g` (where the certificate is needed: a small `g'`
/// there), on unit, thin (to `L/r = 10³`), tapered and bent tubes with rays that graze.
/// Dropping the Taylor remainder (`ρ = 0` in the bounds) makes it fail.
#[test]
fn p_monotone_claims_hold() {
    use crate::math::roots::Bracket;
    fn run<T: Scalar>(rng: &mut Rng) -> [usize; 3] {
        // [intervals, monotone claims, definite claims]
        let mut tally = [0usize; 3];
        for k in 0..3000 {
            let len = 2.0;
            let r = match k % 3 {
                0 => 0.3,
                1 => len / 10f64.powf(rng.range(1.0, 3.0)),
                _ => len * rng.range(0.01, 0.2),
            };
            let axis = rng.unit();
            let b0 = rng.unit() * rng.range(0.0, 2.0);
            let b2 = b0 + axis * len;
            let b1 = (b0 + b2) * 0.5 + rng.unit() * (len * rng.range(0.0, 1.5));
            let radii = if k % 5 == 4 { [r, r * rng.range(0.2, 1.0), 0.0] } else { [r, r * rng.range(0.5, 1.5), r] };
            let Ok(tube) = QuadTube::new([b0, b1, b2], radii) else { continue };
            let u = rng.range(0.0, 1.0);
            let aim = tube.point(u) + rng.unit() * (tube.radius(u).max(1e-3 * r) * rng.range(0.5, 1.2));
            let dir = rng.unit();
            let ray = Ray::new(aim - dir * rng.range(3.0, 8.0), dir);
            let Ok(tt) = QuadTube::<T>::new(
                [tube.b[0].cast(), tube.b[1].cast(), tube.b[2].cast()],
                [T::from_f64(radii[0]), T::from_f64(radii[1]), T::from_f64(radii[2])],
            ) else {
                continue;
            };
            let rr = Ray::new(ray.o.cast::<T>(), ray.d.cast::<T>());
            let Some(rs) = RaySpace::new(&tt, &rr) else { continue };
            let h1 = rs.h1();
            let hf = [h1[0].to_f64(), h1[1].to_f64()];
            let ([wa, wb, wc], [ra, rb, rc]) = rs.dg.coeffs_f64();
            // P and its magnitude formula at t, f64.
            let p = |t: f64| {
                let (w, w1) = (wa * (t * t) + wb * t + wc, wa * (2.0 * t) + wb);
                let (r, r1) = (ra * t * t + rb * t + rc, 2.0 * ra * t + rb);
                let (g, g1) = (r * r - w.dot(w), 2.0 * (r * r1 - w.dot(w1)));
                let hp = hf[0] + hf[1] * t;
                let ab = |v: V3<f64>| V3::new(v.x.abs(), v.y.abs(), v.z.abs());
                let (wa_, w1a) = (ab(w), ab(w1));
                let (ga, g1a) = (r * r + wa_.dot(wa_), 2.0 * ((r * r1).abs() + wa_.dot(w1a)));
                (4.0 * hp * hp * g - g1 * g1, 4.0 * hp * hp * ga + g1a * g1a)
            };
            let roots = rs.dg.g_breakpoints(Bracket::Newton).roots;
            for j in 0..8 {
                let c = if j < 4 { roots[1 + j].to_f64() } else { rng.range(0.0, 1.0) };
                let w = 10f64.powf(rng.range(-5.0, 0.0));
                let (a, b) = (T::from_f64((c - w).max(0.0)), T::from_f64((c + w).min(1.0)));
                if b <= a {
                    continue;
                }
                tally[0] += 1;
                let (mono, definite) = rs.dg.p_monotone(a, b, h1);
                if !mono && !definite {
                    continue;
                }
                let (af, bf) = (a.to_f64(), b.to_f64());
                let s: Vec<(f64, f64)> = (0..=1000).map(|i| p(af + (bf - af) * i as f64 / 1000.0)).collect();
                let slack = |x: (f64, f64), y: (f64, f64)| 32.0 * f64::EPSILON * (x.1 + y.1);
                if mono {
                    tally[1] += 1;
                    let up = s.windows(2).any(|v| v[1].0 - v[0].0 > slack(v[0], v[1]));
                    let down = s.windows(2).any(|v| v[0].0 - v[1].0 > slack(v[0], v[1]));
                    assert!(!(up && down), "P not monotone on [{af}, {bf}]: {tube:?} {ray:?}");
                }
                if definite {
                    tally[2] += 1;
                    let pos = s.iter().any(|x| x.0 > slack(*x, *x));
                    let neg = s.iter().any(|x| x.0 < -slack(*x, *x));
                    assert!(!(pos && neg), "P changes sign on [{af}, {bf}]: {tube:?} {ray:?}");
                }
            }
        }
        tally
    }
    let mut rng = Rng(StdRng::seed_from_u64(23));
    for (name, t) in [("f32", run::<f32>(&mut rng)), ("f64", run::<f64>(&mut rng))] {
        println!("{name}: [intervals, monotone claims, definite claims] = {t:?}");
        assert!(t[1] * 10 >= t[0] && t[2] * 10 >= t[0], "{name}: too few claims to test: {t:?}");
    }
}
