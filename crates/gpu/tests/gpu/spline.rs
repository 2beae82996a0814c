//! The WGSL spline piece kernel (`shaders/spline.wgsl`) against the CPU's `f32` kernel with its
//! default solver (`Solver::Polynomial`) on the spline accuracy generators: the length/radius
//! sweep's families (`tubecast_oracle::thin_case`: thin/long up to `L/r = 10⁴`, far origin,
//! grazing, pinched, taper, cusp, bulge, inside, scales, direction ratios) and the stability
//! report's regions (`tubecast_oracle::spline_case`).
//!
//! Error analysis. The CPU kernel's interval is, up to a shift of at most `E` along the ray,
//! exactly the interval of a tube whose radius is within `E` of the given one, with
//! `E = 1024·ε·R + 8·ε·|o − p(½)|` (`tubecast::spline_error_band`, derived in
//! `src/kernel/spline.rs`, "Conditioning"; `ε = 2⁻²³`). That derivation bounds each rounding of
//! the formulas, not the path that reaches them: the WGSL runs the same formulas (the
//! Polynomial solver's cascade path for every ray, where the CPU takes its certified count
//! first when it can: both are held to the same band by the kernel's own tests), and an
//! adapter whose division or square root is a few ulps off perturbs each operation by a few
//! `ε`, inside the factor the bound leaves. So the GPU answer is judged as the CPU's is
//! (`tests/splines/conditioning.rs`): a hit only where the tube inflated by `E` is hit,
//! a hit wherever the tube deflated by `E` is hit, entry and exit between the inflated and
//! deflated tubes' (± `E` along the ray), by the independent thin-tube oracle
//! (`tubecast_oracle::quad_crossing_offset`). Then GPU and CPU agree on hit/miss wherever the
//! line is outside the band (the deflated tube hit, or the inflated one missed), and their `t`
//! lie in one bracket of that width.

use tubecast::{Interval, QuadTube, Ray, Solver, V3};
use tubecast_gpu::kernel::{Local, Pairs};
use tubecast_oracle::{
    quad_crossing_offset, report_spline_case, thin_case, ThinCase, Vec3, SPLINE_REGIONS, THIN_FAMILIES,
};

fn v32(v: Vec3) -> V3<f32> {
    V3::new(v.x as f32, v.y as f32, v.z as f32)
}

/// What is wrong with a kernel answer `got` (hit: entry, exit) on case `c` for the band `e`,
/// if anything; and whether the case lies outside the band (hit/miss then decided).
fn judge(got: Option<(f64, f64)>, c: &ThinCase, e: f64) -> (Option<String>, bool) {
    let infl = quad_crossing_offset(&c.tube, &c.ray, e);
    let defl = quad_crossing_offset(&c.tube, &c.ray, -e);
    let dt = e / c.ray.d.length();
    let decided = infl.is_none() || defl.is_some();
    let wrong = match (got, infl, defl) {
        (Some(g), None, _) => Some(format!("phantom hit {g:?}: the tube inflated by E misses")),
        (None, _, Some(w)) => Some(format!("false miss: the tube deflated by E is hit at {w:?}")),
        (Some((ti, to)), Some((ai, ao)), defl) => {
            let (bi, bo) = defl.unwrap_or((f64::INFINITY, -f64::INFINITY));
            let ok = ti >= ai - dt && to <= ao + dt && ti <= bi + dt && to >= bo - dt && ti <= to + 2.0 * dt;
            (!ok).then(|| format!("{ti} {to} outside [{ai}, {bi}] / [{bo}, {ao}] ± {dt}"))
        }
        _ => None,
    };
    (wrong, decided)
}

fn answer(iv: &Interval<f32>) -> Option<(f64, f64)> {
    iv.hit.then(|| (f64::from(iv.entry.t), f64::from(iv.exit.t)))
}

/// The spline accuracy generators' cases that the `f32` kernel takes: name, case, the `f32`
/// tube and the `f32` ray. Segments the f32 kernel refuses (extents whose square overflows it:
/// the Scale family's largest) are left out, as the CPU refuses them too.
fn accuracy_cases() -> Vec<(String, ThinCase, QuadTube<f32>, Ray<f32>)> {
    let mut cases = Vec::new();
    for family in THIN_FAMILIES {
        for ratio in [1.0, 1e1, 1e2, 1e3, 1e4] {
            for seed in 0..8 {
                cases.push((format!("{family:?} L/r={ratio:e} seed {seed}"), thin_case(seed, ratio, family)));
            }
        }
    }
    for region in SPLINE_REGIONS {
        // The stability report's cases at seed 1.
        for i in 0..60 {
            let c = ThinCase::from(&report_spline_case(1, region, i));
            cases.push((format!("{region:?} case {i}"), c));
        }
    }
    let mut kept = Vec::new();
    for (name, c) in cases {
        let Ok(tube) = QuadTube::new(c.tube.b.map(v32), c.tube.r.map(|x| x as f32)) else { continue };
        let ray = Ray::new(v32(c.ray.o), v32(c.ray.d));
        kept.push((name, c, tube, ray));
    }
    kept
}

#[test]
fn spline_kernel_within_the_band_of_the_cpu() {
    let Some(gpu) = crate::gpu("spline_kernel_within_the_band_of_the_cpu") else { return };
    let pairs = Pairs::new(&gpu).unwrap();
    let kept = accuracy_cases();
    let prims: Vec<Local> = kept.iter().map(|k| Local::Spline(k.2)).collect();
    let rays: Vec<Ray<f32>> = kept.iter().map(|k| k.3).collect();
    let got = pairs.line_intervals(&gpu, &prims, &rays).unwrap();
    let eps = f64::from(f32::EPSILON);
    let (mut bad, mut same_bits, mut hits, mut decided_n) = (Vec::new(), 0, 0, 0);
    for ((name, c, tube, ray), g) in kept.iter().zip(&got) {
        let cpu = tube.line_interval_with(ray, Solver::Polynomial);
        let e = tubecast::spline_error_band(eps, c.extent, c.origin_dist);
        let (wrong, decided) = judge(answer(g), c, e);
        if let Some(why) = wrong {
            bad.push(format!("{name}: GPU {why}\n  gpu {g:?}\n  cpu {cpu:?}\n  {c:?}"));
        }
        if decided {
            decided_n += 1;
            if g.hit != cpu.hit {
                bad.push(format!("{name}: hit/miss differs outside the band: gpu {g:?} cpu {cpu:?}"));
            }
        }
        hits += usize::from(g.hit);
        same_bits += usize::from(g.hit == cpu.hit && (!g.hit || (g.entry.t == cpu.entry.t && g.exit.t == cpu.exit.t)));
    }
    eprintln!(
        "spline kernel: {} cases ({hits} GPU hits, {decided_n} outside the band), {same_bits} bit-identical to the CPU's",
        kept.len()
    );
    assert!(kept.len() > 600 && hits > 200, "{} cases, {hits} hits", kept.len());
    assert!(bad.is_empty(), "{} failures:\n{}", bad.len(), bad.join("\n"));
}

/// The tree tests' spline scene: a small furball and bundle with the `--splines` model, and its
/// wide tree (which must hold spline pieces, or the tests would compare links only).
fn spline_scene() -> (tubecast_render::scene::Scene, tubecast_render::accel::WideBvh) {
    use tubecast_render::accel::{Tracer, WideBvh};
    use tubecast_render::scene::{generate, Model, Scene};
    let mut lines = generate::furball(40, 12, 2);
    lines.extend(generate::bundle(20, 12, 3));
    let scene = Scene::from_polylines(&lines, 0.05, "furball").unwrap();
    let bvh = WideBvh::from_scene(&scene, Model::Splines).unwrap();
    assert!((0..bvh.prim_count() as u32).any(|i| bvh.prim(i).quad().is_some()), "no spline pieces");
    (scene, bvh)
}

/// Spline pieces through the tree: a generated bundle and furball with the `--splines` model,
/// GPU closest hits against the CPU tracer's (the tree test's checks, with [`crate::bound`]'s
/// spline `E`) and the tree walk against the GPU brute force, bit for bit. The brute force runs
/// in item ranges (`GpuScene::closest_hits` with `Walk::Brute`): over all of this scene's spline
/// pieces at once, lavapipe's loop budget ran out and it found no hits at all
/// (`shaders/tree.wgsl`'s `loops_cut`).
#[test]
fn spline_tree_walk_matches_the_cpu() {
    let Some(gpu) = crate::gpu("spline_tree_walk_matches_the_cpu") else { return };
    let (fur, bvh) = spline_scene();
    let (_, hits, _) = crate::tree::compare_with(&gpu, &fur, &bvh, 200, "furball, splines");
    assert!(hits > 80, "{hits} hits");
}

/// `render --splines --device gpu` against the CPU render of the shipped tractogram, by the
/// render test's per-pixel tolerance (`tests/gpu/render.rs`) with the spline `E`: opaque, with
/// a shadow ray and AO, and transparent (the union boundaries of the spline pieces' exact line
/// pieces, `GpuScene::line_intervals`).
#[test]
fn gpu_render_matches_the_cpu_with_splines() {
    use std::path::Path;
    use tubecast_render::scene::{Model, Scene};
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = Scene::load(&root.join("reference/readers/nibabel/standard.trk"), 0.2).unwrap();
    crate::render::check_model(&scene, Model::Splines, true, "standard.trk, splines");
}

/// `intersect --splines --query piece` on the GPU: the first union component of the spline
/// pieces against the CPU's `first_component`, on rays from outside and from inside the tubes,
/// by the piece test's band (`tests/gpu/piece.rs`) with [`crate::bound`]'s spline `E` (twice
/// the kernel's band): each boundary is a crossing of one piece within `E` of its surface, so
/// GPU and CPU boundaries of one component differ along the ray by at most
/// `(E_gpu + E_cpu + 2δ)/γ`, or more only at a near-touch. Ray 92 here once found no
/// component on lavapipe: it ran beside a ray whose component chains through many pieces, and
/// the two spent the driver's loop budget (`shaders/tree.wgsl`'s `loops_cut`).
#[test]
fn first_piece_matches_the_cpu_with_splines() {
    let Some(gpu) = crate::gpu("first_piece_matches_the_cpu_with_splines") else { return };
    let (scene, bvh) = spline_scene();
    let (both, near_touch) = crate::piece::compare_first_pieces(&gpu, &scene, &bvh, 300, 23, "splines");
    eprintln!("first piece, splines: {both} of 300 rays hit on both; {near_touch} boundaries at near-touches");
    assert!(both > 100, "{both}");
}

/// The exact pieces (`shaders/spline.wgsl`'s `spline_pieces`, the CPU's
/// `QuadTube::intersect_pieces` with `Solver::Polynomial`: one interval per real interval of `g`)
/// against the CPU's on the accuracy generators' cases, on the whole line. By the error analysis
/// in the module docs each piece is, up to a shift of `E` along the ray, a piece of a tube whose
/// radius is within `E` of the given one, on either side. So:
/// * the hull of the GPU's pieces is judged as the hull is (the oracle's inflated and deflated
///   tubes), hit/miss equal to the CPU's outside the band;
/// * outside the band the pieces pair up with the CPU's, in order along the line, and each
///   GPU boundary lies within `(2E + 2E)/γ` of the CPU's along the line (`|d| = 1`): each is
///   within `2E` of the exact surface across it (`E` across, `E` along the ray: the piece
///   test's `crate::bound`), and a surface point moved by `e` across the surface moves by
///   `e/γ` along a line that crosses it at cosine `γ` (the CPU normal's with `d`). Inside the
///   band a piece may be missing or split on one side (a graze or a near-touch of two pieces).
#[test]
fn spline_pieces_match_the_cpu() {
    let Some(gpu) = crate::gpu("spline_pieces_match_the_cpu") else { return };
    let pairs = Pairs::new(&gpu).unwrap();
    let kept = accuracy_cases();
    let tubes: Vec<QuadTube<f32>> = kept.iter().map(|k| k.2).collect();
    // The whole line, as the tree takes each piece's line interval (`Prim::pieces`).
    let rays: Vec<Ray<f32>> =
        kept.iter().map(|k| Ray::with_range(k.3.o, k.3.d, f32::NEG_INFINITY, f32::INFINITY)).collect();
    let got = pairs.spline_pieces(&gpu, &tubes, &rays).unwrap();
    let eps = f64::from(f32::EPSILON);
    let sorted = |ivs: &[Interval<f32>; 5]| {
        let mut v: Vec<Interval<f32>> = ivs.iter().filter(|iv| iv.hit).copied().collect();
        v.sort_by(|a, b| a.entry.t.total_cmp(&b.entry.t));
        v
    };
    let (mut bad, mut pieces, mut multi, mut same_bits, mut worst) = (Vec::new(), 0, 0, 0, 0.0f64);
    for ((name, c, tube, _), (ray, g)) in kept.iter().zip(rays.iter().zip(&got)) {
        let cpu = tube.intersect_pieces(ray, Solver::Polynomial);
        let (gs, cs) = (sorted(g), sorted(&cpu));
        let e = tubecast::spline_error_band(eps, c.extent, c.origin_dist);
        let hull = gs.iter().fold(Interval::miss(), |h: Interval<f32>, p| h.hull(*p));
        let (wrong, decided) = judge(answer(&hull), c, e);
        if let Some(why) = wrong {
            bad.push(format!("{name}: GPU pieces' hull {why}\n  gpu {gs:?}\n  cpu {cs:?}"));
        }
        pieces += gs.len();
        multi += usize::from(gs.len() > 1);
        same_bits += usize::from(gs.len() == cs.len() && gs.iter().zip(&cs).all(|(a, b)| answer(a) == answer(b)));
        if !decided {
            continue;
        }
        if gs.len() != cs.len() {
            bad.push(format!(
                "{name}: {} GPU pieces, {} CPU pieces outside the band\n  gpu {gs:?}\n  cpu {cs:?}",
                gs.len(),
                cs.len()
            ));
            continue;
        }
        let dn = f64::from(ray.d.length());
        for (a, b) in gs.iter().zip(&cs) {
            for (x, y) in [(a.entry, b.entry), (a.exit, b.exit)] {
                let gamma = f64::from(y.n.dot(ray.d)).abs() / dn;
                let off = f64::from(x.t - y.t).abs() * dn * gamma.max(1e-12);
                worst = worst.max(off / e);
                if off > 4.0 * e {
                    bad.push(format!(
                        "{name}: GPU boundary {} CPU {} apart {off:e} across > 4E = {:e}",
                        x.t,
                        y.t,
                        4.0 * e
                    ));
                }
            }
        }
    }
    eprintln!(
        "spline pieces: {} cases, {pieces} GPU pieces ({multi} cases with several), {same_bits} cases bit-identical \
         to the CPU's; largest boundary offset across the surface {worst:.3}·E (allowed 4E)",
        kept.len()
    );
    assert!(pieces > 200 && multi > 5, "{pieces} pieces, {multi} cases with several: the test says little");
    assert!(bad.is_empty(), "{} failures:\n{}", bad.len(), bad.join("\n"));
}
