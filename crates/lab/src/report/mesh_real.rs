//! The mesh and simplification trade-off on real-world-like scenes: a real tractogram
//! (nibabel's `standard.trk`), a tractogram-like fibre bundle (Russig's *Bundle*) and the
//! neuron assembly of the README render (`tubecast generate neurons --n 2`). Per scene and
//! representation (exact kernels, the automatic choice within ε, the certified mesh): model
//! size, memory and frame time against the certified error — the axes of `mesh.md`, with the
//! error on x.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::mesh::{err, estimate, measure_scene, table, MeshRow, Plan};
use super::runs::{header, CHART};
use super::{ensure_dir, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tubecast::V3;
use tubecast_render::scene::{generate, Scene};

/// Choice tolerances, in units of the scene's largest radius.
pub const CHOSEN_EPS: [f64; 3] = [1e-1, 1e-2, 1e-3];
/// Mesh tolerances, in units of the scene's largest radius.
pub const MESH_EPS: [f64; 2] = [1e-2, 1e-3];
/// Meshes whose estimated peak memory while building exceeds this are skipped (about 6·10⁶
/// triangles: build time on 2 cores).
pub const MAX_BUILD_BYTES: f64 = 1e9;
/// Marker per scene (colour per representation).
const MARKERS: [Marker; 3] = [Marker::Dot, Marker::Triangle, Marker::Cross];
/// x position of a certified error of 0 (drawn at this floor and marked `0`).
const X_FLOOR: f64 = 1e-7;

/// nibabel's `standard.trk` (pinned under `reference/readers/nibabel`, MIT).
pub fn standard_trk() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/readers/nibabel/standard.trk")
}

/// The three scenes, named: (name, scene). `quick` makes them small (for tests).
pub fn scenes(opts: &ReportOptions, quick: bool) -> Result<Vec<(String, Scene)>, ReportError> {
    // nibabel's file at the README render's radius: 0.4 % of the points' bounding-box diagonal.
    let probe = Scene::load(&standard_trk(), 1.0).map_err(err)?;
    let st = probe.stats();
    let diag = (V3::from(st.bounds.1) - V3::from(st.bounds.0)).length();
    let trk = Scene::load(&standard_trk(), 0.004 * diag).map_err(err)?;
    let fibres = if quick { 4 } else { 60 };
    let bundle = Scene::from_polylines(&generate::bundle(fibres, 84, opts.seed), 0.12, "bundle").map_err(err)?;
    let n = if quick { 1 } else { 2 };
    let swc = generate::neurons(n, &[generate::base_neuron(opts.seed)], opts.seed);
    let neurons = Scene::from_swc(&swc, "neurons").map_err(err)?;
    Ok(vec![
        (format!("standard.trk (nibabel, {} streamlines)", trk.chains().len()), trk),
        (format!("Bundle ({fibres} fibres × 84 links)"), bundle),
        (format!("neurons --n {n} (README render, {} neurons)", n * n * n), neurons),
    ])
}

/// The first `k ≤ 200` links as a scene of their own (the mesh estimate's sample) and the
/// scale `links / k`.
fn sample(scene: &Scene) -> (Scene, f64) {
    let k = scene.links.len().min(200);
    let part = Scene {
        links: scene.links.iter().take(k).collect(),
        values: Vec::new(),
        coverage: Vec::new(),
        ..scene.clone()
    };
    (part, scene.links.len() as f64 / k.max(1) as f64)
}

fn chart(
    title: &str,
    y_desc: &str,
    rows: &[(String, MeshRow)],
    r_max: &[(String, f64)],
    y: &dyn Fn(&MeshRow) -> f64,
) -> Chart {
    let kind = |m: &str| m.split(' ').next().unwrap_or(m).to_string();
    let mut series: Vec<Series> = Vec::new();
    for (si, (scene, rm)) in r_max.iter().enumerate() {
        for (ki, k) in ["exact", "chosen", "chosen+splines", "mesh"].iter().enumerate() {
            let points: Vec<Pt> = rows
                .iter()
                .filter(|(s, r)| s == scene && kind(&r.model) == *k)
                .map(|(_, r)| {
                    let x = r.certified / rm;
                    let zero = x.partial_cmp(&X_FLOOR) != Some(std::cmp::Ordering::Greater);
                    let text = if *k == "exact" { Some("exact".to_string()) } else { zero.then(|| "0".to_string()) };
                    Pt { x: x.max(X_FLOOR), y: y(r), marker: MARKERS[si % 3], text }
                })
                .collect();
            if !points.is_empty() {
                series.push(Series { label: format!("{k}: {}", short(scene)), color: ki, points, line: *k != "exact" });
            }
        }
    }
    Chart {
        title: title.into(),
        x_desc: format!("certified error / largest radius (log; 0 drawn at {X_FLOOR:e})"),
        y_desc: y_desc.into(),
        x: XAxis::Log,
        y_floor: 1e-4,
        series,
        note: Some(format!(
            "colour: representation\n{}",
            r_max
                .iter()
                .enumerate()
                .map(|(i, (s, _))| format!("{} {}", ["●", "▲", "✕"][i % 3], short(s)))
                .collect::<Vec<_>>()
                .join("  ")
        )),
    }
}

fn short(scene: &str) -> String {
    scene.split(" (").next().unwrap_or(scene).to_string()
}

/// The report: writes `mesh_real.md`, `mesh_real.svg` (frame time) and `mesh_real_memory.svg`
/// into `out`.
pub fn run_mesh_real(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(opts.threads).build().map_err(err)?;
    let quick = opts.max_segments < 10_000;
    let scenes = scenes(opts, quick)?;
    let bar = progress(opts, scenes.len() as u64, "mesh-real");
    let plan = Plan {
        chosen: &CHOSEN_EPS,
        splines: true,
        mesh: if quick { &MESH_EPS[..1] } else { &MESH_EPS },
        max_bytes: MAX_BUILD_BYTES,
    };
    let (mut rows, mut r_max, mut md_tables) = (Vec::new(), Vec::new(), String::new());
    for (name, scene) in &scenes {
        let (mut notes, mut skipped) = (String::new(), Vec::new());
        let (part, scale) = sample(scene);
        let rs = measure_scene(scene, &plan, &|e| estimate(&part, scale, e), opts, &pool, &mut notes, &mut skipped)?;
        let rm = (0..scene.nodes.len()).map(|i| scene.radius(i)).fold(0.0, f64::max);
        let _ = write!(
            md_tables,
            "\n## {name}\n\n{} nodes, {} links, largest radius r = {}.\n\n{}",
            scene.nodes.len(),
            scene.links.len(),
            super::fmt_num(rm),
            table(&rs)
        );
        md_tables.push_str(&notes);
        rows.extend(rs.into_iter().map(|r| (name.clone(), r)));
        r_max.push((name.clone(), rm));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut md = header(
        "Model size, memory and frame time against certified error on real-world-like scenes",
        opts,
        "cargo run --release -p tubecast-lab -- mesh-real",
    );
    let _ = write!(
        md,
        "Three scenes a user renders: a real tractogram (nibabel's `standard.trk`, radius 0.4 % of its diagonal, \
         as the README render), a tractogram-like bundle of fibres (Russig's *Bundle*, radius 0.12, seed {}) and the \
         neuron assembly of the README render (`tubecast generate neurons`, seed {}, SWC radii). Per scene the exact \
         kernels, the automatic choice within ε = k·r (`scene::choice`: merged links, spheres, cylinders, cones; \
         k ∈ {{10⁻¹, 10⁻², 10⁻³}}), once from links only (`chosen`) and once also fitting quadratic spline pieces \
         to runs of links (`chosen+splines`, `choose_with(.., true)`, as `render --tolerance` does; its frame time \
         is measured with the spline pieces traced by the exact spline kernel) and the certified mesh (`tessellate`, obvhs triangle BVH) at k ∈ {{10⁻², 10⁻³}} \
         where its estimated peak memory while building is ≤ {:.1} GB; r = the scene's largest radius. Columns as in \
         [mesh.md](mesh.md): certified error (absolute, the representation's two-sided Hausdorff bound), model \
         size (prims in the model name, triangles), build, memory, one opaque lit {}×{} frame on {} thread(s), and \
         the image difference to the exact render. Charts: frame time and memory against certified error / r \
         (error 0 drawn at {X_FLOOR:e}, marked).",
        opts.seed, opts.seed, MAX_BUILD_BYTES / 1e9, opts.image, opts.image, opts.threads
    );
    md.push('\n');
    md.push_str(&md_tables);
    let mdp = out.join("mesh_real.md");
    write_text(&mdp, &md)?;
    let c1 = out.join("mesh_real.svg");
    let c2 = out.join("mesh_real_memory.svg");
    let t = format!("Frame time against certified error ({0}×{0}, {1} thread(s))", opts.image, opts.threads);
    chart::write_svg(&c1, &chart(&t, "frame ms (log)", &rows, &r_max, &|r| r.frame_s * 1e3), CHART)?;
    let t = "Memory against certified error";
    chart::write_svg(&c2, &chart(t, "tracer memory MB (log)", &rows, &r_max, &|r| r.bytes as f64 / 1e6), CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![c1, c2] })
}
