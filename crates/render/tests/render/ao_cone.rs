//! Cone-traced ambient occlusion (`render::ConeAo`) against the ray reference
//! (`render::ray_occlusion`, rays through the BVH's `any_hit` on the exact tubes), in the two
//! configurations where the answer is known exactly, with bounds from the footprint contract
//! of `render/ao.rs` (a sample at axis distance `t` reads 0 unless a tube comes within
//! `reach(t) = max(t·tan θ, √3·h) + h/2` of it; a base voxel whose centre is `h/2` inside a
//! tube reads 1):
//!
//! * **Open** — points on the outside of one straight tube (convex: every outward ray misses,
//!   so the exact occlusion is 0). The tube lies below the tangent plane at `q`, and cone `i`'s
//!   axis point at `t` is `ε + s₀ + t·cos φᵢ` above it; the height minus `reach` is concave in
//!   `t`, so the cone reads only zeros when it is `≥ 0` at `t = 0` and `t = D`. The bound
//!   `B_N` = share of the `N` cones failing that test; cone AO must be `≤ B_N`, and `B_N`
//!   falls to 0 as `N` grows (the cones narrow): the cone estimate converges to the reference.
//! * **Buried** — points inside a dense bundle (parallel tubes of radius 1 on a square lattice
//!   of spacing 1, so every point is within `√2/2` of an axis: at least `1 − √2/2 = 0.29` deep
//!   in one tube). The apex `q + s₀·n` is then so deep that the base voxel containing it
//!   (centre within `√3·h/2` of it) has its centre `≥ 0.29 − √3·h/2 ≥ h/2` inside a tube and
//!   reads 1, so every cone is fully occluded: exactly 1, as every ray (starting inside) is.
//!
//! And never NaN, on generated scenes (bundle, furball) with any point and normal.

use tubecast::V3;
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::render::{cone_axes, ray_occlusion, render, AoMethod, Camera, ConeAo, ConeParams, Options};
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::Scene;

/// Occlusion distance of every case.
const D: f64 = 3.0;

fn tube(a: [f64; 3], b: [f64; 3]) -> Polyline {
    Polyline { points: vec![a, b], radii: vec![] }
}

/// Share of the `n` cones that the "open" argument (module docs) cannot clear, for an apex
/// `eps + s₀` above the tangent plane of a convex solid.
fn open_bound(ao: &ConeAo, n: u32, eps: f64) -> f64 {
    let (axes, tan) = cone_axes(n);
    let (h, s0) = (ao.voxel_size(), ao.apex_offset());
    let clear = |t: f64, cos: f64| eps + s0 + t * cos >= (t * tan).max(3f64.sqrt() * h) + h / 2.0;
    let fail = axes.iter().filter(|a| !(clear(0.0, a[2]) && clear(D, a[2]))).count();
    fail as f64 / n as f64
}

#[test]
fn open_tube_is_unoccluded_within_the_bound_and_the_bound_vanishes() {
    let scene = Scene::from_polylines(&[tube([-20.0, 0.0, 0.0], [20.0, 0.0, 0.0])], 1.0, "t").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let eps = 1e-3;
    let mut rng = Rng::new(5);
    let points: Vec<(V3<f64>, V3<f64>)> = (0..24)
        .map(|_| {
            let (x, a) = (rng.range(-5.0, 5.0), rng.range(0.0, 2.0 * std::f64::consts::PI));
            let n = V3::new(0.0, a.cos(), a.sin());
            (V3::new(x, 0.0, 0.0) + n * (1.0 + eps), n)
        })
        .collect();
    for (k, &(q, n)) in points.iter().enumerate() {
        assert_eq!(ray_occlusion(&bvh, q, n, D, 1024, k as u64), 0.0, "a ray from the convex tube hit it");
    }
    let mut last = f64::INFINITY;
    for cones in [4, 16, 64, 256] {
        let ao = ConeAo::build(&scene, D, &ConeParams { cones, ..ConeParams::default() });
        let bound = open_bound(&ao, cones, eps);
        let worst = points.iter().map(|&(q, n)| ao.occlusion(q, n)).fold(0.0, f64::max);
        println!("N = {cones:3}: bound {bound:.4}, worst cone AO {worst:.4}");
        assert!(worst <= bound, "N = {cones}: cone AO {worst} above the footprint bound {bound}");
        assert!(bound <= last, "the bound must not grow with N");
        last = bound;
    }
    assert_eq!(last, 0.0, "narrow cones clear the open tube entirely");
}

#[test]
fn point_inside_a_dense_bundle_is_fully_occluded() {
    let lines: Vec<Polyline> = (-4..=4)
        .flat_map(|y| (-4..=4).map(move |z| tube([-6.0, y as f64, z as f64], [6.0, y as f64, z as f64])))
        .collect();
    let scene = Scene::from_polylines(&lines, 1.0, "dense").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let mut rng = Rng::new(9);
    for cones in [1, 6, 32] {
        let ao = ConeAo::build(&scene, D, &ConeParams { cones, ..ConeParams::default() });
        // The derivation needs the apex 0.29 − √3·h/2 ≥ h/2 deep: h ≤ 0.21.
        assert!(ao.voxel_size() * (3f64.sqrt() / 2.0 + 0.5) <= 1.0 - 0.5f64.sqrt());
        for k in 0..20 {
            let q = V3::new(rng.range(-1.0, 1.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let n = V3::from(rng.unit());
            assert_eq!(ao.occlusion(q, n), 1.0, "N = {cones}, point {k}");
            assert_eq!(ray_occlusion(&bvh, q, n, D, 64, k), 1.0);
        }
    }
}

#[test]
fn cone_ao_is_never_nan() {
    let bundle = Scene::from_polylines(&generate::bundle(20, 30, 3), 0.12, "b").unwrap();
    let fur = Scene::from_polylines(&generate::furball(60, 20, 4), 0.06, "f").unwrap();
    let empty = Scene::from_polylines(&[], 0.1, "e").unwrap();
    let mut rng = Rng::new(11);
    for (scene, dist) in [(&bundle, 5.0), (&fur, 1.0), (&empty, 1.0), (&fur, 0.0), (&fur, f64::NAN), (&fur, 1e300)] {
        let ao = ConeAo::build(scene, dist, &ConeParams { cones: 8, voxels: 8.0, ..ConeParams::default() });
        let st = scene.stats();
        for k in 0..200 {
            let q = match k % 5 {
                0 => V3::new(f64::NAN, 0.0, 0.0),
                1 => V3::new(1e300, -1e300, 0.0),
                _ if st.is_empty() => V3::from(rng.unit()),
                _ => V3::new(
                    rng.range(st.bounds.0[0], st.bounds.1[0]),
                    rng.range(st.bounds.0[1], st.bounds.1[1]),
                    rng.range(st.bounds.0[2], st.bounds.1[2]),
                ),
            };
            let n = if k % 7 == 0 { V3::new(0.0, 0.0, 0.0) } else { V3::from(rng.unit()) };
            let v = ao.occlusion(q, n);
            assert!((0.0..=1.0).contains(&v), "occlusion {v} at {q:?} {n:?}");
        }
    }
}

#[test]
fn cone_ao_renders_finite_and_only_darkens() {
    let scene = Scene::from_polylines(&generate::bundle(30, 20, 2), 0.3, "b").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let st = scene.stats();
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 48, 32).unwrap();
    let plain = render(&scene, &bvh, &cam, &Options::default()).unwrap();
    let opts = Options { ao: 8, ao_method: AoMethod::Cone, ..Options::default() };
    let cone = render(&scene, &bvh, &cam, &opts).unwrap();
    // Lit shading is 0.25·ambient + 0.75·diffuse·(0.5 + 0.5·ambient) (+ specular, likewise
    // scaled): non-decreasing in ambient ∈ [0, 1], equal at ambient = 1.
    for (a, b) in cone.rgb.iter().zip(&plain.rgb) {
        assert!(a.iter().all(|c| c.is_finite()));
        assert!(a.iter().zip(b).all(|(x, y)| x <= y), "AO brightened a pixel: {a:?} vs {b:?}");
    }
    let sum = |i: &tubecast_render::render::Image| i.rgb.iter().map(|c| (c[0] + c[1] + c[2]) as f64).sum::<f64>();
    assert!(sum(&cone) < sum(&plain), "no pixel darkened in a bundle");
}
