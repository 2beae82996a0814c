//! The grid-resolution section of the voxel report: the resolutions the cost models choose
//! (`GridParams::cells_per_prim: None`; per ray, and per frame with `rays_per_build`, module
//! docs of `tubecast_render::accel::grid`) against a sweep of fixed cells-per-link `λ`, in
//! process CPU time, on the bundle and the Furball; and a least-squares fit of the build's
//! costs per cell and per reference, in primitive tests, beside the model's `BUILD_COST`.

use super::voxel_clock::Clock;
use super::{fmt_num, ReportError, ReportOptions};
use std::fmt::Write as _;
use tubecast::{Ray, V3};
use tubecast_render::accel::grid::{expected_references, Grid, GridParams, SceneSums, BUILD_COST};
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Prim, Scene};

/// The fixed `λ` of the sweep.
const LAMBDAS: [f64; 8] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];

/// One measured grid (best of the repetitions): build and render CPU seconds, cells per link,
/// cells, references, and references over the model's expected count `E(h)`.
#[derive(Clone, Copy)]
struct Point {
    build: f64,
    trace: f64,
    lambda: f64,
    cells: f64,
    refs: f64,
    refs_model: f64,
}

fn measure(
    scene: &Scene,
    cam: &Camera,
    params: GridParams,
    reps: usize,
    pool: &rayon::ThreadPool,
) -> Result<Point, ReportError> {
    let prims = scene.primitives();
    let (mut build, mut trace, mut grid) = (f64::INFINITY, f64::INFINITY, None);
    for _ in 0..reps {
        let p = prims.clone();
        let t0 = Clock::now();
        let g = pool.install(|| Grid::build_with(p, &params));
        let t1 = Clock::now();
        pool.install(|| render(scene, &g, cam, &Options::default())).map_err(|e| ReportError::Render(e.to_string()))?;
        trace = trace.min(Clock::now().since(t1));
        build = build.min(t1.since(t0));
        grid = Some(g);
    }
    let g = grid.ok_or_else(|| ReportError::Render("no repetition".into()))?;
    let cells = g.dims().iter().map(|&d| d as f64).product::<f64>();
    let refs = g.references() as f64;
    let refs_model = refs / expected_references(&SceneSums::of(&prims), g.voxel_size());
    Ok(Point { build, trace, lambda: cells / prims.len().max(1) as f64, cells, refs, refs_model })
}

/// CPU nanoseconds of one primitive test (`Prim::first_hit`) on `prims`: rays through random
/// points of random primitives' boxes (about half of them hit), best of 3 passes.
fn test_ns(prims: &[Prim], seed: u64) -> f64 {
    let mut rng = generate::Rng::new(seed);
    let pairs: Vec<(usize, Ray<f64>)> = (0..20_000)
        .map(|_| {
            let k = (rng.uniform() * prims.len() as f64) as usize % prims.len();
            let (a, b) = prims[k].aabb();
            let p = V3::new(rng.range(a[0], b[0]), rng.range(a[1], b[1]), rng.range(a[2], b[2]));
            let d = V3::from(rng.unit());
            (k, Ray::new(p - d * 10.0, d))
        })
        .collect();
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t0 = Clock::now();
        let mut hits = 0usize;
        for _ in 0..10 {
            hits += pairs.iter().filter(|(k, r)| prims[*k].first_hit(r).is_some()).count();
        }
        best = best.min(Clock::now().since(t0) / (10 * pairs.len()) as f64);
        std::hint::black_box(hits);
    }
    best * 1e9
}

/// Least squares of build seconds `≈ a·N + b·cells + c·refs`, each row weighted by 1/build (relative
/// error), by the normal equations (3×3, Cramer). `(a, b, c)` in seconds.
fn fit(rows: &[[f64; 4]]) -> [f64; 3] {
    let (mut m, mut v) = ([[0.0; 3]; 3], [0.0; 3]);
    for r in rows {
        let w = 1.0 / r[3];
        let x = [r[0] * w, r[1] * w, r[2] * w];
        for i in 0..3 {
            v[i] += x[i];
            for j in 0..3 {
                m[i][j] += x[i] * x[j];
            }
        }
    }
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    std::array::from_fn(|k| {
        let mut mk = m;
        (0..3).for_each(|i| mk[i][k] = v[i]);
        det(&mk) / d
    })
}

/// The section (markdown) at each of `sizes` links, on `pool`.
pub(super) fn section(sizes: &[usize], opts: &ReportOptions, pool: &rayon::ThreadPool) -> Result<String, ReportError> {
    let rays = (opts.image as f64).powi(2);
    let mut md = format!(
        "\n## Grid resolution: the cost models against fixed λ (same run)\n\nThe default grid picks its voxel side \
         by minimising a cost model: per ray (*static*: DDA steps against primitive tests, `rays_per_build: None`) \
         or per frame (*frame*: the build's cells and references, counted → prefix-summed → scattered, plus the \
         frame's {img}² rays, `rays_per_build: Some({img}²)`); inputs are the link count, total length and radius, \
         Σr(r + l/2), the solid volume and the box; rules and derivations in the module docs of \
         `tubecast_render::accel::grid` (ρ = `STEP_COST`, `BUILD_COST` = {bc} cell / {br} reference, from an \
         operation count). Each row sweeps fixed cells per link λ ∈ {{{lams}}} (`GridParams::cells_per_prim`) on the \
         same scene; opaque {img}×{img} frames (primary rays, lit), {threads} thread(s), process CPU time, best of 2 \
         (one at 10⁶ links). *Frame*: build + render, the dynamic-scene cost. Ratios: a model's time over the best \
         fixed λ's (1 = as good as the best of the sweep; below 1 better than all of them). *refs / E(h)*: the \
         frame grid's references over the model's expected count.\n\n\
         | resolution: scene | links | frame model λ | frame build (ms) | frame render (ms) | best fixed λ: frame | \
         best frame (ms) | **frame model / best frame** | static model λ | static model / best frame | λ = 2 / best \
         frame | static model / best render | refs / E(h) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        lams = LAMBDAS.map(|l| l.to_string()).join(", "),
        img = opts.image,
        threads = opts.threads,
        bc = BUILD_COST.per_cell,
        br = BUILD_COST.per_reference,
    );
    let (mut fit_rows, mut worst, mut ns_test) = (Vec::new(), 0.0f64, Vec::new());
    for &links in sizes {
        let reps = if links >= 1_000_000 { 1 } else { 2 };
        let err = |e: tubecast_render::scene::SceneError| ReportError::Render(e.to_string());
        let bundle =
            Scene::from_polylines(&generate::bundle(links.div_ceil(84), 84, opts.seed), 0.12, "b").map_err(err)?;
        let fur =
            Scene::from_polylines(&generate::furball(links.div_ceil(20), 20, opts.seed), 0.06, "f").map_err(err)?;
        for (name, scene) in [("bundle", &bundle), ("furball", &fur)] {
            let st = scene.stats();
            let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, opts.image, opts.image)
                .map_err(|e| ReportError::Render(e.to_string()))?;
            let n = scene.links.len() as f64;
            let at =
                |cells_per_prim, rays_per_build| GridParams { cells_per_prim, rays_per_build, ..Default::default() };
            let stat = measure(scene, &cam, at(None, None), reps, pool)?;
            let frame = measure(scene, &cam, at(None, Some(rays)), reps, pool)?;
            let fixed: Vec<(f64, Point)> = LAMBDAS
                .iter()
                .map(|&l| measure(scene, &cam, at(Some(l), None), reps, pool).map(|m| (l, m)))
                .collect::<Result<_, _>>()?;
            for m in fixed.iter().map(|f| &f.1).chain([&stat, &frame]) {
                fit_rows.push([n, m.cells, m.refs, m.build]);
            }
            if links <= 10_000 {
                ns_test.push(test_ns(&scene.primitives(), opts.seed));
            }
            let best = |key: &dyn Fn(&Point) -> f64| {
                fixed
                    .iter()
                    .min_by(|a, b| key(&a.1).total_cmp(&key(&b.1)))
                    .map(|(l, m)| (*l, key(m)))
                    .unwrap_or((0.0, 1.0))
            };
            let (_, br) = best(&|m| m.trace);
            let (lf, bf) = best(&|m| m.build + m.trace);
            let two = fixed.iter().find(|(l, _)| *l == 2.0).map_or(f64::NAN, |(_, m)| m.build + m.trace);
            worst = worst.max((frame.build + frame.trace) / bf);
            let _ = writeln!(
                md,
                "| {name} | {} | {:.2} | {} | {} | {lf} | {} | **{:.2}** | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
                scene.links.len(),
                frame.lambda,
                fmt_num(frame.build * 1e3),
                fmt_num(frame.trace * 1e3),
                fmt_num(bf * 1e3),
                (frame.build + frame.trace) / bf,
                stat.lambda,
                (stat.build + stat.trace) / bf,
                two / bf,
                stat.trace / br,
                frame.refs_model,
            );
        }
    }
    let [a, b, c] = fit(&fit_rows);
    let ci = ns_test.iter().sum::<f64>() / ns_test.len().max(1) as f64;
    let _ = write!(
        md,
        "\nMaximum frame model / best frame over these rows: **{worst:.2}**.\n\n*Fit of the build costs* (least \
         squares of the build CPU time of all {} grids above ≈ a·N + b·cells + c·references, rows weighted by \
         1/time): a = {} ns per link, b = {} ns per cell, c = {} ns per reference. One primitive test \
         (`Prim::first_hit`, rays through random points of random links' boxes, 10³–10⁴-link scenes, mean of {}) \
         costs C_I = {} ns, so b/C_I = {:.3} and c/C_I = {:.3} against the model's `BUILD_COST` {} and {} (not \
         fitted: the table uses the operation count).\n",
        fit_rows.len(),
        fmt_num(a * 1e9),
        fmt_num(b * 1e9),
        fmt_num(c * 1e9),
        ns_test.len(),
        fmt_num(ci),
        b * 1e9 / ci,
        c * 1e9 / ci,
        BUILD_COST.per_cell,
        BUILD_COST.per_reference,
    );
    Ok(md)
}
