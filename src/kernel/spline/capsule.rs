//! A static filter before the kernel, cheaper than an oriented-box test: the chord
//! capsule. It rejects, with a dozen dot products and one division, lines that the kernel's
//! own set-up (re-centring, bounding radius, [`super::ray_space`]'s control-triangle test)
//! would reject more expensively, and it never changes an answer (the caller also masks its
//! lanes, so a lane still equals the scalar call bit for bit).
//!
//! *Containment.* `p(t) − [(1−t)b₀ + t b₂] = 2t(1−t)·(b₁ − (b₀+b₂)/2)`, so the centre line is
//! within `σ = ½|b₁ − (b₀+b₂)/2|` of the chord `[b₀, b₂]`, and `r(t) ≤ ρ = max rᵢ` (Bernstein
//! weights are a convex combination): the sweep lies in the capsule of radius `ρ + σ` about
//! the chord. The kernel's interval is that of a tube within the band `E = 1024ε·R +
//! 8ε·|o − p(½)|` of the given one (parent module, "Conditioning"), so a line farther than
//! `ρ + σ + E` from the chord is a kernel miss.
//!
//! *Rounding.* Everything is in units of `S`, the largest of `|b₂ − b₀|∞`, `|b₁ − (b₀+b₂)/2|∞`
//! and `ρ` (so `R ≤ 4S`; the scaling by `1/S` is one rounding per coordinate). With `w = b₀ − o`,
//! `v = b₂ − b₀` (units of `S`, `|v| ≤ √3`), the line's offsets `w⊥ = w − d(w·d)/|d|²`,
//! `v⊥` err by `≤ 8ε|w|`, `8ε|v|`; the parameter `s = −w⊥·v⊥/|v⊥|²` (clamped) errs by
//! `δs` with `|v⊥|·δs ≤ 4ε(|w| + |v|)`, which moves the computed distance `|w⊥ + s·v⊥|` by at
//! most that much (a first-order bound; the distance is flat at an interior optimum); the sum
//! adds `4ε(|w| + |v|)`. So the computed distance is within `24ε(|w| + |v|) + 3ε·dist` of the
//! line's distance to the chord. In units of `S` the bounding radius is `R ≤ |b₀ − p(½)| + ρ ≤
//! ½(|v| + |σ|) + ρ ≤ 2.8`, so `E ≤ 2880ε + 8ε(|w| + 1.8)`. The margin `M = 2¹⁴ε + 64ε·|w|₁`
//! exceeds `E` plus the rounding above (`≤ 2950ε + 32ε|w|` with `3ε·dist` absorbed by the
//! comparison of squares) by a factor over 2, so a rejected line misses the tube inflated by
//! `E`: the kernel misses it (a phantom hit needs a candidate whose gap is `≥ −τ`, inside `E`). The test
//! `capsule_rejects_only_kernel_misses` compares filtered and unfiltered answers bit for bit.
//! Squares of the scaled sizes stay finite unless `|w|` exceeds `~10¹⁹·S`, where `lim²` is
//! `∞` and nothing is rejected; non-finite or zero `S` rejects nothing.

use super::QuadTube;
use crate::ray::Ray;
use crate::real::Real;
use crate::vec::V3;

/// 1-norm (an upper bound of the length).
#[inline(always)]
fn n1<T: Real>(x: V3<T>) -> T {
    x.x.abs() + x.y.abs() + x.z.abs()
}

/// Lanes whose line surely misses the tube (see the module docs).
#[inline(always)]
pub(super) fn capsule_misses<T: Real>(tube: &QuadTube<T>, ray: &Ray<T>) -> T::Mask {
    let (zero, one) = (T::zero(), T::one());
    let [b0, b1, b2] = tube.b;
    let rho = tube.r[0].max(tube.r[1]).max(tube.r[2]);
    let v = b2 - b0;
    let sag = b1 - (b0 + b2) * T::cst(0.5);
    let s = v.max_abs().max(sag.max_abs()).max(rho);
    let ok = s.gt(zero) & s.is_finite();
    let inv = one / T::select(ok, s, one);
    let (v, sag, rho, w) = (v * inv, sag * inv, rho * inv, (b0 - ray.o) * inv);
    let d = ray.d;
    let d2 = d.length2();
    let id2 = one / T::select(d2.gt(zero), d2, one);
    let wp = w - d * (w.dot(d) * id2);
    let vp = v - d * (v.dot(d) * id2);
    let vp2 = vp.length2();
    let u = (-wp.dot(vp) / T::select(vp2.gt(zero), vp2, one)).clamp(zero, one);
    let dist2 = (wp + vp * u).length2();
    let sigma = T::cst(0.5) * n1(sag);
    let eps = T::epsilon();
    let reach = rho + sigma + T::cst(16384.0) * eps + T::cst(64.0) * eps * n1(w);
    // NaN and ∞ compare false: no rejection.
    ok & d2.gt(zero) & dist2.gt(reach * reach)
}

#[cfg(test)]
mod tests {
    use super::super::tests::Rng;
    use crate::kernel::spline::QuadTube;
    use crate::ray::Ray;
    use crate::Solver;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    /// Where the filter rejects, the kernel misses: filtered and unfiltered answers are equal
    /// bit for bit in `f32` and `f64`, over thin and long tubes (L/r 1…10⁵), bent and
    /// straight ones, a zero-radius end, scales 10⁻⁶…10⁶, far origins (10⁶ lengths) and lines
    /// passing the chord at `(ρ + σ)(1 + δ)`, `δ` from `−10⁻³` to `10`. It must also reject
    /// many lines close to the capsule (else it filters nothing).
    #[test]
    fn capsule_rejects_only_kernel_misses() {
        let mut rng = Rng(StdRng::seed_from_u64(10));
        let (mut rejected, mut near_rejected) = (0, 0);
        for k in 0..6000 {
            let scale = 10f64.powf(rng.range(-6.0, 6.0));
            let len = scale;
            let r = len / 10f64.powf(rng.range(0.0, 5.0));
            let axis = rng.unit();
            let off = rng.unit() * (scale * 10f64.powf(rng.range(-1.0, 3.0)));
            let bend = [0.0, 1e-3, 0.1, 0.5][k % 4];
            let b0 = off;
            let b2 = off + axis * len;
            let b1 = (b0 + b2) * 0.5 + rng.unit() * (len * bend);
            let rr = if k % 5 == 0 { [r, r * 0.5, 0.0] } else { [r, r * rng.range(0.5, 2.0), r * rng.range(0.5, 1.0)] };
            let Ok(tube) = QuadTube::new([b0, b1, b2], rr) else { continue };
            let sag = (b1 - (b0 + b2) * 0.5).length() * 0.5;
            let rho = rr[0].max(rr[1]).max(rr[2]);
            let at = b0 + axis * (len * rng.range(-0.2, 1.2));
            let dir = match k % 6 {
                0 => axis,
                1 => (axis + rng.unit() * 1e-4).normalize_or_zero(),
                _ => rng.unit(),
            };
            let side = dir.cross(rng.unit()).normalize_or_zero();
            let delta = [-1e-3, 0.0, 1e-6, 1e-4, 1e-2, 0.1, 1.0, 10.0][k % 8];
            let far = if k % 3 == 0 { 1e6 } else { 3.0 };
            let o = at + side * ((rho + sag) * (1.0 + delta)) - dir * (len * far);
            let ray = Ray::new(o, dir);
            let (f, u) = (
                tube.line_interval_with(&ray, Solver::Polynomial),
                tube.line_interval_unfiltered(&ray, Solver::Polynomial),
            );
            assert_eq!(f, u, "f64 case {k}: {tube:?} {ray:?}");
            let t32: QuadTube<f32> = tube.cast();
            let ray32 = Ray::new(o.cast::<f32>(), dir.cast::<f32>());
            let (f, u) = (
                t32.line_interval_with(&ray32, Solver::Polynomial),
                t32.line_interval_unfiltered(&ray32, Solver::Polynomial),
            );
            assert_eq!(f, u, "f32 case {k}: {t32:?} {ray32:?}");
            if super::capsule_misses(&tube, &ray) {
                rejected += 1;
                near_rejected += usize::from(delta <= 0.1);
            }
        }
        assert!(rejected > 1500 && near_rejected > 300, "rejected {rejected}, near the capsule {near_rejected}");
    }
}
