//! Renders checked against direct kernel calls: the depth buffer against f64 round-cone
//! kernels, BVH queries against brute force (including grazing rays), and transparent
//! compositing of two crossing tubes against an analytic expectation (no interior surfaces).

use crate::common::{compare_depth, flat, render_links};
use tubecast::{Primitive, Ray, V3};
use tubecast_render::accel::Bvh;
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, ColorBy, Options};
use tubecast_render::scene::{generate, Scene};

#[test]
fn depth_buffer_equals_direct_f64_kernel_calls() {
    let (scene, _, cam, img) = render_links(&generate::helix(24), 32, &flat(ColorBy::Direction, 1.0));
    // Reference: every link through the f64 stable kernel, no BVH, no f32.
    let reference = |_, _, ray: &Ray<f64>| {
        let mut best: Option<(f64, V3<f64>)> = None;
        for k in 0..scene.links.len() {
            if let Some(tubecast::Hit { t, n, .. }) = scene.link(k).intersect(ray).first_hit(0.0, f64::INFINITY) {
                if best.map_or(true, |b| t < b.0) {
                    best = Some((t, n));
                }
            }
        }
        best
    };
    // Near a silhouette (|n·d̂| small) hit/miss and t are ill-conditioned: a position error δ
    // moves t by δ/|n·d̂|, and a ray within δ of the outline may hit or miss; |n·d̂| < 0.02
    // is skipped. The renderer's f32 kernel works on offsets ≤ s ≈ 1 (half a link plus a
    // radius ≤ 0.6) from the link midpoint: a few ulps, δ ≲ 8·2⁻²⁴·s ≈ 5e-7, in position;
    // with |n·d̂| ≥ 0.02 that is ≤ 2.5e-5 in t (|d| ≥ 1 here).
    let tol = 5e-5;
    compare_depth(&img, &cam, 0.02, tol, reference).assert_covers("the helix", tol, 100, 10);
}

#[test]
fn bvh_closest_and_any_hit_equal_brute_force_including_grazing_rays() {
    let nodes = generate::neurons(1, &[generate::base_neuron(3)], 5);
    let scene = Scene::from_swc(&nodes, "n").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let mut rng = generate::Rng::new(42);
    let mut checked = 0;
    for i in 0..400 {
        // Aim at a random link: half of the rays graze it, passing at 0.999999·radius from a
        // point of its axis, perpendicular to the axis.
        let p = &bvh.prims[(rng.uniform() * bvh.prims.len() as f64) as usize];
        let cone = p.round_cone().expect("the link model has no spline primitives");
        let a = V3::from(p.origin) + cone.a.cast::<f64>();
        let b = V3::from(p.origin) + cone.b.cast::<f64>();
        let u = rng.uniform();
        let c = a + (b - a) * u;
        let r = cone.ra as f64 + (cone.rb as f64 - cone.ra as f64) * u;
        let axis = (b - a).normalize_or_zero();
        let mut side = V3::from(rng.unit());
        side = (side - axis * side.dot(axis)).normalize_or_zero();
        let along = axis.cross(side);
        let target = if i % 2 == 0 { c + side * (0.999_999 * r) } else { c + V3::from(rng.unit()) * (0.5 * r) };
        let dir = if i % 2 == 0 && along.length() > 0.5 { along } else { V3::from(rng.unit()) };
        let ray = Ray::new(target - dir * 300.0, dir);
        let mut best: Option<f64> = None;
        for q in &bvh.prims {
            if let Some(tubecast::Hit { t, .. }) = q.intersect(&ray).first_hit(0.0, f64::INFINITY) {
                best = Some(best.map_or(t, |b: f64| b.min(t)));
            }
        }
        let got = bvh.closest_hit(&ray).map(|h| h.t);
        assert_eq!(got, best, "ray {i}: BVH closest hit differs from brute force over the same primitives");
        assert_eq!(bvh.any_hit(&ray), best.is_some(), "ray {i}: any-hit");
        checked += best.is_some() as usize;
    }
    assert!(checked > 300, "most rays must hit ({checked})");
}

/// Entry and exit of the line `o + t·d` with the infinite cylinder of radius 1 around
/// coordinate axis `k` (0: x, 1: y), by the quadratic formula; `None` on a miss.
fn cyl(o: V3<f64>, d: V3<f64>, k: usize) -> Option<(f64, f64)> {
    let (o2, d2) = if k == 0 { ([o.y, o.z], [d.y, d.z]) } else { ([o.x, o.z], [d.x, d.z]) };
    let a = d2[0] * d2[0] + d2[1] * d2[1];
    let b = o2[0] * d2[0] + o2[1] * d2[1];
    let c = o2[0] * o2[0] + o2[1] * o2[1] - 1.0;
    let disc = b * b - a * c;
    (disc > 0.0).then(|| ((-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a))
}

#[test]
fn transparent_crossing_tubes_composite_only_exterior_boundaries() {
    // Tube X along x (colour by direction: red), tube Y along y (green), radius 1, crossing.
    let lines = vec![
        Polyline { points: vec![[-10.0, 0.0, 0.0], [10.0, 0.0, 0.0]], radii: vec![1.0, 1.0] },
        Polyline { points: vec![[0.0, -10.0, 0.0], [0.0, 10.0, 0.0]], radii: vec![1.0, 1.0] },
    ];
    let scene = Scene::from_polylines(&lines, 1.0, "cross").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let cam = Camera::look_at(V3::new(0.4, 0.3, 8.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 30.0, 32, 32).unwrap();
    let alpha = 0.5;
    let img = render(&scene, &bvh, &cam, &flat(ColorBy::Direction, alpha)).unwrap();
    let colour = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let (mut merged, mut mixed, mut checked) = (0, 0, 0);
    for y in 0..32 {
        for x in 0..32 {
            let ray = cam.ray(x, y);
            let iv: Vec<(f64, f64, usize)> =
                (0..2).filter_map(|k| cyl(ray.o, ray.d, k).map(|(a, b)| (a, b, k))).collect();
            // Boundaries of the union as (t, owner): overlapping intervals merge.
            let mut bounds: Vec<(f64, usize)> = Vec::new();
            match iv.as_slice() {
                [] => {}
                [(a, b, k)] => bounds.extend([(*a, *k), (*b, *k)]),
                [p, q] => {
                    let (p, q) = if p.0 <= q.0 { (p, q) } else { (q, p) };
                    // Skip near-ties, where rounding may pick either owner (|Δt| < 1e-6).
                    let near = |u: f64, v: f64| (u - v).abs() < 1e-6;
                    if near(p.0, q.0) || near(p.1, q.1) || near(p.1, q.0) {
                        continue;
                    }
                    if q.0 <= p.1 {
                        let out = if q.1 > p.1 { q } else { p };
                        bounds.extend([(p.0, p.2), (out.1, out.2)]);
                        merged += 1;
                        mixed += (p.2 != out.2) as usize;
                    } else {
                        bounds.extend([(p.0, p.2), (p.1, p.2), (q.0, q.2), (q.1, q.2)]);
                    }
                }
                _ => unreachable!(),
            }
            // Skip grazing rays (an interval shorter than 1e-3 is within ~1e-6 of tangency).
            if iv.iter().any(|(a, b, _)| b - a < 1e-3) {
                continue;
            }
            // Front-to-back: C = Σ Tᵢ·α·cᵢ + T·background, Tᵢ = (1 − α)^i.
            let mut exp = [0.0f64; 3];
            let mut tr = 1.0;
            for (_, k) in &bounds {
                for c in 0..3 {
                    exp[c] += tr * alpha * colour[*k][c];
                }
                tr *= 1.0 - alpha;
            }
            for e in &mut exp {
                *e += tr * 1.0;
            }
            let got = img.at(x, y);
            for c in 0..3 {
                // f32 accumulation of ≤ 4 terms in [0, 1]: ≤ 8 ulps of 1 ≈ 1e-6.
                assert!((got[c] as f64 - exp[c]).abs() < 1e-5, "pixel ({x},{y}) {got:?} vs {exp:?}");
            }
            checked += 1;
        }
    }
    assert!(merged > 20, "pixels through the crossing ({merged})");
    assert!(mixed > 0, "some rays enter one tube and leave through the other");
    assert!(checked > 900, "checked {checked} pixels");
}

#[test]
fn bad_options_and_cameras_are_errors() {
    let scene = Scene::from_polylines(&generate::helix(4), 1.0, "h").unwrap();
    let bvh = Bvh::build(scene.primitives());
    let cam = Camera::look_at(V3::new(0.0, 0.0, 30.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 40.0, 4, 4).unwrap();
    for o in [
        Options { opacity: 0.0, ..Options::default() },
        Options { opacity: 1.5, ..Options::default() },
        Options { opacity: f64::NAN, ..Options::default() },
        Options { ao: 5000, ..Options::default() },
        Options { background: [2.0, 0.0, 0.0], ..Options::default() },
        Options { color: ColorBy::Solid([f32::NAN, 0.0, 0.0]), ..Options::default() },
    ] {
        assert!(render(&scene, &bvh, &cam, &o).is_err(), "{o:?}");
    }
    let z = V3::zero();
    let up = V3::new(0.0, 1.0, 0.0);
    assert!(Camera::look_at(z, z, up, 40.0, 4, 4).is_err());
    assert!(Camera::look_at(V3::new(0.0, 5.0, 0.0), z, up, 40.0, 4, 4).is_err());
    assert!(Camera::look_at(V3::new(1.0, 0.0, 0.0), z, up, 0.0, 4, 4).is_err());
    assert!(Camera::look_at(V3::new(1.0, 0.0, 0.0), z, up, 40.0, 0, 4).is_err());
    assert!(Camera::look_at(V3::new(f64::NAN, 0.0, 0.0), z, up, 40.0, 4, 4).is_err());
}

#[test]
fn shading_options_render_without_nan() {
    let (scene, bvh, cam, plain) = render_links(&generate::helix(16), 16, &Options::default());
    for o in [
        Options { ao: 4, shadows: true, color: ColorBy::Radius, ..Options::default() },
        Options { opacity: 0.3, color: ColorBy::Type, ..Options::default() },
    ] {
        let img = render(&scene, &bvh, &cam, &o).unwrap();
        assert!(img.rgb.iter().flatten().all(|c| c.is_finite() && (0.0..=1.5).contains(c)));
        // Same geometry, so the same pixels see tubes.
        let seen = |i: &tubecast_render::render::Image| i.depth.iter().filter(|d| d.is_finite()).count();
        assert_eq!(seen(&img), seen(&plain));
    }
    // Ambient occlusion and shadows only darken: every pixel ≤ the plain render.
    let ao = render(&scene, &bvh, &cam, &Options { ao: 8, shadows: true, ..Options::default() }).unwrap();
    assert!(ao.rgb.iter().zip(&plain.rgb).all(|(a, p)| (0..3).all(|c| a[c] <= p[c] + 1e-6)));
    assert!(ao.rgb.iter().zip(&plain.rgb).any(|(a, p)| a[0] < p[0] - 1e-3));
}

/// Every BVH query on a dense furball (BVH leaves of several links, tested as lane packets
/// with the `wide` feature) against brute force over the same primitives: closest hit
/// (`t`, normal, `u`, primitive, link — all bit for bit), any hit, and the set of line
/// intervals with their primitive ids. The packet path must equal the scalar path exactly
/// (the lane kernel equals the scalar kernel bit for bit), so the tolerance is zero.
#[test]
fn bvh_queries_on_dense_links_equal_brute_force_bitwise() {
    let scene = Scene::from_polylines(&generate::furball(40, 20, 7), 0.05, "furball").unwrap();
    let bvh = Bvh::build(scene.primitives());
    bvh_queries_equal_brute_force_bitwise(&bvh, |p, u| {
        let cone = p.round_cone().expect("the link model has no spline primitives");
        cone.a.cast::<f64>() * (1.0 - u) + cone.b.cast::<f64>() * u
    });
}

/// The same for the spline model (leaves of several spline sub-segments, each tested on the
/// scalar path: spline lane packets ran opaque frames at 0.72–1.06× the speed, `frame/*/splines`
/// in `benches/frames.rs`, so the BVH does not build them). Closest and any hit take the
/// pieces where a ray starts inside a bent segment's hull.
#[test]
fn bvh_queries_on_dense_splines_equal_brute_force_bitwise() {
    let scene = Scene::from_polylines(&generate::furball(40, 20, 7), 0.05, "furball").unwrap();
    let prims = scene.spline_primitives().unwrap();
    assert!(prims.iter().all(|p| p.quad().is_some()), "the spline model of curved hairs is all splines");
    let bvh = Bvh::build(prims);
    bvh_queries_equal_brute_force_bitwise(&bvh, |p, u| p.quad().unwrap().cast::<f64>().point(u));
}

/// Closest hit, any hit and line intervals of `bvh` against brute force over its primitives,
/// bit for bit, on 300 rays aimed within two radii of `centre(prim, u)` (a point of a random
/// primitive's centre line relative to its origin).
fn bvh_queries_equal_brute_force_bitwise(bvh: &Bvh, centre: impl Fn(&tubecast_render::scene::Prim, f64) -> V3<f64>) {
    let mut rng = generate::Rng::new(11);
    let (mut hits, mut intervals) = (0, 0);
    for i in 0..300 {
        // Aim near a random primitive's axis (within two radii), so most rays hit.
        let p = &bvh.prims[(rng.uniform() * bvh.prims.len() as f64) as usize];
        let u = rng.uniform();
        let c = V3::from(p.origin) + centre(p, u);
        let target = c + V3::from(rng.unit()) * (2.0 * p.max_radius() as f64 * rng.uniform());
        let dir = V3::from(rng.unit());
        // Some rays start inside the scene (shadow-ray-like), some far outside.
        let back = if i % 3 == 0 { 0.0 } else { 50.0 };
        let ray = Ray::new(target - dir * back, dir * (0.5 + rng.uniform()));
        // Closest hit.
        let mut best: Option<(f64, V3<f64>, f64, u32)> = None;
        for (k, q) in bvh.prims.iter().enumerate() {
            if let Some(tubecast::Hit { t, n, u, .. }) = q.first_hit(&ray) {
                if best.map_or(true, |b| t < b.0) {
                    best = Some((t, n, u, k as u32));
                }
            }
        }
        let got = bvh.closest_hit(&ray);
        assert_eq!(got.map(|h| h.t), best.map(|b| b.0), "ray {i}: closest t");
        if let (Some(h), Some(b)) = (got, best) {
            // A tie in t between two primitives may pick either; compare that primitive's own result.
            let own = bvh.prims[h.id as usize].first_hit(&ray).unwrap();
            assert_eq!((h.t, h.n, h.u), (own.t, own.n, own.u), "ray {i}: hit data of its primitive");
            if h.id != b.3 {
                assert_eq!(h.t, b.0, "ray {i}: a different primitive only on a tie");
            }
            hits += 1;
        }
        assert_eq!(bvh.any_hit(&ray), best.is_some(), "ray {i}: any-hit");
        // Line intervals, as sets of (id, bits of every field).
        let key = |id: u32, iv: &tubecast::Interval<f64>| {
            (
                id,
                [iv.entry.t, iv.exit.t, iv.entry.u, iv.exit.u, iv.entry.n.x, iv.entry.n.y, iv.entry.n.z, iv.exit.n.x]
                    .map(f64::to_bits),
            )
        };
        let mut ivs = Vec::new();
        bvh.line_intervals(&ray, &mut ivs);
        let mut got: Vec<_> = ivs.iter().map(|t| key(t.id, &t.iv)).collect();
        let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
        let mut want = Vec::new();
        for (k, q) in bvh.prims.iter().enumerate() {
            q.pieces(&line, |iv| want.push(key(k as u32, &iv)));
        }
        got.sort();
        want.sort();
        assert_eq!(got, want, "ray {i}: line intervals");
        intervals += want.len();
    }
    assert!(hits > 100, "most rays must hit ({hits})");
    assert!(intervals > 300, "rays must cross many links ({intervals} intervals)");
}
