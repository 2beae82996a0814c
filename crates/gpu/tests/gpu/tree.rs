//! The tree walk on the GPU against the CPU's wide BVH over the same primitives, on generated
//! scenes (a furball, a bundle, Han's neuron assembly) and on the shipped files
//! (`reference/readers/nibabel/standard.trk`, an SWC tree).
//!
//! Error analysis (the `scene` module docs of the crate derive it): a GPU hit point lies within
//! `E + δ` of its primitive's exact surface, `E` the stable kernel's bound for that primitive
//! and local ray (`tubecast_oracle::link_error_bound`, ε = 2⁻²³) and `δ = GpuScene::band()` the
//! `f32` move to the local origin. So the checks are:
//! * the GPU tree walk equals the GPU brute force bit for bit (the culling is conservative and
//!   ties are decided by one rule, so only the visiting order differs);
//! * each GPU hit point is within `E + E₆₄ + δ` of the surface of the primitive it names;
//! * GPU and CPU agree on hit/miss, and on `t` within `(E_gpu + E_cpu + 2δ)/(γ·|d|)` (`γ` the
//!   incidence cosine), except where the line passes within `2E + δ` of the surface of the
//!   primitive only one of them hit first (a graze), or the crossing lies within that
//!   tolerance of the ray's range ends.

use crate::{bound, link_of, ov};
use std::path::Path;
use tubecast::{Hit, Ray, V3};
use tubecast_gpu::{Gpu, GpuScene, Walk};
use tubecast_oracle::{sweep_dist, Line};
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::{Model, Prim, Scene};

/// A ray aimed near a random node: from 40 away (`k` even) or from the node itself.
fn aim(rng: &mut Rng, scene: &Scene, k: usize) -> Ray<f64> {
    let p = crate::near_node(rng, scene);
    let d = V3::from(rng.unit()) * rng.range(0.5, 2.0);
    let o = if k.is_multiple_of(2) { p - d * (40.0 / d.length()) } else { p };
    Ray::with_range(o, d, 0.0, 60.0)
}

/// Compare the GPU with the CPU on `n` rays into `scene`; returns (rays, hits, worst
/// |Δt|·|d|/(E + δ) over agreeing hits).
pub(crate) fn compare(gpu: &Gpu, scene: &Scene, n: usize, name: &str) -> (usize, usize, f64) {
    compare_with(gpu, scene, &WideBvh::from_scene(scene, Model::Links).unwrap(), n, name)
}

/// [`compare`] on a given tree over `scene`'s primitives (links, spheres or spline pieces: `E`
/// and the gap are [`crate::bound`]'s and [`crate::gap`]'s), the tree walk also held to the GPU
/// brute force bit for bit.
pub(crate) fn compare_with(gpu: &Gpu, scene: &Scene, bvh: &WideBvh, n: usize, name: &str) -> (usize, usize, f64) {
    let gs = GpuScene::upload(gpu, bvh).unwrap();
    let delta = gs.band();
    let mut rng = Rng::new(7);
    let rays: Vec<Ray<f64>> = (0..n).map(|k| aim(&mut rng, scene, k)).collect();
    let tree = gs.closest_hits(&rays, Walk::Tree).unwrap();
    // Brute force is O(rays × items): a prefix of the rays suffices to check the walk.
    let brute = gs.closest_hits(&rays[..n.min(1500)], Walk::Brute).unwrap();
    let eps = f64::from(f32::EPSILON);
    let (mut hits, mut worst) = (0, 0.0f64);
    for (k, ray) in rays.iter().enumerate() {
        let g = tree[k];
        if let Some(&b) = brute.get(k) {
            let key = |h: Option<Hit<f64>>| h.map(|h| (h.t.to_bits(), h.id));
            let c = bvh.closest_hit(ray);
            assert_eq!(key(g), key(b), "{name} ray {k}: tree walk {g:?} != brute force {b:?} (CPU {c:?})");
        }
        let c = bvh.closest_hit(ray);
        let len = ray.d.length();
        let line = Line { o: ov(ray.o), d: ov(ray.d) };
        if let Some(g) = g {
            hits += 1;
            let p = bvh.prim(g.id);
            // (Spline pieces: the kernel test judges their crossings against the oracle.)
            if p.quad().is_none() {
                let e = bound(&p, ray, eps) + bound(&p, ray, f64::EPSILON) + delta;
                let (sd, _) = sweep_dist(&link_of(&p), ov(ray.at(g.t)));
                assert!(sd.abs() <= e, "{name} ray {k}: GPU hit point {sd:e} off its surface (E + δ = {e:e})");
            }
        }
        // Within the band of primitive `p`: the line's gap to it, or the crossing's distance
        // to the range ends.
        let grazes = |p: &Prim, t: f64, tol: f64| {
            crate::gap(p, &line).abs() <= tol
                || (t - ray.t_min).abs() * len <= tol
                || (t - ray.t_max).abs() * len <= tol
        };
        match (g, c) {
            (None, None) => {}
            (Some(h), None) | (None, Some(h)) => {
                let p = bvh.prim(h.id);
                let tol = 2.0 * bound(&p, ray, eps) + delta;
                assert!(grazes(&p, h.t, tol), "{name} ray {k}: GPU {g:?}, CPU {c:?}, outside the band {tol:e}");
            }
            (Some(g), Some(c)) => {
                let (pg, pc) = (bvh.prim(g.id), bvh.prim(c.id));
                let e = bound(&pg, ray, eps) + bound(&pc, ray, eps) + 2.0 * delta;
                let gamma = c.n.dot(ray.d * (1.0 / len)).abs();
                let dt = (g.t - c.t).abs() * len;
                if dt * gamma <= e {
                    worst = worst.max(dt * gamma / e);
                } else {
                    // The earlier hit's primitive was grazed by the side that went past it.
                    let (early, t) = if g.t < c.t { (&pg, g.t) } else { (&pc, c.t) };
                    let tol = 2.0 * bound(early, ray, eps) + delta;
                    assert!(
                        grazes(early, t, tol),
                        "{name} ray {k}: GPU {g:?}, CPU {c:?}: Δt·γ·|d| {:e} > {e:e}",
                        dt * gamma
                    );
                }
            }
        }
    }
    eprintln!(
        "{name}: {n} rays, {hits} GPU hits, {} bytes uploaded, δ = {delta:e}, worst |Δt|·γ·|d|/(E + δ) {worst:.3}",
        gs.bytes()
    );
    (n, hits, worst)
}

#[test]
fn tree_walk_matches_the_cpu_on_generated_scenes() {
    let Some(gpu) = crate::gpu("tree_walk_matches_the_cpu_on_generated_scenes") else { return };
    let mut lines = generate::furball(150, 12, 2);
    lines.extend(generate::helix(30));
    let fur = Scene::from_polylines(&lines, 0.05, "furball").unwrap();
    let (_, hits, _) = compare(&gpu, &fur, 6000, "furball");
    assert!(hits > 1000, "{hits} hits");
    let bundle = Scene::from_polylines(&generate::bundle(60, 20, 3), 0.02, "bundle").unwrap();
    compare(&gpu, &bundle, 4000, "bundle");
    let bases: Vec<_> = (0..2).map(generate::base_neuron).collect();
    let neurons = Scene::from_swc(&generate::neurons(2, &bases, 5), "neurons").unwrap();
    let (_, hits, _) = compare(&gpu, &neurons, 6000, "neurons");
    assert!(hits > 500, "{hits} hits");
}

#[test]
fn tree_walk_matches_the_cpu_on_shipped_files() {
    let Some(gpu) = crate::gpu("tree_walk_matches_the_cpu_on_shipped_files") else { return };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for (file, radius) in
        [("reference/readers/nibabel/standard.trk", 0.2), ("crates/cli/tests/data/simplify/tree.simplified.swc", 0.5)]
    {
        let scene = Scene::load(&root.join(file), radius).unwrap();
        compare(&gpu, &scene, 4000, file);
    }
}

#[test]
fn any_hit_agrees_with_closest_hit() {
    let Some(gpu) = crate::gpu("any_hit_agrees_with_closest_hit") else { return };
    let scene = Scene::from_polylines(&generate::bundle(40, 10, 9), 0.05, "bundle").unwrap();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    let mut rng = Rng::new(3);
    let rays: Vec<Ray<f64>> = (0..4000).map(|k| aim(&mut rng, &scene, k)).collect();
    let any = gs.any_hits(&rays).unwrap();
    let closest = gs.closest_hits(&rays, Walk::Tree).unwrap();
    for (k, (a, c)) in any.iter().zip(&closest).enumerate() {
        assert_eq!(*a, c.is_some(), "ray {k}");
    }
    assert!(any.iter().filter(|&&a| a).count() > 500);
}

#[test]
fn empty_scene_misses() {
    let Some(gpu) = crate::gpu("empty_scene_misses") else { return };
    let scene = Scene::from_polylines(&[], 0.1, "empty").unwrap();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    let ray = Ray::new(V3::new(0.0, 0.0, -1.0), V3::new(0.0, 0.0, 1.0));
    assert_eq!(gs.closest_hits(&[ray], Walk::Tree).unwrap(), vec![None]);
    assert_eq!(gs.any_hits(&[ray]).unwrap(), vec![false]);
}

#[test]
fn hit_table_rows_are_the_gpu_hits() {
    let Some(gpu) = crate::gpu("hit_table_rows_are_the_gpu_hits") else { return };
    let scene = Scene::from_polylines(&generate::bundle(20, 10, 4), 0.05, "bundle").unwrap();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    let mut rng = Rng::new(11);
    let rays: Vec<Ray<f64>> = (0..500).map(|k| aim(&mut rng, &scene, k)).collect();
    let rows = tubecast_gpu::closest_table_gpu(&gs, &bvh, &rays).unwrap();
    let hits = gs.closest_hits(&rays, Walk::Tree).unwrap();
    for (row, hit) in rows.iter().zip(&hits) {
        match hit {
            Some(h) => assert_eq!((row[0], row[5]), (h.t, f64::from(bvh.prim(h.id).link))),
            None => assert_eq!(*row, tubecast_render::accel::MISS_ROW),
        }
    }
    assert!(hits.iter().filter(|h| h.is_some()).count() > 100);
}

/// A scene 10⁶ from the world origin: the GPU moves rays in `f32` relative to the tree centre,
/// so its band `δ` scales with the scene's size, not with its distance from the origin.
#[test]
fn tree_walk_matches_the_cpu_far_from_the_origin() {
    let Some(gpu) = crate::gpu("tree_walk_matches_the_cpu_far_from_the_origin") else { return };
    let mut lines = generate::bundle(40, 20, 8);
    for l in &mut lines {
        for p in &mut l.points {
            *p = [p[0] + 1.0e6, p[1] - 2.0e6, p[2] + 5.0e5];
        }
    }
    let scene = Scene::from_polylines(&lines, 0.05, "far bundle").unwrap();
    let (_, hits, _) = compare(&gpu, &scene, 3000, "far bundle");
    assert!(hits > 1000, "{hits} hits");
}

/// Spheres (links stored as their larger end sphere) and the primitives stored whole
/// (`WideBvh::build`, no clusters) go through the same walk.
#[test]
fn tree_walk_matches_the_cpu_with_spheres_stored_whole() {
    use tubecast_render::io::Polyline;
    use tubecast_render::scene::PrimKind;
    let Some(gpu) = crate::gpu("tree_walk_matches_the_cpu_with_spheres_stored_whole") else { return };
    // Chains whose radius jumps so that one end sphere swallows the next: stored as spheres.
    let mut rng = Rng::new(5);
    let lines: Vec<Polyline> = (0..200)
        .map(|_| {
            let c = V3::from(rng.unit()) * 10.0;
            let points: Vec<[f64; 3]> =
                (0..6).map(|i| (c + V3::new(0.3 * f64::from(i), 0.0, 0.0)).to_array()).collect();
            let radii = (0..6).map(|i| if i % 2 == 0 { 0.5 } else { 0.1 }).collect();
            Polyline { points, radii }
        })
        .collect();
    let scene = Scene::from_polylines(&lines, 0.1, "beads").unwrap();
    let prims = scene.primitives();
    let spheres = prims.iter().filter(|p| p.kind() == PrimKind::Sphere).count();
    assert!(spheres > 100, "{spheres} spheres");
    let bvh = WideBvh::build(prims);
    let (_, hits, _) = compare_with(&gpu, &scene, &bvh, 3000, "beads");
    assert!(hits > 1000, "{hits} hits");
}
