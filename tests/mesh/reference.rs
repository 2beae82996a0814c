//! Our certified meshes against the manifold3d meshes of the same tubes (`reference/`): at
//! the error manifold3d's mesh reaches (its measured sagitta `h`, one-sided; plus the chord
//! error of its sampled spline), our mesh is certified to that error **both ways**, and the
//! exact points of the fixtures (numpy, independent of this crate: first hits on the true
//! surface, points at a known signed distance) confirm it: every exact boundary point is
//! within ε of our mesh, and outside points keep their distance to within ε.

use crate::common::MeshDist;
use crate::fixtures::{load, Scene};
use tubecast::{tessellate_link, tessellate_spline, Mesh};

/// Rounding: numpy's exact points are within a few ulps of the scene scale (≤ 10) of the true
/// surface, our vertices likewise; 64 ulps of 10 covers both.
const SLACK: f64 = 64.0 * f64::EPSILON * 10.0;

fn our_mesh(scene: &Scene, eps: f64) -> Mesh {
    let mut mesh = Mesh::default();
    match scene {
        Scene::Links(links) => links.iter().for_each(|l| mesh.append(&tessellate_link(l, eps).unwrap())),
        Scene::Spline(q) => mesh = tessellate_spline(&[*q], eps).unwrap(),
    }
    mesh
}

fn check(name: &str) {
    let fx = load(name);
    let eps = fx.mesh.sagitta + fx.mesh.chord_error;
    let mesh = our_mesh(&fx.scene, eps);
    assert!(mesh.certified <= eps);
    eprintln!(
        "{name}: at ε = {eps:.3e}: ours {} triangles (two-sided, certified {:.3e}), manifold3d n = {} {} triangles (one-sided)",
        mesh.triangles.len(),
        mesh.certified,
        fx.mesh.n,
        fx.mesh.triangles
    );
    let md = MeshDist::new(&mesh);
    let mut hits = 0;
    for ray in &fx.rays {
        if let Some(ex) = &ray.exact {
            hits += 1;
            let d = md.dist(ex.point);
            assert!(d <= eps + SLACK, "{name}: exact hit {:?} is {d} from our mesh (ε {eps})", ex.point);
        }
    }
    assert!(hits > 50, "{name}: {hits} exact hits");
    for s in fx.sdf.iter().filter(|s| s.exact >= 0.0) {
        let d = md.dist(s.x);
        assert!((d - s.exact).abs() <= eps + SLACK, "{name}: point at exact distance {} is {d} from our mesh", s.exact);
    }
}

#[test]
fn bifurcation_at_manifolds_coarse_error() {
    check("bifurcation_n64");
}

#[test]
fn single_links_at_manifolds_error() {
    check("link_steep");
}

#[test]
fn spline_at_manifolds_error() {
    check("spline_quadratic");
}
