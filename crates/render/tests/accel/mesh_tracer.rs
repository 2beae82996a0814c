//! The mesh path against the exact kernels: every mesh hit lies within the tracer's bound
//! of the exact surface, every exact hit the mesh misses only grazes the solid (no point of
//! the exact chord deeper than the bound), the transparent-path intervals agree with the
//! closest hit, colouring indexes the scene's primitives, and the exporters write what an
//! independent glTF reader reads back.

use tubecast::{Primitive, Ray, V3};
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::io::Polyline;
use tubecast_render::mesh::{export, tessellate, MeshTracer};
use tubecast_render::scene::{generate, Model, Scene};

fn scene() -> Scene {
    let mut lines = generate::helix(24);
    lines.push(Polyline {
        points: vec![[0.0, 0.0, -3.0], [0.5, 0.2, 0.0], [0.0, 0.0, 3.0]],
        radii: vec![0.3, 0.6, 0.1],
    });
    Scene::from_polylines(&lines, 0.4, "test").unwrap()
}

/// Rays from a ring of eyes through the scene's box.
fn rays(scene: &Scene, n: usize) -> Vec<Ray<f64>> {
    let (lo, hi) = scene.stats().bounds;
    let c = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    let r = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let a = i as f64 * 0.731;
            let eye = c + V3::new(a.cos(), 0.3 * (j as f64 - n as f64 / 2.0) / n as f64, a.sin()) * (2.0 * r);
            let target = c + V3::new((j as f64 / n as f64 - 0.5) * r, ((i * 7 % n) as f64 / n as f64 - 0.5) * r, 0.0);
            out.push(Ray::new(eye, target - eye));
        }
    }
    out
}

fn exact_sdf(scene: &Scene, p: V3<f64>) -> f64 {
    (0..scene.links.len()).map(|k| scene.link(k).sdf(p)).fold(f64::INFINITY, f64::min)
}

#[test]
fn mesh_hits_lie_within_the_bound() {
    let scene = scene();
    for eps in [1e-2, 1e-3] {
        let m = tessellate(&scene, Model::Links, eps).unwrap();
        assert!(m.mesh.certified <= eps);
        let tracer = MeshTracer::build(&m, scene.primitives());
        let exact = Bvh::build(scene.primitives());
        // Rounding: the f64 plane recomputation and the SDF are a few ulps of the scene
        // scale (≤ 10): 1e-12 covers them.
        let tol = tracer.error() + 1e-12;
        let (mut both, mut grazing) = (0, 0);
        for ray in rays(&scene, 40) {
            match (tracer.closest_hit(&ray), exact.closest_hit(&ray)) {
                (Some(h), e) => {
                    let d = exact_sdf(&scene, ray.at(h.t));
                    assert!(d.abs() <= tol, "ε {eps}: mesh hit at sdf {d}");
                    assert!(h.entering && (h.n.length() - 1.0).abs() < 1e-9);
                    assert!((h.id as usize) < tracer.prim_count());
                    both += usize::from(e.is_some());
                }
                (None, Some(e)) => {
                    // The mesh holds the exact solid eroded by its bound: a missed chord is shallow.
                    let iv = scene.link(exact.prim(e.id).link as usize).intersect(&ray);
                    let mid = ray.at(0.5 * (iv.entry.t + iv.exit.t));
                    assert!(exact_sdf(&scene, mid) >= -tol, "ε {eps}: mesh missed a deep chord");
                    grazing += 1;
                }
                (None, None) => {}
            }
        }
        assert!(both > 300, "ε {eps}: {both} rays hit both");
        assert!(grazing * 20 < both, "ε {eps}: {grazing} grazing misses");
    }
}

#[test]
fn intervals_agree_with_the_closest_hit_and_shadow_rays() {
    let scene = scene();
    let m = tessellate(&scene, Model::Splines, 1e-2).unwrap();
    let tracer = MeshTracer::build(&m, scene.spline_primitives().unwrap());
    for ray in rays(&scene, 20) {
        let mut ivs = Vec::new();
        tracer.line_intervals(&ray, &mut ivs);
        let hit = tracer.closest_hit(&ray);
        assert_eq!(hit.is_some(), tracer.any_hit(&ray));
        let first = ivs.iter().map(|t| t.iv.entry.t).filter(|&t| t >= 0.0).fold(f64::INFINITY, f64::min);
        if let Some(h) = hit {
            // Same triangle plane arithmetic on both paths: equal to rounding of t (scene ≤ 10).
            assert!((first - h.t).abs() <= 1e-9 * (1.0 + h.t), "interval entry {first} vs hit {}", h.t);
            assert!(ivs.iter().all(|t| t.iv.entry.t <= t.iv.exit.t && (t.id as usize) < tracer.prim_count()));
        } else {
            assert!(first.is_infinite());
        }
    }
}

#[test]
fn exports_read_back() {
    let scene = scene();
    let m = tessellate(&scene, Model::Links, 1e-2).unwrap();
    let glb = export::glb(&m);
    let g = gltf::Gltf::from_slice(&glb).expect("valid GLB");
    let prim = g.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(prim.indices().unwrap().count(), 3 * m.mesh.triangles.len());
    assert_eq!(prim.get(&gltf::Semantic::Positions).unwrap().count(), m.mesh.positions.len());
    let ply = export::ply(&m);
    let head_end = ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    assert_eq!(ply.len() - head_end, 12 * m.mesh.positions.len() + 13 * m.mesh.triangles.len());
    assert!(export::write(std::path::Path::new("x.stl"), &m).is_err());
}

#[test]
fn bad_tolerances_are_errors() {
    let scene = scene();
    for eps in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-14] {
        assert!(tessellate(&scene, Model::Links, eps).is_err(), "ε {eps}");
    }
}
