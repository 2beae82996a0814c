//! CSG union (Han §4.3) against membership sampled along the ray with the independent oracle.
//!
//! Scenes: a bifurcation (3–5 links sharing a node, different radii) plus a short polyline;
//! rays from outside and from inside. Error analysis: every link's interval ends are within
//! `E = 64ε(S + D)` of that link's surface (tests/kernels/link/properties.rs), so a reported boundary lies
//! within E of the union's surface, and membership decided by the oracle at points farther than
//! `2E` from every surface is unambiguous. Checks:
//! 1. boundaries are sorted and alternate entry/exit, starting with an exit iff the origin is
//!    inside;
//! 2. each boundary point is on the union's surface (|min_k sdf_k| ≤ E);
//! 3. between consecutive boundaries (and before the first / after the last), every sample whose
//!    distance to the surface exceeds 2E has the membership the boundaries imply;
//! 4. no interior surface survives: a boundary never lies inside another link by more than E.

use crate::common::*;
use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tubecast::csg::{union, Tagged};
use tubecast::Hit;
use tubecast::{Primitive, Ray, RoundCone, V3};

fn scene(seed: u64) -> Vec<RoundCone<f64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let node = V::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
    let rn = rng.gen_range(0.2..0.6);
    let mut links = Vec::new();
    let branches = rng.gen_range(3..=5);
    for _ in 0..branches {
        let dir = V::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let dir = dir * (1.0 / dir.length().max(1e-3));
        let end = node + dir * rng.gen_range(1.0..3.0);
        links.push(RoundCone::new(node, rn, end, rng.gen_range(0.05..0.5)).unwrap());
    }
    // A polyline continuing from the first branch's end.
    let mut p = links[0].b;
    let mut r = links[0].rb;
    for _ in 0..3 {
        let q = p + V::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let rq = rng.gen_range(0.05..0.4);
        links.push(RoundCone::new(p, r, q, rq).unwrap());
        p = q;
        r = rq;
    }
    links
}

fn scene_sdf(links: &[RoundCone<f64>], x: V) -> f64 {
    links.iter().map(|l| sweep_dist(l, x).0).fold(f64::INFINITY, f64::min)
}

fn boundaries(links: &[RoundCone<f64>], ray: &Ray<f64>) -> Vec<Hit<f64>> {
    let mut ivs: Vec<Tagged<f64>> =
        links.iter().enumerate().map(|(i, l)| Tagged { iv: l.intersect(ray), id: i as u32 }).collect();
    let mut out = Vec::new();
    let n = union(&mut ivs, ray.t_min, ray.t_max, |b| out.push(b));
    assert_eq!(n, out.len());
    out
}

proptest! {
    #[test]
    fn union_boundaries_equal_membership_transitions(seed in any::<u64>(), inside in any::<bool>(), k in 0usize..8) {
        let links = scene(seed);
        let mut rng = StdRng::seed_from_u64(seed ^ 0x9e37_79b9);
        let l = &links[k % links.len()];
        let target = l.a + (l.b - l.a) * rng.gen_range(0.0..1.0);
        let dir = V::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let dir = dir * (1.0 / dir.length().max(1e-3));
        let o = if inside { target } else { target - dir * 8.0 };
        let ray = Ray::new(o, dir);
        let bs = boundaries(&links, &ray);
        let e = 64.0 * f64::EPSILON * 16.0;
        let origin_inside = scene_sdf(&links, o) < 0.0;
        // 1. order and alternation
        for w in bs.windows(2) {
            prop_assert!(w[0].t <= w[1].t);
            prop_assert!(w[0].entering != w[1].entering, "two {} in a row", if w[0].entering {"entries"} else {"exits"});
        }
        if let Some(f) = bs.first() {
            if scene_sdf(&links, o).abs() > 2.0 * e {
                prop_assert_eq!(f.entering, !origin_inside);
            }
        }
        // 2 + 4. on the union's surface, not inside any other link
        for b in &bs {
            let x = ray.at(b.t);
            prop_assert!(scene_sdf(&links, x).abs() <= e, "boundary off the union surface: {:e}", scene_sdf(&links, x));
            prop_assert!((b.n.length() - 1.0).abs() < 1e-12);
        }
        // 3. membership between boundaries
        let t_end = bs.last().map_or(20.0, |b| b.t + 5.0);
        let n = 4000;
        for i in 0..=n {
            let t = t_end * i as f64 / n as f64;
            let sd = scene_sdf(&links, ray.at(t));
            if sd.abs() <= 2.0 * e {
                continue;
            }
            let crossed = bs.iter().filter(|b| b.t < t).count();
            let start_in = bs.first().map_or(origin_inside, |b| !b.entering);
            let expect_in = start_in ^ (crossed % 2 == 1);
            prop_assert_eq!(sd < 0.0, expect_in, "t = {}: membership {} but boundaries say {}", t, sd < 0.0, expect_in);
        }
    }
}

#[test]
fn bifurcation_along_a_branch_has_only_exterior_boundaries() {
    // Node at the origin (r = 1) with branches to ±5x̂ (r = 0.5) and to 5ŷ (r = 0.3).
    // A ray along the x axis from x = −10 enters the left end sphere at x = −5.5 (t = 4.5) and
    // leaves the right one at x = 5.5 (t = 15.5): exactly two boundaries, whatever the overlaps.
    let o = V3::new(0.0, 0.0, 0.0);
    let links = vec![
        RoundCone::new(o, 1.0, V3::new(5.0, 0.0, 0.0), 0.5).unwrap(),
        RoundCone::new(o, 1.0, V3::new(-5.0, 0.0, 0.0), 0.5).unwrap(),
        RoundCone::new(o, 1.0, V3::new(0.0, 5.0, 0.0), 0.3).unwrap(),
    ];
    let ray = Ray::new(V3::new(-10.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0));
    let bs = boundaries(&links, &ray);
    assert_eq!(bs.len(), 2, "{bs:?}");
    assert!(bs[0].entering && !bs[1].entering);
    assert!((bs[0].t - 4.5).abs() < 1e-12 && (bs[1].t - 15.5).abs() < 1e-12);
    assert_eq!((bs[0].id, bs[1].id), (1, 0));
    // From inside the node: only the exit at x = 5.5 (t = 5.5).
    let inside = Ray::new(o, V3::new(1.0, 0.0, 0.0));
    let bs = boundaries(&links, &inside);
    assert_eq!(bs.len(), 1);
    assert!(!bs[0].entering && (bs[0].t - 5.5).abs() < 1e-12);
    // Disjoint pieces: two separate tubes give four boundaries.
    let two = vec![
        RoundCone::new(V3::new(0.0, -1.0, 0.0), 0.5, V3::new(0.0, 1.0, 0.0), 0.5).unwrap(),
        RoundCone::new(V3::new(3.0, -1.0, 0.0), 0.5, V3::new(3.0, 1.0, 0.0), 0.5).unwrap(),
    ];
    let bs = boundaries(&two, &ray);
    let ts: Vec<f64> = bs.iter().map(|b| b.t).collect();
    let want = [9.5, 10.5, 12.5, 13.5];
    assert_eq!(ts.len(), 4);
    for (a, b) in ts.iter().zip(want) {
        assert!((a - b).abs() < 1e-12, "{ts:?}");
    }
}
