//! The spline kernel's solver choice, [`Solver`], and the polynomial root finders it uses
//! (re-exported from the crate's shared maths).
//!
//! * [`bisection`]: fixed iteration count (Russig and Salm use 10 on the GPU).
//! * [`itp`]: Oliveira & Takahashi's ITP method (interpolate, truncate, project) — never
//!   slower than bisection in the worst case, superlinear on smooth roots.
//! * [`newton`]: safeguarded Newton (`rtsafe`): a Newton step where it stays inside the
//!   bracket and shrinks fast enough, bisection otherwise.
//! * [`cascade_level`], [`poly_breakpoints`]: the derivative cascade (Russig §3.2, Salm §3.2):
//!   between consecutive roots of `u'` the function `u` is monotone and holds at most one root.

pub use crate::math::quadric::quadratic_roots_in;
pub use crate::math::roots::{
    bisection, cascade_level, default_tol, derivative, horner, itp, newton, opposite, poly_breakpoints, poly_mul,
    Bracket, MAX_ITER,
};

/// Root-finding strategy of the spline kernel ([`crate::kernel::spline::QuadTube`]).
///
/// All variants are exact in the sense that they bracket every critical point the method's
/// model admits; they differ in the work per bracket and in the final accuracy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Russig's cascade (real intervals of `g` by `g''` analytic → `g'` → `g`; minima of `f`
    /// by `f'''` → `f''` → `f'` on each real interval) with fixed-iteration bisection in every
    /// bracket. `iters = 10` is Salm's setting; the `t` error is `2^-iters` of the bracket.
    /// The cascade relies on Russig's empirical claim (at most one root of `f'''` per real
    /// interval), which has counterexamples (`tests/spline_claims.rs`); so do `Itp`, `Newton`.
    Bisection {
        /// Bisection steps per bracket.
        iters: u32,
    },
    /// Russig's cascade with the ITP method in every bracket, to a `t` tolerance of a few ulps.
    Itp,
    /// Russig's cascade with safeguarded Newton on the polynomial levels (`g'`, `g`) and on
    /// `f'`, ITP on `f'''` and `f''` (whose derivatives are not worth forming).
    Newton,
    /// The polynomial form: critical points of `f = h − √g` and of the exit `e = h + √g` are
    /// the roots of `P = 4h′²g − g′²` (degree 6; `h′g′ ≥ 0` at those of `f`); all roots of `P`
    /// in `[0, 1]` by the derivative cascade (`P⁗` analytic) with safeguarded Newton. Relies on
    /// no empirical claim about the number of roots of `f'`.
    Polynomial,
}

impl Default for Solver {
    /// [`Solver::Polynomial`]: the one whose correctness rests on no empirical claim.
    fn default() -> Self {
        Solver::Polynomial
    }
}
