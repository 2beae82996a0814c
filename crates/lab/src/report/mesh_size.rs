//! Model size against certified error, per representation, on the real-world-like scenes of
//! `mesh_real.md`: the links as they are (exact), the simplified link model (`scene::choice`),
//! the per-chain shells (`mesh::tessellate`, Salm-style: overlapping closed shells composited
//! through a depth buffer) and the surface of the union (`mesh::tessellate_union_with`, with
//! `Bodies::Hulls` what `tubecast mesh --hulls` writes, with `Bodies::Runs` what `tubecast mesh
//! --runs` writes; `tubecast mesh` writes one of them, chosen by the scene),
//! at ε = k·r̄ (r̄ the mean node radius).
//!
//! A mesh is built where its estimated triangle count is within the run's cap; above it the
//! row gives the estimate (marked `est.`), which is the answer on this machine for that size.

use super::chart::{self, Chart, Marker, Pt, Series, XAxis};
use super::mesh::{err, estimate};
use super::mesh_real::scenes;
use super::runs::{header, CHART};
use super::{ensure_dir, fmt_num, progress, write_text, ReportError, ReportFiles, ReportOptions};
use std::fmt::Write as _;
use std::path::Path;
use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::mesh::{export, tessellate, tessellate_union_with, Bodies, MeshError, SceneMesh, UnionOptions};
use tubecast_render::scene::choice::{choose_with, Tolerance};
use tubecast_render::scene::{Model, Scene};

/// Tolerances, in units of the scene's mean node radius r̄.
pub const SIZE_EPS: [f64; 2] = [1e-2, 1e-3];
/// Meshes whose estimated triangle count exceeds this are not built (the full run; about
/// 1 GB of `f64` mesh while building and minutes of union contouring on 2 cores).
pub const MAX_TRIANGLES: f64 = 2e7;
/// The union's estimate above which it is not built, full run (manifold's union: about a
/// minute per 2·10⁵ triangles on 2 loaded cores, the certificate and refinements included).
pub const MAX_UNION_TRIANGLES: f64 = 3e6;
/// The union is also not built where its own memory estimate exceeds this (bytes): the row is
/// then the estimate.
pub const UNION_MEMORY_LIMIT: u64 = 5 << 30;
/// The caps of the quick (test) run.
pub const QUICK_MAX_TRIANGLES: f64 = 4e5;
/// Links of the union's sample: one contiguous run from the middle of the scene (links of one
/// chain meet as they do in the scene, so the sample's crease and cap area is typical).
pub const UNION_SAMPLE_LINKS: usize = 12;

/// Representations, in chart order (colour index).
pub const KINDS: [&str; 5] = ["exact links", "simplified links", "shells", "union", "union, runs"];

/// One representation of one scene at one tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct SizeRow {
    /// Scene name.
    pub scene: String,
    /// One of [`KINDS`].
    pub kind: &'static str,
    /// ε / r̄ (0 for the exact links).
    pub k: f64,
    /// The scene's mean node radius r̄.
    pub r_mean: f64,
    /// Certified two-sided Hausdorff bound (absolute; NaN where estimated).
    pub certified: f64,
    /// Primitives of a link model (0 for meshes).
    pub prims: usize,
    /// Triangles (0 for link models).
    pub triangles: f64,
    /// Meshes: the binary PLY `tubecast mesh` writes; link models: primitives + BVH in memory.
    pub bytes: f64,
    /// An estimate (not built).
    pub estimated: bool,
}

/// Bytes of the binary PLY of `v` vertices and `t` triangles with certified bound `bound`
/// (`export::ply`: 12 per vertex, 13 per triangle, and the header, which names the counts and
/// the bound).
pub fn ply_bytes(v: f64, t: f64, bound: f64) -> f64 {
    let mut m = SceneMesh::default();
    m.mesh.certified = bound;
    let head = export::ply(&m).len() as f64; // the header with counts "0"
    head + (digits(v) - 1.0) + (digits(t) - 1.0) + 12.0 * v + 13.0 * t
}

fn digits(x: f64) -> f64 {
    format!("{}", x.round().max(0.0) as u64).len() as f64
}

/// The mean node radius.
pub fn mean_radius(scene: &Scene) -> f64 {
    let n = scene.nodes.len().max(1);
    (0..scene.nodes.len()).map(|i| scene.radius(i)).sum::<f64>() / n as f64
}

/// Lateral area of the links' frusta (overlaps counted twice: an upper estimate of the union's
/// area along chains).
fn lateral_area(scene: &Scene) -> f64 {
    scene
        .links
        .iter()
        .map(|[a, b]| {
            let (ra, rb) = (scene.radius(a as usize), scene.radius(b as usize));
            let l = (V3::from(scene.nodes[b as usize].pos) - V3::from(scene.nodes[a as usize].pos)).length();
            std::f64::consts::PI * (ra + rb) * (l * l + (ra - rb) * (ra - rb)).sqrt()
        })
        .sum()
}

/// The union mesh's size (the hulls', [`Bodies::Hulls`]) estimated from a contiguous run of
/// `n` links from the middle of the scene, meshed for real at `eps`: its triangles per unit
/// of lateral area, scaled to the scene's lateral area (the union's spheres are resolved per
/// node radius at the same ε, so the density carries over between runs of similar radii).
/// High where the scene's chains are longer than the sample: the sample's two end caps (half
/// a node sphere each) are spread over its few links.
pub fn union_estimate(scene: &Scene, eps: f64, n: usize) -> Result<f64, ReportError> {
    let n = n.min(scene.links.len());
    if n == 0 {
        return Ok(0.0);
    }
    let start = (scene.links.len() - n) / 2;
    let part = Scene {
        links: scene.links.iter_from(start).take(n).collect(),
        values: Vec::new(),
        coverage: Vec::new(),
        ..scene.clone()
    };
    // Under the same memory limit as the rows built: a sample whose refinements would not fit
    // keeps its last mesh; one whose first union would not fit has no estimate (infinite: the
    // row is left out).
    let opts = UnionOptions { memory_limit: Some(UNION_MEMORY_LIMIT), bodies: Bodies::Hulls };
    let m = match tessellate_union_with(&part, eps, &opts) {
        Ok((m, _)) => m,
        Err(MeshError::Memory { .. }) => return Ok(f64::INFINITY),
        Err(e) => return Err(err(e)),
    };
    let density = m.mesh.triangles.len() as f64 / lateral_area(&part);
    Ok(density * lateral_area(scene))
}

fn mesh_row(scene: &str, kind: &'static str, k: f64, r_mean: f64, m: &SceneMesh) -> SizeRow {
    SizeRow {
        scene: scene.into(),
        kind,
        k,
        r_mean,
        certified: m.mesh.certified,
        prims: 0,
        triangles: m.mesh.triangles.len() as f64,
        bytes: export::ply(m).len() as f64,
        estimated: false,
    }
}

fn estimated_row(scene: &str, kind: &'static str, k: f64, r_mean: f64, t: f64) -> SizeRow {
    // The header names the bound: taken as ε (a few bytes either way).
    // A closed surface of genus 0 per part has V = T/2 + 2 per part: T/2 for large meshes.
    SizeRow {
        scene: scene.into(),
        kind,
        k,
        r_mean,
        certified: f64::NAN,
        prims: 0,
        triangles: t,
        bytes: ply_bytes(t / 2.0, t, k * r_mean),
        estimated: true,
    }
}

/// The rows of one scene: the exact links, then per tolerance k·r̄ the simplified links, the
/// shells and the union (built where the estimate is within `cap` triangles, `union_cap` for
/// the union).
pub fn measure_sizes(
    name: &str,
    scene: &Scene,
    ks: &[f64],
    cap: f64,
    union_cap: f64,
    pool: &rayon::ThreadPool,
) -> Result<Vec<SizeRow>, ReportError> {
    let r = mean_radius(scene);
    let bvh = pool.install(|| Bvh::build(scene.primitives()));
    let mut rows = vec![SizeRow {
        scene: name.into(),
        kind: KINDS[0],
        k: 0.0,
        r_mean: r,
        certified: 0.0,
        prims: scene.links.len(),
        triangles: 0.0,
        bytes: bvh.memory_bytes() as f64,
        estimated: false,
    }];
    // The shells' estimate: the first 200 links tessellated for real, scaled by the link count.
    let ks_shell = scene.links.len().min(200);
    let part = Scene {
        links: scene.links.iter().take(ks_shell).collect(),
        values: Vec::new(),
        coverage: Vec::new(),
        ..scene.clone()
    };
    let scale = scene.links.len() as f64 / ks_shell.max(1) as f64;
    for &k in ks {
        let eps = k * r;
        let c = choose_with(scene, &Tolerance::Absolute(eps), false);
        let prims = c.prims.len();
        let bvh = pool.install(|| Bvh::build(c.prims));
        rows.push(SizeRow {
            scene: name.into(),
            kind: KINDS[1],
            k,
            r_mean: r,
            certified: c.worst,
            prims,
            triangles: 0.0,
            bytes: bvh.memory_bytes() as f64,
            estimated: false,
        });
        let est = estimate(&part, scale, eps)?.triangles;
        rows.push(if est <= cap {
            mesh_row(name, KINDS[2], k, r, &pool.install(|| tessellate(scene, Model::Links, eps)).map_err(err)?)
        } else {
            estimated_row(name, KINDS[2], k, r, est)
        });
        let est = pool.install(|| union_estimate(scene, eps, UNION_SAMPLE_LINKS))?;
        let opts = UnionOptions { memory_limit: Some(UNION_MEMORY_LIMIT), bodies: Bodies::Hulls };
        let built = if est <= union_cap {
            match pool.install(|| tessellate_union_with(scene, eps, &opts)) {
                Ok((m, _)) => Some(m),
                Err(MeshError::Memory { .. }) => None,
                Err(e) => return Err(err(e)),
            }
        } else {
            None
        };
        match built {
            Some(m) => rows.push(mesh_row(name, KINDS[3], k, r, &m)),
            None if est.is_finite() => rows.push(estimated_row(name, KINDS[3], k, r, est)),
            None => {}
        }
        // The runs' union has no estimate of its own (its size depends on how many streamlines
        // graze, which a sample does not show): it is built where the union's or the shells'
        // estimate is within the union's cap, and has no row elsewhere.
        let shells = rows.iter().rev().find(|x| x.kind == KINDS[2]).map_or(f64::INFINITY, |x| x.triangles);
        if est.min(shells) <= union_cap {
            let opts = UnionOptions { bodies: Bodies::Runs, ..opts };
            match pool.install(|| tessellate_union_with(scene, eps, &opts)) {
                Ok((m, _)) => rows.push(mesh_row(name, KINDS[4], k, r, &m)),
                Err(MeshError::Memory { .. }) => {}
                Err(e) => return Err(err(e)),
            }
        }
    }
    Ok(rows)
}

/// The markdown table of `rows`.
pub fn size_table(rows: &[SizeRow]) -> String {
    let mut md = String::from(
        "| scene | representation | ε / r̄ | certified error | primitives | triangles | bytes | built |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.scene,
            r.kind,
            if r.k == 0.0 { "-".to_string() } else { format!("{}", r.k) },
            fmt_num(r.certified),
            r.prims,
            fmt_num(r.triangles),
            fmt_num(r.bytes),
            if r.estimated { "est." } else { "yes" }
        );
    }
    md
}

/// The chart: bytes against certified error / r̄, one colour per representation, one marker
/// per scene; estimated meshes drawn at their ε (their bound is ε by construction of the
/// estimate, not measured), marked `est.`.
fn size_chart(rows: &[SizeRow], names: &[String]) -> Chart {
    const MARKERS: [Marker; 3] = [Marker::Dot, Marker::Triangle, Marker::Cross];
    const X_FLOOR: f64 = 1e-7;
    let mut series = Vec::new();
    for (si, name) in names.iter().enumerate() {
        for (ki, kind) in KINDS.iter().enumerate() {
            let points: Vec<Pt> = rows
                .iter()
                .filter(|r| &r.scene == name && r.kind == *kind)
                .map(|r| {
                    let x = if r.estimated { r.k } else { r.certified / r.r_mean };
                    let text = if r.estimated {
                        Some("est.".to_string())
                    } else if r.k == 0.0 {
                        Some("exact".to_string())
                    } else {
                        None
                    };
                    Pt { x: x.max(X_FLOOR), y: r.bytes, marker: MARKERS[si % 3], text }
                })
                .collect();
            if !points.is_empty() {
                let short = name.split(" (").next().unwrap_or(name);
                series.push(Series { label: format!("{kind}: {short}"), color: ki, points, line: ki != 0 });
            }
        }
    }
    Chart {
        title: "Size against certified error".into(),
        x_desc: format!("certified error / mean radius (log; 0 drawn at {X_FLOOR:e})"),
        y_desc: "bytes (log): meshes as PLY, link models in memory".into(),
        x: XAxis::Log,
        y_floor: 1e2,
        series,
        note: Some(format!(
            "colour: representation\n{}",
            names
                .iter()
                .enumerate()
                .map(|(i, s)| format!("{} {}", ["●", "▲", "✕"][i % 3], s.split(" (").next().unwrap_or(s)))
                .collect::<Vec<_>>()
                .join("  ")
        )),
    }
}

/// The report: writes `mesh_size.md` and `mesh_size.svg` into `out`. Scenes as
/// `mesh_real.md`'s (the quick run's small ones in tests).
pub fn run_mesh_size(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(opts.threads).build().map_err(err)?;
    let quick = opts.max_segments < 10_000;
    let (cap, union_cap) =
        if quick { (QUICK_MAX_TRIANGLES, QUICK_MAX_TRIANGLES) } else { (MAX_TRIANGLES, MAX_UNION_TRIANGLES) };
    let scenes = scenes(opts, quick)?;
    let bar = progress(opts, scenes.len() as u64, "mesh-size");
    let (mut rows, mut names) = (Vec::new(), Vec::new());
    for (name, scene) in &scenes {
        let short = name.split(" (").next().unwrap_or(name).to_string();
        rows.extend(measure_sizes(&short, scene, &SIZE_EPS, cap, union_cap, &pool)?);
        names.push(short);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut md = header(
        "Model size against certified error: link models, shells and the union mesh",
        opts,
        "cargo run --release -p tubecast-lab -- mesh-size",
    );
    let _ = write!(
        md,
        "The scenes of [mesh_real.md](mesh_real.md) ({}), each at ε = k·r̄, k ∈ {{10⁻², 10⁻³}}, r̄ the scene's \
         mean node radius, in five representations: the links as they are (`exact links`, no modelling error), the \
         simplified link model (`scene::choice`: merged links, spheres, cylinders, cones within ε), the per-chain \
         **shells** (`tubecast mesh --shells`: one closed shell per chain and split joint, overlapping where chains \
         meet, each certified against its own chain; Salm-style, for renderers that composite through a depth \
         buffer) and the **union** (`tubecast mesh --hulls`: one closed, embedded surface per component, certified \
         against the union's exact surface). Bytes: meshes as the binary PLY `tubecast mesh` writes (12 per vertex, 13 per \
         triangle), link models as primitives + BVH in memory. Certified error: the representation's two-sided \
         Hausdorff bound (absolute). A mesh is built where its estimated triangle count is at most {:.0e} \
         (union: {:.0e}, and its own memory estimate within {:.1} GB); above it the row is the estimate (`est.`: \
         shells from the first 200 links tessellated for real, scaled by the link count; union from a run of {} \
         links from the middle of the scene meshed for real at the same ε, its triangles per unit of lateral tube \
         area scaled to the scene's lateral area, high by up to about 2× where the scene's chains are longer \
         than the sample (its end caps); PLY bytes for V = T/2) and is drawn at ε; a union whose sample itself \
         exceeds the memory limit has no row. The union is \
         manifold's union of the links' sphere hulls, certified against the exact union \
         (`docs/design/union-mesh.md`); **union, runs** (`tubecast mesh --runs`) the same union with each \
         equal-radius stretch of a chain meshed as one body of mitred rings, graded towards grazing tubes, \
         built where the union's or the shells' estimate is within the union's cap (no estimate otherwise: \
         its size depends on how many streamlines graze). `tubecast mesh` without either flag builds the runs \
         where at least half the links lie on runs of four links or more (here the Bundle), the hulls \
         otherwise. \
         Chart: bytes against certified error / r̄, one colour per representation, one marker per scene.\n\n",
        names.join(", "),
        cap,
        union_cap,
        UNION_MEMORY_LIMIT as f64 / 1e9,
        UNION_SAMPLE_LINKS
    );
    md.push_str(&size_table(&rows));
    md.push_str(&closing_note(&rows, &names));
    let mdp = out.join("mesh_size.md");
    write_text(&mdp, &md)?;
    let cp = out.join("mesh_size.svg");
    chart::write_svg(&cp, &size_chart(&rows, &names), CHART)?;
    Ok(ReportFiles { markdown: mdp, charts: vec![cp] })
}

/// The closing note: per scene and tolerance, the union's size over the shells' and over the
/// simplified links'.
fn closing_note(rows: &[SizeRow], names: &[String]) -> String {
    let mut s = String::from("\n");
    for name in names {
        for &k in &SIZE_EPS {
            let get = |kind: &str| rows.iter().find(|r| &r.scene == name && r.kind == kind && r.k == k);
            let (Some(c), Some(sh), Some(u)) = (get(KINDS[1]), get(KINDS[2]), get(KINDS[3])) else { continue };
            let est = |r: &SizeRow| if r.estimated { " (est.)" } else { "" };
            let runs = match get(KINDS[4]) {
                Some(x) => format!(
                    " Union with runs: {} triangles, {} bytes, certified {}, {:.2}× the shells' bytes.",
                    fmt_num(x.triangles),
                    fmt_num(x.bytes),
                    fmt_num(x.certified),
                    x.bytes / sh.bytes
                ),
                None => String::new(),
            };
            let _ = writeln!(
                s,
                "- {name}, ε = {k}·r̄: union {} triangles, {} bytes{}; shells {} triangles, {} bytes{}; simplified links {} primitives, {} bytes. Union / shells: {:.1}× the bytes.{runs}",
                fmt_num(u.triangles),
                fmt_num(u.bytes),
                est(u),
                fmt_num(sh.triangles),
                fmt_num(sh.bytes),
                est(sh),
                c.prims,
                fmt_num(c.bytes),
                u.bytes / sh.bytes
            );
        }
    }
    s
}
