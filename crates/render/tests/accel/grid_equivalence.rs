//! The voxel grid (`accel::grid`) against the BVH: same kernels, so on every scene and ray set
//! the closest hit (t, normal, u, link, entering), any-hit and the first component of the CSG
//! union (transparency) must be bit-identical. The primitive *index* may differ (the BVH
//! reorders its primitives); an exact tie in `t` between two primitives may then be resolved
//! differently, and is counted, not failed, when `t` is equal. Scenes: helix (cones), bundle
//! and furball (thin, tapering), a neuron (SWC cones and spheres), the helix as spline tubes,
//! the bundle far from the origin, and two clusters with empty space between them (skipped by
//! the grid's block level). Rays: random through the scene box, grazing a link
//! (0.999999 r), starting inside a tube (shadow-like), and axis-parallel on voxel planes.

use tubecast::{Ray, V3};
use tubecast_render::accel::grid::{Grid, GridParams, Voxelizer};
use tubecast_render::accel::{first_component, Bvh, Tracer};
use tubecast_render::io::Polyline;
use tubecast_render::scene::{generate, Prim, Scene};

fn scenes() -> Vec<(&'static str, Vec<Prim>)> {
    let lines = |l: &[Polyline], name| Scene::from_polylines(l, 0.2, name).unwrap();
    let far: Vec<Polyline> = generate::bundle(30, 20, 3)
        .into_iter()
        .map(|p| Polyline { points: p.points.iter().map(|q| q.map(|x| x + 1e5)).collect(), radii: p.radii })
        .collect();
    // Two helices 200 units apart: most blocks between them are empty (skipped).
    let mut apart = generate::helix(30);
    apart.extend(generate::helix(30).into_iter().map(|p| Polyline {
        points: p.points.iter().map(|q| [q[0] + 200.0, q[1] + 150.0, q[2]]).collect(),
        radii: p.radii,
    }));
    let neuron = Scene::from_swc(&generate::neurons(1, &[generate::base_neuron(3)], 5), "n").unwrap();
    vec![
        ("helix", lines(&generate::helix(60), "h").primitives()),
        ("bundle", lines(&generate::bundle(40, 30, 1), "b").primitives()),
        ("furball", lines(&generate::furball(150, 20, 2), "f").primitives()),
        ("neuron", neuron.primitives()),
        ("helix splines", lines(&generate::helix(24), "s").spline_primitives().unwrap()),
        ("far bundle", lines(&far, "far").primitives()),
        ("two clusters", lines(&apart, "apart").primitives()),
    ]
}

/// Box of the primitives.
fn bounds(prims: &[Prim]) -> ([f64; 3], [f64; 3]) {
    prims.iter().fold(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]), |(lo, hi), p| {
        let (a, b) = p.aabb();
        (std::array::from_fn(|i| lo[i].min(a[i])), std::array::from_fn(|i| hi[i].max(b[i])))
    })
}

/// The ray sets for one scene and grid.
fn rays(prims: &[Prim], grid: &Grid, seed: u64) -> Vec<Ray<f64>> {
    let mut rng = generate::Rng::new(seed);
    let (lo, hi) = bounds(prims);
    let mut out = Vec::new();
    let inside =
        |rng: &mut generate::Rng| V3::new(rng.range(lo[0], hi[0]), rng.range(lo[1], hi[1]), rng.range(lo[2], hi[2]));
    let size = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    for i in 0..300 {
        // Random: from outside through a point of the box.
        let target = inside(&mut rng);
        let d = V3::from(rng.unit());
        out.push(Ray::new(target - d * (2.0 * size), d));
        // Aimed at a link: grazing (0.999999 r, perpendicular) or into it, from far or from
        // inside (t_min = 0 at a point on the axis: a shadow ray leaving the tube).
        let p = &prims[(rng.uniform() * prims.len() as f64) as usize % prims.len()];
        let Some(c) = p.round_cone() else { continue };
        let o = V3::from(p.origin);
        let (a, b) = (o + c.a.cast::<f64>(), o + c.b.cast::<f64>());
        let u = rng.uniform();
        let x = a + (b - a) * u;
        let r = c.ra as f64 + (c.rb as f64 - c.ra as f64) * u;
        let axis = (b - a).normalize_or_zero();
        let mut side = V3::from(rng.unit());
        side = (side - axis * side.dot(axis)).normalize_or_zero();
        let along = axis.cross(side);
        match i % 3 {
            0 if along.length() > 0.5 => out.push(Ray::new(x + side * (0.999_999 * r) - along * size, along)),
            1 => out.push(Ray::new(x, V3::from(rng.unit()))),
            _ => out.push(Ray::new(x - d * size, d)),
        }
    }
    // Axis-parallel rays on voxel planes (both coordinates across the direction on planes).
    let (g, h, dims) = (grid.corner(), grid.voxel_size(), grid.dims());
    for k in 0..150 {
        let axis = k % 3;
        let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut o = [0.0; 3];
        o[axis] = g[axis] - h;
        o[p] = g[p] + h * (rng.uniform() * dims[p] as f64).floor();
        o[q] = g[q] + h * (rng.uniform() * dims[q] as f64).floor();
        let mut d = [0.0; 3];
        d[axis] = 1.0;
        out.push(Ray::new(V3::from(o), V3::from(d)));
    }
    out
}

/// Compare grid and BVH on `rays`; returns (rays hitting, ties).
fn compare(name: &str, grid: &dyn Tracer, bvh: &dyn Tracer, rays: &[Ray<f64>]) -> (usize, usize) {
    let (mut hits, mut ties) = (0, 0);
    for (i, ray) in rays.iter().enumerate() {
        let (g, b) = (grid.closest_hit(ray), bvh.closest_hit(ray));
        match (g, b) {
            (None, None) => {}
            (Some(g), Some(b)) => {
                hits += 1;
                assert_eq!(g.t, b.t, "{name} ray {i}: closest t");
                // One `closer` rule in both: the same crossing, bit for bit, and the same
                // primitive unless two coincident primitives give that very crossing.
                let (pg, pb) = (grid.prim(g.id), bvh.prim(b.id));
                assert_eq!((g.n, g.u, g.entering), (b.n, b.u, b.entering), "{name} ray {i}");
                if pg != pb {
                    ties += 1;
                }
            }
            _ => panic!("{name} ray {i}: grid {g:?} vs BVH {b:?}"),
        }
        assert_eq!(grid.any_hit(ray), bvh.any_hit(ray), "{name} ray {i}: any-hit");
        let (fg, fb) = (first_component(grid, ray), first_component(bvh, ray));
        let link = |t: &dyn Tracer, h: tubecast::Hit<f64>| (h.t, h.n, h.u, t.prim(h.id).link);
        let (fg, fb) = (fg.map(|(e, x)| (link(grid, e), link(grid, x))), fb.map(|(e, x)| (link(bvh, e), link(bvh, x))));
        assert_eq!(fg, fb, "{name} ray {i}: first component, owners included");
    }
    (hits, ties)
}

#[test]
fn grid_answers_equal_the_bvh_on_every_scene() {
    for (k, (name, prims)) in scenes().into_iter().enumerate() {
        let bvh = Bvh::build(prims.clone());
        let grid = Grid::build(prims.clone());
        let rays = rays(&prims, &grid, 100 + k as u64);
        let (hits, ties) = compare(name, &grid, &bvh, &rays);
        println!("{name}: {} prims, grid {:?}, {hits}/{} rays hit, {ties} ties", prims.len(), grid.dims(), rays.len());
        assert!(hits > rays.len() / 4, "{name}: too few hits ({hits}) to be a test");
        assert!(ties * 100 <= hits, "{name}: {ties} ties in t between different primitives");
        if name == "two clusters" {
            assert!(grid.occupied_fraction() < 0.5, "{name}: empty space not marked ({})", grid.occupied_fraction());
        }
    }
}

#[test]
fn grid_resolution_does_not_change_answers() {
    let prims = Scene::from_polylines(&generate::helix(40), 0.2, "h").unwrap().primitives();
    let bvh = Bvh::build(prims.clone());
    for lambda in [0.01, 0.5, 16.0, 200.0] {
        let grid =
            Grid::build_with(prims.clone(), &GridParams { cells_per_prim: Some(lambda), ..GridParams::default() });
        let rays = rays(&prims, &grid, 7);
        compare(&format!("helix λ={lambda}"), &grid, &bvh, &rays);
    }
}

/// The DDA-built (centre-line) grid loses hits: every answer it gives is one of the BVH's
/// candidates, but rays through voxels that a tube enters and its centre line does not miss.
#[test]
fn centre_line_grid_has_false_misses() {
    let lines = generate::bundle(40, 30, 1);
    let prims = Scene::from_polylines(&lines, 0.2, "b").unwrap().primitives();
    let bvh = Bvh::build(prims.clone());
    // Voxels about the tube diameter: the regime of Kraaijeveld's Fig. 7 artifacts.
    let params = GridParams { cells_per_prim: Some(16.0), voxelizer: Voxelizer::CentreLine, ..GridParams::default() };
    let grid = Grid::build_with(prims.clone(), &params);
    let (mut misses, mut wrong, mut hits) = (0, 0, 0);
    for ray in rays(&prims, &grid, 9) {
        match (grid.closest_hit(&ray), bvh.closest_hit(&ray)) {
            (None, Some(_)) => misses += 1,
            (Some(g), Some(b)) if g.t != b.t => wrong += 1,
            (Some(_), None) => panic!("a hit the BVH does not have"),
            (_, b) => hits += b.is_some() as usize,
        }
    }
    println!("centre-line grid {:?}: {misses} false misses, {wrong} wrong hits, {hits} right", grid.dims());
    assert!(misses + wrong > 0, "the non-conservative grid was expected to lose hits");
}

#[test]
fn empty_grid_misses() {
    let grid = Grid::build(Vec::new());
    let ray = Ray::new(V3::new(0.0, 0.0, -1.0), V3::new(0.0, 0.0, 1.0));
    assert!(grid.closest_hit(&ray).is_none() && !grid.any_hit(&ray));
    assert!(first_component(&grid, &ray).is_none());
}
