//! The speed and scale report.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::runs::{header, CHART};
use super::{ensure_dir, fmt_num, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One measured scene of the speed report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedRow {
    /// Links in the scene.
    pub segments: usize,
    /// BVH build, seconds.
    pub build_s: f64,
    /// Opaque frame, seconds.
    pub opaque_s: f64,
    /// Transparent (CSG) frame, seconds.
    pub transparent_s: f64,
}

/// Speed/scale: writes `speed.md` and `speed.svg` into `out`. Scenes: Russig's *Furball*
/// construction (tapering hairs, 78 links each) at 10³, 10⁴, … links up to
/// [`ReportOptions::max_segments`]; one opaque and one transparent (opacity 0.5, CSG) frame of
/// `image × image` pixels each, on [`ReportOptions::threads`] threads.
pub fn run_speed(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    use tubecast_render::accel::Bvh;
    use tubecast_render::render::{render, Camera, Options};
    use tubecast_render::scene::{generate, Scene};
    opts.validate()?;
    ensure_dir(out)?;
    let mut sizes = Vec::new();
    let mut n = 1000usize;
    while n <= opts.max_segments {
        sizes.push(n);
        n *= 10;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads)
        .build()
        .map_err(|e| ReportError::Render(format!("thread pool: {e}")))?;
    let bar = progress(opts, sizes.len() as u64 * 3, "speed");
    let mut rows = Vec::new();
    for &n in &sizes {
        let tubes = n.div_ceil(78);
        let lines = generate::furball(tubes, 78, opts.seed);
        let scene = Scene::from_polylines(&lines, 0.05, "furball").map_err(|e| ReportError::Render(e.to_string()))?;
        let st = scene.stats();
        let cam = Camera::fit(st.bounds.0, st.bounds.1, 35.0, opts.image, opts.image)
            .map_err(|e| ReportError::Render(e.to_string()))?;
        let t0 = Instant::now();
        let bvh = pool.install(|| Bvh::build(scene.primitives()));
        let build_s = t0.elapsed().as_secs_f64();
        bar.inc(1);
        let time = |o: Options| -> Result<f64, ReportError> {
            let t0 = Instant::now();
            pool.install(|| render(&scene, &bvh, &cam, &o)).map_err(|e| ReportError::Render(e.to_string()))?;
            Ok(t0.elapsed().as_secs_f64())
        };
        let opaque_s = time(Options::default())?;
        bar.inc(1);
        let transparent_s = time(Options { opacity: 0.5, ..Options::default() })?;
        bar.inc(1);
        rows.push(SpeedRow { segments: scene.links.len(), build_s, opaque_s, transparent_s });
    }
    bar.finish_and_clear();
    let px = (opts.image as f64).powi(2);
    let mut md = header("Speed and scale", opts, "cargo run --release -p tubecast-lab -- speed");
    let _ = write!(
        md,
        "Generated *Furball* scenes (tapering hairs of 78 cone links, seed {}), BVH build and one {}×{} frame \
         (primary rays only, lit, no shadows/AO) opaque and transparent (opacity 0.5: every interval along the \
         pixel's line through the CSG union), on {} thread(s). Rays/s = pixels / frame time.\n\n",
        opts.seed, opts.image, opts.image, opts.threads
    );
    md.push_str("| segments | BVH build (ms) | opaque frame (ms) | opaque rays/s | transparent frame (ms) | transparent rays/s |\n|---|---|---|---|---|---|\n");
    for r in &rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            r.segments,
            fmt_num(r.build_s * 1e3),
            fmt_num(r.opaque_s * 1e3),
            fmt_num(px / r.opaque_s),
            fmt_num(r.transparent_s * 1e3),
            fmt_num(px / r.transparent_s)
        );
    }
    if let (Some(a), Some(b)) = (rows.first(), rows.last()) {
        if b.segments > a.segments {
            let g = |x: f64, y: f64| (y / x).ln() / (b.segments as f64 / a.segments as f64).ln();
            let _ = write!(
                md,
                "\nGrowth exponent k in time ∝ segments^k between {} and {} segments: BVH build {:.2}, opaque frame {:.2}, \
                 transparent frame {:.2}.\n",
                a.segments,
                b.segments,
                g(a.build_s, b.build_s),
                g(a.opaque_s, b.opaque_s),
                g(a.transparent_s, b.transparent_s)
            );
        }
    }
    let mdp = out.join("speed.md");
    write_text(&mdp, &md)?;
    let line = |label: &str, c: usize, f: &dyn Fn(&SpeedRow) -> f64| Series {
        label: label.into(),
        color: c,
        points: rows
            .iter()
            .map(|r| Pt { x: r.segments as f64, y: f(r) * 1e3, marker: Marker::Dot, text: None })
            .collect(),
        line: true,
    };
    let c = Chart {
        title: format!("Frame time vs segments ({0}×{0}, {1} thread(s))", opts.image, opts.threads),
        x_desc: "segments (log)".into(),
        y_desc: "milliseconds (log)".into(),
        x: XAxis::Log,
        y_floor: 1e-3,
        series: vec![
            line("opaque frame", 0, &|r| r.opaque_s),
            line("transparent (CSG) frame", 1, &|r| r.transparent_s),
            line("BVH build", 2, &|r| r.build_s),
        ],
        note: None,
    };
    let cp = out.join("speed.svg");
    chart::write_svg(&cp, &c, CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}
