// Shared by fuzz/fuzz_targets/sphere.rs and tests/kernels/fuzz_corpus.rs.
// Bytes -> (centre, radius, ray). Valid input (finite, r² normal, ray validated) must give in
// f64, f32 and f64x4/f32x8 lanes: no NaN, t_in <= t_out, unit normals, and for f64 hit points
// within E = 16ε(|o − c| + r) of the sphere (re-centred formulation: ≤ 8 roundings on vectors of
// size ≤ |o − c| + r, plus forming o + t·d).
use tubecast::{Primitive, Ray, Real, Sphere, V3};
include!("decode.rs");
include!("sane.rs");

fn f(data: &[u8], i: usize) -> f64 {
    f64_at(data, i * 8)
}

pub fn check(data: &[u8]) {
    let c = V3::new(f(data, 0), f(data, 1), f(data, 2));
    let r = f(data, 3);
    let ray = Ray::new(V3::new(f(data, 4), f(data, 5), f(data, 6)), V3::new(f(data, 7), f(data, 8), f(data, 9)));
    if !c.is_finite() || (r * r).is_nan() || r * r < f64::MIN_POSITIVE || !(r * r).is_finite() || ray.validate().is_err() {
        return;
    }
    if !(c - ray.o).length2().is_finite() {
        return;
    }
    let iv = Sphere { c, r }.intersect(&ray);
    sane(&iv);
    if iv.hit {
        let e = 16.0 * f64::EPSILON * ((ray.o - c).length() + r);
        for t in [iv.entry.t, iv.exit.t].into_iter().filter(|t| t.is_finite()) {
            let x = ray.at(t);
            if x.is_finite() {
                let d = (x - c).length() - r;
                // Forming x = o + t·d in absolute coordinates rounds by ε·(|o| + |t·d|) per
                // component, and |x − c| by ε·|x|: 4ε(|o| + |t·d| + |c|) covers both.
                let fx = 4.0 * f64::EPSILON * (ray.o.length() + (t * ray.d.length()).abs() + c.length());
                assert!(d.abs() <= e + fx, "off sphere by {d:e} (E {e:e} + {fx:e})");
            }
        }
    }
    let iv4 = Sphere::<tubecast::WideF64x4> { c: V3::broadcast(c), r: Real::splat(r) }.intersect(&Ray::broadcast(ray));
    assert_eq!(iv4.lane(3), iv, "f64x4 lane differs from scalar");
    let (c32, r32) = (c.cast::<f32>(), r as f32);
    let ray32 = Ray::new(ray.o.cast::<f32>(), ray.d.cast::<f32>());
    if c32.is_finite() && r32 * r32 >= f32::MIN_POSITIVE && (r32 * r32).is_finite() && ray32.validate().is_ok() && (c32 - ray32.o).length2().is_finite() {
        let a = Sphere { c: c32, r: r32 }.intersect(&ray32);
        sane(&a);
        let iv8 = Sphere::<tubecast::WideF32x8> { c: V3::broadcast(c32), r: Real::splat(r32) }.intersect(&Ray::broadcast(ray32));
        assert_eq!(iv8.lane(5), a, "f32x8 lane differs from scalar");
    }
}
