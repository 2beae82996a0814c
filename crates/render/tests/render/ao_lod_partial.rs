//! Kanzler's AO (cones over the LoD opacities of the quantized lines, `ConeAo::from_lod`)
//! against the exact occlusion under a layer of lines, the setting of Kanzler et al.'s shadows.
//!
//! # The scene and its exact occlusion
//! Lines along `x` at height `C = 1`, `y = −Y, −Y + s, …, Y`, `x ∈ [−X, X]` (`X = Y = 4.5`),
//! tubes of radius `r = 0.02` at spacing `s = r ≤ 2r`: every ray that crosses the plane `z = C`
//! at `|x|, |y| ≤ X` is inside a tube there. From `q = 0` (normal `+z`) the ray along `d`
//! crosses it at `t = C/d_z` and horizontal distance `≤ √(D² − C²) = 3.87 < X` while `t ≤ D = 4`;
//! it cannot touch a tube before `z = C − r`. With `d_z² = 1 − u` uniform (cosine-weighted
//! directions), `A* ∈ [1 − (C/D)², 1 − ((C − r)/D)²] = [0.9375, 0.93775]`.
//!
//! # The LoD's opacities here (from its definition, `quantized::lod`)
//! Grid of side `h = D/voxels ≥ 2r`, corner chosen so that `z = C` is the middle of voxel row
//! `k₀ = 2`. Every line crosses each voxel of row `k₀` in its path along `x` with length `h`
//! (its two ends snap to the same bins of opposite faces), and a voxel of that row whose `x`
//! and `y` ranges lie in `[−X, X]` holds `n ≥ ⌊h/s⌋ ≥ h/r − 1` lines, so `α = min(1, 2nr/h) = 1`
//! (as `2 − 2r/h ≥ 1`). No other level-0 voxel holds a segment, and a coarser voxel is non-zero
//! only if it contains a non-zero one.
//!
//! # The bracket at finite N and h
//! With `x(t) = q + s₀n + t·a` along a cone axis `a` and `W(t) = max(h, t·tanθ/√3)` the
//! largest sample voxel (as in `ao_cone_partial.rs`):
//! * **Zero** if every `x(t)`, `t ∈ [0, D]`, is farther than `√3·W(t)` from the box `M` of all
//!   non-zero level-0 voxels, `[−X − h, X + h]² × [C − h/2, C + h/2]`.
//! * **One** if a level-0 sample lands in the box `S = [−X + h, X − h]² × [C − h/2, C + h/2)`
//!   (its voxel is then an opaque one). Level 0 holds while `t·tanθ < 2√3h`, and there the
//!   samples are at `t = k·h` exactly (`t₀ = 0`, steps of `w = h`), so this is checked at those
//!   `t` with a margin of `10⁻⁹` for the rounding of the sums.
//!
//! The zero condition is checked on a grid of step `δ` with the margin `(1 + tanθ)·δ/2`, so
//! `L = #sure ones/N ≤ LoD cone AO ≤ U = #not sure zeros/N`. Once `tanθ ≤ 2√3h/D` the whole
//! cone stays at level 0 and both ends tend to the exact hit fraction as `N → ∞`, `h → 0`.

use tubecast::{Ray, V3};
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::quantized::{Lod, QuantizedLines};
use tubecast_render::render::{cone_axes, ray_occlusion, ConeAo, ConeParams};
use tubecast_render::scene::Scene;

const R: f64 = 0.02;
const C: f64 = 1.0;
const D: f64 = 4.0;
const X: f64 = 4.5;

fn lines() -> Vec<Polyline> {
    let n = (2.0 * X / R).round() as usize;
    (0..=n)
        .map(|k| {
            let y = -X + R * k as f64;
            Polyline { points: vec![[-X, y, C], [X, y, C]], radii: vec![] }
        })
        .collect()
}

fn exact_range() -> (f64, f64) {
    (1.0 - (C / D).powi(2), 1.0 - ((C - R) / D).powi(2))
}

/// The cone axes in world space for `n = +z` (the frame of `render::ao` for `+z`: `b₁ = +y`,
/// `b₂ = −x`) from the published `cone_axes`.
fn axes(n: u32) -> Vec<V3<f64>> {
    cone_axes(n).0.iter().map(|a| V3::new(-a[1], a[0], a[2])).collect()
}

/// Distance from `x` to the box `[−e, e]² × [C − h/2, C + h/2]`; negative inside (minus the
/// depth).
fn box_dist(x: V3<f64>, e: f64, h: f64) -> f64 {
    let out = [x.x.abs() - e, x.y.abs() - e, (x.z - C).abs() - h / 2.0];
    let outside = out.iter().map(|v| v.max(0.0).powi(2)).sum::<f64>().sqrt();
    outside + out.iter().copied().fold(f64::NEG_INFINITY, f64::max).min(0.0)
}

/// `(L, U)` of the module docs.
fn bracket(n: u32, h: f64, s0: f64, tan: f64) -> (f64, f64) {
    let delta = h / 50.0;
    let margin = (1.0 + tan) * delta / 2.0;
    let (mut sure_one, mut maybe) = (0, 0);
    for a in axes(n) {
        let at = |t: f64| V3::new(0.0, 0.0, s0) + a * t;
        let zero = (0..=(D / delta).floor() as usize).all(|i| {
            let t = i as f64 * delta;
            box_dist(at(t), X + h, h) - 3f64.sqrt() * h.max(t * tan / 3f64.sqrt()) > margin
        });
        let full = (0..)
            .map(|k| k as f64 * h)
            .take_while(|&t| t <= D && t * tan < 2.0 * 3f64.sqrt() * h * (1.0 - 1e-9))
            .any(|t| box_dist(at(t), X - h, h) <= -1e-9);
        sure_one += full as usize;
        maybe += !zero as usize;
    }
    (sure_one as f64 / n as f64, maybe as f64 / n as f64)
}

#[test]
fn the_layer_blocks_what_the_analytic_occlusion_says() {
    // 4,096 rays: standard error ≤ 1/128; 4σ = 0.031 around the exact range.
    let scene = Scene::from_polylines(&lines(), R, "layer").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let (lo, hi) = exact_range();
    let q = V3::new(0.0, 0.0, 0.0);
    let ao = ray_occlusion(&bvh, q, V3::new(0.0, 0.0, 1.0), D, 4096, 3);
    assert!(ao >= lo - 0.031 && ao <= hi + 0.031, "ray AO {ao} vs [{lo}, {hi}]");
    // A steep ray between two line axes still meets a tube; a flat one passes under D.
    assert!(bvh.any_hit(&Ray::with_range(q, V3::new(0.3, R / 2.0, 1.0).normalize_or_zero(), 0.0, D)));
    assert!(!bvh.any_hit(&Ray::with_range(q, V3::new(1.0, 0.0, 0.2).normalize_or_zero(), 0.0, D)));
}

#[test]
fn lod_cone_ao_stays_in_its_bracket_which_closes_on_the_exact_occlusion() {
    let lines = lines();
    let (lo, hi) = exact_range();
    let q = V3::new(0.0, 0.0, 0.0);
    let n = V3::new(0.0, 0.0, 1.0);
    let mut devs = Vec::new();
    for (cones, voxels) in [(16u32, 16.0), (64, 16.0), (256, 32.0), (1024, 64.0)] {
        let h = D / voxels;
        assert!(h >= 2.0 * R, "the opacity derivation needs h ≥ 2r");
        let cells = ((2.0 * X + 2.0 * h) / h).ceil() as u32;
        let corner = [-X - h, -X - h, C - 2.5 * h];
        let ql = QuantizedLines::new(&lines, corner, h, [cells, cells, 5], 16);
        let ao = ConeAo::from_lod(&Lod::build(&ql, R), D, &ConeParams { cones, ..ConeParams::default() });
        let (s0, tan) = (ao.apex_offset(), ao.tan_half_angle());
        assert!((ao.voxel_size() - h).abs() < 1e-12 && (s0 - 2.5 * h).abs() < 1e-12);
        if cones == 16 {
            assert!(2.0 * 3f64.sqrt() * h < D * tan, "N = 16 must read the coarse levels");
        }
        let (l, u) = bracket(cones, h, s0, tan);
        let v = ao.occlusion(q, n);
        let dev = (u - lo).max(hi - l);
        println!("N = {cones}, {voxels} voxels/D: L = {l:.4} ≤ LoD cone {v:.4} ≤ U = {u:.4}; |cone − A*| ≤ {dev:.4}");
        assert!(l <= v && v <= u, "N = {cones}, {voxels}/D: LoD cone {v} outside [{l}, {u}]");
        devs.push(dev);
    }
    // Margins of the bracket are linear in h and tanθ, both halved (or more) at each step
    // once the cones stay at level 0 (N ≥ 64 here): the bound on |cone − A*| must not grow,
    // and must fall once it is below its cap 1 − (C/D)² (the first steps can sit at the cap).
    for w in devs.windows(2) {
        assert!(w[1] <= w[0] + 1e-12, "the bracket must not widen: {devs:?}");
    }
    let last = devs.len() - 1;
    assert!(devs[last] <= 0.75 * devs[last - 1], "the bracket must close: {devs:?}");
}
