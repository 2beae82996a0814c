//! The occupancy pyramid (`accel::grid::Pyramid`): every level keeps the base level's mass
//! (each coarse voxel is the mean of its 8 children, zero-padded, so `Σ level k+1 · 8 = Σ level
//! k` up to `f32` rounding: relative `≤ 8·2⁻²⁴` per level of summation at these sizes), values
//! stay in `[0, 1]`, and the clipping planes at interior nodes stop a straight tube split into
//! links from counting its joints twice.

use tubecast_render::accel::grid::Pyramid;
use tubecast_render::io::Polyline;
use tubecast_render::scene::{generate, Scene};

fn mass(v: &[f32]) -> f64 {
    v.iter().map(|&x| x as f64).sum()
}

#[test]
fn levels_keep_the_mass_and_stay_in_unit_range() {
    let scene = Scene::from_polylines(&generate::helix(80), 0.2, "h").unwrap();
    let p = Pyramid::build(&scene, [-6.0, -6.0, -1.0], 0.5, [24, 24, 44], 0.25);
    assert_eq!(p.levels.last().unwrap().dims, [1, 1, 1]);
    let base = mass(&p.levels[0].values);
    assert!(base > 10.0);
    for (k, l) in p.levels.iter().enumerate() {
        assert!(l.values.iter().all(|&v| (0.0..=1.0).contains(&v)), "level {k} out of [0, 1]");
        let m = mass(&l.values) * 8f64.powi(k as i32);
        assert!((m - base).abs() <= base * 8.0 * 2f64.powi(-24) * 8.0, "level {k}: mass {m} vs base {base}");
    }
}

#[test]
fn clipping_planes_stop_joints_counting_twice() {
    // One straight tube (radius 1.5 voxels) across an 8³-voxel-thick box, as 1 link and as 12.
    let (a, b) = ([-2.0, 4.3, 5.1], [26.0, 6.7, 3.9]);
    let split: Vec<[f64; 3]> =
        (0..=12).map(|i| std::array::from_fn(|j| a[j] + (b[j] - a[j]) * i as f64 / 12.0)).collect();
    let one = Scene::from_polylines(&[Polyline { points: vec![a, b], radii: vec![] }], 1.5, "1").unwrap();
    let many = Scene::from_polylines(&[Polyline { points: split.clone(), radii: vec![] }], 1.5, "12").unwrap();
    let build = |s: &Scene| mass(&Pyramid::build(s, [0.0; 3], 1.0, [24, 12, 10], 0.5).levels[0].values);
    let (m1, m12) = (build(&one), build(&many));
    // Unclipped: 11 joint spheres (each ≈ 4/3·π·1.5³ ≈ 14 voxels) counted twice over, minus what
    // the per-voxel clamp to 1 absorbs — the clipped sum must be far closer to the single link.
    let unclipped: f64 = (0..12)
        .map(|i| {
            let s =
                Scene::from_polylines(&[Polyline { points: vec![split[i], split[i + 1]], radii: vec![] }], 1.5, "p")
                    .unwrap();
            build(&s)
        })
        .sum();
    println!("one link {m1:.2}, 12 clipped links {m12:.2}, 12 unclipped links summed {unclipped:.2}");
    assert!((m12 - m1).abs() < 0.25 * (unclipped - m1), "clipping did not remove the joints' double count");
}
