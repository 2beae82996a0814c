// Shared by fuzz/fuzz_targets/csg.rs and tests/kernels/fuzz_corpus.rs.
// Bytes -> up to 6 links and a ray; the CSG union of their intervals must be sorted, alternate
// entry/exit, lie in [t_min, t_max], carry unit normals and no NaN, and never report more
// boundaries than 2 × intervals.
use tubecast::csg::{union, Tagged};
use tubecast::{Primitive, Ray, RoundCone, V3};
include!("decode.rs");

fn f(data: &[u8], i: usize) -> f64 {
    let b = bytes8(data, i * 8);
    // Keep the fuzzer near useful magnitudes: map raw bits to [-8, 8] half the time.
    let x = f64::from_le_bytes(b);
    if b[7] & 1 == 0 { (b[0] as f64 - 128.0) / 16.0 } else { x }
}

pub fn check(data: &[u8]) {
    let v = |i| V3::new(f(data, i), f(data, i + 1), f(data, i + 2));
    let ray = Ray::with_range(v(0), v(3), f(data, 6).min(0.0), f64::INFINITY);
    if ray.validate().is_err() {
        return;
    }
    let n = (data.len() / 64).min(6);
    let mut ivs = Vec::new();
    for k in 0..n {
        let base = 7 + k * 8;
        if let Ok(l) = RoundCone::new(v(base), f(data, base + 3).abs(), v(base + 4), f(data, base + 7).abs()) {
            ivs.push(Tagged { iv: l.intersect(&ray), id: k as u32 });
        }
    }
    let total = ivs.iter().filter(|t| t.iv.hit).count();
    let mut out = Vec::new();
    let m = union(&mut ivs, ray.t_min, ray.t_max, |b| out.push(b));
    assert_eq!(m, out.len());
    assert!(m <= 2 * total);
    for w in out.windows(2) {
        assert!(w[0].t <= w[1].t, "unsorted {out:?}");
        assert!(w[0].entering != w[1].entering, "not alternating {out:?}");
    }
    for b in &out {
        assert!(!b.t.is_nan() && b.t >= ray.t_min && b.t <= ray.t_max);
        assert!((b.n.length() - 1.0).abs() < 1e-9, "normal {b:?}");
    }
}
