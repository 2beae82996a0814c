//! The Embree peer report (feature `embree`).

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::eval::percentile;
use super::oracle::{self, LinkCase, LinkRegion};
use super::runs::link_cases;
use super::{ensure_dir, fmt_num, machine, progress, write_text, ReportError, ReportFiles, ReportOptions};
use crate::peer::embree::{Device, Scene as EScene};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use tubecast::{Primitive, Ray, RoundCone};

/// First crossing in `[0, ∞)` of a line interval.
fn first(t_in: f64, t_out: f64) -> Option<f64> {
    if t_in >= 0.0 {
        Some(t_in)
    } else if t_out >= 0.0 {
        Some(t_out)
    } else {
        None
    }
}

#[derive(Default)]
struct Agree {
    n: usize,
    must_hit: usize,
    must_miss: usize,
    fm: [usize; 2],
    fh: [usize; 2],
    same_answer: usize,
    dt: Vec<f64>,
    err: [Vec<f64>; 2],
}

/// Best wall time of `reps` runs of `f` (and its last result).
pub(super) fn best_of<F: FnMut() -> usize>(reps: usize, mut f: F) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut hits = 0;
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        hits = std::hint::black_box(f());
        best = best.min(t0.elapsed().as_secs_f64());
    }
    (best, hits)
}

/// Embree 3 as a peer: writes `peers.md` and `peers.svg` into `out`.
///
/// * Per-ray agreement and error against the `f64` oracle, per failure region: for every link
///   case a one-segment `ROUND_LINEAR_CURVE` scene (flags 0: the convex hull of both spheres,
///   the same solid as ours) and the same `f32` ray; compared with our stable `f32` kernel.
/// * Mrays/s in one run: a generated *Furball* scene ([`ReportOptions::max_segments`] links,
///   at most 10⁵) as isolated Embree round linear segments vs our BVH + stable `f32` kernels,
///   on the same `f32` camera rays, single thread; and Embree's `ROUND_HERMITE_CURVE` on the same
///   polylines (Catmull-Rom tangents) for speed only — a swept circle, not our sphere sweep.
pub fn run_peers(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    use tubecast_render::accel::Bvh;
    use tubecast_render::render::Camera;
    use tubecast_render::scene::{generate, Scene};
    opts.validate()?;
    ensure_dir(out)?;
    let perr = |e: crate::peer::embree::EmbreeError| ReportError::Peer(e.to_string());
    let dev = Device::new().map_err(perr)?;
    let bar = progress(opts, oracle::LINK_REGIONS.len() as u64 + 3, "peers");
    let mut rows: Vec<(LinkRegion, Agree)> = Vec::new();
    for &region in &oracle::LINK_REGIONS {
        let cases: Vec<LinkCase> = link_cases(opts, region);
        let mut a = Agree { n: cases.len(), ..Agree::default() };
        for c in &cases {
            let tr = oracle::link_truth(c);
            let l32: RoundCone<f32> = oracle::round_cone(&c.link).cast();
            let (o, d) = (oracle::v3(c.ray.o).cast::<f32>(), oracle::v3(c.ray.d).cast::<f32>());
            let ours = l32.intersect(&Ray::new(o, d));
            let ours = if ours.hit { first(ours.entry.t as f64, ours.exit.t as f64) } else { None };
            let scene = EScene::round_linear(&dev, &[l32]).map_err(perr)?;
            let emb = scene.intersect(o.to_array(), d.to_array(), 0.0, f32::INFINITY).map(|h| h.t as f64);
            let (_, e) = oracle::link_bound(c, f32::EPSILON as f64, 1.0);
            let truth = tr.iv.and_then(|(a, b)| first(a, b));
            let dl = c.ray.d.length();
            let r = c.link.ra.max(c.link.rb);
            let must_hit = tr.gap < -e && tr.iv.is_some_and(|iv| iv.1 > 2.0 * e / dl);
            let must_miss = tr.gap > e || tr.iv.is_some_and(|iv| iv.1 < -2.0 * e / dl);
            a.same_answer += usize::from(ours.is_some() == emb.is_some());
            if let (Some(x), Some(y)) = (ours, emb) {
                a.dt.push((x - y).abs() * dl / r);
            }
            for (k, got) in [ours, emb].into_iter().enumerate() {
                if must_hit && got.is_none() {
                    a.fm[k] += 1;
                }
                if must_miss && got.is_some() {
                    a.fh[k] += 1;
                }
                if let (true, Some(g), Some(t)) = (must_hit, got, truth) {
                    a.err[k].push((g - t).abs() * dl / r);
                }
            }
            a.must_hit += usize::from(must_hit);
            a.must_miss += usize::from(must_miss);
        }
        rows.push((region, a));
        bar.inc(1);
    }

    // Scene-level speed, one thread each, same f32 rays.
    let n = opts.max_segments.min(100_000);
    let lines = generate::furball(n.div_ceil(78), 78, opts.seed);
    let scene = Scene::from_polylines(&lines, 0.05, "furball").map_err(|e| ReportError::Render(e.to_string()))?;
    let st = scene.stats();
    let side = opts.image.max(16);
    let cam =
        Camera::fit(st.bounds.0, st.bounds.1, 35.0, side, side).map_err(|e| ReportError::Render(e.to_string()))?;
    let crate::peer::SceneInputs { rays32, rays64, links32 } = crate::peer::scene_inputs(&scene, &cam, side);
    let t0 = Instant::now();
    let emb = EScene::round_linear(&dev, &links32).map_err(perr)?;
    let emb_build = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let bvh = Bvh::build(scene.primitives());
    let our_build = t0.elapsed().as_secs_f64();
    bar.inc(1);
    let reps = 3;
    let (t_emb, h_emb) = best_of(reps, || emb.count_hits(&rays32));
    let (t_our, h_our) = best_of(reps, || rays64.iter().filter(|r| bvh.closest_hit(r).is_some()).count());
    bar.inc(1);
    // Per-ray agreement on the scene rays.
    let mut ehits = Vec::new();
    emb.intersect_all(&rays32, &mut ehits);
    let diam = 2.0 * 0.06;
    let (mut same, mut dts) = (0usize, Vec::new());
    for (r, e) in rays64.iter().zip(&ehits) {
        let o = bvh.closest_hit(r).map(|h| h.t);
        same += usize::from(o.is_some() == e.is_some());
        if let (Some(x), Some(y)) = (o, e) {
            dts.push((x - y.t as f64).abs() * r.d.length() / diam);
        }
    }
    // Embree round Hermite on the same polylines (Catmull-Rom tangents), speed only.
    let mut segs = Vec::new();
    for l in &lines {
        let p = &l.points;
        let m = |k: usize| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(p.len() - 1));
            let s = 1.0 / (b - a) as f64;
            [0, 1, 2].map(|i| ((p[b][i] - p[a][i]) * s) as f32)
        };
        let rr = |k: usize| l.radii.get(k).copied().unwrap_or(0.05) as f32;
        for k in 0..p.len() - 1 {
            let (m0, m1) = (m(k), m(k + 1));
            segs.push((
                [p[k][0] as f32, p[k][1] as f32, p[k][2] as f32, rr(k)],
                [m0[0], m0[1], m0[2], rr(k + 1) - rr(k)],
                [p[k + 1][0] as f32, p[k + 1][1] as f32, p[k + 1][2] as f32, rr(k + 1)],
                [m1[0], m1[1], m1[2], rr(k + 1) - rr(k)],
            ));
        }
    }
    let herm = EScene::round_hermite(&dev, &segs).map_err(perr)?;
    let (t_herm, h_herm) = best_of(reps, || herm.count_hits(&rays32));
    drop((herm, emb));
    bar.inc(1);
    // Speed and memory per scene: Furball and a dense tractography-like Bundle at the report's
    // size, and at 10⁶ links with --big.
    let mut sizes = vec![opts.max_segments.min(100_000)];
    if opts.max_segments >= 1_000_000 {
        sizes.push(1_000_000);
    }
    // And a real tractogram: nibabel's standard.trk (the largest the repository ships).
    use super::peers_speed::{measure, Rays};
    let render_err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
    let mut scenes = Vec::new();
    for &m in &sizes {
        let fur = generate::furball(m.div_ceil(78), 78, opts.seed);
        scenes.push(("Furball", Scene::from_polylines(&fur, 0.05, "furball").map_err(render_err)?));
        let bun = generate::bundle(m.div_ceil(84), 84, opts.seed);
        scenes.push(("Bundle", Scene::from_polylines(&bun, 0.12, "bundle").map_err(render_err)?));
    }
    let trk = concat!(env!("CARGO_MANIFEST_DIR"), "/../../reference/readers/nibabel/standard.trk");
    scenes.push(("standard.trk", Scene::load(std::path::Path::new(trk), 0.5).map_err(render_err)?));
    let mut speed_rows = Vec::new();
    for (name, scene) in &scenes {
        for kind in [Rays::Camera, Rays::Random] {
            speed_rows.push(measure(&dev, name, scene, side, kind)?);
        }
    }
    bar.finish_and_clear();

    let nr = rays32.len() as f64;
    let mut md = format!(
        "# Embree 3 as a peer\n\nGenerated by `cargo run --release -p tubecast-lab --features embree -- peers{}` \
         (seed {}, {} link cases per region). Machine: {}.\n\n",
        if opts.max_segments >= 1_000_000 { " --big" } else { "" },
        opts.seed,
        opts.link_cases,
        machine()
    );
    md.push_str(
        "Embree `ROUND_LINEAR_CURVE` segments with flags 0 (no neighbours) are the convex hull of the two \
         end spheres — the same solid as our links (see `crates/lab/src/peer/mod.rs`). Both sides get the same `f32` link \
         and ray. Compared: the first surface crossing in `[0, ∞)`. `must-hit`/`must-miss`: oracle verdicts \
         outside the `f32` error band of `tests/kernels/link/properties.rs`. Errors in units of the link's largest radius.\n\n\
         ## Per-ray agreement and error against the f64 oracle\n\n",
    );
    md.push_str(
        "| region | cases | same hit/miss | p99 |Δt| ours vs Embree (r) | must-hit | false miss ours | false miss Embree | must-miss | false hit ours | false hit Embree | p99 err ours (r) | p99 err Embree (r) | max err ours (r) | max err Embree (r) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (r, a) in &rows {
        let mx = |v: &Vec<f64>| v.iter().copied().fold(f64::NAN, f64::max);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.name(),
            a.n,
            a.same_answer,
            fmt_num(percentile(&a.dt, 0.99)),
            a.must_hit,
            a.fm[0],
            a.fm[1],
            a.must_miss,
            a.fh[0],
            a.fh[1],
            fmt_num(percentile(&a.err[0], 0.99)),
            fmt_num(percentile(&a.err[1], 0.99)),
            fmt_num(mx(&a.err[0])),
            fmt_num(mx(&a.err[1]))
        );
    }
    let _ = write!(
        md,
        "\n## Speed (one run, one thread, same {side}×{side} f32 camera rays)\n\n\
         Scene: *Furball*, {} links (isolated segments on both sides). Build: Embree {} ms (quality high, robust), \
         ours {} ms.\n\n| tracer | surface | Mrays/s | hits |\n|---|---|---|---|\n\
         | tubecast BVH + stable f32 link | sphere sweep (round cone) | {} | {} |\n\
         | Embree ROUND_LINEAR_CURVE | sphere sweep (round cone) | {} | {} |\n\
         | Embree ROUND_HERMITE_CURVE | swept circle (speed only, not our surface) | {} | {} |\n\n\
         Ratio Embree linear / tubecast: {:.2}. Scene rays answering the same hit/miss: {} of {}; p99 |Δt| where both \
         hit: {} tube diameters.\n",
        scene.links.len(),
        fmt_num(emb_build * 1e3),
        fmt_num(our_build * 1e3),
        fmt_num(nr / t_our / 1e6),
        h_our,
        fmt_num(nr / t_emb / 1e6),
        h_emb,
        fmt_num(nr / t_herm / 1e6),
        h_herm,
        (nr / t_emb) / (nr / t_our),
        same,
        rays32.len(),
        fmt_num(percentile(&dts, 0.99)),
    );
    let _ = write!(
        md,
        "\n## Speed and memory per scene (one run, the same {side}×{side} f32 rays on both sides)\n\n\
         Camera rays: a fitted camera's pixels; random rays: origins uniform in the scene's box, directions \
         uniform on the sphere. Embree `rtcIntersect1` on `ROUND_LINEAR_CURVE` isolated segments (quality \
         high, robust) against our binary `Bvh` (lane packets) and the 8-wide `WideBvh` (float SoA tree over \
         obvhs's PLOC build, static link filter; \"compact\" is what the CLI uses); ratios above 1 favour us. \
         Tracing only: scene loading, building and output are not in Mrays/s (build times have their own \
         column). All threads: rays in chunks of 256 over rayon's pool, both sides. \
         Embree's bytes: its device memory monitor after the build (vertex, index and flag buffers, BVH); \
         ours: primitives + tree (`Tracer::memory_bytes`; the scene's nodes and links are extra).\n\n{}",
        super::peers_speed::table(&speed_rows)
    );
    let mdp = out.join("peers.md");
    write_text(&mdp, &md)?;
    let names: Vec<String> = rows.iter().map(|(r, _)| r.name().to_string()).collect();
    let ser = |label: &str, c: usize, k: usize, off: f64| Series {
        label: label.into(),
        color: c,
        points: rows
            .iter()
            .enumerate()
            .map(|(i, (_, a))| Pt {
                x: i as f64 + off,
                y: percentile(&a.err[k], 0.99),
                marker: Marker::Dot,
                text: None,
            })
            .collect(),
        line: false,
    };
    let c = Chart {
        title: "p99 first-hit t error vs f64 oracle, f32 inputs".into(),
        x_desc: String::new(),
        y_desc: "p99 t error in radii (log)".into(),
        x: XAxis::Categories(names),
        y_floor: 1e-10,
        series: vec![ser("tubecast stable f32", 0, 0, -0.1), ser("Embree round linear", 3, 1, 0.1)],
        note: None,
    };
    let cp = out.join("peers.svg");
    chart::write_svg(&cp, &c, (1000, 620))?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}
