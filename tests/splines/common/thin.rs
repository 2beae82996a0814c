//! The backward-error judge of the length/radius sweep (`tests/splines/conditioning.rs`,
//! `tests/splines/approximate_solvers.rs`); the band `E` is
//! [`tubecast::spline_error_band`], derived in `src/kernel/spline.rs` ("Conditioning").

use tubecast::{QuadTube, Ray, Scalar, Solver, V3};
use tubecast_oracle::{quad_crossing_offset, ThinCase, Vec3};

/// The accurate solvers (every one the renderer or `intersect` can select but `Bisection{10}`,
/// which is approximate: `tests/splines/approximate_solvers.rs`).
pub const ACCURATE: [Solver; 4] = [Solver::Polynomial, Solver::Itp, Solver::Newton, Solver::Bisection { iters: 40 }];

/// The backward-error band `E` of a case (length units), for machine epsilon `eps`: the
/// kernel's [`tubecast::spline_error_band`] with the oracle's own `R` and `|o − p(½)|`.
pub fn band(eps: f64, c: &ThinCase) -> f64 {
    tubecast::spline_error_band(eps, c.extent, c.origin_dist)
}

/// The kernel's line interval in precision `T` (inputs are `T`-representable).
pub fn kernel<T: Scalar>(c: &ThinCase, solver: Solver) -> Option<(f64, f64)> {
    let v = |p: Vec3| V3::new(T::from_f64(p.x), T::from_f64(p.y), T::from_f64(p.z));
    let tube = QuadTube::new(c.tube.b.map(v), c.tube.r.map(T::from_f64)).expect("valid case");
    let iv = tube.line_interval_with(&Ray::new(v(c.ray.o), v(c.ray.d)), solver);
    iv.hit.then(|| (iv.entry.t.to_f64(), iv.exit.t.to_f64()))
}

/// How an answer is wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrong {
    /// A hit where the tube inflated by `E` is missed.
    Phantom,
    /// A miss where the tube deflated by `E` is hit.
    FalseMiss,
    /// A hit whose entry or exit lies outside the inflated/deflated tubes' (± `E` along the ray).
    Outside,
}

/// What went wrong with one answer, if anything (kind and description).
pub fn judge(got: Option<(f64, f64)>, c: &ThinCase, e: f64) -> Option<(Wrong, String)> {
    let infl = quad_crossing_offset(&c.tube, &c.ray, e);
    let defl = quad_crossing_offset(&c.tube, &c.ray, -e);
    let dt = e / c.ray.d.length();
    match (got, infl, defl) {
        (Some(g), None, _) => Some((Wrong::Phantom, format!("phantom hit {g:?}: the tube inflated by E misses"))),
        (None, _, Some(w)) => Some((Wrong::FalseMiss, format!("false miss: the tube deflated by E is hit at {w:?}"))),
        (Some((ti, to)), Some((ai, ao)), defl) => {
            let (bi, bo) = defl.unwrap_or((f64::INFINITY, -f64::INFINITY));
            let ok = ti >= ai - dt && to <= ao + dt && ti <= bi + dt && to >= bo - dt && ti <= to + 2.0 * dt;
            (!ok).then(|| (Wrong::Outside, format!("{ti} {to} outside [{ai}, {bi}] / [{bo}, {ao}] ± {dt}")))
        }
        _ => None,
    }
}
