//! Cone-traced AO against the exact occlusion on a partly occluded point: a long tube of radius
//! ρ = 0.5 lying at height c = 1 over the shaded point, parallel to its surface.
//!
//! # What the cone AO must approach
//! From `q = 0` with normal `+z`, the ray along the cosine-weighted direction `d` meets the
//! infinite cylinder `{y² + (z − c)² ≤ ρ²}` iff its projection on the `yz` plane points within
//! `±α` of `+z`, `sin α = ρ/c`: `|d_y| ≤ tan α·d_z` ⇔ `d_y² ≤ sin²α·(1 − d_x²)`. Cosine-weighted
//! directions are uniform on the unit disc of `(d_x, d_y)` (Malley), and that region is an
//! ellipse of area `π·sin α`: the occlusion is `ρ/c = 0.5`. With the distance limit `D = 4` a
//! hit counts only if it is within `D`; the entry lies at most `c/√(1 − d_x²)` along the ray, so
//! only directions with `|d_x| > k = √(1 − c²/D²)` can be lost: their measure in the ellipse is
//! `e = sin α·2(acos k − k√(1 − k²))/π = 0.00338`. The tube is a single link from `x = −6` to
//! `6`, and no ray or sample used here reaches `|x| > 5.5`, so it acts as the infinite cylinder.
//! Hence `A* ∈ [0.5 − e, 0.5]`.
//!
//! # The bracket at finite N and h (from the footprint contract of `render::ao`)
//! A cone from the apex `p = q + s₀·n` along axis `a` samples `x(t) = p + t·a` at `t₀ = 0`,
//! `t_{k+1} = t_k + w(t_k)` while `t ≤ D`, with `w(t) ≤ W(t) = max(h, t·tanθ/√3)`.
//! * **Zero** if every `x(t)`, `t ∈ [0, D]`, is farther than `reach(t) = max(t·tanθ, √3h) + h/2`
//!   from the tube (module docs of `render::ao`).
//! * **One** if some sample lies at depth `≥ √3·w + √3·h/2` inside the tube: every base voxel
//!   centre of the level voxel read is then `≥ √3h/2` inside, where the occupancy is exactly 1,
//!   so the sample is opaque. That is sure when the depth condition with `W` holds on an interval
//!   `[t₁, t₂] ⊂ [0, D]` with `t₂ − t₁ ≥ W(t₂)` (a step cannot jump over it).
//!
//! Both conditions are checked on a grid of step `δ` in `t` with the Lipschitz margin
//! `(1 + tanθ)·δ/2` (distances to the axis are 1-Lipschitz in `t`, `W` and `reach` are
//! `tanθ`-Lipschitz at most), so `L = #sure ones/N ≤ cone AO ≤ U = #not sure zeros/N`. As
//! `N → ∞` and `h → 0` both ends tend to the axes' exact hit fraction from `q`, i.e. to `A*`.

use tubecast::{Ray, V3};
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::render::{ray_occlusion, ConeAo, ConeParams};
use tubecast_render::scene::Scene;

const RHO: f64 = 0.5;
const C: f64 = 1.0;
const D: f64 = 4.0;

fn scene() -> Scene {
    let line = Polyline { points: vec![[-6.0, 0.0, C], [6.0, 0.0, C]], radii: vec![] };
    Scene::from_polylines(&[line], RHO, "tube").unwrap()
}

/// The analytic occlusion range `[0.5 − e, 0.5]` (module docs).
fn exact_range() -> (f64, f64) {
    let k = (1.0 - C * C / (D * D)).sqrt();
    let e = RHO / C * 2.0 * (k.acos() - k * (1.0 - k * k).sqrt()) / std::f64::consts::PI;
    (RHO / C - e, RHO / C)
}

/// The cone axes in world space for `n = +z`: the Vogel spiral of `render::ao` (recomputed
/// here), in that module's tangent frame for `+z`, `b₁ = +y`, `b₂ = −x`.
fn axes(n: u32) -> Vec<V3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let r2 = (i as f64 + 0.5) / n as f64;
            let (r, phi) = (r2.sqrt(), golden * i as f64);
            let (a0, a1) = (r * phi.cos(), r * phi.sin());
            V3::new(-a1, a0, (1.0 - r2).sqrt())
        })
        .collect()
}

/// `(L, U)` of the module docs for `n` cones, base voxel `h`, apex offset `s0`.
fn bracket(n: u32, h: f64, s0: f64, tan: f64) -> (f64, f64) {
    let delta = h / 50.0;
    let margin = (1.0 + tan) * delta / 2.0;
    let steps = (D / delta).floor() as usize;
    let (mut sure_one, mut maybe) = (0, 0);
    for a in axes(n) {
        let axis_dist = |t: f64| {
            let x = V3::new(0.0, 0.0, s0) + a * t;
            (x.y * x.y + (x.z - C) * (x.z - C)).sqrt()
        };
        let w = |t: f64| h.max(t * tan / 3f64.sqrt());
        let reach = |t: f64| (t * tan).max(3f64.sqrt() * h) + h / 2.0;
        let (mut run_start, mut full) = (None, false);
        let mut zero = true;
        for i in 0..=steps {
            let t = i as f64 * delta;
            let d = axis_dist(t);
            if d - RHO - reach(t) <= margin {
                zero = false;
            }
            let deep = RHO - d - 3f64.sqrt() * w(t) - 3f64.sqrt() * h / 2.0 >= margin;
            match (deep, run_start) {
                (true, None) => run_start = Some(t),
                (true, Some(t1)) if t - t1 >= w(t) => full = true,
                (false, _) => run_start = None,
                _ => {}
            }
        }
        sure_one += full as usize;
        maybe += !zero as usize;
    }
    (sure_one as f64 / n as f64, maybe as f64 / n as f64)
}

#[test]
fn the_ray_reference_matches_the_analytic_occlusion() {
    // 4,096 rays: standard error ≤ 1/(2·64) = 0.0078; 4σ = 0.031 around [0.5 − e, 0.5].
    let s = scene();
    let bvh = Bvh::build(s.primitives());
    let (lo, hi) = exact_range();
    let ao = ray_occlusion(&bvh, V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 1.0), D, 4096, 11);
    assert!(ao >= lo - 0.031 && ao <= hi + 0.031, "ray AO {ao} vs [{lo}, {hi}]");
    // The tube really is partly in the way: straight up is blocked, sideways open.
    assert!(bvh.any_hit(&Ray::with_range(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 1.0), 0.0, D)));
    assert!(!bvh.any_hit(&Ray::with_range(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 1.0, 0.2), 0.0, D)));
}

#[test]
fn cone_ao_stays_in_its_bracket_which_closes_on_the_exact_occlusion() {
    let s = scene();
    let (lo, hi) = exact_range();
    let q = V3::new(0.0, 0.0, 0.0);
    let n = V3::new(0.0, 0.0, 1.0);
    let mut widths = Vec::new();
    for (cones, voxels) in [(16, 16.0), (64, 32.0), (256, 64.0), (1024, 128.0)] {
        let ao = ConeAo::build(&s, D, &ConeParams { cones, voxels, ..ConeParams::default() });
        let (h, s0, tan) = (ao.voxel_size(), ao.apex_offset(), ao.tan_half_angle());
        assert!((h - D / voxels).abs() < 1e-12, "grid not coarsened: h = {h}");
        let (l, u) = bracket(cones, h, s0, tan);
        let v = ao.occlusion(q, n);
        // The bracket's worst distance to the exact value: the bound on |v − A*|.
        let dev = (u - lo).max(hi - l);
        println!("N = {cones}, {voxels} voxels/D: L = {l:.4} ≤ cone {v:.4} ≤ U = {u:.4}; |cone − A*| ≤ {dev:.4}");
        assert!(l <= v && v <= u, "N = {cones}, {voxels}/D: cone {v} outside [{l}, {u}]");
        widths.push((u - l, dev));
    }
    // Every margin of the bracket (apex offset 2.5h, reach √3h + h/2 and t·tanθ, the depth
    // terms) is linear in h or tanθ, and each step halves both (h ∝ 1/voxels, tanθ ≈ √(2/N)): the
    // width must halve asymptotically; 0.6 leaves room for the finite axis count (steps of 1/N).
    for w in widths.windows(2) {
        assert!(w[1].0 <= w[0].0, "the bracket must not widen: {widths:?}");
    }
    for w in widths[1..].windows(2) {
        assert!(w[1].0 <= 0.6 * w[0].0 && w[1].1 <= 0.6 * w[0].1, "the bracket must close: {widths:?}");
    }
}
