//! The dynamic-scene report: every frame moves the lines, so every frame rebuilds its
//! acceleration structure; build + render per frame for the voxel grid
//! (`tubecast_render::accel::grid::Grid`) against the BVH, opaque and transparent.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::runs::{header, CHART};
use super::{ensure_dir, fmt_num, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast_render::accel::grid::Grid;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Prim, Scene};

/// Frames per configuration (the median is reported).
const FRAMES: usize = 3;

/// One measured configuration: median build and render time per frame, seconds.
#[derive(Clone, Copy, Debug)]
struct Row {
    links: usize,
    accel: &'static str,
    opacity: f64,
    build_s: f64,
    render_s: f64,
}

type Build = fn(Vec<Prim>) -> Box<dyn Tracer + Send>;
const ACCELS: [(&str, Build); 2] = [("grid", |p| Box::new(Grid::build(p))), ("bvh", |p| Box::new(Bvh::build(p)))];

/// Russig's bundle (84 links per fibre) with every fibre swayed by the frame number.
fn frame_scene(base: &[Polyline], frame: usize) -> Result<Scene, ReportError> {
    let ph = 0.4 * frame as f64;
    let sway = |q: &[f64; 3]| [q[0], q[1] + 2.0 * (0.05 * q[0] + ph).sin(), q[2]];
    let lines: Vec<Polyline> =
        base.iter().map(|p| Polyline { points: p.points.iter().map(sway).collect(), radii: p.radii.clone() }).collect();
    Scene::from_polylines(&lines, 0.12, "bundle").map_err(|e| ReportError::Render(e.to_string()))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median build and render seconds of `FRAMES` moved frames of `base` with `build`.
fn measure(
    base: &[Polyline],
    build: Build,
    opts: &Options,
    image: u32,
    pool: &rayon::ThreadPool,
) -> Result<(f64, f64), ReportError> {
    let (mut tb, mut tr) = (Vec::new(), Vec::new());
    for f in 0..FRAMES {
        let scene = frame_scene(base, f)?;
        let prims = scene.primitives();
        let st = scene.stats_of(&prims);
        let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, image, image)
            .map_err(|e| ReportError::Render(e.to_string()))?;
        let t0 = Instant::now();
        let tracer = pool.install(|| build(prims));
        let t1 = Instant::now();
        pool.install(|| render(&scene, tracer.as_ref(), &cam, opts)).map_err(|e| ReportError::Render(e.to_string()))?;
        tb.push((t1 - t0).as_secs_f64());
        tr.push(t1.elapsed().as_secs_f64());
    }
    Ok((median(tb), median(tr)))
}

/// Dynamic scenes: writes `voxel.md` and `voxel.svg` into `out`. Bundles of 10⁴ links up to
/// [`ReportOptions::max_segments`] (×10), each frame moved and rebuilt; `image × image`
/// frames, opaque and transparent (opacity 0.3), on [`ReportOptions::threads`] threads.
pub fn run_voxel(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let sizes: Vec<usize> =
        [1000, 10_000, 100_000, 1_000_000].into_iter().filter(|&n| n <= opts.max_segments).collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads)
        .build()
        .map_err(|e| ReportError::Render(format!("thread pool: {e}")))?;
    let bar = progress(opts, sizes.len() as u64 * 4, "voxel");
    let mut rows = Vec::new();
    for &links in &sizes {
        let base = generate::bundle(links.div_ceil(84), 84, opts.seed);
        for opacity in [1.0, 0.3] {
            let o = Options { opacity, ..Options::default() };
            for (accel, build) in ACCELS {
                let (build_s, render_s) = measure(&base, build, &o, opts.image, &pool)?;
                rows.push(Row { links: base.len() * 84, accel, opacity, build_s, render_s });
                bar.inc(1);
            }
        }
    }
    bar.finish_and_clear();
    let mdp = out.join("voxel.md");
    write_text(&mdp, &markdown(&rows, opts))?;
    let cp = out.join("voxel.svg");
    chart::write_svg(&cp, &frame_chart(&rows, opts), CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}

fn markdown(rows: &[Row], opts: &ReportOptions) -> String {
    let mut md = header("Dynamic line sets: voxel grid vs BVH", opts, "cargo run --release -p tubecast-lab -- voxel");
    let _ = write!(
        md,
        "Russig's *Bundle* (84 links per fibre, radius 0.12, seed {}) swayed every frame, so every frame rebuilds \
         its structure from scratch: grid (conservative voxelization, cubic cells ≈ 2 per link, count → prefix sum → \
         fill) or BVH (obvhs PLOC). Per frame: build and one {}×{} render (primary rays, lit), opaque and \
         transparent (opacity 0.3, CSG union); median of {FRAMES} frames, {} thread(s). Ratio: grid frame / BVH \
         frame in the same run (below 1: the grid wins).\n\n",
        opts.seed, opts.image, opts.image, opts.threads
    );
    md.push_str("| links | mode | grid build (ms) | grid render (ms) | BVH build (ms) | BVH render (ms) | grid frame / BVH frame |\n|---|---|---|---|---|---|---|\n");
    for g in rows.iter().filter(|r| r.accel == "grid") {
        let Some(b) = rows.iter().find(|r| r.accel == "bvh" && r.links == g.links && r.opacity == g.opacity) else {
            continue;
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.2} |",
            g.links,
            if g.opacity < 1.0 { "transparent" } else { "opaque" },
            fmt_num(g.build_s * 1e3),
            fmt_num(g.render_s * 1e3),
            fmt_num(b.build_s * 1e3),
            fmt_num(b.render_s * 1e3),
            (g.build_s + g.render_s) / (b.build_s + b.render_s)
        );
    }
    md
}

fn frame_chart(rows: &[Row], opts: &ReportOptions) -> Chart {
    let mut series = Vec::new();
    for (k, (accel, opacity)) in [("grid", 1.0), ("bvh", 1.0), ("grid", 0.3), ("bvh", 0.3)].into_iter().enumerate() {
        let mode = if opacity < 1.0 { "transparent" } else { "opaque" };
        let points = rows
            .iter()
            .filter(|r| r.accel == accel && r.opacity == opacity)
            .map(|r| Pt { x: r.links as f64, y: (r.build_s + r.render_s) * 1e3, marker: Marker::Dot, text: None })
            .collect();
        series.push(Series { label: format!("{accel} {mode}: build + render"), color: k, points, line: true });
    }
    Chart {
        title: format!("Dynamic frame (rebuild + render, {0}×{0}, {1} thread(s))", opts.image, opts.threads),
        x_desc: "links (log)".into(),
        y_desc: "milliseconds per frame (log)".into(),
        x: XAxis::Log,
        y_floor: 1e-2,
        series,
        note: None,
    }
}
