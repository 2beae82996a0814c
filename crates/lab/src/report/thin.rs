//! The spline kernel's length/radius sweep, which shows whether its error stays linear in `L/r`:
//! `L/r = 10 … 10⁵` over the eleven thin-tube
//! families of `tests/splines/conditioning.rs` ([`tubecast_oracle::thin_case`]), every solver in
//! `f32` and `f64`, judged against the independent thin-tube oracle
//! ([`tubecast_oracle::quad_crossing_offset`]) with the kernel's derived backward-error band
//! (`src/kernel/spline.rs`, "Conditioning")
//!
//! `E = 1024·ε·R + 8·ε·|o − p(½)|`, `R = max|bᵢ − p(½)| + max rᵢ`.
//!
//! *Must hit*: the tube deflated by `E` is hit (a miss is a false miss). *Must miss*: the tube
//! inflated by `E` is missed (a hit is a false hit). *Outside E*: a hit whose entry or exit lies
//! outside the inflated/deflated tubes' (± `E` along the ray). Error: `|Δt|·|d|` over the
//! largest control radius against the exact tube, max over the hits of every family but
//! grazing (there `t` is ill-conditioned by the angle, not by the kernel). Lanes are not run:
//! every lane equals the scalar call bit for bit (`tests/splines/kernel.rs`).

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::eval::{solver_name, Precision};
use super::runs::{header, CHART};
use super::{ensure_dir, fmt_num, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use tubecast::{QuadTube, Ray, Scalar, Solver, V3};
use tubecast_oracle::{quad_crossing_offset, thin_case, ThinCase, ThinFamily, Vec3, THIN_FAMILIES};

/// The ratios of the sweep.
const RATIOS: [f64; 5] = [1e1, 1e2, 1e3, 1e4, 1e5];

/// The solvers of the sweep: the accurate ones, then the approximate bisections.
const SOLVERS: [Solver; 6] = [
    Solver::Polynomial,
    Solver::Itp,
    Solver::Newton,
    Solver::Bisection { iters: 40 },
    Solver::Bisection { iters: 20 },
    Solver::Bisection { iters: 10 },
];

/// Tallies of one solver × precision × ratio.
#[derive(Clone, Copy, Debug, Default)]
struct Tally {
    must_hit: usize,
    false_miss: usize,
    must_miss: usize,
    false_hit: usize,
    outside: usize,
    max_err_r: f64,
    max_band_r: f64,
}

/// The band `E` of a case (length units) for machine epsilon `eps`
/// ([`tubecast::spline_error_band`], with the oracle's `R` and `|o − p(½)|`).
fn band(eps: f64, c: &ThinCase) -> f64 {
    tubecast::spline_error_band(eps, c.extent, c.origin_dist)
}

/// The kernel's line interval in precision `T` (the case's numbers are `f32`-representable).
fn kernel<T: Scalar>(c: &ThinCase, solver: Solver) -> Option<(f64, f64)> {
    let v = |p: Vec3| V3::new(T::from_f64(p.x), T::from_f64(p.y), T::from_f64(p.z));
    let tube = QuadTube::new(c.tube.b.map(v), c.tube.r.map(T::from_f64)).ok()?;
    let iv = tube.line_interval_with(&Ray::new(v(c.ray.o), v(c.ray.d)), solver);
    iv.hit.then(|| (iv.entry.t.to_f64(), iv.exit.t.to_f64()))
}

/// The oracle's answers for one case in one precision: the inflated and deflated tubes'.
struct Judged {
    e: f64,
    infl: Option<(f64, f64)>,
    defl: Option<(f64, f64)>,
}

impl Judged {
    fn new(eps: f64, c: &ThinCase) -> Self {
        let e = band(eps, c);
        Self { e, infl: quad_crossing_offset(&c.tube, &c.ray, e), defl: quad_crossing_offset(&c.tube, &c.ray, -e) }
    }

    /// Count one answer.
    fn tally(&self, t: &mut Tally, c: &ThinCase, got: Option<(f64, f64)>) {
        let dt = self.e / c.ray.d.length();
        t.must_hit += usize::from(self.defl.is_some());
        t.must_miss += usize::from(self.infl.is_none());
        match (got, self.infl, self.defl) {
            (Some(_), None, _) => t.false_hit += 1,
            (None, _, Some(_)) => t.false_miss += 1,
            (Some((ti, to)), Some((ai, ao)), defl) => {
                let (bi, bo) = defl.unwrap_or((f64::INFINITY, -f64::INFINITY));
                let ok = ti >= ai - dt && to <= ao + dt && ti <= bi + dt && to >= bo - dt;
                t.outside += usize::from(!ok);
            }
            _ => {}
        }
    }
}

/// Largest control radius.
fn rmax(c: &ThinCase) -> f64 {
    c.tube.r.iter().fold(0.0f64, |a, &x| a.max(x))
}

/// Runs the sweep: tallies indexed `[solver][precision (f32, f64)][ratio]`.
fn sweep(opts: &ReportOptions) -> Vec<[[Tally; 5]; 2]> {
    let seeds = (opts.spline_cases as u64 / 20).max(2);
    let bar = progress(opts, (RATIOS.len() * THIN_FAMILIES.len()) as u64, "thin sweep");
    let mut out = vec![[[Tally::default(); 5]; 2]; SOLVERS.len()];
    for (ri, &ratio) in RATIOS.iter().enumerate() {
        for family in THIN_FAMILIES {
            for k in 0..seeds {
                let c = thin_case(opts.seed.wrapping_mul(0x9E37_79B9).wrapping_add(k), ratio, family);
                let exact = quad_crossing_offset(&c.tube, &c.ray, 0.0);
                for (pi, eps) in [f32::EPSILON as f64, f64::EPSILON].into_iter().enumerate() {
                    let j = Judged::new(eps, &c);
                    for (si, &s) in SOLVERS.iter().enumerate() {
                        let got = if pi == 0 { kernel::<f32>(&c, s) } else { kernel::<f64>(&c, s) };
                        let t = &mut out[si][pi][ri];
                        j.tally(t, &c, got);
                        t.max_band_r = t.max_band_r.max(j.e / rmax(&c));
                        if let (Some((ti, to)), Some((xi, xo)), false) = (got, exact, family == ThinFamily::Grazing) {
                            let err = (ti - xi).abs().max((to - xo).abs()) * c.ray.d.length() / rmax(&c);
                            t.max_err_r = t.max_err_r.max(err);
                        }
                    }
                }
            }
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    out
}

fn prec_name(pi: usize) -> &'static str {
    [Precision::F32, Precision::F64][pi].name()
}

/// The length/radius sweep: writes `thin.md` (+ `thin.tables.json`), `thin_error.svg` and
/// `thin_false.svg` into `out`.
pub fn run_thin(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let res = sweep(opts);
    let seeds = (opts.spline_cases / 20).max(2);
    let mut md = header(
        "Spline tubes: error and false answers against L/r",
        opts,
        "cargo run --release -p tubecast-lab -- thin",
    );
    let _ = write!(
        md,
        "The eleven thin-tube families of `tests/splines/conditioning.rs` (unit, bulge, cusp, taper, grazing, far \
         origin, inside, inside beside an end crossed at right angles, pinched, scale 2^±50, direction ratio \
         2⁴⁰), {seeds} seeds each per ratio, every solver \
         in `f32` and `f64`, against the independent thin-tube oracle. Band `E = 1024·ε·R + 8·ε·|o − p(½)|` \
         (derived in `src/kernel/spline.rs`). must-hit: the tube deflated by `E` is hit; must-miss: the tube \
         inflated by `E` is missed; outside E: entry or exit outside the inflated/deflated tubes' ± `E`. \
         max err (r): the largest entry/exit error in radii over the hits of every family but grazing. \
         max E (r): the largest band in radii. Bisection with 10 and 20 steps is approximate (documented).\n\n"
    );
    let _ = writeln!(
        md,
        "| solver | precision | L/r | max err (r) | max E (r) | must-hit | false miss | must-miss | false hit | outside E |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
    for (si, s) in SOLVERS.iter().enumerate() {
        for (pi, row) in res[si].iter().enumerate() {
            for (ri, t) in row.iter().enumerate() {
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    solver_name(*s),
                    prec_name(pi),
                    fmt_num(RATIOS[ri]),
                    fmt_num(t.max_err_r),
                    fmt_num(t.max_band_r),
                    t.must_hit,
                    t.false_miss,
                    t.must_miss,
                    t.false_hit,
                    t.outside
                );
            }
        }
    }
    md.push_str(&super::thin_render::helix_section(opts)?);
    let mdp = out.join("thin.md");
    write_text(&mdp, &md)?;
    let c1 = out.join("thin_error.svg");
    let c2 = out.join("thin_false.svg");
    let err =
        chart_of(&res, "Splines: max entry/exit error vs L/r", "max t error in radii (log)", 1e-16, |t| t.max_err_r);
    let fm = chart_of(
        &res,
        "Splines: false-miss rate vs L/r (0 drawn at 1e-4)",
        "false misses / must-hit (log)",
        1e-4,
        |t| t.false_miss as f64 / t.must_hit.max(1) as f64,
    );
    chart::write_svg(&c1, &err, CHART)?;
    chart::write_svg(&c2, &fm, CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![c1, c2] })
}

/// One line per solver × precision of `y(tally)` against `L/r`.
fn chart_of(res: &[[[Tally; 5]; 2]], title: &str, y_desc: &str, floor: f64, y: impl Fn(&Tally) -> f64) -> Chart {
    let mut series = Vec::new();
    for (si, s) in SOLVERS.iter().enumerate() {
        for (pi, row) in res[si].iter().enumerate() {
            let marker = if pi == 0 { Marker::Dot } else { Marker::Cross };
            series.push(Series {
                label: format!("{} {}", solver_name(*s), prec_name(pi)),
                color: si,
                points: row.iter().zip(RATIOS).map(|(t, x)| Pt { x, y: y(t), marker, text: None }).collect(),
                line: true,
            });
        }
    }
    Chart {
        title: title.into(),
        x_desc: "L/r (log)".into(),
        y_desc: y_desc.into(),
        x: XAxis::Log,
        y_floor: floor,
        series,
        note: Some("● f32  ✕ f64".into()),
    }
}
