//! The `accel` fuzz finding `regression-long-link-epsilon`: six links near the origin
//! and one link 7.26·10⁶ long. The 8-wide tree missed a hit that brute force finds, because
//! obvhs's wide node test culls every box a ray leaves before its absolute `t = 10⁻⁴` and the
//! clipped ray restarted only `4·pad·scale ≤ 8.6·10⁻⁵` before the scene (root cause and bound:
//! `accel/mod.rs`, "obvhs's absolute entry bound").
//!
//! The right answer is brute force over the same primitives (the oracle of the fuzz check,
//! `fuzz/checks/accel.rs`, included here): every accelerator must return exactly its closest
//! `t`, any-hit and union of line intervals, bit for bit. On the finding itself the `f64` link
//! oracle also confirms, independently of the kernels, that the ray enters the link brute force
//! reports and where.

mod accel {
    include!("../../../../fuzz/checks/accel.rs");
}

use tubecast::{Ray, RoundCone, V3};
use tubecast_oracle::{line_gap, line_interval, link_error_bound, sweep_normal, Line, Link, Vec3};
use tubecast_render::accel::{Tracer, WideBvh};
use tubecast_render::io::Polyline;
use tubecast_render::scene::generate::Rng;
use tubecast_render::scene::{Model, Node, Prim, Radii, Scene};

fn finding() -> Vec<u8> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/corpus/accel/regression-long-link-epsilon");
    std::fs::read(path).unwrap()
}

/// The links (as `f64` round cones) and rays of a fuzz-format input (the check's decoding).
fn decode(data: &[u8]) -> (Vec<RoundCone<f64>>, Vec<Ray<f64>>) {
    let f = |i: usize| {
        let b = |k: usize| data.get(1 + 4 * i + k).copied().unwrap_or(0);
        f32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f64
    };
    let v = |i: usize| V3::new(f(i), f(i + 1), f(i + 2));
    let n = data[0] as usize % 9;
    let links = (0..n).filter_map(|k| RoundCone::new(v(8 * k), f(8 * k + 3), v(8 * k + 4), f(8 * k + 7)).ok());
    let rays = (0..8).map(|j| 8 * n + 6 * j).take_while(|&s| 4 * (s + 6) < data.len());
    (links.collect(), rays.map(|s| Ray::new(v(s), v(s + 3))).collect())
}

/// Brute force: the closest hit's `t` over `prims`.
fn brute(prims: &[Prim], ray: &Ray<f64>) -> Option<f64> {
    prims.iter().filter_map(|p| p.first_hit(ray)).map(|h| h.t).reduce(f64::min)
}

/// The finding: ray 1 hits link 1 (brute force, t = 5.7994…); the wide tree answered no hit.
/// The link oracle (`f64`, no kernel code) confirms the hit: the line passes `−gap` inside link 1
/// and enters it where brute force says, within the primitive's error. Error of brute force's `t`
/// against the oracle: the primitive stores its ends in `f32` relative to its midpoint
/// (`≤ 2⁻²⁴·|end − mid|` per coordinate, `|end − mid| ≤ 1.4`, radii `≤ 2⁻²⁴·0.3`), so its surface
/// is within `s = 2⁻²⁴·(√3·1.4 + 0.3)` of the link's; the `f32` kernel's own hit-point error is
/// `E` of [`link_error_bound`] with `2⁻²⁴` (the bound `tests/kernels/link/properties.rs` holds the kernels
/// to), the oracle's the same with `2⁻⁵³`; along the ray these move the entry by `(s + E + E₆₄)/(γ·|d|)`,
/// `γ` the incidence cosine at the oracle's entry.
#[test]
fn the_long_link_finding_is_hit_by_every_accelerator() {
    let data = finding();
    let (links, rays) = decode(&data);
    assert_eq!((links.len(), rays.len()), (6, 6));
    assert!(links[3].a.x < -7.2e6 && links[3].b.x > -1.2, "the long link: {:?}", links[3]);
    let prims: Vec<Prim> = links.iter().enumerate().map(|(k, l)| Prim::from_link(l, k as u32)).collect();
    let ray = rays[1];
    let t = brute(&prims, &ray).expect("brute force hits");
    let hit_link = prims.iter().find(|p| p.first_hit(&ray).map(|h| h.t) == Some(t)).unwrap().link as usize;
    assert_eq!(hit_link, 1);

    let o = |v: V3<f64>| Vec3::new(v.x, v.y, v.z);
    let l = &links[1];
    let link = Link { a: o(l.a), ra: l.ra, b: o(l.b), rb: l.rb };
    let line = Line { o: o(ray.o), d: o(ray.d) };
    let (gap, _) = line_gap(&link, &line);
    assert!(gap < -0.01, "the ray passes {gap} from link 1");
    let t_in = line_interval(&link, &line).unwrap().t_in;
    let eps = 2f64.powi(-24);
    let mid = (link.a + link.b) * 0.5;
    let s = eps * (3f64.sqrt() * (link.a - mid).max_abs().max((link.b - mid).max_abs()) + l.ra.max(l.rb));
    let size = (link.b - link.a).length().max(l.ra).max(l.rb);
    let e = |eps: f64| link_error_bound(&link, line.o, size, eps);
    let gamma = sweep_normal(&link, line.at(t_in)).dot(line.d).abs() / line.d.length();
    let tol = (s + e(eps) + e(f64::EPSILON)) / (gamma * line.d.length());
    assert!((t - t_in).abs() <= tol, "brute force t {t}, oracle {t_in}, tolerance {tol}");

    for (name, tracer) in accel::tracers(&prims) {
        assert_eq!(tracer.closest_hit(&ray).map(|h| h.t.to_bits()), Some(t.to_bits()), "{name}");
    }
    // Everything the fuzz check claims, on every ray of the input (also the compact trees).
    accel::check(&data);
}

/// A scene of the finding's shape as a fuzz-format input: `small` links of length ≲ 3 in a box of
/// side 4 at the origin, one link `ratio` times longer (of length `2·ratio`) along `axis` (either
/// way) ending near them, and 8 rays, each aimed at a random point of a small link's axis and
/// starting inside it or up to 1 or 10 before it.
fn family_input(rng: &mut Rng, axis: usize, ratio: f64, small: usize) -> Vec<u8> {
    let mut out = vec![(small + 1) as u8];
    let mut put = |v: &[f64]| v.iter().for_each(|&x| out.extend((x as f32).to_le_bytes()));
    let mut ends = Vec::new();
    for _ in 0..small {
        let a = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
        let d = rng.unit();
        let len = rng.range(0.3, 3.0);
        let b: [f64; 3] = std::array::from_fn(|i| a[i] + d[i] * len);
        ends.push((a, b));
        put(&[a[0], a[1], a[2], rng.range(0.05, 0.4), b[0], b[1], b[2], rng.range(0.05, 0.4)]);
    }
    let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
    let near: [f64; 3] = std::array::from_fn(|i| if i == axis { sign * 1.1 } else { rng.range(-1.5, 1.5) });
    let mut far = near;
    far[axis] += sign * 2.0 * ratio;
    put(&[far[0], far[1], far[2], 0.32, near[0], near[1], near[2], 0.17]);
    for j in 0..8 {
        let (a, b) = ends[(rng.uniform() * small as f64) as usize];
        let u = rng.uniform();
        let p: [f64; 3] = std::array::from_fn(|i| a[i] + (b[i] - a[i]) * u);
        let scale = rng.range(0.5, 2.0);
        let d = rng.unit().map(|x| x * scale);
        let back = [0.0, 1.0, 10.0][j % 3] * rng.uniform() / V3::from(d).length();
        put(&[p[0] - d[0] * back, p[1] - d[1] * back, p[2] - d[2] * back, d[0], d[1], d[2]]);
    }
    out
}

/// The generated family: for each axis and each ratio 10³…10⁸, a few scenes; every accelerator
/// (binary BVH, `WideBvh::build`, the grid, and the compact `WideBvh::from_scene` trees of the
/// fuzz check, plus the compact tree built in chunks of two items, which adds top nodes) equals
/// brute force on every ray. The rays are aimed through the small links, so most of them hit
/// (counted: the test is not vacuous).
#[test]
fn tiny_links_beside_a_huge_one_equal_brute_force() {
    let mut rng = Rng::new(1515);
    let (mut rays, mut hits) = (0, 0);
    for axis in 0..3 {
        for e in 3..=8 {
            for _ in 0..2 {
                let data = family_input(&mut rng, axis, 10f64.powi(e), 4);
                accel::check(&data);
                let (links, rs) = decode(&data);
                assert_eq!(links.len(), 5, "every generated link is valid");
                let prims: Vec<Prim> = links.iter().enumerate().map(|(k, l)| Prim::from_link(l, k as u32)).collect();
                let lines: Vec<Polyline> = links
                    .iter()
                    .map(|l| Polyline { points: vec![l.a.to_array(), l.b.to_array()], radii: vec![l.ra, l.rb] })
                    .collect();
                let scene = Scene::from_polylines(&lines, 1.0, "family").unwrap();
                let chunked = WideBvh::from_scene_chunked(&scene, Model::Links, 2).unwrap();
                let own: Vec<Prim> = (0..chunked.prim_count() as u32).map(|i| chunked.prim(i)).collect();
                for ray in &rs {
                    accel::agree("compact wide bvh in chunks of 2", &chunked, &own, ray);
                    rays += 1;
                    hits += usize::from(brute(&prims, ray).is_some());
                }
            }
        }
    }
    assert!(rays == 288 && hits > rays * 9 / 10, "{hits} hits of {rays} rays");
}

/// A second finding of the same campaign (`regression-point-scene-pad`): the check's chain of
/// one point, a sphere of radius 2.4·10⁻³⁹ at `(−0.34, −0.58, 0.78)`. Its diagonal is 0, its
/// box padding `64·ε·|centre| = 1.1·10⁻¹⁴`, and the frame scaled it by `2¹⁰⁰⁰` (from the
/// diagonal), so the padded `f32` box was `±∞` and obvhs's child ordering panicked on its NaN
/// centre. Now the frame is scaled by the padded box's size: the trees build, and every one of
/// them equals brute force on the input's rays (the fuzz check), and the trees do on rays through
/// the point.
#[test]
fn a_one_point_scene_builds_and_equals_brute_force() {
    let data =
        std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/corpus/accel/regression-point-scene-pad"))
            .unwrap();
    accel::check(&data);
    let c = V3::new(-0.3430919051170349, -0.5837545394897461, 0.7784315943717957);
    let line = Polyline { points: vec![c.to_array()], radii: vec![2.3716710261989307e-39] };
    // Scenes refuse that radius now (below `scene::MIN_RADIUS`), so the tree is built on the
    // scene as it was, assembled directly: the trees must still build and equal brute force.
    assert!(Scene::from_polylines(&[line], 1.0, "point").is_err());
    let (nodes, links) = (vec![Node { pos: c.to_array() }], vec![[0, 0]].into());
    let scene = Scene { nodes, links, radii: Radii::uniform(2.3716710261989307e-39), ..Scene::default() };
    let wide = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let own: Vec<Prim> = (0..wide.prim_count() as u32).map(|i| wide.prim(i)).collect();
    let mut rng = Rng::new(7);
    for _ in 0..50 {
        let d = V3::from(rng.unit());
        let ray = Ray::new(c - d * 2.0, d);
        accel::agree("compact wide bvh", &wide, &own, &ray);
        for (name, tracer) in accel::tracers(&own) {
            accel::agree(name, tracer.as_ref(), &own, &ray);
        }
    }
}
