// Interval sanity, shared by the kernel fuzz checks (each `include!`s this file): no NaN in any
// field; on a hit `t_in ≤ t_out`, unit normals (to 1e-12 in f64, 1e-5 in f32: a few roundings of
// a normalisation) and curve parameters in [0, 1].

/// Panics unless `iv` satisfies the invariants above.
pub fn sane<T: tubecast::Scalar>(iv: &tubecast::Interval<T>) {
    let all = [iv.entry.t, iv.exit.t, iv.entry.u, iv.exit.u, iv.entry.n.x, iv.entry.n.y, iv.entry.n.z, iv.exit.n.x, iv.exit.n.y, iv.exit.n.z];
    assert!(all.iter().all(|x| !x.to_f64().is_nan()), "NaN in {iv:?}");
    if iv.hit {
        assert!(iv.entry.t <= iv.exit.t, "t_in > t_out: {iv:?}");
        let tol = if T::EPS.to_f64() < 1e-10 { 1e-12 } else { 1e-5 };
        for n in [iv.entry.n, iv.exit.n] {
            assert!((n.length().to_f64() - 1.0).abs() <= tol, "normal not unit: {n:?} in {iv:?}");
        }
        for u in [iv.entry.u, iv.exit.u] {
            assert!(u.to_f64() >= 0.0 && u.to_f64() <= 1.0, "u out of range: {iv:?}");
        }
    }
}
