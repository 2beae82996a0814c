// Interval sanity, shared by the kernel fuzz checks (each `include!`s this file): no NaN in any
// field; on a hit `t_in ≤ t_out`, unit normals (to 1e-12 in f64, 1e-5 in f32: a few roundings of
// a normalisation) and curve parameters in [0, 1].

/// Panics unless `iv` satisfies the invariants above.
pub fn sane<T: tubecast::Scalar>(iv: &tubecast::Interval<T>) {
    let all = [iv.t_in, iv.t_out, iv.u_in, iv.u_out, iv.n_in.x, iv.n_in.y, iv.n_in.z, iv.n_out.x, iv.n_out.y, iv.n_out.z];
    assert!(all.iter().all(|x| !x.to_f64().is_nan()), "NaN in {iv:?}");
    if iv.hit {
        assert!(iv.t_in <= iv.t_out, "t_in > t_out: {iv:?}");
        let tol = if T::EPS.to_f64() < 1e-10 { 1e-12 } else { 1e-5 };
        for n in [iv.n_in, iv.n_out] {
            assert!((n.length().to_f64() - 1.0).abs() <= tol, "normal not unit: {n:?} in {iv:?}");
        }
        for u in [iv.u_in, iv.u_out] {
            assert!(u.to_f64() >= 0.0 && u.to_f64() <= 1.0, "u out of range: {iv:?}");
        }
    }
}
