//! Polynomial root isolation by the derivative cascade, and bracketed root solvers.
//!
//! Everything here is generic over [`Real`] and branch-free in the data (lanes use masks and
//! `select`); loops whose trip count depends on the data (ITP, Newton) run until **every**
//! lane has converged and freeze the lanes that already have, so a lane's result is the same
//! as the scalar call's for the same input (the arithmetic is the same sequence of IEEE
//! operations; no fused multiply-add is used).
//!
//! # Derivative cascade (Russig §3.2, Salm §3.2)
//! If `u` is monotone between consecutive *breakpoints* `x₀ < x₁ < … < x_k`, each piece holds
//! at most one root, found by a bracketed solver where the end values differ in sign. The
//! roots of `u` are then the breakpoints of its antiderivative's level. [`cascade_level`] does
//! one level with fixed-size arrays: a piece without a sign change yields a *placeholder*
//! (its right end, or its left end when `u` is exactly zero there) so the output stays sorted
//! and has a fixed length — extra breakpoints only split monotone pieces further, which is
//! harmless, and placeholders are extrema of `u`'s antiderivative's derivative (so double roots
//! without a sign change still appear among the breakpoints).
//!
//! # Solvers
//! * [`bisection`]: fixed iteration count (Russig and Salm use 10 on the GPU).
//! * [`itp`]: Oliveira & Takahashi's ITP method (interpolate, truncate, project) — never
//!   slower than bisection in the worst case, superlinear on smooth roots.
//! * [`halley_or_newton`]: safeguarded Newton (`rtsafe`): a Newton step where it stays
//!   inside the bracket, bisection otherwise; with Halley's step where it is safe ([`halley`],
//!   [`cascade_level_halley`]).

use super::quadric::quadratic_roots_in;
use crate::real::{Mask, Real};

/// How one bracket is solved (the per-bracket part of a [`crate::kernel::roots::Solver`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bracket {
    /// Fixed-iteration bisection.
    Bisection(u32),
    /// ITP to the default tolerance.
    Itp,
    /// Safeguarded Newton to the default tolerance (needs the derivative).
    Newton,
}

/// Horner evaluation of `c[0] + c[1]·x + … + c[N−1]·x^(N−1)`.
#[inline(always)]
pub fn horner<T: Real, const N: usize>(c: &[T; N], x: T) -> T {
    horner_slice(c, x)
}

/// Horner evaluation of `c[0] + c[1]·x + … + c[len−1]·x^(len−1)` (`c` non-empty).
#[inline(always)]
fn horner_slice<T: Real>(c: &[T], x: T) -> T {
    let mut i = c.len() - 1;
    let mut acc = c[i];
    while i > 0 {
        i -= 1;
        acc = acc * x + c[i];
    }
    acc
}

/// Product of two polynomials (`K = N + M − 1`).
#[inline(always)]
pub fn poly_mul<T: Real, const N: usize, const M: usize, const K: usize>(a: &[T; N], b: &[T; M]) -> [T; K] {
    debug_assert!(K + 1 == N + M);
    let mut c = [T::zero(); K];
    for i in 0..N {
        for j in 0..M {
            c[i + j] += a[i] * b[j];
        }
    }
    c
}

/// Lane-wise "strictly opposite signs".
#[inline(always)]
pub fn opposite<T: Real>(fa: T, fb: T) -> T::Mask {
    let z = T::zero();
    (fa.lt(z) & fb.gt(z)) | (fa.gt(z) & fb.lt(z))
}

/// Fixed-iteration bisection of `f` on `[a, b]` (`f(a) = fa`); returns the midpoint of the last
/// bracket. Where `f(a)`, `f(b)` do not differ in sign the result is some point of `[a, b]`.
#[inline(always)]
pub fn bisection<T: Real>(f: impl Fn(T) -> T, a: T, b: T, fa: T, iters: u32) -> T {
    let half = T::cst(0.5);
    let neg_a = fa.lt(T::zero());
    let (mut a, mut b) = (a, b);
    for _ in 0..iters {
        let m = (a + b) * half;
        let neg_m = f(m).lt(T::zero());
        // Same sign as at a: the root is in [m, b].
        let same = (neg_m & neg_a) | (!neg_m & !neg_a);
        a = T::select(same, m, a);
        b = T::select(same, b, m);
    }
    (a + b) * half
}

/// Default absolute tolerance on a root in `[0, 1]`: 4 ulps of 1.
#[inline(always)]
pub fn default_tol<T: Real>() -> T {
    T::epsilon() * T::cst(4.0)
}

/// Iteration cap of ITP and Newton: more than bisection needs to reach [`default_tol`] from a
/// unit bracket in either precision (≤ 51 halvings for f64), so the cap never binds on a
/// valid bracket; it bounds the work on pathological input.
pub const MAX_ITER: u32 = 64;

/// ITP (Oliveira & Takahashi 2020) with `κ₁ = 0.2/(b − a)`, `κ₂ = 2`, `n₀ = 1`, on a valid
/// bracket (`valid`: `fa`, `fb` of strictly opposite signs; other lanes return the midpoint).
/// Stops when the bracket is at most `2·tol` wide (returning its midpoint) or when two
/// successive ITP points are within `tol` (returning the last one: the interpolation
/// converges superlinearly while one bracket end may stay put, as in regula falsi).
#[inline(always)]
pub fn itp<T: Real>(f: impl Fn(T) -> T, a: T, b: T, fa: T, fb: T, valid: T::Mask, tol: T) -> T {
    let mut s = Itp::new(a, b, fa, fb, valid, tol);
    let mut it = 0;
    while !s.done.all() && it < MAX_ITER {
        it += 1;
        let x = s.point();
        s.update(x, f(x), it);
    }
    s.result()
}

/// The state of one [`itp`] solve.
#[derive(Clone, Copy)]
struct Itp<T: Real> {
    /// `f`'s sign flip making `y(a) < 0 < y(b)`.
    s: T,
    a: T,
    b: T,
    ya: T,
    yb: T,
    k1: T,
    rmax: T,
    tol: T,
    done: T::Mask,
    stepped: T::Mask,
    xprev: T,
    xlast: T,
}

impl<T: Real> Itp<T> {
    #[inline(always)]
    fn new(a: T, b: T, fa: T, fb: T, valid: T::Mask, tol: T) -> Self {
        let (zero, one, half) = (T::zero(), T::one(), T::cst(0.5));
        // Orient: y = s·f with y(a) < 0 < y(b).
        let s = T::select(fa.gt(zero), -one, one);
        let w0 = b - a;
        let k1 = T::cst(0.2) / T::select(w0.gt(zero), w0, one);
        let xprev = (a + b) * half;
        Self {
            s,
            a,
            b,
            ya: fa * s,
            yb: fb * s,
            k1,
            // ε·2^(n_max − j) with n_max = log2(w0/2ε) + n₀ (real-valued): starts at w0.
            rmax: w0,
            tol,
            done: !valid | w0.le(tol * T::cst(2.0)),
            stepped: T::Mask::splat(false),
            xprev,
            xlast: xprev,
        }
    }

    /// The next ITP point.
    #[inline(always)]
    fn point(&self) -> T {
        let (zero, one, half) = (T::zero(), T::one(), T::cst(0.5));
        let (a, b, ya, yb) = (self.a, self.b, self.ya, self.yb);
        let w = b - a;
        let xh = (a + b) * half;
        let r = self.rmax - w * half;
        let delta = self.k1 * w * w;
        let den = yb - ya;
        let xf = (yb * a - ya * b) / T::select(den.gt(zero), den, one);
        let sigma = T::select(xh.ge(xf), one, -one);
        let xt = T::select(delta.le((xh - xf).abs()), xf + sigma * delta, xh);
        let x = T::select((xt - xh).abs().le(r), xt, xh - sigma * r);
        x.clamp(a, b)
    }

    /// Take `f(x) = fx` (iteration `it`, from 1).
    #[inline(always)]
    fn update(&mut self, x: T, fx: T, it: u32) {
        let zero = T::zero();
        let y = fx * self.s;
        let act = !self.done;
        let lo = act & y.lt(zero);
        let hi = act & y.gt(zero);
        let ex = act & y.eq(zero);
        self.a = T::select(lo | ex, x, self.a);
        self.ya = T::select(lo, y, self.ya);
        self.b = T::select(hi | ex, x, self.b);
        self.yb = T::select(hi, y, self.yb);
        self.rmax = T::select(act, self.rmax * T::cst(0.5), self.rmax);
        let st = act & (x - self.xprev).abs().le(self.tol) & T::Mask::splat(it > 1);
        self.stepped = self.stepped | st | (act & ex);
        self.xlast = T::select(act, x, self.xlast);
        self.xprev = T::select(act, x, self.xprev);
        self.done = self.done | (self.b - self.a).le(self.tol * T::cst(2.0)) | ex | st;
    }

    #[inline(always)]
    fn result(&self) -> T {
        T::select(self.stepped, self.xlast, (self.a + self.b) * T::cst(0.5))
    }
}

/// Safeguarded Newton (`rtsafe`, [`halley_or_newton`]) taking Halley's step `x − 2ff'/(2f'² − ff'')`
/// where that falls strictly inside the bracket and is within `[⅔, 2]` times Newton's (cubic
/// convergence near a simple root: a solve from the regula-falsi start takes fewer dependent
/// steps, and dependent steps are most of what the spline's `g'`, `g` and `P` solves cost on a
/// hit); Newton's step otherwise. On the bracket `[a, b, f(a), f(b)]`, from `x0` where it lies strictly inside (NaN: the regula-falsi point).
#[inline(always)]
pub fn halley<T: Real>(
    f: impl Fn(T) -> T,
    df: impl Fn(T) -> T,
    d2f: impl Fn(T) -> T,
    bracket: [T; 4],
    x0: T,
    valid: T::Mask,
    tol: T,
) -> T {
    halley_or_newton(f, df, d2f, true, bracket, x0, valid, tol)
}

/// The safeguarded Newton solve on `[a, b, f(a), f(b)]`: Newton's steps, or Halley's (`use_d2`,
/// [`halley`]) where they qualify, from `x0` where it lies strictly inside `(a, b)` (NaN: the
/// regula-falsi point; [`Newton::new_at`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn halley_or_newton<T: Real>(
    f: impl Fn(T) -> T,
    df: impl Fn(T) -> T,
    d2f: impl Fn(T) -> T,
    use_d2: bool,
    [a, b, fa, fb]: [T; 4],
    x0: T,
    valid: T::Mask,
    tol: T,
) -> T {
    let mut s = Newton::new_at(a, b, fa, fb, x0, valid, tol);
    let mut it = 0;
    while !s.done.all() && it < MAX_ITER {
        it += 1;
        let d2 = if use_d2 { d2f(s.x) } else { T::zero() };
        s.step(f(s.x), df(s.x), d2, use_d2);
    }
    s.x
}

/// The regula-falsi point `a − f(a)(b − a)/(f(b) − f(a))` of the bracket `[a, b]` (inside it
/// where `f(a)`, `f(b)` have opposite signs; `a` where they are equal).
#[inline(always)]
pub(crate) fn regula_falsi<T: Real>(a: T, b: T, fa: T, fb: T) -> T {
    let den = fb - fa;
    a - fa * (b - a) / T::select(den.eq(T::zero()), T::one(), den)
}

/// The root of the Taylor model `f + f'δ + ½f''δ²` (`[f, f', f'']` at `e`) on the side `dir`
/// (`±1`) nearest to `e`, as `e + δ`: a start for a bracketed Halley solve from a bracket end
/// (NaN where the model has no root on that side; the solve then starts at the regula-falsi
/// point). Roots `q/(½f'')` and `f/q` with `q = −½(f' + sgn(f')√(f'² − 2ff''))`, no
/// cancellation.
#[inline(always)]
pub(crate) fn model_start<T: Real>(e: T, dir: T, [f, f1, f2]: [T; 3]) -> T {
    let (zero, half) = (T::zero(), T::cst(0.5));
    let disc = f1 * f1 - T::cst(2.0) * f * f2;
    let sq = disc.max(zero).sqrt();
    let q = -half * (f1 + T::select(f1.ge(zero), sq, -sq));
    let (d1, d2) = (q / (half * f2), f / q);
    let (ok1, ok2) = ((d1 * dir).gt(zero), (d2 * dir).gt(zero));
    let d = T::select(ok1 & (!ok2 | d1.abs().le(d2.abs())), d1, T::select(ok2, d2, T::cst(f64::NAN)));
    T::select(disc.ge(zero), e + d, T::cst(f64::NAN))
}

/// Two independent [`halley`] solves of one function in lock step (brackets
/// `[[a₀, a₁], [b₀, b₁], [f(a₀), f(a₁)], [f(b₀), f(b₁)]]`, starts `x0`): each result is bit for
/// bit the one [`halley`] returns (the same operations; a solve that has converged is frozen
/// while the other runs). Lock step lets the processor overlap two chains of dependent steps
/// (the spline's entry and exit, solved side by side).
#[inline(always)]
pub fn halley_pair<T: Real>(
    f: impl Fn(T) -> T,
    df: impl Fn(T) -> T,
    d2f: impl Fn(T) -> T,
    brackets: [[T; 2]; 4],
    x0: [T; 2],
    valid: [T::Mask; 2],
    tol: T,
) -> [T; 2] {
    pair_of(f, df, d2f, true, brackets, x0, valid, tol)
}

/// Two [`halley_or_newton`] solves in lock step (as [`halley_pair`]), from the starts `x0`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn pair_of<T: Real>(
    f: impl Fn(T) -> T,
    df: impl Fn(T) -> T,
    d2f: impl Fn(T) -> T,
    use_d2: bool,
    [a, b, fa, fb]: [[T; 2]; 4],
    x0: [T; 2],
    valid: [T::Mask; 2],
    tol: T,
) -> [T; 2] {
    let mut s = [
        Newton::new_at(a[0], b[0], fa[0], fb[0], x0[0], valid[0], tol),
        Newton::new_at(a[1], b[1], fa[1], fb[1], x0[1], valid[1], tol),
    ];
    let mut it = 0;
    while !(s[0].done.all() && s[1].done.all()) && it < MAX_ITER {
        it += 1;
        let (x0, x1) = (s[0].x, s[1].x);
        let (y0, y1) = (f(x0), f(x1));
        let (d0, d1) = (df(x0), df(x1));
        let (e0, e1) = if use_d2 { (d2f(x0), d2f(x1)) } else { (T::zero(), T::zero()) };
        s[0].step(y0, d0, e0, use_d2);
        s[1].step(y1, d1, e1, use_d2);
    }
    [s[0].x, s[1].x]
}

/// The state of one safeguarded Newton solve ([`halley_or_newton`]): a Newton (or Halley)
/// step of `f/df` where it falls strictly inside the current bracket, bisection otherwise;
/// stops when a step is at most `tol`, the bracket is at most `tol` wide, or a Newton step
/// lands within `tol` beyond an end whose value is within `2·tol·|f'|` of zero (the root is
/// then that end, to first order).
#[derive(Clone, Copy)]
struct Newton<T: Real> {
    /// `f`'s sign flip making `y(a) < 0 < y(b)`.
    s: T,
    a: T,
    b: T,
    ya: T,
    yb: T,
    x: T,
    tol: T,
    done: T::Mask,
}

impl<T: Real> Newton<T> {
    #[inline(always)]
    fn new(a: T, b: T, fa: T, fb: T, valid: T::Mask, tol: T) -> Self {
        let (zero, one, half) = (T::zero(), T::one(), T::cst(0.5));
        let s = T::select(fa.gt(zero), -one, one);
        let (ya, yb) = (fa * s, fb * s);
        // Start at the regula-falsi point (inside the bracket for a valid one).
        let x = T::select(valid, regula_falsi(a, b, ya, yb).clamp(a, b), (a + b) * half);
        Self { s, a, b, ya, yb, x, tol, done: !valid | (b - a).le(tol) }
    }

    /// [`Self::new`] starting at `x0` where it lies strictly inside `(a, b)` (false for NaN),
    /// at the regula-falsi point elsewhere.
    #[inline(always)]
    fn new_at(a: T, b: T, fa: T, fb: T, x0: T, valid: T::Mask, tol: T) -> Self {
        let mut s = Self::new(a, b, fa, fb, valid, tol);
        s.x = T::select(valid & x0.gt(a) & x0.lt(b), x0, s.x);
        s
    }

    /// One step from `f(x) = fx`, `f'(x) = dfx` (and `f''(x) = d2fx` where `use_d2`: Halley's
    /// step where it falls strictly inside the bracket).
    #[inline(always)]
    fn step(&mut self, fx: T, dfx: T, d2fx: T, use_d2: bool) {
        let (zero, half, tol) = (T::zero(), T::cst(0.5), self.tol);
        let (x, s) = (self.x, self.s);
        let act = !self.done;
        let y = fx * s;
        let dy = dfx * s;
        let lo = act & y.lt(zero);
        let hi = act & y.gt(zero);
        self.a = T::select(lo, x, self.a);
        self.b = T::select(hi, x, self.b);
        self.ya = T::select(lo, y, self.ya);
        self.yb = T::select(hi, y, self.yb);
        let (a, b) = (self.a, self.b);
        let xn = x - y / dy;
        let inside = xn.gt(a) & xn.lt(b); // false for NaN / ±∞
        let xm = (a + b) * half;
        // A root within rounding of a bracket end (a root of `f` at a breakpoint of the
        // cascade's level below, where `f` is flat) makes every Newton step overshoot that
        // end, and bisection then crept towards it for up to ~40 steps (a noticeable share of
        // the spline cascade's solves took 16 or more). Newton landing within `tol` beyond an
        // end whose value is within `2·tol·|f'|` of zero puts the root within `2·tol` of that
        // end to first order: take the end.
        let reach = (dy * tol).abs() * T::cst(2.0);
        let at_a = !inside & xn.le(a) & xn.ge(a - tol) & self.ya.abs().le(reach);
        let at_b = !inside & xn.ge(b) & xn.le(b + tol) & self.yb.abs().le(reach);
        let mut xnew = T::select(inside, xn, T::select(at_a, a, T::select(at_b, b, xm)));
        if use_d2 {
            // Halley's step is Newton's times 1/(1 − L/2), L = f f''/f'²; taken only where
            // |L| ≤ 1, so that it is within [⅔, 2] times Newton's and a step ≤ tol means what
            // it means for Newton. (Near a bracket end where f' → 0 — the cascade's pieces end
            // at the roots of f' — Halley's step tends to −2f'/f'' → 0 while f ≠ 0: unguarded,
            // it stopped there, far from the root.)
            let (two, d2y) = (T::cst(2.0), d2fx * s);
            let (dy2, yd2) = (dy * dy, y * d2y);
            let xh = x - two * y * dy / (two * dy2 - yd2);
            let take = yd2.abs().le(dy2) & xh.gt(a) & xh.lt(b); // false for NaN / ±∞
            xnew = T::select(take, xh, xnew);
        }
        let step = (xnew - x).abs();
        let conv = y.eq(zero) | step.le(tol) | (b - a).le(tol) | at_a | at_b;
        self.x = T::select(act & !y.eq(zero), xnew, x);
        self.done = self.done | (act & conv);
    }
}

/// One level of the derivative cascade on fixed-size buffers.
///
/// `bp[..n]` are sorted breakpoints between which `f` is monotone; returns `n + 1` breakpoints
/// `bp[0], x₁, …, x_{n−1}, bp[n−1]` where `x_i` is the root of `f` in piece `i` (or a
/// placeholder, see the module docs). `df` is only called by [`Bracket::Newton`].
#[inline(always)]
pub fn cascade_level<T: Real>(
    bp: &[T; 8],
    n: usize,
    f: impl Fn(T) -> T + Copy,
    df: impl Fn(T) -> T + Copy,
    method: Bracket,
) -> [T; 8] {
    level_with(bp, n, f, df, |_| T::zero(), false, method, no_start)
}

/// [`cascade_level`] with [`Bracket::Newton`] solving by [`halley`] (`d2f` the second
/// derivative), each solve started at `start(a, b, f(a), f(b))` where that lies strictly
/// inside its bracket (NaN, e.g. [`no_start`]: at the regula-falsi point).
#[inline(always)]
pub fn cascade_level_halley<T: Real>(
    bp: &[T; 8],
    n: usize,
    f: impl Fn(T) -> T + Copy,
    df: impl Fn(T) -> T + Copy,
    d2f: impl Fn(T) -> T + Copy,
    start: impl Fn(T, T, T, T) -> T + Copy,
) -> [T; 8] {
    level_with(bp, n, f, df, d2f, true, Bracket::Newton, start)
}

/// No start: every solve of [`cascade_level_halley`] from the regula-falsi point.
#[inline(always)]
pub fn no_start<T: Real>(_: T, _: T, _: T, _: T) -> T {
    T::cst(f64::NAN)
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn level_with<T: Real>(
    bp: &[T; 8],
    n: usize,
    f: impl Fn(T) -> T + Copy,
    df: impl Fn(T) -> T + Copy,
    d2f: impl Fn(T) -> T + Copy,
    use_d2: bool,
    method: Bracket,
    start: impl Fn(T, T, T, T) -> T + Copy,
) -> [T; 8] {
    debug_assert!((2..8).contains(&n));
    let mut fv = [T::zero(); 8];
    for i in 0..n {
        fv[i] = f(bp[i]);
    }
    let mut out = [T::zero(); 8];
    out[0] = bp[0];
    out[n] = bp[n - 1];
    let tol = default_tol::<T>();
    // A function value of exactly 0 at a piece end carries no sign. For polynomials that is a
    // root at the end; for the spline's scaled sign functions (`2√g·f'` …) it happens where
    // g = 0 while f' ≠ 0, so the sign is taken a little inside, at √ε of the piece width
    // (a root closer than that to the end is represented by the end, a candidate anyway).
    let nudge = T::epsilon().sqrt();
    // Newton's pieces with a sign change somewhere: (piece, bracket, lanes).
    let mut pend = [(0usize, [T::zero(); 4], T::Mask::splat(false)); 7];
    let mut np = 0;
    for i in 0..n - 1 {
        let (mut a, mut b, mut fa, mut fb) = (bp[i], bp[i + 1], fv[i], fv[i + 1]);
        let (za, zb) = (fa.eq(T::zero()), fb.eq(T::zero()));
        if (za | zb).any() {
            let w = (b - a) * nudge;
            let (a2, b2) = (a + w, b - w);
            let ok = w.gt(T::zero());
            let (za, zb) = (za & ok, zb & ok);
            if za.any() {
                a = T::select(za, a2, a);
                fa = T::select(za, f(a2), fa);
            }
            if zb.any() {
                b = T::select(zb, b2, b);
                fb = T::select(zb, f(b2), fb);
            }
        }
        let valid = opposite(fa, fb);
        // Placeholder: the left end if f is exactly 0 there, else the right end.
        let ph = T::select(fv[i].eq(T::zero()), bp[i], bp[i + 1]);
        out[i + 1] = ph;
        if valid.none() {
            continue;
        }
        if method == Bracket::Newton && T::LANES == 1 {
            // Solved below, two pieces at a time (scalars only: in lanes a pair runs until
            // both solves have converged in every lane, which measured slower than one at a time).
            pend[np] = (i, [a, b, fa, fb], valid);
            np += 1;
            continue;
        }
        let r = match method {
            Bracket::Bisection(k) => bisection(f, a, b, fa, k),
            Bracket::Itp => itp(f, a, b, fa, fb, valid, tol),
            Bracket::Newton => halley_or_newton(f, df, d2f, use_d2, [a, b, fa, fb], start(a, b, fa, fb), valid, tol),
        };
        out[i + 1] = T::select(valid, r, ph);
    }
    // Scalar Newton solves in pairs ([`pair_of`]: the same roots as one at a time).
    let mut k = 0;
    while k < np {
        let (i, [a, b, fa, fb], valid) = pend[k];
        if k + 1 < np {
            let (j, [a2, b2, fa2, fb2], valid2) = pend[k + 1];
            let x0 = [start(a, b, fa, fb), start(a2, b2, fa2, fb2)];
            let [r, r2] =
                pair_of(f, df, d2f, use_d2, [[a, a2], [b, b2], [fa, fa2], [fb, fb2]], x0, [valid, valid2], tol);
            out[i + 1] = T::select(valid, r, out[i + 1]);
            out[j + 1] = T::select(valid2, r2, out[j + 1]);
            k += 2;
        } else {
            let r = halley_or_newton(f, df, d2f, use_d2, [a, b, fa, fb], start(a, b, fa, fb), valid, tol);
            out[i + 1] = T::select(valid, r, out[i + 1]);
            k += 1;
        }
    }
    out
}

/// All real roots of the polynomial `c` (degree `N − 1 ≤ 6`) in `[lo, hi]`, as breakpoints:
/// returns `(buf, n)` with `buf[..n]` sorted, `buf[0] = lo`, `buf[n−1] = hi`, every root of `c`
/// in `[lo, hi]` that changes sign among `buf[1..n−1]` (and every root of even multiplicity that
/// is an extremum found by a lower level), plus placeholders. Uses the derivative cascade
/// from the quadratic `c^(N−3)` (analytic) upward with the given bracket method.
#[inline(always)]
pub fn poly_breakpoints<T: Real, const N: usize>(c: &[T; N], lo: T, hi: T, method: Bracket) -> ([T; 8], usize) {
    assert!((3..=7).contains(&N), "degree 2..=6");
    // Derivatives d[k] = c^(k), stored padded to 7 coefficients.
    let mut ders = [[T::zero(); 7]; 5];
    ders[0][..N].copy_from_slice(c);
    for k in 1..N - 2 {
        for i in 0..N - k {
            ders[k][i] = ders[k - 1][i + 1] * T::cst((i + 1) as f64);
        }
    }
    let top = N - 3; // ders[top] is quadratic
    let q = [ders[top][0], ders[top][1], ders[top][2]];
    let (x1, x2) = quadratic_roots_in(&q, lo, hi);
    let mut bp = [hi; 8];
    bp[0] = lo;
    bp[1] = x1;
    bp[2] = x2;
    bp[3] = hi;
    let mut n = 4;
    let mut k = top;
    while k > 0 {
        k -= 1;
        // Level k's derivative is level k + 1: the same products `c_i·i` as differentiating
        // on the fly, so the same values.
        let (p, dp) = (ders[k], ders[k + 1]);
        let deg = N - 1 - k;
        let f = move |x: T| horner_slice(&p[..=deg], x);
        let df = move |x: T| horner_slice(&dp[..deg], x);
        bp = cascade_level(&bp, n, f, df, method);
        n += 1;
    }
    (bp, n)
}

#[cfg(test)]
mod tests;
