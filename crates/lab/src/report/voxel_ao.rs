//! Ambient occlusion, error against cost: voxel cone tracing on the occupancy pyramid
//! (`tubecast_render::render::ConeAo`, by cone count and pyramid resolution) and a few rays
//! through the wide BVH, both against the same reference — many cosine-weighted rays through
//! the exact tubes (`render::ray_occlusion`) — on the same shaded points (the primary hits of a
//! fitted camera), on a generated bundle and the Furball.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::runs::CHART;
use super::voxel_clock::Clock;
use super::{ensure_dir, fmt_num, machine, progress, write_text, ReportError, ReportFiles, ReportOptions};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast::V3;
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::render::{ray_occlusion, Camera, ConeAo, ConeParams};
use tubecast_render::scene::{generate, Scene};

/// Rays per point of the reference (standard error ≤ 1/(2√1024) = 0.0156 per point).
const REF_RAYS: u32 = 1024;
/// Cone counts and ray counts compared.
const SAMPLES: [u32; 4] = [1, 4, 16, 64];
/// Pyramid resolutions: base voxels across the occlusion distance.
const VOXELS: [f64; 3] = [8.0, 16.0, 32.0];
/// LoD resolutions (quantization voxels across the occlusion distance).
const LOD_VOXELS: [f64; 2] = [16.0, 32.0];
/// Method names: cones on the pyramid (line and volume opacity), cones on Kanzler's LoD.
const CONES: &str = "cones";
const VOLUME: &str = "cones, volume model";
const LOD: &str = "cones, LoD opacities";

/// One method setting on one scene.
#[derive(Clone, Debug)]
struct Row {
    scene: &'static str,
    /// "cones" or "rays".
    method: &'static str,
    samples: u32,
    /// Base voxels across D (cones only; NaN for rays).
    voxels: f64,
    build_ms: f64,
    ns_per_point: f64,
    mean: f64,
    max: f64,
    bias: f64,
}

/// A shaded point `q` (offset off the surface as the renderer does) and its unit normal
/// facing the camera.
pub(super) type Point = (V3<f64>, V3<f64>);

/// The primary hits of a `side × side` camera fitted to the scene.
pub(super) fn shaded_points(scene: &Scene, bvh: &dyn Tracer, side: u32) -> Result<Vec<Point>, ReportError> {
    let st = scene.stats();
    let cam =
        Camera::fit(st.bounds.0, st.bounds.1, 40.0, side, side).map_err(|e| ReportError::Render(e.to_string()))?;
    let mut pts = Vec::new();
    for y in 0..side {
        for x in 0..side {
            let ray = cam.ray(x, y);
            if let Some(hit) = bvh.closest_hit(&ray) {
                let p = ray.at(hit.t);
                let n = if hit.n.dot(ray.d) > 0.0 { -hit.n } else { hit.n };
                let eps = 1e-3 * bvh.prim(hit.id).max_radius() as f64 + 1e-12 * p.max_abs();
                pts.push((p + n * eps, n));
            }
        }
    }
    Ok(pts)
}

/// Mean and max absolute error and the mean signed error of `est` against `reference`.
pub(super) fn errors(est: &[f64], reference: &[f64]) -> (f64, f64, f64) {
    let n = est.len().max(1) as f64;
    let d: Vec<f64> = est.iter().zip(reference).map(|(e, r)| e - r).collect();
    // `+ 0.0`: an empty sum is −0.0.
    let mean = d.iter().map(|x| x.abs()).sum::<f64>() / n + 0.0;
    let max = d.iter().map(|x| x.abs()).fold(0.0, f64::max);
    (mean, max, d.iter().sum::<f64>() / n + 0.0)
}

/// Least process CPU time a timed batch runs: the clock ([`Clock`]) advances in scheduler
/// ticks (4 ms here), so a batch of ≥ 40 ms is read to within 10 %.
pub(super) const BATCH_S: f64 = 0.04;

/// `f` run until at least [`BATCH_S`] of process CPU time has passed (at least once): its last
/// value and the CPU seconds per run.
pub(super) fn cpu_each<R>(mut f: impl FnMut() -> R) -> (R, f64) {
    let t0 = Clock::now();
    let mut runs = 1u32;
    let mut out = f();
    while Clock::now().since(t0) < BATCH_S {
        out = f();
        runs += 1;
    }
    (out, Clock::now().since(t0) / f64::from(runs))
}

/// Values of `f` on every point and the best time per point (ns of process CPU time,
/// [`Clock`]) over batches of passes ([`cpu_each`]) within `budget_ms` of wall time (at least
/// one), on this thread.
pub(super) fn timed(pts: &[Point], budget_ms: u64, f: impl Fn(usize, &Point) -> f64) -> (Vec<f64>, f64) {
    let start = Instant::now();
    let values: Vec<f64> = pts.iter().enumerate().map(|(k, p)| f(k, p)).collect();
    let mut best = f64::INFINITY;
    loop {
        let (_, s) = cpu_each(|| std::hint::black_box(pts.iter().enumerate().map(|(k, p)| f(k, p)).sum::<f64>()));
        best = best.min(s * 1e9 / pts.len().max(1) as f64);
        if start.elapsed().as_millis() as u64 >= budget_ms {
            return (values, best);
        }
    }
}

/// Every setting on one scene.
fn scene_rows(name: &'static str, scene: &Scene, opts: &ReportOptions, bar: &indicatif::ProgressBar) -> Vec<Row> {
    let (bvh, bvh_s) = cpu_each(|| WideBvh::build(scene.primitives()));
    let bvh_ms = bvh_s * 1e3;
    let st = scene.stats();
    let dist = 0.1 * (V3::from(st.bounds.1) - V3::from(st.bounds.0)).length();
    let pts = shaded_points(scene, &bvh, (opts.image / 4).max(8)).unwrap_or_default();
    let reference: Vec<f64> = pts
        .par_iter()
        .enumerate()
        .map(|(k, &(q, n))| ray_occlusion(&bvh, q, n, dist, REF_RAYS, 1 << 40 | k as u64))
        .collect();
    let mut rows = Vec::new();
    for &samples in &SAMPLES {
        let (est, ns) = timed(&pts, opts.time_ms, |k, &(q, n)| ray_occlusion(&bvh, q, n, dist, samples, k as u64));
        let (mean, max, bias) = errors(&est, &reference);
        rows.push(Row {
            scene: name,
            method: "rays",
            samples,
            voxels: f64::NAN,
            build_ms: bvh_ms,
            ns_per_point: ns,
            mean,
            max,
            bias,
        });
        bar.inc(1);
    }
    let settings = VOXELS.iter().map(|&v| (v, CONES)).chain([(16.0, VOLUME)]).chain(LOD_VOXELS.map(|v| (v, LOD)));
    for (voxels, method) in settings {
        for &samples in &SAMPLES {
            let p = ConeParams { cones: samples, voxels, lines: method != VOLUME, ..ConeParams::default() };
            let (ao, build_s) = cpu_each(|| {
                if method == LOD {
                    ConeAo::build_lod(scene, dist, &p)
                } else {
                    ConeAo::build(scene, dist, &p)
                }
            });
            let build_ms = build_s * 1e3;
            let (est, ns) = timed(&pts, opts.time_ms, |_, &(q, n)| ao.occlusion(q, n));
            let (mean, max, bias) = errors(&est, &reference);
            rows.push(Row { scene: name, method, samples, voxels, build_ms, ns_per_point: ns, mean, max, bias });
            bar.inc(1);
        }
    }
    rows
}

/// Writes `voxel_ao.md` (+ `.tables.json`) and `voxel_ao.svg` into `out`: bundle and Furball of
/// about 10⁴ links (10³ with `--quick`-sized `max_segments`), shaded points from a
/// `image/4`-square camera, occlusion distance 0.1 of the scene diagonal (the renderer's).
pub fn run_voxel_ao(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let links = opts.max_segments.min(10_000);
    let bundle = Scene::from_polylines(&generate::bundle(links.div_ceil(84), 84, opts.seed), 0.12, "bundle");
    let fur = Scene::from_polylines(&generate::furball(links.div_ceil(20), 20, opts.seed), 0.06, "furball");
    let err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
    let (bundle, fur) = (bundle.map_err(err)?, fur.map_err(err)?);
    let bar = progress(opts, 2 * (SAMPLES.len() * (2 + VOXELS.len() + LOD_VOXELS.len())) as u64, "voxel AO");
    let mut rows = scene_rows("bundle", &bundle, opts, &bar);
    rows.extend(scene_rows("furball", &fur, opts, &bar));
    bar.finish_and_clear();
    let mdp = out.join("voxel_ao.md");
    write_text(&mdp, &markdown(&rows, &[("bundle", bundle.links.len()), ("furball", fur.links.len())], opts))?;
    let cp = out.join("voxel_ao.svg");
    chart::write_svg(&cp, &ao_chart(&rows), CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}

fn markdown(rows: &[Row], sizes: &[(&str, usize)], opts: &ReportOptions) -> String {
    let mut md = format!(
        "# Ambient occlusion: voxel cone tracing against rays\n\nGenerated by `cargo run --release -p tubecast-lab -- \
         voxel-ao` (plain release build, no RUSTFLAGS).\nMachine: {}.\n\n",
        machine()
    );
    let sz: Vec<String> = sizes.iter().map(|(n, l)| format!("{n} {l} links")).collect();
    let _ = write!(
        md,
        "Scenes: {} (seed {}). Shaded points: the primary hits of a {side}×{side} camera fitted to each scene, \
         offset off the surface as the renderer does. Occlusion: the cosine-weighted share of the hemisphere whose \
         rays meet a tube within D = 0.1 × scene diagonal (the renderer's). Reference: {REF_RAYS} rays per point \
         through the wide BVH on the exact tubes (its own standard error ≤ 0.0156 per point, so maxima over \
         thousands of points carry up to ≈ 0.06 of reference noise). Methods: `rays` = N rays per point (other \
         seeds); `cones` = N cones through the occupancy pyramid with the given base voxels across D (apex 2.5 \
         voxels off the surface, PWAA clamp ½ voxel, line opacity model: extinction o/(2r̄)); `cones, volume \
         model` = the same with the volume fraction as opacity; `cones, LoD opacities` = the same cones through \
         Kanzler et al.'s LoD of the scene's quantized lines (Q = 16, the given quantization voxels across D; \
         opacity min(1, Σ2r·l/h²) averaged 2³ → 1 per level, `ConeAo::build_lod`). Time: process CPU time \
         (`/proc/self/task/*/schedstat`, which advances in 4 ms scheduler ticks, so every figure is a batch of \
         ≥ 40 ms divided by its runs), one thread, best batch, per shaded point; build = pyramid \
         (cones), quantization + LoD (LoD cones) or wide BVH (rays), once per frame for a dynamic scene. Errors in occlusion \
         units [0, 1]; bias = mean signed error (negative: too open).\n\n",
        sz.join(", "),
        opts.seed,
        side = (opts.image / 4).max(8),
    );
    md.push_str(
        "| scene | method | N | voxels per D | build (ms) | ns per point | mean abs error | max abs error | bias |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let vox = if r.voxels.is_nan() { "-".to_string() } else { format!("{}", r.voxels) };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {vox} | {} | {} | {:.4} | {:.4} | {:+.4} |",
            r.scene,
            r.method,
            r.samples,
            fmt_num(r.build_ms),
            fmt_num(r.ns_per_point),
            r.mean,
            r.max,
            r.bias
        );
    }
    md
}

fn ao_chart(rows: &[Row]) -> Chart {
    let mut series = Vec::new();
    let mut groups: Vec<(&str, &str, f64)> = Vec::new();
    for r in rows {
        if !groups
            .iter()
            .any(|g| g.0 == r.scene && g.1 == r.method && (g.2 == r.voxels || g.2.is_nan() && r.voxels.is_nan()))
        {
            groups.push((r.scene, r.method, r.voxels));
        }
    }
    for (k, &(scene, method, voxels)) in groups.iter().enumerate() {
        let of = |r: &&Row| {
            r.scene == scene && r.method == method && (r.voxels == voxels || voxels.is_nan() && r.voxels.is_nan())
        };
        let label = match (voxels.is_nan(), method) {
            (true, _) => format!("{scene}: rays"),
            (false, CONES) => format!("{scene}: cones, {voxels} voxels/D"),
            (false, m) => format!("{scene}: {m}, {voxels} voxels/D"),
        };
        for (max, marker) in [(false, Marker::Dot), (true, Marker::Cross)] {
            let points = rows
                .iter()
                .filter(of)
                .map(|r| Pt {
                    x: r.ns_per_point,
                    y: if max { r.max } else { r.mean },
                    marker,
                    text: (!max).then(|| format!("{}", r.samples)),
                })
                .collect();
            let label = if max { format!("{label} (max)") } else { label.clone() };
            series.push(Series { label, color: k, points, line: !max });
        }
    }
    Chart {
        title: "Ambient occlusion: error against cost (N cones or rays per point)".into(),
        x_desc: "ns per shaded point, one thread (log)".into(),
        y_desc: "abs error against 1024-ray reference (log)".into(),
        x: XAxis::Log,
        y_floor: 1e-4,
        series,
        note: Some("dot + line: mean |error|; cross: max |error|; labels: N".into()),
    }
}
