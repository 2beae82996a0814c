// Differential check of the accelerators (they must agree bit for bit), shared by fuzz/fuzz_targets/accel.rs and
// crates/render/tests/io/fuzz_corpus.rs: on a scene decoded from the input, every accelerator
// (`tracers`) gives exactly what a brute-force loop over the same primitives gives — the same
// kernels run on the same rays, so the bound is zero: the closest hit's t (and whether there is
// one), any-hit, and the CSG union of all line intervals, bit for bit. Culling may only skip
// primitives that the kernels would miss.
#[allow(unused_imports)]
use tubecast::csg::{union, Tagged};
#[allow(unused_imports)]
use tubecast::{Ray, RoundCone, V3};
use tubecast_render::accel::grid::Grid;
use tubecast_render::accel::{Bvh, Tracer, WideBvh};
use tubecast_render::io::Polyline;
use tubecast_render::scene::{Model, Prim, Scene};

/// The little-endian `f32` at 4-byte slot `i` (bytes past the end read as 0), widened.
fn f32_at(data: &[u8], i: usize) -> f64 {
    let mut b = [0u8; 4];
    for (k, x) in b.iter_mut().enumerate() {
        *x = *data.get(4 * i + k).unwrap_or(&0);
    }
    f32::from_le_bytes(b) as f64
}

/// Every accelerator over `prims`.
pub fn tracers(prims: &[Prim]) -> Vec<(&'static str, Box<dyn Tracer>)> {
    vec![
        ("bvh", Box::new(Bvh::build(prims.to_vec()))),
        ("wide bvh", Box::new(WideBvh::build(prims.to_vec()))),
        ("grid", Box::new(Grid::build(prims.to_vec()))),
    ]
}

/// Input: byte 0 = number of links n (mod 9), then n links of 8 f32 (a, ra, b, rb), then rays
/// of 6 f32 (o, d) until the input ends (at most 8). Invalid links and rays are skipped.
pub fn check(data: &[u8]) {
    let n = *data.first().unwrap_or(&0) as usize % 9;
    let rest = data.get(1..).unwrap_or(&[]);
    let f = |i: usize| f32_at(rest, i);
    let v = |i: usize| V3::new(f(i), f(i + 1), f(i + 2));
    let mut prims = Vec::new();
    for k in 0..n {
        let s = 8 * k;
        if let Ok(l) = RoundCone::new(v(s), f(s + 3), v(s + 4), f(s + 7)) {
            // The renderer's own limit on coordinates (its scenes refuse larger ones) and on
            // radii (a non-zero one below MIN_RADIUS underflows when squared in f32).
            let tiny = |r: f64| r > 0.0 && r < tubecast_render::scene::MIN_RADIUS;
            if l.a.max_abs().max(l.b.max_abs()).max(l.ra).max(l.rb) <= tubecast_render::scene::MAX_COORD
                && !tiny(l.ra)
                && !tiny(l.rb)
            {
                prims.push(Prim::from_link(&l, k as u32));
            }
        }
    }
    let rays: Vec<Ray<f64>> = (0..8)
        .map(|j| 8 * n + 6 * j)
        .take_while(|&s| 4 * (s + 6) <= rest.len())
        .map(|s| Ray::new(v(s), v(s + 3)))
        .filter(|r| r.validate().is_ok() && r.o.max_abs() <= tubecast_render::scene::MAX_COORD)
        .collect();
    let rays = near(&prims, rays);
    for (name, tr) in tracers(&prims) {
        for ray in &rays {
            agree(name, tr.as_ref(), &prims, ray);
        }
    }
    // The compact 8-wide tree built from a scene of the same links: as independent links, and as
    // one polyline through the links' first ends (consecutive links share nodes and cluster).
    // Its primitives are its own stored ones ([`Tracer::prim`]: links share one f64 origin per
    // cluster), so brute force runs over those.
    let mut lines: Vec<Polyline> = Vec::new();
    let mut chain = Polyline { points: Vec::new(), radii: Vec::new() };
    for p in &prims {
        let Some(c) = p.round_cone() else { continue };
        let org = V3::from(p.origin);
        let (a, b) = (org + c.a.cast::<f64>(), org + c.b.cast::<f64>());
        lines.push(Polyline { points: vec![a.to_array(), b.to_array()], radii: vec![c.ra as f64, c.rb as f64] });
        chain.points.push(a.to_array());
        chain.radii.push(c.ra as f64);
    }
    for lines in [lines, vec![chain]] {
        let Ok(scene) = Scene::from_polylines(&lines, 1.0, "fuzz") else { continue };
        let compact = WideBvh::from_scene(&scene, Model::Links).expect("a links model builds");
        let own: Vec<Prim> = (0..compact.prim_count() as u32).map(|i| compact.prim(i)).collect();
        // Judged by this scene's own size: the chain through the first ends can be far smaller
        // than the scene of all links (fuzz finding regression-chain-smaller-than-scene: two
        // spheres of radius 2.7e-32, a ray origin 1.8e-8 = 1.7e23 of their diagonals away, where
        // the f64 sphere kernel's rounding, ε·1.8e-8 = 4e-24, dwarfs the spheres and it reports a
        // hit that no padded box can contain).
        for ray in &near(&own, rays.clone()) {
            agree("compact wide bvh", &compact, &own, ray);
        }
    }
}

/// The rays whose origins lie within 2³³ diagonals of the box of `prims` (all rays if none).
///
/// The claim holds for origins within 2³³ scene diagonals of the scene: along a ray the f64
/// ray parameter resolves positions only to ε·|o − scene| (ε = 2⁻⁵³), and beyond 2³³·D that
/// exceeds the accelerators' box padding D·2⁻¹⁶/8, so where along the line the scene lies is
/// itself below the arithmetic's resolution (a fuzz input, regression-far-origin-restart, has
/// its origin 1e24 diagonals away; the kernels there report a zero-length touch).
fn near(prims: &[Prim], rays: Vec<Ray<f64>>) -> Vec<Ray<f64>> {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in prims {
        let (a, b) = p.aabb();
        lo = std::array::from_fn(|i| lo[i].min(a[i]));
        hi = std::array::from_fn(|i| hi[i].max(b[i]));
    }
    let centre = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    let diag = V3::new(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]).length();
    rays.into_iter().filter(|r| prims.is_empty() || (r.o - centre).length() <= 2f64.powi(33) * diag).collect()
}

/// `tracer` against brute force over `prims` on one ray.
pub fn agree(name: &str, tracer: &dyn Tracer, prims: &[Prim], ray: &Ray<f64>) {
    // Brute force under the one `closer` rule (a primitive's hit carries its link as id).
    let brute = prims.iter().filter_map(|p| p.first_hit(ray)).fold(None, |mut best, h| {
        h.keep_closer(&mut best);
        best
    });
    let got = tracer.closest_hit(ray);
    assert_eq!(got.map(|h| h.t.to_bits()), brute.map(|h| h.t.to_bits()), "{name}: closest hit of {ray:?}");
    if let (Some(h), Some(b)) = (got, brute) {
        let p = tracer.prim(h.id);
        assert_eq!(p.first_hit(ray).map(|x| x.t.to_bits()), Some(h.t.to_bits()), "{name}: hit's own primitive");
        let bits = |x: tubecast::Hit<f64>| (x.n.x.to_bits(), x.n.y.to_bits(), x.n.z.to_bits(), x.u.to_bits());
        assert_eq!((p.link, bits(h), h.entering), (b.id, bits(b), b.entering), "{name}: the closer rule, {ray:?}");
    }
    let brute_any = prims.iter().any(|p| p.meets(ray));
    assert_eq!(tracer.any_hit(ray), brute_any, "{name}: any hit of {ray:?}");
    let bounds = |ivs: &mut Vec<Tagged<f64>>| {
        let mut b: Vec<(u64, bool)> = Vec::new();
        union(ivs, f64::NEG_INFINITY, f64::INFINITY, |x: tubecast::Hit<f64>| b.push((x.t.to_bits(), x.entering)));
        b
    };
    let mut mine = Vec::new();
    tracer.line_intervals(ray, &mut mine);
    let mut all = Vec::new();
    let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
    for (k, p) in prims.iter().enumerate() {
        p.pieces(&line, |iv| all.push(Tagged { iv, id: k as u32 }));
    }
    assert_eq!(bounds(&mut mine), bounds(&mut all), "{name}: union of line intervals of {ray:?}");
}
