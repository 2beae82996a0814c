// Shared by fuzz/fuzz_targets/link.rs and tests/fuzz_corpus_link.rs.
// Bytes -> (link, ray) in f64; invalid input must be rejected by the validators (no panic);
// valid input must give, for the stable, Han precomputed and Han on-the-fly kernels in f64 and
// f32: no NaN, t_in <= t_out, unit normals; and for the stable kernel hit points on the surface
// within E = 64ε(S + D) + 8εS/max(c², 32ε) (the bound derived in tests/link_props.rs).
#[allow(unused_imports)]
use tubecast::{HanLink, Interval, Primitive, Ray, RoundCone, Scalar, V3};

fn f(data: &[u8], i: usize) -> f64 {
    let mut b = [0u8; 8];
    for k in 0..8 {
        b[k] = *data.get(i * 8 + k).unwrap_or(&0);
    }
    f64::from_le_bytes(b)
}

fn sane<T: Scalar>(iv: &Interval<T>) {
    let all = [iv.t_in, iv.t_out, iv.u_in, iv.u_out, iv.n_in.x, iv.n_in.y, iv.n_in.z, iv.n_out.x, iv.n_out.y, iv.n_out.z];
    assert!(all.iter().all(|x| !x.to_f64().is_nan()), "NaN in {iv:?}");
    if iv.hit {
        assert!(iv.t_in <= iv.t_out, "t_in > t_out: {iv:?}");
        let tol = if T::EPS.to_f64() < 1e-10 { 1e-12 } else { 1e-5 };
        for n in [iv.n_in, iv.n_out] {
            let l = n.length().to_f64();
            assert!((l - 1.0).abs() <= tol, "normal not unit: {n:?} in {iv:?}");
        }
        assert!(iv.u_in.to_f64() >= 0.0 && iv.u_in.to_f64() <= 1.0 && iv.u_out.to_f64() >= 0.0 && iv.u_out.to_f64() <= 1.0);
    }
}

fn bound(l: &RoundCone<f64>, ray: &Ray<f64>, eps: f64) -> f64 {
    let len = (l.b - l.a).length();
    let size = len.max(l.ra).max(l.rb);
    let m = (l.a + l.b) * 0.5;
    let mut e = 64.0 * eps * (size + (ray.o - m).length());
    let s = if len > 0.0 { (l.ra - l.rb) / len } else { 1.0 };
    let c2 = (1.0 - s) * (1.0 + s);
    if c2 > 0.0 {
        e += 8.0 * eps * size / c2.max(32.0 * eps);
    }
    e
}

pub fn check(data: &[u8]) {
    let v = |i| V3::new(f(data, i), f(data, i + 1), f(data, i + 2));
    let Ok(link) = RoundCone::new(v(0), f(data, 3), v(4), f(data, 7)) else { return };
    let ray = Ray::new(v(8), v(11));
    if ray.validate().is_err() {
        return;
    }
    let st = link.intersect(&ray);
    sane(&st);
    sane(&HanLink::new(&link).intersect(&ray));
    sane(&link.intersect_han_on_the_fly(&ray));
    // The accuracy bound is stated for inputs whose lengths span less than 1e12 (≈ 1/(500ε)):
    // beyond that a sphere can be smaller than one ulp of the distance to it, and only the
    // no-NaN / ordering / unit-normal invariants above are promised.
    let lens = [(link.b - link.a).length(), link.ra, link.rb, (ray.o - link.a).length()];
    let hi = lens.iter().cloned().fold(0.0, f64::max);
    let lo = lens.iter().cloned().filter(|x| *x > 0.0).fold(f64::INFINITY, f64::min);
    if st.hit && hi / lo < 1e12 {
        let e = bound(&link, &ray, f64::EPSILON);
        // (t may overflow to ±∞ when the radius dwarfs |d|; such a t has no point to check.)
        for t in [st.t_in, st.t_out].into_iter().filter(|t| t.is_finite()) {
            let x = ray.at(t);
            if !x.is_finite() {
                continue;
            }
            // Forming x = o + t·d and the SDF add ≤ 4ε(|o − m| + |t·d|) + 8ε·S, within E's factor 2.
            let d = link.sdf(x);
            // Plus the absolute rounding of x = o + t·d and of the SDF's x − a: 4ε(|o| + |t·d| + |a|).
            let fx = 4.0 * f64::EPSILON * (ray.o.length() + (t * ray.d.length()).abs() + link.a.length());
            assert!(d.abs() <= 2.0 * e + fx, "hit point off the surface by {d:e} > 2E + {fx:e} = {:e}", 2.0 * e + fx);
        }
    }
    // Same link and ray in f32, when representable.
    let l32: RoundCone<f32> = link.cast();
    let r32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    if RoundCone::new(l32.a, l32.ra, l32.b, l32.rb).is_ok() && r32.validate().is_ok() {
        sane(&l32.intersect(&r32));
        sane(&HanLink::new(&l32).intersect(&r32));
    }
}
