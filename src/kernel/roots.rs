//! The spline kernel's solver choice, [`Solver`]. The root finders it selects (bisection, ITP,
//! safeguarded Newton, the derivative cascade) live in the crate's shared maths (`math::roots`).

/// Root-finding strategy of the spline kernel ([`crate::QuadTube::intersect_with`]).
///
/// Which is exact and which approximate:
///
/// | solver | answer |
/// |---|---|
/// | [`Solver::Polynomial`] (default) | exact to the kernel's band; rests on no empirical claim |
/// | [`Solver::Newton`], [`Solver::Itp`] | accurate where Russig's claim holds; where it fails the interval can lie inside the true one |
/// | [`Solver::Bisection`] | approximate below about 30 steps; as `Itp` from 40 |
///
/// ```
/// use tubecast::{QuadTube, Ray, Solver, V3};
/// let tube = QuadTube::new([V3::new(0.0f64, 0.0, 0.0), V3::new(1.0, 1.0, 0.0), V3::new(2.0, 0.0, 0.0)], [0.2; 3])?;
/// let ray = Ray::new(V3::new(1.0, 0.5, -5.0), V3::new(0.0, 0.0, 1.0));
/// let exact = tube.intersect_with(&ray, Solver::Polynomial);
/// let fast = tube.intersect_with(&ray, Solver::Bisection { iters: 10 });
/// assert!(exact.hit && fast.hit && (exact.entry.t - fast.entry.t).abs() < 1e-2);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Russig's cascade (real intervals of `g` by `g'''` analytic → `g''` → `g'` → `g`; minima of `f`
    /// by `f'''` → `f''` → `f'` on each real interval) with fixed-iteration bisection in every
    /// bracket. `iters = 10` is Salm's setting; the `t` error is `2^-iters` of the bracket.
    /// The cascade relies on Russig's empirical claim (at most one root of `f'''` per real
    /// interval), which has counterexamples (`tests/splines/derivative_roots.rs`); so do `Itp`, `Newton`.
    ///
    /// **Approximate below about 30 steps**: a `t` located to `2^-iters` puts a thin tube's
    /// entry far from the critical point (its width in `t` is `~r/L`) and can lose a real
    /// interval narrower than `2^-iters` — false misses and late entries outside the kernel's
    /// band (`tests/splines/approximate_solvers.rs` measures them). Never a default; `iters ≥ 40` meets
    /// the band of the accurate solvers (`tests/splines/conditioning.rs`).
    Bisection {
        /// Bisection steps per bracket.
        iters: u32,
    },
    /// Russig's cascade with the ITP method in every bracket, to a `t` tolerance of a few ulps.
    ///
    /// **Not exact where Russig's claim fails** (as `Bisection` and `Newton`): it can take a
    /// segment end for an interior extremum, e.g. an exit 0.055 inside a bulging tube
    /// (`tests/splines/regressions.rs`, `bulge_itp_ci_finding`). Every value it reports is a real
    /// sphere's entry or exit, so its interval lies inside the true one; the renderer and the
    /// CLI use [`Solver::Polynomial`].
    Itp,
    /// Russig's cascade with `g''`'s roots in closed form, safeguarded Newton on the
    /// polynomial levels (`g'`, `g`) and on `f'`, ITP on `f'''` and `f''` (whose derivatives
    /// are not worth forming).
    Newton,
    /// The polynomial form: critical points of `f = h − √g` and of the exit `e = h + √g` are
    /// the roots of `P = 4h′²g − g′²` (degree 6; `h′g′ ≥ 0` at those of `f`); all roots of `P`
    /// in `[0, 1]` by the derivative cascade (`P⁗` analytic) with safeguarded Newton, and the
    /// roots and maxima of `g` (`g''` analytic), as candidates, the best polished. Relies on
    /// no empirical claim about the number of roots of `f'`.
    Polynomial,
}

impl Default for Solver {
    /// [`Solver::Polynomial`]: the one whose correctness rests on no empirical claim.
    fn default() -> Self {
        Solver::Polynomial
    }
}
