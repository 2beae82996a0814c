//! Scene building: primitive selection, and far-from-origin precision of the local-origin
//! f32 primitives versus a naive absolute-f32 path.

use tubecast::{Primitive, Ray, RoundCone, V3};
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::scene::{PrimKind, Scene, Shape};

#[test]
fn primitive_selection_models_no_more_than_needed() {
    let lines = vec![
        // equal radii → cylinder; varying → cone; second sphere inside the first → sphere.
        Polyline {
            points: vec![[0.0; 3], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.1, 0.0, 0.0]],
            radii: vec![0.5, 0.5, 0.3, 0.1],
        },
        // a single point → an isolated sphere.
        Polyline { points: vec![[9.0, 9.0, 9.0]], radii: vec![] },
    ];
    let s = Scene::from_polylines(&lines, 0.7, "t").unwrap();
    let kinds: Vec<PrimKind> = s.primitives().iter().map(|p| p.kind()).collect();
    assert_eq!(kinds, vec![PrimKind::Cylinder, PrimKind::Cone, PrimKind::Sphere, PrimKind::Sphere]);
    let st = s.stats();
    assert_eq!((st.nodes, st.links, st.cylinders, st.cones, st.spheres), (5, 4, 1, 1, 2));
    // Bounds: x from −0.5 (first sphere) to 9.7 (isolated sphere of default radius 0.7).
    assert_eq!(st.bounds.0[0], -0.5);
    assert_eq!(st.bounds.1[0], 9.7);
    // The contained link is modelled by its larger sphere: centre (4, 0, 0), radius 0.3.
    let p = s.primitives()[2];
    assert_eq!((p.origin, p.shape), ([4.0, 0.0, 0.0], Shape::Sphere { r: 0.3 }));
}

#[test]
fn bad_scene_input_is_an_error() {
    let l = |p: [f64; 3], r: f64| vec![Polyline { points: vec![[0.0; 3], p], radii: vec![r, r] }];
    for (lines, what) in [
        (l([1.0, 0.0, 0.0], -1.0), "negative radius"),
        (l([1e19, 0.0, 0.0], 1.0), "exceeds"),
        (l([1.0, 0.0, 0.0], 0.0), "zero radius at both ends"),
    ] {
        let e = Scene::from_polylines(&lines, 0.5, "in.tck").unwrap_err();
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
    for r in [0.0, -1.0, f64::NAN] {
        assert!(Scene::from_polylines(&l([1.0; 3], 1.0), r, "x").is_err());
    }
    // No polylines used to be refused ("no nodes"); it is the empty scene now
    // (tests/scene_empty.rs), still with the default radius checked.
    assert_eq!(Scene::from_polylines(&[], 0.5, "in.tck").unwrap(), Scene::default());
    assert!(Scene::from_polylines(&[], -1.0, "in.tck").is_err());
}

/// Hand-derived reference: a ray along +y at height z above the axis of the cylinder
/// `y² + z² = r²` (axis x) starting at y = −5 enters at `t = 5 − √(r² − z²)`.
fn reference_t(z: f64, r: f64) -> f64 {
    5.0 - (r * r - z * z).sqrt()
}

#[test]
fn far_from_origin_keeps_precision_and_naive_f32_does_not() {
    let r = 0.01;
    let zs = [0.0, 0.004, 0.0087, -0.0063];
    let mut worst_local = 0.0f64;
    let mut worst_naive = 0.0f64;
    for c in [[0.0, 0.0, 0.0], [1e6 + 0.3, 1e6 + 0.7, -1e6 + 0.1]] {
        let c = V3::new(c[0], c[1], c[2]);
        let a = c - V3::new(0.5, 0.0, 0.0);
        let b = c + V3::new(0.5, 0.0, 0.0);
        let s = Scene::from_polylines(
            &[Polyline { points: vec![a.to_array(), b.to_array()], radii: vec![r, r] }],
            1.0,
            "t",
        )
        .unwrap();
        let bvh = Bvh::build(s.primitives());
        for &z in &zs {
            let o = c + V3::new(0.1, -5.0, z);
            let ray = Ray::new(o, V3::new(0.0, 1.0, 0.0));
            let hit = bvh.closest_hit(&ray).expect("the ray crosses the tube");
            worst_local = worst_local.max((hit.t - reference_t(z, r)).abs());
            // Naive: world coordinates rounded to f32, f32 kernel.
            let link = RoundCone { a: a.cast::<f32>(), ra: r as f32, b: b.cast::<f32>(), rb: r as f32 };
            let r32 = Ray::new(o.cast::<f32>(), V3::new(0.0f32, 1.0, 0.0));
            let e = match link.intersect(&r32).first_hit(0.0, f32::INFINITY) {
                Some(h) => (h.t as f64 - reference_t(z, r)).abs(),
                None => f64::INFINITY,
            };
            if c.x != 0.0 {
                worst_naive = worst_naive.max(e);
            }
        }
    }
    eprintln!("worst |dt|: local-origin f32 {worst_local:e}, naive absolute f32 {worst_naive:e}");
    // Local path: offsets ≤ 0.6 are rounded to f32 (≤ 0.6·2⁻²⁴ ≈ 3.6e-8 per component), the
    // f32 kernel adds a few ulps of the same size, and the hit is at most r/√(r² − z²) ≈ 2.03
    // times more sensitive than a head-on hit for |z| ≤ 0.0087; so ≈ 2·(few·3.6e-8) ≲ 5e-7.
    // 1e-6 allows that with margin; it is 1% of the radius.
    assert!(worst_local < 1e-6, "local-origin f32 error {worst_local:e}");
    // Naive f32 at 1e6: coordinates move by up to 1/32 (f32 spacing there is 1/16), i.e.
    // by more than the radius; it must be visibly worse (misses count as infinite error).
    assert!(worst_naive > 1e-3, "naive f32 error {worst_naive:e} unexpectedly small");
}

/// Memory per primitive: the `f64` origin (24 bytes), the link index and the largest shape, a
/// spline sub-segment's three `f32` control points and radii (48 bytes) plus its half and the
/// tag, padded to 8: 80 bytes, as before `Prim` held its shape as an enum.
#[test]
fn primitive_size_does_not_grow() {
    assert_eq!(std::mem::size_of::<tubecast_render::scene::Prim>(), 80);
}
