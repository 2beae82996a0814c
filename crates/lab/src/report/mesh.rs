//! Salm's question on our side: a certified triangle mesh (the mesh path) against the exact
//! kernels — build time, memory and frame time against scene size, and the image difference
//! to the exact render.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::runs::{header, CHART};
use super::{ensure_dir, fmt_num, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::mesh::{tessellate, MeshTracer};
use tubecast_render::render::{render, Camera, Image, Options};
use tubecast_render::scene::choice::{choose, Tolerance};
use tubecast_render::scene::{generate, Model, Scene};

/// Tolerances of the mesh path, in units of the scene's largest radius.
pub const RELATIVE_EPS: [f64; 2] = [1e-2, 1e-3];
/// Configurations whose estimated triangle count exceeds this are skipped (memory).
pub const MAX_TRIANGLES: f64 = 3e7;

/// One measured configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshRow {
    /// Links in the scene.
    pub segments: usize,
    /// `exact` or the mesh tolerance relative to the largest radius.
    pub model: String,
    /// Certified error (absolute; 0 for the exact kernels' model error).
    pub certified: f64,
    /// Triangles (0 for the exact kernels).
    pub triangles: usize,
    /// Tessellation + BVH build, seconds.
    pub build_s: f64,
    /// Tracer memory (primitives or triangles + BVH), bytes.
    pub bytes: usize,
    /// One opaque frame, seconds.
    pub frame_s: f64,
    /// Pixels whose coverage (hit or miss) differs from the exact render, fraction.
    pub coverage_diff: f64,
    /// Largest per-channel difference to the exact render among pixels both cover.
    pub max_rgb_diff: f64,
}

pub(super) fn err(e: impl std::fmt::Display) -> ReportError {
    ReportError::Render(e.to_string())
}

/// Coverage mismatch fraction and largest channel difference on pixels both renders cover.
fn diff(a: &Image, b: &Image) -> (f64, f64) {
    let mut cov = 0usize;
    let mut worst: f64 = 0.0;
    for i in 0..a.rgb.len() {
        let (ha, hb) = (a.depth[i].is_finite(), b.depth[i].is_finite());
        if ha != hb {
            cov += 1;
        } else if ha {
            for c in 0..3 {
                worst = worst.max((a.rgb[i][c] - b.rgb[i][c]).abs() as f64);
            }
        }
    }
    (cov as f64 / a.rgb.len().max(1) as f64, worst)
}

/// One Furball scene of about `n` links: the exact row and a row per tolerance (or a skipped
/// note).
fn measure(
    n: usize,
    opts: &ReportOptions,
    pool: &rayon::ThreadPool,
    notes: &mut String,
) -> Result<Vec<MeshRow>, ReportError> {
    let lines = generate::furball(n.div_ceil(78), 78, opts.seed);
    let scene = Scene::from_polylines(&lines, 0.05, "furball").map_err(err)?;
    let one = Scene::from_polylines(&lines[..1], 0.05, "one").map_err(err)?;
    let est = |eps: f64| -> Result<f64, ReportError> {
        Ok(tessellate(&one, Model::Links, eps).map_err(err)?.mesh.triangles.len() as f64 * lines.len() as f64)
    };
    let plan = Plan { chosen: &RELATIVE_EPS, mesh: &RELATIVE_EPS, max_triangles: MAX_TRIANGLES };
    measure_scene(&scene, &plan, &est, opts, pool, notes)
}

/// What to measure on one scene: the automatic choice at `chosen`·r and the mesh at `mesh`·r
/// (r the scene's largest radius), a mesh only where the estimated triangle count is at most
/// `max_triangles`.
pub(super) struct Plan<'a> {
    pub(super) chosen: &'a [f64],
    pub(super) mesh: &'a [f64],
    pub(super) max_triangles: f64,
}

/// One scene: the exact row, a row per choice tolerance and per mesh tolerance (or a skipped
/// note); `est(ε)` estimates the mesh's triangle count at absolute tolerance ε.
pub(super) fn measure_scene(
    scene: &Scene,
    plan: &Plan<'_>,
    est: &dyn Fn(f64) -> Result<f64, ReportError>,
    opts: &ReportOptions,
    pool: &rayon::ThreadPool,
    notes: &mut String,
) -> Result<Vec<MeshRow>, ReportError> {
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 35.0, opts.image, opts.image).map_err(err)?;
    let r_max = (0..scene.nodes.len()).map(|i| scene.radius(i)).fold(0.0, f64::max);
    let frame = |t: &dyn Tracer| -> Result<(Image, f64), ReportError> {
        let t0 = Instant::now();
        let img = pool.install(|| render(scene, t, &cam, &Options::default())).map_err(err)?;
        Ok((img, t0.elapsed().as_secs_f64()))
    };
    let t0 = Instant::now();
    let bvh = pool.install(|| Bvh::build(scene.primitives()));
    let build_s = t0.elapsed().as_secs_f64();
    frame(&bvh)?; // warm-up (thread pool, page faults): every timed frame below runs warm
    let (exact, frame_s) = frame(&bvh)?;
    let segments = scene.links.len();
    let mut rows = vec![MeshRow {
        segments,
        model: "exact".into(),
        certified: 0.0,
        triangles: 0,
        build_s,
        bytes: bvh.memory_bytes(),
        frame_s,
        coverage_diff: 0.0,
        max_rgb_diff: 0.0,
    }];
    drop(bvh);
    for &k in plan.chosen {
        // The automatic choice: merged links, spheres, cylinders, cones within ε.
        let t0 = Instant::now();
        let c = choose(scene, &Tolerance::Absolute(k * r_max));
        let bvh = pool.install(|| Bvh::build(c.prims.clone()));
        let build_s = t0.elapsed().as_secs_f64();
        let (img, frame_s) = frame(&bvh)?;
        let (coverage_diff, max_rgb_diff) = diff(&exact, &img);
        rows.push(MeshRow {
            segments,
            model: format!("chosen ε = {k}·r ({} prims)", c.prims.len()),
            certified: c.worst,
            triangles: 0,
            build_s,
            bytes: bvh.memory_bytes(),
            frame_s,
            coverage_diff,
            max_rgb_diff,
        });
    }
    for &k in plan.mesh {
        let eps = k * r_max;
        let est = est(eps)?;
        if est > plan.max_triangles {
            let _ = writeln!(notes, "- {segments} segments at ε = {k}·r skipped: about {est:.1e} triangles.");
            continue;
        }
        let t0 = Instant::now();
        let m = pool.install(|| tessellate(scene, Model::Links, eps)).map_err(err)?;
        let tracer = pool.install(|| MeshTracer::build(&m, scene.primitives()));
        let build_s = t0.elapsed().as_secs_f64();
        let (img, frame_s) = frame(&tracer)?;
        let (coverage_diff, max_rgb_diff) = diff(&exact, &img);
        rows.push(MeshRow {
            segments,
            model: format!("mesh ε = {k}·r"),
            certified: tracer.error(),
            triangles: tracer.triangle_count(),
            build_s,
            bytes: tracer.memory_bytes(),
            frame_s,
            coverage_diff,
            max_rgb_diff,
        });
    }
    Ok(rows)
}

/// The markdown table of `rows` (frame / exact against the exact row of the same size).
pub(super) fn table(rows: &[MeshRow]) -> String {
    let mut md = String::new();
    md.push_str("| segments | model | certified error | triangles | build (ms) | memory (MB) | frame (ms) | frame / exact | coverage diff | max Δrgb |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let exact =
            rows.iter().find(|e| e.segments == r.segments && e.model == "exact").map_or(f64::NAN, |e| e.frame_s);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {}% | {} |",
            r.segments,
            r.model,
            fmt_num(r.certified),
            r.triangles,
            fmt_num(r.build_s * 1e3),
            fmt_num(r.bytes as f64 / 1e6),
            fmt_num(r.frame_s * 1e3),
            fmt_num(r.frame_s / exact),
            fmt_num(100.0 * r.coverage_diff),
            fmt_num(r.max_rgb_diff)
        );
    }
    md
}

/// The mesh report: writes `mesh.md` and `mesh.svg` into `out`. Scenes as the speed report's
/// (*Furball*, 10³ … [`ReportOptions::max_segments`] links), one opaque `image × image` frame.
pub fn run_mesh(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(opts.threads).build().map_err(err)?;
    let mut sizes = vec![1000usize];
    while sizes[sizes.len() - 1] * 10 <= opts.max_segments {
        sizes.push(sizes[sizes.len() - 1] * 10);
    }
    let bar = progress(opts, sizes.len() as u64, "mesh");
    let (mut rows, mut notes) = (Vec::new(), String::new());
    for &n in &sizes {
        rows.extend(measure(n, opts, &pool, &mut notes)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut md = header(
        "Mesh path against the exact kernels (Salm's question)",
        opts,
        "cargo run --release -p tubecast-lab -- mesh",
    );
    let _ = write!(
        md,
        "Generated *Furball* scenes (tapering hairs of 78 cone links, radius ≤ r = 0.05·…, seed {}); the exact \
         kernels (BVH over the links), the automatic choice within ε (`scene::choice`: merged links, \
         spheres, cylinders, cones; exact kernels on fewer primitives) and the certified mesh (`tubecast::tessellate_chain_solid` per hair, obvhs \
         triangle BVH, triangles in f32) at ε = 10⁻²·r and 10⁻³·r, r the scene's largest radius. Build = \
         tessellation + BVH; memory = what the tracer holds; one opaque lit {}×{} frame on {} thread(s). \
         Image difference to the exact render: pixels whose coverage differs, and the largest channel \
         difference where both cover. Certified = the mesh's two-sided Hausdorff bound plus the f32 storage \
         rounding.\n\n",
        opts.seed, opts.image, opts.image, opts.threads
    );
    md.push_str(&table(&rows));
    if !notes.is_empty() {
        md.push('\n');
        md.push_str(&notes);
    }
    let mdp = out.join("mesh.md");
    write_text(&mdp, &md)?;
    let family = |m: &str| m.split(" (").next().unwrap_or(m).to_string();
    let models: Vec<String> =
        rows.iter().filter(|r| r.segments == rows[0].segments).map(|r| family(&r.model)).collect();
    let series = |f: &dyn Fn(&MeshRow) -> f64, off: usize, what: &str| -> Vec<Series> {
        models
            .iter()
            .enumerate()
            .map(|(i, m)| Series {
                label: format!("{what}: {m}"),
                color: off + i,
                points: rows
                    .iter()
                    .filter(|r| &family(&r.model) == m)
                    .map(|r| Pt { x: r.segments as f64, y: f(r), marker: Marker::Dot, text: None })
                    .collect(),
                line: true,
            })
            .collect()
    };
    let mut all = series(&|r| r.frame_s * 1e3, 0, "frame ms");
    all.extend(series(&|r| r.bytes as f64 / 1e6, models.len(), "memory MB"));
    let c = Chart {
        title: format!("Mesh path vs exact kernels ({0}×{0}, {1} thread(s))", opts.image, opts.threads),
        x_desc: "segments (log)".into(),
        y_desc: "frame ms / memory MB (log)".into(),
        x: XAxis::Log,
        y_floor: 1e-3,
        series: all,
        note: None,
    };
    let cp = out.join("mesh.svg");
    chart::write_svg(&cp, &c, CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}
