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
use tubecast_render::scene::choice::{choose_with, Tolerance};
use tubecast_render::scene::{generate, Model, Scene};

/// Tolerances of the mesh path, in units of the scene's largest radius.
pub const RELATIVE_EPS: [f64; 2] = [1e-2, 1e-3];
/// A mesh whose estimated peak memory while building ([`Estimate::peak_bytes`]) exceeds this
/// is not built; the report gives its estimate instead. The machine the reports run on has
/// 23 GB shared with other jobs.
pub const MAX_BUILD_BYTES: f64 = 4e9;
/// The same limit in the tiny test run: the 10⁻²·r mesh of 10³ links (≈ 50 MB) is built and
/// the 10⁻³·r one (≈ 0.3 GB) is skipped, so the test sees both paths.
pub const QUICK_BUILD_BYTES: f64 = 1.5e8;

/// A mesh's size, estimated before building it from a sample of the scene tessellated and
/// traced for real, scaled by the scene's size over the sample's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Triangles.
    pub triangles: f64,
    /// Bytes the finished tracer holds ([`Tracer::memory_bytes`] per triangle of the sample).
    pub tracer_bytes: f64,
    /// Peak bytes while building: the finished tracer, the scene mesh it is built from
    /// (`f64` vertices, indices, link tags, part ids) and the unordered `f32` triangle copy the
    /// BVH builder reads (obvhs's own scratch not counted, so this is a lower bound).
    pub peak_bytes: f64,
}

/// The estimate at absolute tolerance `eps` for a scene `scale` times the size of `sample`.
pub(super) fn estimate(sample: &Scene, scale: f64, eps: f64) -> Result<Estimate, ReportError> {
    let m = tessellate(sample, Model::Links, eps).map_err(err)?;
    let t = m.mesh.triangles.len();
    if t == 0 {
        return Ok(Estimate { triangles: 0.0, tracer_bytes: 0.0, peak_bytes: 0.0 });
    }
    let mesh_bytes = m.mesh.memory_bytes() + 4 * (m.mesh.tags.len() + m.part.len());
    let tracer = MeshTracer::build(&m, sample.primitives());
    let tri = MeshTracer::TRIANGLE_BYTES;
    let tracer_bytes = tracer.memory_bytes() as f64 * scale;
    Ok(Estimate {
        triangles: t as f64 * scale,
        tracer_bytes,
        peak_bytes: tracer_bytes + ((mesh_bytes + t * tri) as f64) * scale,
    })
}

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
    skipped: &mut Vec<Skipped>,
) -> Result<Vec<MeshRow>, ReportError> {
    let lines = generate::furball(n.div_ceil(78), 78, opts.seed);
    let scene = Scene::from_polylines(&lines, 0.05, "furball").map_err(err)?;
    // Four hairs, scaled by the hair count (hairs differ in shape, not in link count).
    let k = lines.len().min(4);
    let sample = Scene::from_polylines(&lines[..k], 0.05, "sample").map_err(err)?;
    let est = |eps: f64| estimate(&sample, lines.len() as f64 / k as f64, eps);
    let max_bytes = if opts.max_segments < 10_000 { QUICK_BUILD_BYTES } else { MAX_BUILD_BYTES };
    let plan = Plan { chosen: &RELATIVE_EPS, splines: false, mesh: &RELATIVE_EPS, max_bytes };
    measure_scene(&scene, &plan, &est, opts, pool, notes, skipped)
}

/// What to measure on one scene: the automatic choice at `chosen`·r (links only, and also
/// with quadratic spline pieces when `splines`) and the mesh at `mesh`·r (r the scene's
/// largest radius), a mesh only where its estimated peak memory is at most `max_bytes`.
pub(super) struct Plan<'a> {
    pub(super) chosen: &'a [f64],
    pub(super) splines: bool,
    pub(super) mesh: &'a [f64],
    pub(super) max_bytes: f64,
}

/// A mesh configuration that was not built: its size and the estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    /// Links in the scene.
    pub segments: usize,
    /// Mesh tolerance relative to the largest radius.
    pub k: f64,
    /// The estimate.
    pub est: Estimate,
}

/// The note line of a skipped mesh.
fn skipped_note(s: &Skipped, max_bytes: f64) -> String {
    format!(
        "- {} segments, mesh at ε = {}·r: not built — estimated {:.2e} triangles, {:.2} GB for the tracer, \
         ≥ {:.2} GB peak while building (this run's limit: {:.2} GB).\n",
        s.segments,
        s.k,
        s.est.triangles,
        s.est.tracer_bytes / 1e9,
        s.est.peak_bytes / 1e9,
        max_bytes / 1e9
    )
}

/// One scene: the exact row, a row per choice tolerance and per mesh tolerance (or a skipped
/// note, and the estimate in `skipped`); `est(ε)` estimates the mesh at absolute tolerance ε.
pub(super) fn measure_scene(
    scene: &Scene,
    plan: &Plan<'_>,
    est: &dyn Fn(f64) -> Result<Estimate, ReportError>,
    opts: &ReportOptions,
    pool: &rayon::ThreadPool,
    notes: &mut String,
    skipped: &mut Vec<Skipped>,
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
    let variants: &[bool] = if plan.splines { &[false, true] } else { &[false] };
    for (&k, &fit) in plan.chosen.iter().flat_map(|k| variants.iter().map(move |f| (k, f))) {
        // The automatic choice: merged links, spheres, cylinders, cones (and with `fit`,
        // quadratic spline pieces) within ε.
        let t0 = Instant::now();
        let c = choose_with(scene, &Tolerance::Absolute(k * r_max), fit);
        let bvh = pool.install(|| Bvh::build(c.prims.clone()));
        let build_s = t0.elapsed().as_secs_f64();
        let (img, frame_s) = frame(&bvh)?;
        let (coverage_diff, max_rgb_diff) = diff(&exact, &img);
        let (name, pieces) =
            if fit { ("chosen+splines", format!(", {} spline pieces", c.splines)) } else { ("chosen", String::new()) };
        rows.push(MeshRow {
            segments,
            model: format!("{name} ε = {k}·r ({} prims{pieces})", c.prims.len()),
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
        if est.peak_bytes > plan.max_bytes {
            let s = Skipped { segments, k, est };
            notes.push_str(&skipped_note(&s, plan.max_bytes));
            skipped.push(s);
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
    let (mut rows, mut notes, mut skipped) = (Vec::new(), String::new(), Vec::new());
    for &n in &sizes {
        rows.extend(measure(n, opts, &pool, &mut notes, &mut skipped)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let cmd = if opts.max_segments >= 1_000_000 {
        "cargo run --release -p tubecast-lab -- mesh --big"
    } else {
        "cargo run --release -p tubecast-lab -- mesh"
    };
    let mut md = header("Mesh path against the exact kernels (Salm's question)", opts, cmd);
    let _ = write!(
        md,
        "Generated *Furball* scenes (tapering hairs of 78 cone links, radius ≤ r = 0.05·…, seed {}); the exact \
         kernels (BVH over the links), the automatic choice within ε (`scene::choice`: merged links, \
         spheres, cylinders, cones; exact kernels on fewer primitives) and the certified mesh (`tubecast::tessellate_chain_solid` per hair, obvhs \
         triangle BVH, triangles in f32) at ε = 10⁻²·r and 10⁻³·r, r the scene's largest radius. Build = \
         tessellation + BVH; memory = what the tracer holds; one opaque lit {}×{} frame on {} thread(s). \
         Image difference to the exact render: pixels whose coverage differs, and the largest channel \
         difference where both cover. Certified = the mesh's two-sided Hausdorff bound plus the f32 storage \
         rounding. A mesh is built only where its estimated peak memory while building is ≤ {:.1} GB \
         (estimate: four hairs tessellated and traced, scaled by the hair count); above it the \
         notes below the table give the estimated triangles and bytes — on this machine that is the answer \
         for those sizes — and the memory chart draws the estimated tracer memory (✕, `est.`).\n\n",
        opts.seed,
        opts.image,
        opts.image,
        opts.threads,
        if opts.max_segments < 10_000 { QUICK_BUILD_BYTES } else { MAX_BUILD_BYTES } / 1e9
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
    for (i, &k) in RELATIVE_EPS.iter().enumerate() {
        let points: Vec<Pt> = skipped
            .iter()
            .filter(|s| s.k == k)
            .map(|s| Pt {
                x: s.segments as f64,
                y: s.est.tracer_bytes / 1e6,
                marker: Marker::Cross,
                text: Some("est.".into()),
            })
            .collect();
        if !points.is_empty() {
            let label = format!("memory MB, estimated (not built): mesh ε = {k}·r");
            all.push(Series { label, color: 2 * models.len() + i, points, line: false });
        }
    }
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
