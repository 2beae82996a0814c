//! The dynamic-scene report: every frame moves the lines, so every frame rebuilds its
//! acceleration structure; build + render per frame for the voxel grid
//! (`tubecast_render::accel::grid::Grid`) against the BVH and (feature `embree`) Embree 3,
//! opaque and transparent (Embree's transparent frames composite every surface crossing it
//! reports, overlaps included, see `crate::peer::embree_tracer`).

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::runs::CHART;
use super::voxel_clock::Clock;
use super::{ensure_dir, fmt_num, machine, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use tubecast_render::accel::grid::{Grid, GridParams};
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, Image, Options};
use tubecast_render::scene::{generate, Prim, Scene};

/// Frames per configuration (the median is reported).
const FRAMES: usize = 3;

/// One measured configuration: median build and render time per frame, seconds, the fraction
/// of pixels whose coverage (hit or miss) differs from the BVH's in the last frame, and the
/// mean and max per-channel |difference| of that frame's colour from the grid's.
#[derive(Clone, Copy, Debug)]
struct Row {
    links: usize,
    accel: &'static str,
    opacity: f64,
    build_s: f64,
    render_s: f64,
    coverage_diff: f64,
    pixel_diff: [f64; 2],
}

/// Builds a tracer over one frame's primitives.
type Build<'a> = Box<dyn Fn(Vec<Prim>) -> Result<Box<dyn Tracer + Send>, ReportError> + Send + Sync + 'a>;

/// The accelerators of the report: grid, BVH and (feature `embree`) Embree 3 on as many threads
/// as ours.
/// The grid is told the frame's ray count (`rays`, one primary ray per pixel), so its
/// resolution minimises build + render (`GridParams::rays_per_build`).
fn accels<'a>(threads: usize, rays: f64) -> Result<Vec<(&'static str, Build<'a>)>, ReportError> {
    let grid = GridParams { rays_per_build: Some(rays), ..GridParams::default() };
    #[cfg_attr(not(feature = "embree"), allow(unused_mut))]
    let mut v: Vec<(&'static str, Build<'a>)> = vec![
        ("grid", Box::new(move |p| Ok(Box::new(Grid::build_with(p, &grid)) as Box<dyn Tracer + Send>))),
        ("bvh", Box::new(|p| Ok(Box::new(Bvh::build(p)) as Box<dyn Tracer + Send>))),
    ];
    #[cfg(feature = "embree")]
    {
        use crate::peer::{embree::Device, embree_tracer::EmbreeTracer};
        let dev = Device::with_threads(threads).map_err(|e| ReportError::Peer(e.to_string()))?;
        v.push((
            "embree",
            Box::new(move |p| {
                let t = EmbreeTracer::build(&dev, p).map_err(|e| ReportError::Peer(e.to_string()))?;
                Ok(Box::new(t) as Box<dyn Tracer + Send>)
            }),
        ));
    }
    let _ = threads;
    Ok(v)
}

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

/// Median build and render seconds of `FRAMES` moved frames of `base` with `build`, and the
/// last frame.
fn measure(
    base: &[Polyline],
    build: &Build,
    opts: &Options,
    image: u32,
    pool: &rayon::ThreadPool,
) -> Result<(f64, f64, Image), ReportError> {
    let (mut tb, mut tr, mut last) = (Vec::new(), Vec::new(), None);
    for f in 0..FRAMES {
        let scene = frame_scene(base, f)?;
        let prims = scene.primitives();
        let st = scene.stats_of(&prims);
        let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, image, image)
            .map_err(|e| ReportError::Render(e.to_string()))?;
        let t0 = Clock::now();
        let tracer = pool.install(|| build(prims))?;
        let t1 = Clock::now();
        let img = pool
            .install(|| render(&scene, tracer.as_ref(), &cam, opts))
            .map_err(|e| ReportError::Render(e.to_string()))?;
        tb.push(t1.since(t0));
        tr.push(Clock::now().since(t1));
        last = Some(img);
    }
    let img = last.ok_or_else(|| ReportError::Render("no frame".into()))?;
    Ok((median(tb), median(tr), img))
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
    let accels = accels(opts.threads, (opts.image as f64).powi(2))?;
    let bar = progress(opts, sizes.len() as u64 * 2 * accels.len() as u64, "voxel");
    let mut rows = Vec::new();
    for &links in &sizes {
        let base = generate::bundle(links.div_ceil(84), 84, opts.seed);
        for opacity in [1.0, 0.3] {
            let o = Options { opacity, ..Options::default() };
            let mut images: Vec<(&str, Image)> = Vec::new();
            for (accel, build) in &accels {
                let (build_s, render_s, img) = measure(&base, build, &o, opts.image, &pool)?;
                let links = base.len() * 84;
                rows.push(Row { links, accel, opacity, build_s, render_s, coverage_diff: 0.0, pixel_diff: [0.0; 2] });
                images.push((accel, img));
                bar.inc(1);
            }
            compare(&mut rows, &images);
        }
    }
    bar.finish_and_clear();
    let mut md = markdown(&rows, opts);
    let small: Vec<usize> = sizes.iter().copied().filter(|&n| n <= 100_000).collect();
    md.push_str(&super::voxel_levels::ablation(&small, opts, &pool)?);
    md.push_str(&super::voxel_lambda::section(&sizes, opts, &pool)?);
    let mdp = out.join("voxel.md");
    write_text(&mdp, &md)?;
    let cp = out.join("voxel.svg");
    chart::write_svg(&cp, &frame_chart(&rows, opts), CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}

/// Sets `coverage_diff` (against the BVH's image: the share of pixels whose alpha is 0 in one
/// and not the other) and `pixel_diff` (against the grid's: mean and max of the per-channel
/// |difference| of the composited colour) of the last `images.len()` rows.
fn compare(rows: &mut [Row], images: &[(&str, Image)]) {
    let find = |name: &str| images.iter().find(|(a, _)| *a == name).map(|(_, i)| i);
    let (Some(bvh), Some(grid)) = (find("bvh"), find("grid")) else { return };
    let n = rows.len();
    for (row, (_, img)) in rows[n - images.len()..].iter_mut().zip(images) {
        let diff = img.alpha.iter().zip(&bvh.alpha).filter(|(a, b)| (**a > 0.0) != (**b > 0.0)).count();
        row.coverage_diff = diff as f64 / bvh.alpha.len().max(1) as f64;
        let channels = img.rgb.iter().zip(&grid.rgb).flat_map(|(p, q)| p.iter().zip(q).map(|(a, b)| (a - b).abs()));
        let (sum, max, count) =
            channels.fold((0.0, 0.0f64, 0usize), |(s, m, c), d| (s + d as f64, m.max(d as f64), c + 1));
        row.pixel_diff = [sum / count.max(1) as f64, max];
    }
}

fn markdown(rows: &[Row], opts: &ReportOptions) -> String {
    let mut md = format!(
        "# Dynamic line sets: voxel grid vs BVH vs Embree\n\nGenerated by `cargo run --release -p tubecast-lab \
         --features embree -- voxel{}` (plain release build, no RUSTFLAGS; without `--features embree` the Embree \
         columns are empty).\nMachine: {}.\n\n",
        if opts.max_segments >= 1_000_000 { " --big" } else { "" },
        machine()
    );
    let _ = write!(
        md,
        "Russig's *Bundle* (84 links per fibre, radius 0.12, seed {}) swayed every frame, so every frame rebuilds \
         its structure from scratch: grid (conservative voxelization, cubic cells of the side the frame-cost model picks for the frame's \
         {}² primary rays, build + render (section *Grid resolution*), each link voxelized once into (voxel, link) pairs, counted, prefix-summed and scattered into per-voxel lists; the walk skips \
         empty 4³ blocks), BVH (obvhs PLOC), or Embree 3 (`ROUND_LINEAR_CURVE`, one isolated segment per link, \
         build quality high, robust flag, device limited to as many threads as ours; its answers are its own `f32` \
         ones). Per frame: build and one {}×{} render (primary rays, lit) through the same renderer, opaque and \
         transparent (opacity 0.3, CSG union); median of {FRAMES} frames, {} thread(s); times are process CPU \
         time (all threads, from `/proc/self/task/*/schedstat`), not wall time, because this machine is shared. Embree's closest hit \
         reports one surface crossing, not a segment's interval, so it cannot feed the CSG union; its transparent \
         frames do what an Embree application does: each ray is cast again from just past every hit until a cast \
         misses (`peer::embree_tracer`, re-cast rather than a record-and-reject filter callback: no new `unsafe` \
         FFI, hits arrive sorted; a cast from inside a segment reports its exit), and every reported surface is \
         composited front to back with the same opacity, rebuilt every frame like the others. So surfaces inside \
         other tubes (every joint of a fibre, where consecutive links overlap) are composited too, once per \
         surface: its image differs from ours by design (*pixel diff*: mean and max per-channel |difference| of the last frame's \
         linear colour from the grid's, in [0, 1]). Ratios: frame (build + render) over frame in the same run (below \
         1: the first wins). *Coverage ≠ BVH*: the share of pixels of the last frame that one tracer sees as hit \
         and the BVH as miss or back (the grid's must be 0: same kernels).\n\n",
        opts.seed, opts.image, opts.image, opts.image, opts.threads
    );
    md.push_str(
        "| links | mode | grid build (ms) | grid render (ms) | BVH build (ms) | BVH render (ms) | grid frame / BVH \
         frame |\n|---|---|---|---|---|---|---|\n",
    );
    let find =
        |accel: &str, g: &Row| rows.iter().find(|r| r.accel == accel && r.links == g.links && r.opacity == g.opacity);
    let frame = |r: &Row| r.build_s + r.render_s;
    let mode = |r: &Row| if r.opacity < 1.0 { "transparent" } else { "opaque" };
    for g in rows.iter().filter(|r| r.accel == "grid") {
        let Some(b) = find("bvh", g) else { continue };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.2} |",
            g.links,
            mode(g),
            fmt_num(g.build_s * 1e3),
            fmt_num(g.render_s * 1e3),
            fmt_num(b.build_s * 1e3),
            fmt_num(b.render_s * 1e3),
            frame(g) / frame(b)
        );
    }
    md.push_str(
        "\n| Embree: links | mode | Embree build (ms) | Embree render (ms) | grid / Embree | BVH / Embree | coverage \
         ≠ BVH: grid / Embree | pixel diff from grid: mean / max |\n|---|---|---|---|---|---|---|---|\n",
    );
    for e in rows.iter().filter(|r| r.accel == "embree") {
        let (Some(g), Some(b)) = (find("grid", e), find("bvh", e)) else { continue };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.1e} / {:.1e} | {:.3} / {:.3} |",
            e.links,
            mode(e),
            fmt_num(e.build_s * 1e3),
            fmt_num(e.render_s * 1e3),
            frame(g) / frame(e),
            frame(b) / frame(e),
            g.coverage_diff,
            e.coverage_diff,
            e.pixel_diff[0],
            e.pixel_diff[1]
        );
    }
    md
}

fn frame_chart(rows: &[Row], opts: &ReportOptions) -> Chart {
    let mut series = Vec::new();
    let lines = [("grid", 1.0), ("bvh", 1.0), ("grid", 0.3), ("bvh", 0.3), ("embree", 1.0), ("embree", 0.3)];
    for (k, (accel, opacity)) in lines.into_iter().enumerate() {
        let mode = if opacity < 1.0 { "transparent" } else { "opaque" };
        let points = rows
            .iter()
            .filter(|r| r.accel == accel && r.opacity == opacity)
            .map(|r| Pt { x: r.links as f64, y: (r.build_s + r.render_s) * 1e3, marker: Marker::Dot, text: None })
            .collect::<Vec<_>>();
        if points.is_empty() {
            continue;
        }
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
