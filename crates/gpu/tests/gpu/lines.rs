//! `intersect --query all` on the GPU (line intervals walked on the GPU, their union taken by the
//! CPU's `crossings_table`) against the CPU's `crossings_table`, with the band of the tree test
//! (module docs there):
//! * every GPU interval's entry and exit lies within `E + δ` of its primitive's surface;
//! * every interval of the CPU's that meets the range by more than its tolerance is on the
//!   GPU's list for that ray (the walk culls nothing it needs), and every GPU interval is one of
//!   the CPU's line intervals (same primitive) or a graze (the line passes within `2E + δ`);
//! * the crossings pair up with the CPU's: same direction, `t` within
//!   `(E_gpu + E_cpu + 2δ)/(γ·|d|)`. A crossing on one side only must be explained: its
//!   primitive is grazed (`2E + δ`), or it lies at a near-touch (another line interval starts
//!   where this one ends, or ends where it starts, within `4e/γ`: merged on one side, a gap
//!   on the other), or within the tolerance of the range's ends.

use crate::{bound32, link_of, ov};
use std::collections::HashMap;
use tubecast::{Ray, V3};
use tubecast_gpu::GpuScene;
use tubecast_oracle::{line_gap, sweep_dist, Line};
use tubecast_render::accel::{crossings_table, Tracer, WideBvh};
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::{Model, Prim, Scene};

#[test]
fn all_crossings_match_the_cpu() {
    let Some(gpu) = crate::gpu("all_crossings_match_the_cpu") else { return };
    let scene = crate::fur();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let gs = GpuScene::upload(&gpu, &bvh).unwrap();
    let delta = gs.band();
    let mut rng = Rng::new(23);
    let rays: Vec<Ray<f64>> = (0..2000)
        .map(|k| {
            let p = crate::near_node(&mut rng, &scene);
            let d = V3::from(rng.unit()) * rng.range(0.5, 2.0);
            // From outside the scene, from inside a tube, and a range that starts and ends
            // within the scene (crossings cut at both ends).
            match k % 3 {
                0 => Ray::with_range(p - d * 30.0, d, 0.0, 60.0),
                1 => Ray::with_range(p, d, 0.0, 60.0),
                _ => Ray::with_range(p - d * 30.0, d, 28.0, 33.0),
            }
        })
        .collect();
    // Primitive of each link (one per link on a links scene).
    let prim_of: HashMap<u32, Prim> = (0..bvh.prim_count() as u32).map(|i| (bvh.prim(i).link, bvh.prim(i))).collect();
    assert_eq!(prim_of.len(), bvh.prim_count());

    let ivs = gs.line_intervals(&rays).unwrap();
    let (mut listed, mut graze_only) = (0, 0);
    for (k, ray) in rays.iter().enumerate() {
        let len = ray.d.length();
        let line = Line { o: ov(ray.o), d: ov(ray.d) };
        let mut cpu = Vec::new();
        bvh.line_intervals(ray, &mut cpu);
        for g in &ivs[k] {
            let p = bvh.prim(g.id);
            let e = bound32(&p, ray) + delta;
            for c in [g.iv.entry, g.iv.exit] {
                let (sd, _) = sweep_dist(&link_of(&p), ov(ray.at(c.t)));
                assert!(sd.abs() <= e, "ray {k}: GPU interval end {sd:e} off its surface (E + δ = {e:e})");
            }
            if !cpu.iter().any(|c| c.id == g.id) {
                let gap = line_gap(&link_of(&p), &line).0;
                assert!(gap.abs() <= 2.0 * e, "ray {k}: GPU interval of {} not the CPU's, gap {gap:e}", g.id);
                graze_only += 1;
            }
        }
        listed += ivs[k].len();
        // The CPU's intervals that reach the range by more than their tolerance.
        for c in &cpu {
            let p = bvh.prim(c.id);
            let tol = (2.0 * bound32(&p, ray) + delta) / len;
            let inside = c.iv.exit.t >= ray.t_min + tol && c.iv.entry.t <= ray.t_max - tol;
            let grazed = line_gap(&link_of(&p), &line).0.abs() <= 2.0 * bound32(&p, ray) + delta;
            assert!(!inside || grazed || ivs[k].iter().any(|g| g.id == c.id), "ray {k}: CPU interval {c:?} not listed");
        }
    }

    let got = tubecast_gpu::crossings_table_gpu(&gs, &bvh, &rays).unwrap();
    let want = crossings_table(&bvh, &rays);
    let rows_of =
        |t: &[[f64; 8]], k: usize| -> Vec<[f64; 8]> { t.iter().filter(|r| r[0] == k as f64).copied().collect() };
    let (mut matched, mut explained) = (0, 0);
    for (k, ray) in rays.iter().enumerate() {
        let (g, c) = (rows_of(&got, k), rows_of(&want, k));
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        // Rows in increasing t, per ray.
        assert!(g.windows(2).all(|w| w[0][1] <= w[1][1]), "ray {k}: GPU rows out of order {g:?}");
        let e_of = |r: &[f64; 8]| bound32(&prim_of[&(r[5] as u32)], ray) + delta;
        let gamma = |r: &[f64; 8]| V3::new(r[2], r[3], r[4]).dot(dn).abs().max(1e-12);
        let mut used = vec![false; c.len()];
        let mut lone = Vec::new();
        for a in &g {
            let j = (0..c.len()).find(|&j| {
                !used[j] && c[j][7] == a[7] && (a[1] - c[j][1]).abs() * len * gamma(&c[j]) <= e_of(a) + e_of(&c[j])
            });
            match j {
                Some(j) => {
                    used[j] = true;
                    matched += 1;
                }
                None => lone.push(*a),
            }
        }
        lone.extend(c.iter().zip(&used).filter(|(_, u)| !**u).map(|(r, _)| *r));
        if lone.is_empty() {
            continue;
        }
        let mut cpu = Vec::new();
        bvh.line_intervals(ray, &mut cpu);
        let line = Line { o: ov(ray.o), d: ov(ray.d) };
        for r in &lone {
            let p = prim_of[&(r[5] as u32)];
            let e = e_of(r);
            let tol = 4.0 * (e + delta) / gamma(r);
            let grazed = line_gap(&link_of(&p), &line).0.abs() <= 2.0 * e;
            // An exit (−1) meets another interval's entry, an entry (+1) another's exit.
            let touch = cpu.iter().any(|iv| {
                let other = if r[7] < 0.0 { iv.iv.entry.t } else { iv.iv.exit.t };
                (other - r[1]).abs() * len <= tol
            });
            let at_end = ((r[1] - ray.t_min).abs().min((r[1] - ray.t_max).abs())) * len <= tol;
            assert!(grazed || touch || at_end, "ray {k}: crossing {r:?} on one side only\nGPU {g:?}\nCPU {c:?}");
            explained += 1;
        }
    }
    eprintln!(
        "all crossings: {} rays, {listed} GPU intervals ({graze_only} grazes the CPU lacks), {} GPU rows, {} CPU \
         rows, {matched} matched, {explained} on one side at a graze, near-touch or range end",
        rays.len(),
        got.len(),
        want.len()
    );
    assert!(matched > 3000, "{matched} crossings matched: the test says little");
}

/// An empty scene and rays that miss the scene's box list nothing and give no rows.
#[test]
fn all_crossings_of_misses_are_empty() {
    let Some(gpu) = crate::gpu("all_crossings_of_misses_are_empty") else { return };
    let away = Ray::new(V3::new(100.0, 100.0, 100.0), V3::new(0.0, 0.0, 1.0));
    let empty = Scene::from_polylines(&[], 0.1, "empty").unwrap();
    let bundle = Scene::from_polylines(&generate::bundle(10, 10, 1), 0.05, "bundle").unwrap();
    for scene in [empty, bundle] {
        let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
        let gs = GpuScene::upload(&gpu, &bvh).unwrap();
        assert_eq!(gs.line_intervals(&[away, away]).unwrap(), vec![vec![], vec![]]);
        assert!(tubecast_gpu::crossings_table_gpu(&gs, &bvh, &[away]).unwrap().is_empty());
        assert!(tubecast_gpu::crossings_table_gpu(&gs, &bvh, &[]).unwrap().is_empty());
    }
}
