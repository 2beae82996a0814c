//! The methods the reports compare, how they are run on a case set (results and timing), and
//! how their results are scored against the oracle.

use super::oracle::{self, link_bound, LinkCase, LinkTruth, SplineCase, SplineTruth};
use std::hint::black_box;
use std::time::{Duration, Instant};
use tubecast::baseline::HanLink;
use tubecast::QuadTube;
use tubecast::Solver;
use tubecast::{Interval, Primitive, Ray, Real, RoundCone, Scalar};

/// Lane type of a method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// Scalar `f32`.
    F32,
    /// Scalar `f64`.
    F64,
    /// Eight `f32` lanes (feature `wide`).
    F32x8,
    /// Four `f64` lanes (feature `wide`).
    F64x4,
}

impl Precision {
    /// Every precision this build supports.
    pub fn all() -> Vec<Precision> {
        let mut v = vec![Precision::F32, Precision::F64];
        if cfg!(feature = "wide") {
            v.extend([Precision::F32x8, Precision::F64x4]);
        }
        v
    }
    /// Name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::F32 => "f32",
            Self::F64 => "f64",
            Self::F32x8 => "f32x8",
            Self::F64x4 => "f64x4",
        }
    }
    /// Unit roundoff of one lane.
    pub fn eps(self) -> f64 {
        match self {
            Self::F32 | Self::F32x8 => f32::EPSILON as f64,
            Self::F64 | Self::F64x4 => f64::EPSILON,
        }
    }
    /// Spacing of the lane's floating-point numbers at `x` (one ulp).
    pub fn ulp(self, x: f64) -> f64 {
        match self {
            Self::F32 | Self::F32x8 => {
                let a = (x as f32).abs().max(f32::MIN_POSITIVE);
                (f32::from_bits(a.to_bits() + 1) - a) as f64
            }
            Self::F64 | Self::F64x4 => {
                let a = x.abs().max(f64::MIN_POSITIVE);
                f64::from_bits(a.to_bits() + 1) - a
            }
        }
    }
}

/// Which link kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkKernel {
    /// [`RoundCone::intersect`]: the stable formulation.
    Stable,
    /// [`HanLink::intersect`]: faithful Han et al., transform precomputed (option d).
    HanPrecomputed,
    /// [`RoundCone::intersect_han_on_the_fly`]: faithful, built per call (option c).
    HanOnTheFly,
    /// The link as a straight [`QuadTube`] through the spline kernel with this solver.
    AsSpline(Solver),
}

impl LinkKernel {
    /// Name in tables.
    pub fn name(self) -> String {
        match self {
            Self::Stable => "stable".into(),
            Self::HanPrecomputed => "faithful-precomputed".into(),
            Self::HanOnTheFly => "faithful-on-the-fly".into(),
            Self::AsSpline(s) => format!("as-spline-{}", solver_name(s)),
        }
    }
}

/// Short name of a spline solver setting.
pub fn solver_name(s: Solver) -> String {
    match s {
        Solver::Bisection { iters } => format!("bisection{iters}"),
        Solver::Itp => "itp".into(),
        Solver::Newton => "newton".into(),
        Solver::Polynomial => "polynomial".into(),
    }
}

/// A link method: kernel × precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinkMethod {
    /// Kernel.
    pub kernel: LinkKernel,
    /// Precision.
    pub prec: Precision,
}

impl LinkMethod {
    /// `kernel/precision`.
    pub fn name(&self) -> String {
        format!("{}/{}", self.kernel.name(), self.prec.name())
    }
}

/// A spline method: solver × precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplineMethod {
    /// Solver.
    pub solver: Solver,
    /// Precision.
    pub prec: Precision,
}

impl SplineMethod {
    /// `solver/precision`.
    pub fn name(&self) -> String {
        format!("{}/{}", solver_name(self.solver), self.prec.name())
    }
}

/// The solver settings the reports sweep.
pub fn solvers() -> Vec<Solver> {
    vec![
        Solver::Bisection { iters: 6 },
        Solver::Bisection { iters: 10 },
        Solver::Bisection { iters: 16 },
        Solver::Bisection { iters: 24 },
        Solver::Itp,
        Solver::Newton,
        Solver::Polynomial,
    ]
}

/// Every link method.
pub fn link_methods() -> Vec<LinkMethod> {
    let mut v = Vec::new();
    for prec in Precision::all() {
        for kernel in [
            LinkKernel::Stable,
            LinkKernel::HanPrecomputed,
            LinkKernel::HanOnTheFly,
            LinkKernel::AsSpline(Solver::Polynomial),
        ] {
            v.push(LinkMethod { kernel, prec });
        }
    }
    v
}

/// Every spline method.
pub fn spline_methods() -> Vec<SplineMethod> {
    let mut v = Vec::new();
    for prec in Precision::all() {
        for solver in solvers() {
            v.push(SplineMethod { solver, prec });
        }
    }
    v
}

/// One method's answer for one case, in `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Hit mask (line interval overlaps the ray's range).
    pub hit: bool,
    /// Line entry.
    pub t_in: f64,
    /// Line exit.
    pub t_out: f64,
}

fn outcome<T: Scalar>(iv: &Interval<T>) -> Outcome {
    Outcome { hit: iv.hit, t_in: iv.entry.t.to_f64(), t_out: iv.exit.t.to_f64() }
}

/// Results of one method on a case set, and its cost.
#[derive(Clone, Debug)]
pub struct MethodRun {
    /// One outcome per case.
    pub outcomes: Vec<Outcome>,
    /// Nanoseconds per ray–primitive test (best of the timing repetitions).
    pub ns: f64,
}

/// Run `f` over packs `0..n` for at least `budget` (and at least 3 times); best time per test.
fn time_packs<T: Real>(n: usize, budget: Duration, f: impl Fn(usize) -> Interval<T>) -> f64 {
    let tests = (n * T::LANES).max(1) as f64;
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut reps = 0;
    loop {
        let t0 = Instant::now();
        for i in 0..n {
            black_box(f(black_box(i)));
        }
        best = best.min(t0.elapsed().as_secs_f64());
        reps += 1;
        if (reps >= 3 && start.elapsed() >= budget) || reps >= 10_000 {
            break;
        }
    }
    best * 1e9 / tests
}

fn packs<T: Real>(len: usize) -> usize {
    len.div_ceil(T::LANES)
}

fn idx<T: Real>(i: usize, j: usize, len: usize) -> usize {
    (i * T::LANES + j).min(len - 1)
}

/// The rays of `len` cases in packs of `T::LANES` (the last pack repeats the last case).
fn pack_rays<T: Real>(n: usize, len: usize, ray: impl Fn(usize) -> Ray<f64>) -> Vec<Ray<T>> {
    (0..n)
        .map(|i| {
            Ray::from_fn(|j| {
                let r = ray(idx::<T>(i, j, len));
                Ray::new(r.o.cast(), r.d.cast())
            })
        })
        .collect()
}

/// One outcome per case from the packed results of `f` (padding lanes dropped).
fn unpack_outcomes<T: Real>(n: usize, len: usize, f: &impl Fn(usize) -> Interval<T>) -> Vec<Outcome> {
    let mut outcomes = Vec::with_capacity(len);
    for i in 0..n {
        let iv = f(i);
        for j in 0..T::LANES {
            if i * T::LANES + j < len {
                outcomes.push(outcome(&iv.lane(j)));
            }
        }
    }
    outcomes
}

fn run_link_t<T: Real>(kernel: LinkKernel, cases: &[LinkCase], budget: Duration) -> MethodRun {
    let len = cases.len();
    let n = packs::<T>(len);
    let links: Vec<RoundCone<T>> = (0..n)
        .map(|i| RoundCone::from_lanes(|j| oracle::round_cone(&cases[idx::<T>(i, j, len)].link).cast()))
        .collect();
    let rays = pack_rays::<T>(n, len, |k| oracle::ray(&cases[k].ray));
    let han: Vec<HanLink<T>> = links.iter().map(HanLink::new).collect();
    let tubes: Vec<QuadTube<T>> = if matches!(kernel, LinkKernel::AsSpline(_)) {
        (0..n)
            .map(|i| {
                QuadTube::from_lanes(|j| {
                    let l: RoundCone<T::Elem> = oracle::round_cone(&cases[idx::<T>(i, j, len)].link).cast();
                    // An error cannot happen for validated links; fall back to the centre sphere.
                    QuadTube::from_link(&l).unwrap_or(QuadTube { b: [l.a, l.a, l.a], r: [l.ra, l.ra, l.ra] })
                })
            })
            .collect()
    } else {
        Vec::new()
    };
    let f = |i: usize| -> Interval<T> {
        match kernel {
            LinkKernel::Stable => links[i].intersect(&rays[i]),
            LinkKernel::HanPrecomputed => han[i].intersect(&rays[i]),
            LinkKernel::HanOnTheFly => links[i].intersect_han_on_the_fly(&rays[i]),
            LinkKernel::AsSpline(s) => tubes[i].intersect_with(&rays[i], s),
        }
    };
    let outcomes = unpack_outcomes::<T>(n, len, &f);
    let ns = if budget.is_zero() { f64::NAN } else { time_packs(n, budget, f) };
    MethodRun { outcomes, ns }
}

fn run_spline_t<T: Real>(solver: Solver, cases: &[SplineCase], budget: Duration) -> MethodRun {
    let len = cases.len();
    let n = packs::<T>(len);
    let tubes: Vec<QuadTube<T>> =
        (0..n).map(|i| QuadTube::from_lanes(|j| oracle::quad_tube(&cases[idx::<T>(i, j, len)].tube).cast())).collect();
    let rays = pack_rays::<T>(n, len, |k| oracle::ray(&cases[k].ray));
    let f = |i: usize| tubes[i].intersect_with(&rays[i], solver);
    let outcomes = unpack_outcomes::<T>(n, len, &f);
    let ns = if budget.is_zero() { f64::NAN } else { time_packs(n, budget, f) };
    MethodRun { outcomes, ns }
}

/// A run generic over the lane type, dispatched on a [`Precision`] once ([`run_at`]).
trait LaneRun {
    /// Cases in the run.
    fn len(&self) -> usize;
    /// The run with lanes `T`.
    fn run<T: Real>(&self) -> MethodRun;
}

/// `job` in the lane type of `prec` (no run, `ns` NaN, for an empty case set or a precision
/// this build lacks).
fn run_at(prec: Precision, job: &impl LaneRun) -> MethodRun {
    if job.len() == 0 {
        return MethodRun { outcomes: Vec::new(), ns: f64::NAN };
    }
    match prec {
        Precision::F32 => job.run::<f32>(),
        Precision::F64 => job.run::<f64>(),
        #[cfg(feature = "wide")]
        Precision::F32x8 => job.run::<tubecast::WideF32x8>(),
        #[cfg(feature = "wide")]
        Precision::F64x4 => job.run::<tubecast::WideF64x4>(),
        #[cfg(not(feature = "wide"))]
        _ => MethodRun { outcomes: Vec::new(), ns: f64::NAN },
    }
}

struct LinkRun<'a>(LinkKernel, &'a [LinkCase], Duration);
impl LaneRun for LinkRun<'_> {
    fn len(&self) -> usize {
        self.1.len()
    }
    fn run<T: Real>(&self) -> MethodRun {
        run_link_t::<T>(self.0, self.1, self.2)
    }
}

struct SplineRun<'a>(Solver, &'a [SplineCase], Duration);
impl LaneRun for SplineRun<'_> {
    fn len(&self) -> usize {
        self.1.len()
    }
    fn run<T: Real>(&self) -> MethodRun {
        run_spline_t::<T>(self.0, self.1, self.2)
    }
}

/// Run a link method on `cases`; time it for about `budget` (zero: no timing, `ns` is NaN).
pub fn run_link(m: LinkMethod, cases: &[LinkCase], budget: Duration) -> MethodRun {
    run_at(m.prec, &LinkRun(m.kernel, cases, budget))
}

/// Run a spline method on `cases` (see [`run_link`]).
pub fn run_spline(m: SplineMethod, cases: &[SplineCase], budget: Duration) -> MethodRun {
    run_at(m.prec, &SplineRun(m.solver, cases, budget))
}

/// Scores of one method on one case set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Score {
    /// Cases.
    pub n: usize,
    /// Cases the oracle says must hit (outside the method's error band).
    pub must_hit: usize,
    /// Of those, reported misses.
    pub false_miss: usize,
    /// Cases the oracle says must miss (outside the band).
    pub must_miss: usize,
    /// Of those, reported hits.
    pub false_hit: usize,
    /// `t` errors (max of entry and exit) in units of the primitive's largest radius, one per
    /// robust hit.
    pub err_r: Vec<f64>,
    /// The same errors in ulps of `t` in the method's precision.
    pub err_ulp: Vec<f64>,
    /// Error divided by the `tests/kernels/link/properties.rs` bound for the method's precision (links only;
    /// empty for splines and where the surface has no normal).
    pub bound_ratio: Vec<f64>,
}

/// Percentile `p ∈ [0, 1]` (nearest rank) of unsorted values; NaN when empty.
pub fn percentile(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let k = ((p * s.len() as f64).ceil() as usize).clamp(1, s.len()) - 1;
    s[k]
}

impl Score {
    /// Count one case the oracle decided (`must_hit` / `must_miss`, outside the band) against
    /// the method's answer `hit`.
    fn classify(&mut self, must_hit: bool, must_miss: bool, hit: bool) {
        if must_hit {
            self.must_hit += 1;
            self.false_miss += usize::from(!hit);
        }
        if must_miss {
            self.must_miss += 1;
            self.false_hit += usize::from(hit);
        }
    }

    /// Largest error (radii).
    pub fn max_r(&self) -> f64 {
        self.err_r.iter().copied().fold(f64::NAN, f64::max)
    }
    /// 99th percentile error (radii).
    pub fn p99_r(&self) -> f64 {
        percentile(&self.err_r, 0.99)
    }
    /// Median error (radii).
    pub fn p50_r(&self) -> f64 {
        percentile(&self.err_r, 0.5)
    }
    /// Largest error (ulps).
    pub fn max_ulp(&self) -> f64 {
        self.err_ulp.iter().copied().fold(f64::NAN, f64::max)
    }
    /// 99th percentile error (ulps).
    pub fn p99_ulp(&self) -> f64 {
        percentile(&self.err_ulp, 0.99)
    }
    /// Largest error/bound ratio.
    pub fn max_bound_ratio(&self) -> f64 {
        self.bound_ratio.iter().copied().fold(f64::NAN, f64::max)
    }
    /// False-miss rate among must-hit cases.
    pub fn false_miss_rate(&self) -> f64 {
        self.false_miss as f64 / self.must_hit.max(1) as f64
    }
    /// False-hit rate among must-miss cases.
    pub fn false_hit_rate(&self) -> f64 {
        self.false_hit as f64 / self.must_miss.max(1) as f64
    }
}

/// Score link outcomes against the oracle. The classification band is the
/// `tests/kernels/link/properties.rs` hit-point bound `E` for the method's precision: outside it a correct
/// kernel must classify the case right.
pub fn score_links(prec: Precision, cases: &[LinkCase], truth: &[LinkTruth], out: &[Outcome]) -> Score {
    let mut s = Score { n: cases.len(), ..Score::default() };
    for ((c, tr), o) in cases.iter().zip(truth).zip(out) {
        let (_, e) = link_bound(c, prec.eps(), 1.0);
        let (_, e64) = link_bound(c, f64::EPSILON, 1.0);
        let t_tol = (e + e64) / c.ray.d.length();
        // The cases' rays start at t = 0.
        let must_hit = tr.gap < -e && tr.iv.is_some_and(|iv| iv.1 > 0.0 + t_tol);
        let must_miss = tr.gap > e || tr.iv.is_some_and(|iv| iv.1 < 0.0 - t_tol);
        s.classify(must_hit, must_miss, o.hit);
        if let (true, true, Some((ti, to))) = (o.hit, tr.gap < -e, tr.iv) {
            let r = c.link.ra.max(c.link.rb);
            let dl = c.ray.d.length();
            let (ei, eo) = ((o.t_in - ti).abs(), (o.t_out - to).abs());
            s.err_r.push(ei.max(eo) * dl / r);
            s.err_ulp.push((ei / prec.ulp(ti)).max(eo / prec.ulp(to)));
            let (gi, go) = tr.gamma;
            if gi.is_finite() && go.is_finite() && gi > 0.0 && go > 0.0 {
                let (bi, _) = link_bound(c, prec.eps(), gi);
                let (bo, _) = link_bound(c, prec.eps(), go);
                s.bound_ratio.push((ei / (bi + 1e-12 * ti.abs())).max(eo / (bo + 1e-12 * to.abs())));
            }
        }
    }
    s
}

/// Score spline outcomes against the dense oracle. Band: the kernel's derived backward-error
/// band [`tubecast::spline_error_band`] (`QuadTube::error_band`), plus `1e-9·R` for the
/// sampled oracle.
pub fn score_splines(prec: Precision, cases: &[SplineCase], truth: &[SplineTruth], out: &[Outcome]) -> Score {
    let mut s = Score { n: cases.len(), ..Score::default() };
    for ((c, tr), o) in cases.iter().zip(truth).zip(out) {
        let tube = oracle::quad_tube(&c.tube);
        let band = tube.error_band(oracle::v3(c.ray.o), prec.eps()) + 1e-9 * tube.bounding_radius();
        let dl = c.ray.d.length();
        let must_hit = tr.gap < -band && tr.iv.is_some_and(|iv| iv.1 > band / dl);
        let must_miss = tr.gap > band || tr.iv.is_some_and(|iv| iv.1 < -band / dl);
        s.classify(must_hit, must_miss, o.hit);
        if let (true, true, Some((ti, to))) = (o.hit, tr.gap < -band, tr.iv) {
            let (ei, eo) = ((o.t_in - ti).abs(), (o.t_out - to).abs());
            s.err_r.push(ei.max(eo) * dl / c.radius);
            s.err_ulp.push((ei / prec.ulp(ti)).max(eo / prec.ulp(to)));
        }
    }
    s
}
