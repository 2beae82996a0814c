//! The grid's automatic resolution (module docs of `accel::grid`, "Resolution"): the root of
//! `N·h³ + (2R + Λ/2)·h² = (3/π)·ρ·V` on hand-solved cubics, and grid dims that do not change
//! when the scene is scaled; and the frame-cost resolution ("Resolution with a build"):
//! hand-solved roots, the static side as the rays per build grow without bound, a coarser grid
//! for fewer rays, dims unchanged by scaling.

use std::f64::consts::PI;
use tubecast_render::accel::grid::{
    frame_voxel_size_for, voxel_size_for, BuildCost, Grid, GridParams, SceneSums, BUILD_COST, STEP_COST,
};
use tubecast_render::io::Polyline;
use tubecast_render::scene::Scene;

/// The box volume whose right-hand side `(3/π)·ρ·V` is `k` at `ρ = 1`.
fn volume_for(k: f64) -> f64 {
    k * PI / 3.0
}

fn sums(count: usize, length: f64, radius: f64) -> SceneSums {
    SceneSums { count, length, radius, ..SceneSums::default() }
}

/// Relative tolerance: Newton stops when its step is below 1e-15·h; the residual's own
/// rounding (a few ulps of k ≤ 100) moves the root by far less than 1e-12 relative.
fn close(h: Option<f64>, want: f64) -> bool {
    h.is_some_and(|h| (h - want).abs() <= 1e-12 * want)
}

#[test]
fn the_root_solves_hand_computed_cubics() {
    // 10·2³ + (2·0.5 + 8/2)·2² = 80 + 20 = 100.
    assert!(close(voxel_size_for(&sums(10, 8.0, 0.5), volume_for(100.0), 1.0), 2.0));
    // Point-like primitives (no length, no radius): h³ = k/N. N = 1, k = 8: h = 2; doubling
    // N gives h³ = 4, the short-link regime's ∛2.
    assert!(close(voxel_size_for(&sums(1, 0.0, 0.0), volume_for(8.0), 1.0), 2.0));
    assert!(close(voxel_size_for(&sums(2, 0.0, 0.0), volume_for(8.0), 1.0), 4f64.cbrt()));
    // Long links: N = 1, Λ = 6 (b = 3), k = 4: 1 + 3 = 4, h = 1. Doubling the links (N = 2,
    // Λ = 12): 2h³ + 6h² = 4 ⇔ (h + 1)(h² + 2h − 2) = 0, h = √3 − 1.
    assert!(close(voxel_size_for(&sums(1, 6.0, 0.0), volume_for(4.0), 1.0), 1.0));
    assert!(close(voxel_size_for(&sums(2, 12.0, 0.0), volume_for(4.0), 1.0), 3f64.sqrt() - 1.0));
    // ρ scales the right-hand side: ρ = 2 at half the volume is the first case again.
    assert!(close(voxel_size_for(&sums(10, 8.0, 0.5), volume_for(50.0), 2.0), 2.0));
    // No primitives, no volume, or a non-finite input: no answer (the grid uses one voxel).
    assert_eq!(voxel_size_for(&sums(0, 1.0, 1.0), 1.0, 1.0), None);
    assert_eq!(voxel_size_for(&sums(1, 1.0, 1.0), 0.0, 1.0), None);
    assert_eq!(voxel_size_for(&sums(1, f64::INFINITY, 1.0), 1.0, 1.0), None);
    assert_eq!(voxel_size_for(&sums(1, 1.0, 1.0), f64::NAN, 1.0), None);
}

/// Six fibres of 12 links each, scaled by `s`, radius `0.1·s`.
fn fibres(s: f64) -> Scene {
    let lines: Vec<Polyline> = (0..6)
        .map(|f| Polyline {
            points: (0..13)
                .map(|k| {
                    let (k, f) = (k as f64, f as f64);
                    [s * k, s * (0.3 * f + 0.2 * (0.7 * k + f).sin()), s * (0.1 * k * f).cos()]
                })
                .collect(),
            radii: vec![],
        })
        .collect();
    Scene::from_polylines(&lines, 0.1 * s, "fibres").unwrap()
}

#[test]
fn scaling_the_scene_keeps_the_grid_dims() {
    // Scaling by a power of two scales every length, the box and the root exactly (IEEE
    // operations commute with it), so the dims must be identical, down to tiny and up to huge
    // scenes; the voxel side scales with the scene.
    let base = Grid::build(fibres(1.0).primitives());
    assert!(base.dims().iter().all(|&d| d > 1), "{:?}", base.dims());
    for s in [2f64.powi(-20), 1.0 / 64.0, 1024.0, 2f64.powi(30)] {
        let g = Grid::build(fibres(s).primitives());
        assert_eq!(g.dims(), base.dims(), "scale {s}");
        assert!((g.voxel_size() / (s * base.voxel_size()) - 1.0).abs() < 1e-12, "scale {s}");
    }
}

#[test]
fn the_grid_covers_its_box_and_the_sums_are_the_links() {
    // Dims are the box extents over the model's side, rounded up, so they cover the scene.
    let scene = fibres(1.0);
    let g = Grid::build(scene.primitives());
    let (lo, hi) = scene.stats().bounds;
    for i in 0..3 {
        let ext = hi[i] - lo[i];
        assert!(g.dims()[i] as f64 * g.voxel_size() >= ext, "axis {i}");
    }
    let s = SceneSums::of(&scene.primitives());
    assert_eq!(s.count, 72);
    // Each link steps 1 in x, |Δy| ≤ 0.2·0.7 = 0.14 and |Δz| ≤ 0.1·5 = 0.5 (sin and cos are
    // 1-Lipschitz), so it is in [1, √(1 + 0.14² + 0.5²) = 1.1268]; the 72 radii are 0.1 each,
    // stored in f32 (relative error ≤ 6e-8).
    assert!(s.length >= 72.0 && s.length <= 72.0 * 1.127, "{s:?}");
    assert!((s.radius - 7.2).abs() < 72.0 * 1e-8, "{s:?}");
}

#[test]
fn scenes_1e_minus_30_and_1e30_across_keep_the_grid_dims() {
    // Beyond the scene loader's limits, so the links are scaled directly (by 2^±100, exact in
    // f64 and in the f32 offsets and radii): the resolution is computed in units of the box
    // diagonal, so neither the box volume (10⁻⁹⁰ or 10⁹⁰) nor the sums under- or overflow it.
    use tubecast::{RoundCone, V3};
    use tubecast_render::scene::Prim;
    let base = fibres(1.0).primitives();
    let scaled = |s: f64| -> Vec<Prim> {
        base.iter()
            .map(|p| {
                let c = p.round_cone().unwrap();
                let o = V3::from(p.origin);
                let (a, b) = ((o + c.a.cast::<f64>()) * s, (o + c.b.cast::<f64>()) * s);
                Prim::from_link(&RoundCone::new(a, c.ra as f64 * s, b, c.rb as f64 * s).unwrap(), p.link)
            })
            .collect()
    };
    let g = Grid::build(base.clone());
    for s in [2f64.powi(-100), 2f64.powi(100)] {
        let h = Grid::build(scaled(s));
        assert_eq!(h.dims(), g.dims(), "scale {s}");
        assert!((h.voxel_size() / (s * g.voxel_size()) - 1.0).abs() < 1e-12, "scale {s}");
    }
}

/// Relative tolerance of the frame-cost bisection: it stops at adjacent floats of `[lo, hi]`
/// (relative width 2⁻⁵²), far below 1e-12.
fn close_frame(h: Option<f64>, want: f64) -> bool {
    h.is_some_and(|h| (h - want).abs() <= 1e-12 * want)
}

#[test]
fn the_root_solves_hand_computed_frames() {
    // Unit cube: V = 1, S = 6, mean chord c̄ = 4V/S = 2/3.
    // A point (N = 1), no step cost, cell cost 1: F′ = −3/h⁴ + n·(2/3)·(π/1)·(h/2) = 0,
    // h⁵ = 9/(nπ); n = 9/(32π) gives h = 2.
    let point = SceneSums { count: 1, ..SceneSums::default() };
    let cells = BuildCost { per_cell: 1.0, per_reference: 0.0 };
    assert!(close_frame(frame_voxel_size_for(&point, 1.0, 6.0, 0.0, &cells, 9.0 / (32.0 * PI)), 2.0));
    // 32 times the rays: h⁵ = 1, h = 1.
    assert!(close_frame(frame_voxel_size_for(&point, 1.0, 6.0, 0.0, &cells, 9.0 / PI), 1.0));
    // A segment of length 4 (Λ = 4, R = 0), reference cost 1 only: E′ = −1.5·4/h², and the
    // ray part (π/V)·(Λ/4 + h/2)·c̄·n: −6/h² + n·(2/3)·π·(1 + h/2) = 0. At h = 2: −1.5 +
    // n·(4π/3) = 0, n = 9/(8π).
    let segment = SceneSums { count: 1, length: 4.0, ..SceneSums::default() };
    let refs = BuildCost { per_cell: 0.0, per_reference: 1.0 };
    assert!(close_frame(frame_voxel_size_for(&segment, 1.0, 6.0, 0.0, &refs, 9.0 / (8.0 * PI)), 2.0));
    // No primitives, no volume or area, no rays: no answer.
    assert_eq!(frame_voxel_size_for(&SceneSums::default(), 1.0, 6.0, 0.25, &BUILD_COST, 1e4), None);
    assert_eq!(frame_voxel_size_for(&point, 0.0, 6.0, 0.25, &BUILD_COST, 1e4), None);
    assert_eq!(frame_voxel_size_for(&point, 1.0, 0.0, 0.25, &BUILD_COST, 1e4), None);
    assert_eq!(frame_voxel_size_for(&point, 1.0, 6.0, 0.25, &BUILD_COST, 0.0), None);
    assert_eq!(frame_voxel_size_for(&point, 1.0, 6.0, 0.25, &BUILD_COST, f64::NAN), None);
}

fn with_rays(n: Option<f64>) -> GridParams {
    GridParams { rays_per_build: n, ..GridParams::default() }
}

#[test]
fn many_rays_per_build_give_the_static_side() {
    // F′/n = (per-ray slope) + B′/n: at n = 10¹⁵ the build moves the root by
    // −B′/(n·r″) ≈ 10⁻¹⁵ relative to terms of order one; 10⁻⁹ leaves room for the bisection.
    let s = SceneSums::of(&fibres(1.0).primitives());
    let (v, area) = (12.0 * 3.0 * 2.0, 2.0 * (12.0 * 3.0 + 3.0 * 2.0 + 2.0 * 12.0));
    let h_static = voxel_size_for(&s, v, STEP_COST).unwrap();
    let h = frame_voxel_size_for(&s, v, area, STEP_COST, &BUILD_COST, 1e15).unwrap();
    assert!((h / h_static - 1.0).abs() < 1e-9, "{h} vs static {h_static}");
    // Through the grid: the same voxel side as the default (static) grid.
    let (g, g0) =
        (Grid::build_with(fibres(1.0).primitives(), &with_rays(Some(1e15))), Grid::build(fibres(1.0).primitives()));
    assert!((g.voxel_size() / g0.voxel_size() - 1.0).abs() < 1e-9);
    assert_eq!(g.dims(), g0.dims());
}

#[test]
fn fewer_rays_per_build_give_a_coarser_grid() {
    // B′ < 0 everywhere, so the root lies above the static side and rises as n falls.
    let s = SceneSums::of(&fibres(1.0).primitives());
    let (v, area) = (72.0, 168.0);
    let h_static = voxel_size_for(&s, v, STEP_COST).unwrap();
    let mut last = h_static;
    for n in [1e9, 1e6, 1e4, 1e2] {
        let h = frame_voxel_size_for(&s, v, area, STEP_COST, &BUILD_COST, n).unwrap();
        assert!(h > last, "{n} rays: {h} not above {last}");
        last = h;
    }
    let cells = |g: &Grid| g.dims().iter().map(|&d| d as u64).product::<u64>();
    let mut last = cells(&Grid::build(fibres(1.0).primitives()));
    for n in [1e6, 1e3, 10.0] {
        let g = Grid::build_with(fibres(1.0).primitives(), &with_rays(Some(n)));
        assert!(cells(&g) <= last, "{n} rays: {:?}", g.dims());
        last = cells(&g);
    }
    assert!(last < cells(&Grid::build(fibres(1.0).primitives())), "10 rays per build still at the static grid");
}

#[test]
fn scaling_the_scene_keeps_the_frame_grid_dims() {
    // In units of the box diagonal (exact for powers of two), as the static rule.
    let base = Grid::build_with(fibres(1.0).primitives(), &with_rays(Some(65536.0)));
    for s in [2f64.powi(-20), 1.0 / 64.0, 1024.0, 2f64.powi(30)] {
        let g = Grid::build_with(fibres(s).primitives(), &with_rays(Some(65536.0)));
        assert_eq!(g.dims(), base.dims(), "scale {s}");
        assert!((g.voxel_size() / (s * base.voxel_size()) - 1.0).abs() < 1e-12, "scale {s}");
    }
}
