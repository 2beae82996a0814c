// Shared by fuzz/fuzz_targets/link.rs and tests/kernels/fuzz_corpus.rs.
// Bytes -> (link, ray) in f64; invalid input must be rejected by the validators (no panic);
// valid input must give, for the stable, Han precomputed and Han on-the-fly kernels in f64 and
// f32: no NaN, t_in <= t_out, unit normals; and for the stable kernel hit points on the surface
// within E = 64ε(S + D) + 8εS/max(c², 32ε) (the bound derived in tests/kernels/link/properties.rs).
#[allow(unused_imports)]
use tubecast::baseline::HanLink;
use tubecast::{Primitive, Ray, RoundCone, V3};
include!("decode.rs");
include!("sane.rs");

fn f(data: &[u8], i: usize) -> f64 {
    f64_at(data, i * 8)
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
        // E of tests/kernels/link/properties.rs, from the oracle crate (size S = max(L, ra, rb)).
        let ov = |v: V3<f64>| tubecast_oracle::Vec3::new(v.x, v.y, v.z);
        let ol = tubecast_oracle::Link { a: ov(link.a), ra: link.ra, b: ov(link.b), rb: link.rb };
        let size = (link.b - link.a).length().max(link.ra).max(link.rb);
        let e = tubecast_oracle::link_error_bound(&ol, ov(ray.o), size, f64::EPSILON);
        // (t may overflow to ±∞ when the radius dwarfs |d|; such a t has no point to check.)
        for t in [st.entry.t, st.exit.t].into_iter().filter(|t| t.is_finite()) {
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
