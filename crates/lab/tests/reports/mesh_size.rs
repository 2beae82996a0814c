//! The size report's parts, on scenes small enough to build every representation (about a
//! second each): the byte count it gives for an estimated mesh is the PLY writer's formula,
//! the union's sample estimate lands near the union built, and each row it builds is within
//! its tolerance with the bytes of what `tubecast mesh` writes.

use tubecast_lab::report::{measure_sizes, ply_bytes, size_table, union_estimate, KINDS};
use tubecast_render::io::Polyline;
use tubecast_render::mesh::{export, tessellate_union, tessellate_union_with, Bodies, UnionOptions};
use tubecast_render::scene::Scene;

/// A smooth chain of `n` links of radius 0.5 (a quarter turn of a helix, links about 2.5
/// radii long: tubes meet at every joint with a shallow bend, as in a tractogram).
fn chain(n: usize) -> Scene {
    let points: Vec<[f64; 3]> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::FRAC_PI_2;
            [8.0 * t.cos(), 8.0 * t.sin(), 3.0 * t]
        })
        .collect();
    Scene::from_polylines(&[Polyline { points, radii: vec![] }], 0.5, "chain").unwrap()
}

#[test]
fn estimated_ply_bytes_are_the_writers_count() {
    // The estimate's formula at a built mesh's own counts gives the bytes written.
    let (m, _) = tessellate_union(&chain(3), 2e-2).unwrap();
    let (v, t) = (m.mesh.positions.len() as f64, m.mesh.triangles.len() as f64);
    assert_eq!(ply_bytes(v, t, m.mesh.certified), export::ply(&m).len() as f64);
}

#[test]
fn union_estimate_from_a_sample_is_near_the_union_built() {
    // The union's triangles are two end caps (half a node sphere each, `4k²` triangles) per
    // chain and a strip per link (a few `k` triangles): a 3-link sample of a 10-link chain has
    // the two caps over three links, the chain over ten, so the area-scaled estimate is high,
    // by less than 2× here (the strips and joints carry about half the sample's triangles).
    let s = chain(10);
    let eps = 1e-2;
    // The estimate is the hulls' (the report's `union` rows); ten links of one radius would
    // otherwise be meshed as a run.
    let hulls = UnionOptions { bodies: Bodies::Hulls, ..Default::default() };
    let built = tessellate_union_with(&s, eps, &hulls).unwrap().0.mesh.triangles.len() as f64;
    let est = union_estimate(&s, eps, 3).unwrap();
    let ratio = est / built;
    assert!((1.0..=2.0).contains(&ratio), "estimate {est:e}, built {built:e}");
}

#[test]
fn every_representation_of_a_small_tree_within_its_tolerance() {
    // A bifurcation: three links meeting at a node, radii 0.5 … 0.35 (mean r̄ = 0.425).
    let lines = [
        Polyline { points: vec![[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]], radii: vec![0.5, 0.45] },
        Polyline { points: vec![[3.0, 0.0, 0.0], [5.0, 1.5, 0.0]], radii: vec![0.45, 0.35] },
        Polyline { points: vec![[3.0, 0.0, 0.0], [5.0, -1.0, 0.8]], radii: vec![0.45, 0.4] },
    ];
    let s = Scene::from_polylines(&lines, 0.5, "tree").unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let k = 5e-2;
    let rows = measure_sizes("tree", &s, &[k], 1e7, 1e7, &pool).unwrap();
    assert_eq!(rows.iter().map(|r| r.kind).collect::<Vec<_>>(), KINDS.to_vec());
    let r_mean = rows[0].r_mean;
    for r in &rows {
        assert!(!r.estimated, "{}: built under the cap", r.kind);
        assert!(r.certified <= r.k * r_mean, "{}: certified {:e} > ε {:e}", r.kind, r.certified, r.k * r_mean);
        assert!(r.bytes > 0.0);
        if r.kind == "shells" || r.kind.starts_with("union") {
            assert!(r.triangles > 0.0 && r.prims == 0, "{}", r.kind);
            // A closed mesh: 12 bytes per vertex (at least T/2 + 2) and 13 per triangle.
            assert!(r.bytes >= 12.0 * (r.triangles / 2.0 + 2.0) + 13.0 * r.triangles, "{}", r.kind);
        }
    }
    let md = size_table(&rows);
    assert_eq!(md.lines().count(), 2 + rows.len(), "{md}");
}
