//! Automatic primitive choice against the oracle: the chosen primitives' union stays within
//! the reported worst error (≤ ε) of the scene's links' union, by the oracle's
//! `min_u |x − p(u)| − r(u)` at random points near the tubes; pixel tolerances follow the
//! footprint formula.

use tubecast_oracle::rng::{splitmix, FloatRng};
use tubecast_oracle::{sweep_dist, Link, Vec3};
use tubecast_render::scene::choice::{choose, Tolerance};
use tubecast_render::scene::{generate, Scene};

fn field(links: &[Link], x: Vec3) -> f64 {
    links.iter().map(|l| sweep_dist(l, x).0).fold(f64::INFINITY, f64::min)
}

fn link(a: [f64; 3], ra: f64, b: [f64; 3], rb: f64) -> Link {
    Link { a: Vec3::new(a[0], a[1], a[2]), ra, b: Vec3::new(b[0], b[1], b[2]), rb }
}

#[test]
fn chosen_union_is_within_the_worst_error() {
    let scene = Scene::from_polylines(&generate::furball(6, 78, 3), 0.05, "furball").unwrap();
    let orig: Vec<Link> = (0..scene.links.len())
        .map(|k| {
            let l = scene.link(k);
            link(l.a.to_array(), l.ra, l.b.to_array(), l.rb)
        })
        .collect();
    for eps in [1e-4, 1e-3, 1e-2] {
        let c = choose(&scene, &Tolerance::Absolute(eps));
        assert!(c.worst <= eps && c.prims.len() == c.links.len());
        assert_eq!(c.spheres + c.cylinders + c.cones, c.prims.len());
        assert_eq!(c.prims.len() + c.merged, scene.links.len());
        let chosen: Vec<Link> = c.links.iter().map(|l| link(l.a.to_array(), l.ra, l.b.to_array(), l.rb)).collect();
        let mut rng = splitmix(9);
        // Oracle argmin rounding: ~1e-15 of the scene scale (≤ 10); 1e-12 covers both fields.
        let tol = c.worst + 1e-12;
        for _ in 0..300 {
            let n = &scene.nodes[(rng.uniform() * scene.nodes.len() as f64) as usize % scene.nodes.len()];
            let u = rng.unit();
            let r = rng.range(0.0, 0.1);
            let x = Vec3::new(n.pos[0] + u[0] * r, n.pos[1] + u[1] * r, n.pos[2] + u[2] * r);
            let (f, g) = (field(&orig, x), field(&chosen, x));
            assert!((f - g).abs() <= tol, "ε {eps}: {f} vs {g}, worst {}", c.worst);
        }
        if eps >= 1e-2 {
            assert!(c.prims.len() < scene.links.len());
        }
    }
    // Zero tolerance: only exact merges (D = 0) and shapes; the worst error is 0.
    assert_eq!(choose(&scene, &Tolerance::Absolute(0.0)).worst, 0.0);
}

#[test]
fn pixel_tolerance_is_the_footprint_at_the_nearest_distance() {
    let t = Tolerance::Pixels { eye: [0.0, 0.0, 10.0], fov_deg: 90.0, height: 100, pixels: 0.5 };
    // Box 4 away from the eye: footprint 2·4·tan 45°/100 = 0.08, half a pixel 0.04.
    assert!((t.at([-1.0, -1.0, 5.0], [1.0, 1.0, 6.0]) - 0.04).abs() < 1e-15);
    assert_eq!(t.at([-1.0, -1.0, 9.0], [1.0, 1.0, 11.0]), 0.0); // around the eye: exact
    assert_eq!(Tolerance::Absolute(-1.0).at([0.0; 3], [1.0; 3]), 0.0);
}
