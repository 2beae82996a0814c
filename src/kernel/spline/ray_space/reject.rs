//! Exact early rejections of a line before the ray-space polynomials are formed (most lines
//! miss, and a miss should cost little): the control triangle dilated by the largest radius
//! ([`hull_misses`]), and `g`'s Bernstein coefficients on the four quarters of the segment
//! ([`g_hull_misses`]).

use crate::math::bezier::split_half;
use crate::real::{Mask, Real};
use crate::vec::V3;

/// Lanes whose line surely misses the sweep (an exact early rejection): the
/// centre curve lies in the triangle of its control points `cᵢ` (Bernstein weights are a
/// convex combination) and `r(t) ≤ ρ = max rᵢ` (likewise), so the sweep lies in the triangle
/// dilated by `ρ`, and a line farther than `ρ` from the triangle misses it. Viewed along the
/// line (`d̂`) the line is the origin (the re-centred origin is on it) and the triangle that of
/// `Wᵢ = cᵢ × d̂` (the projection onto the plane ⊥ `d̂`, turned by 90°: an isometry there).
///
/// *Exactness.* Everything is in units of the bounding radius, `|cᵢ| ≤ 2`, `|Wᵢ| ≤ 2`. A lane
/// is rejected only if the origin is **outside** the projected triangle — every edge's
/// orientation `(Wᵢ × Wᵢ₊₁)·d̂` beyond its rounding `16ε(|Wᵢ|² + |Wᵢ₊₁|²)` ≥ `32ε|Wᵢ||Wᵢ₊₁|` on
/// both sides, so a truly inside origin always passes — and its distance to every edge
/// segment exceeds `ρ + 128ε`. Outside a triangle the distance to it is the least distance to
/// its edge segments; each computed distance is within `28ε` (the rounding of `a + e·s`,
/// `|W| ≤ 2`) plus `16ε` (a parameter `s` off by `4ε`: `|e|·δs`, the distance being flat at
/// the optimum) of the true one. So a rejected line is more than `ρ + 84ε > ρ` from the
/// triangle of the (rounded, re-centred) control points: it misses the tube the kernel
/// models (the rounding of `cᵢ`, `rᵢ` is the input perturbation inside the band `E`), and
/// the exact answer is a miss.
#[inline(always)]
pub(super) fn hull_misses<T: Real>(c: [V3<T>; 3], rho: T, dhat: V3<T>) -> T::Mask {
    let (zero, one, eps) = (T::zero(), T::one(), T::epsilon());
    let w = [c[0].cross(dhat), c[1].cross(dhat), c[2].cross(dhat)];
    let lim = rho + T::cst(128.0) * eps;
    let lim2 = lim * lim;
    let (mut far, mut pos, mut neg) = (T::Mask::splat(true), T::Mask::splat(true), T::Mask::splat(true));
    for i in 0..3 {
        let (a, b) = (w[i], w[(i + 1) % 3]);
        let e = b - a;
        let ee = e.length2();
        let s = (-a.dot(e) / T::select(ee.gt(zero), ee, one)).clamp(zero, one);
        far = far & (a + e * s).length2().gt(lim2);
        let o = a.cross(b).dot(dhat);
        let k = T::cst(16.0) * eps * (a.length2() + b.length2());
        pos = pos & o.ge(-k);
        neg = neg & o.le(k);
    }
    far & !(pos | neg) & lim.gt(zero)
}

/// Lanes whose line surely misses the sweep by `g`'s **Bernstein coefficients** (an exact
/// early rejection). In ray space (units of the bounding radius, the line
/// through the origin along `d̂`) the centre's offset from the line is the quadratic Bézier
/// `w(t) = Σ Wᵢ Bᵢ(t)`, `Wᵢ = cᵢ × d̂`, and the radius `r(t) = Σ rᵢ Bᵢ(t)`, so
/// `g = r² − |w|²` is a quartic whose Bernstein coefficients are those of the products
/// (`Bᵢ Bⱼ = C(2,i)C(2,j)/C(4,i+j)·B⁴ᵢ₊ⱼ`):
///
/// `g₀ = r₀² − |W₀|²`, `g₁ = r₀r₁ − W₀·W₁`, `g₂ = (2r₀r₂ + 4r₁² − 2W₀·W₂ − 4|W₁|²)/6`,
/// `g₃ = r₁r₂ − W₁·W₂`, `g₄ = r₂² − |W₂|²`.
///
/// Halved twice by de Casteljau they are `g`'s coefficients on `[0, ¼]`, …, `[¾, 1]`, and on
/// each quarter `g` is at most its largest coefficient (the convex-hull property). A lane is
/// rejected only if every coefficient of every quarter is below `−δ`: then `g < 0` on `[0, 1]`
/// and the line meets no sphere of the sweep — of the rounded, re-centred data, whose rounding
/// is inside the band `E` (as for [`hull_misses`]), so the exact answer is a miss. On the
/// spline bench's rays this rejects 91% of the misses that [`hull_misses`] lets through
/// (`tests::g_hull_rejects_only_misses`).
///
/// *Rounding* (`δ`). For a near lane `|cᵢ| ≤ 2` and `|rᵢ| ≤ 1` (units of the bounding
/// radius). A component of `Wᵢ = cᵢ × d̂` is two products of size ≤ 2 and their difference,
/// with `d̂`'s components within `2ε` of a unit vector's: within `12ε`, so `|δWᵢ| < 21ε`. A dot
/// product `Wᵢ·Wⱼ` (≤ 4) is then within `2·21ε·2 + 3·4ε < 100ε` of the data's, `rᵢrⱼ` within
/// `ε`; each `gₖ` combines them with weights summing to at most 1 on each side, plus at most
/// four roundings of partial sums of size ≤ 8: within `100ε + ε + 32ε < 140ε`. A halving
/// averages values of size ≤ 8 (≤ `8ε` each; averages keep the inherited bound), twice:
/// `δ = 140ε + 16ε < 256ε`.
#[inline(always)]
pub(super) fn g_hull_misses<T: Real>(c: [V3<T>; 3], r: [T; 3], dhat: V3<T>) -> T::Mask {
    let (two, four, sixth) = (T::cst(2.0), T::cst(4.0), T::cst(1.0 / 6.0));
    let w = [c[0].cross(dhat), c[1].cross(dhat), c[2].cross(dhat)];
    let g = [
        r[0] * r[0] - w[0].dot(w[0]),
        r[0] * r[1] - w[0].dot(w[1]),
        (two * r[0] * r[2] + four * r[1] * r[1] - two * w[0].dot(w[2]) - four * w[1].dot(w[1])) * sixth,
        r[1] * r[2] - w[1].dot(w[2]),
        r[2] * r[2] - w[2].dot(w[2]),
    ];
    let lim = -(T::cst(256.0) * T::epsilon());
    let (l, rr) = split_half(&g);
    let mut miss = T::Mask::splat(true);
    for q in [split_half(&l), split_half(&rr)] {
        for part in [q.0, q.1] {
            for v in part {
                miss = miss & v.lt(lim);
            }
        }
    }
    miss
}

#[cfg(test)]
mod tests {
    use super::super::super::tests::Rng;
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;
    use tubecast_oracle::{quad_gap, Line, Quad, Vec3};

    /// Where [`g_hull_misses`] rejects, the line misses the sweep of the very data it was given
    /// (the f64 oracle's sampled gap `min |w| − r` on that data, cast exactly to f64, is
    /// positive: sampling can only overlook a violation, never invent one), in f32 and f64;
    /// over unit, thin (r down to 10⁻⁴ of the extent), tapered-to-zero, pinched (a negative
    /// control radius) and strongly bent segments, lines through a sphere of the sweep at
    /// `(1 + δ)` times its radius, `δ` from `−0.5` (deep) to `2`, most within `10⁻²` of
    /// grazing. It must also reject most of the lines that pass by (else it filters nothing).
    #[test]
    fn g_hull_rejects_only_misses() {
        fn check<T: crate::real::Scalar>(c: [Vec3; 3], r: [f64; 3], d: Vec3) -> bool {
            let v = |p: Vec3| V3::new(T::from_f64(p.x), T::from_f64(p.y), T::from_f64(p.z));
            let cs = [v(c[0]), v(c[1]), v(c[2])];
            let rs = r.map(T::from_f64);
            let miss = g_hull_misses(cs, rs, v(d).normalize_or_zero());
            if miss {
                // The data as the kernel holds it.
                let back = |p: V3<T>| Vec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64());
                let q = Quad { b: cs.map(back), r: rs.map(|x| x.to_f64()) };
                let line = Line { o: Vec3::new(0.0, 0.0, 0.0), d: back(v(d).normalize_or_zero()) };
                let gap = quad_gap(&q, &line, 4000);
                assert!(gap > -1e-12, "rejected a line {gap:e} inside: {q:?} {d:?}");
            }
            miss
        }
        let mut rng = Rng(StdRng::seed_from_u64(12));
        // Lines that pass by, and those rejected, per δ > 0 (1e-4, 1e-2, 0.5, 2).
        let (mut passing, mut rejected) = ([0usize; 4], [0usize; 4]);
        for k in 0..20_000 {
            let u3 = |rng: &mut Rng| {
                let p = rng.unit();
                Vec3::new(p.x, p.y, p.z)
            };
            let (b0, b2) = (u3(&mut rng), u3(&mut rng));
            let bend = if k % 5 == 4 { 3.0 } else { 0.5 };
            let b1 = (b0 + b2) * 0.5 + u3(&mut rng) * (rng.range(0.0, bend));
            let s = 10f64.powf(rng.range(-4.0, -0.5));
            let r = match k % 4 {
                0 => [s, s * rng.range(0.5, 1.5), s * rng.range(0.5, 1.5)],
                1 => [s, s * 0.5, 0.0],
                2 => [s, -s + s * 2e-3, s],
                _ => [0.3, 0.4, 0.2],
            };
            let q = Quad { b: [b0, b1, b2], r };
            let t = rng.range(0.0, 1.0);
            let d = u3(&mut rng);
            let n = Vec3::new(d.y, -d.x, 0.0) * (1.0 / (d.x * d.x + d.y * d.y).sqrt().max(1e-300));
            let delta = [-0.5, -1e-2, -1e-4, 0.0, 1e-4, 1e-2, 0.5, 2.0][k % 8];
            let rt = q.radius(t).max(0.0);
            // The line through the origin along d passes at (1 + δ)·r(t) from p(t).
            let shift = q.point(t) - n * ((1.0 + delta) * rt);
            let mut c = [b0 - shift, b1 - shift, b2 - shift];
            // Into the filter's range: |cᵢ| ≤ 2, |rᵢ| ≤ 1 (units of a bounding radius).
            let big = c.iter().map(|p| (p.x * p.x + p.y * p.y + p.z * p.z).sqrt()).fold(0.0, f64::max) / 2.0;
            let big = big.max(r.iter().fold(0.0f64, |a, x| a.max(x.abs())));
            for p in &mut c {
                *p = *p * (1.0 / big);
            }
            let r = r.map(|x| x / big);
            let m32 = check::<f32>(c, r, d);
            let m64 = check::<f64>(c, r, d);
            if delta > 0.0 {
                let j = k % 8 - 4;
                passing[j] += 2;
                rejected[j] += usize::from(m32) + usize::from(m64);
            }
        }
        println!("g_hull_misses rejected {rejected:?} of {passing:?} lines passing at δ = 1e-4, 1e-2, 0.5, 2");
        // Measured: [0, 6, 211, 4590] of 5000 each (the quarters' hulls are loose within about
        // a radius of the surface). Lines three radii off must mostly go.
        assert!(rejected[3] * 10 > passing[3] * 8, "{rejected:?} of {passing:?}");
    }
}
