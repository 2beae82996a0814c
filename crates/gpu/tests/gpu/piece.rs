//! The first union component on the GPU (`intersect --query piece`) against the CPU's
//! `first_component`, with the band of the tree test (module docs there): the entry is checked
//! as a closest hit is; an exit may differ from the CPU's only where the union's component ends
//! at a near-touch — another interval of the line enters within the band of the earlier of the
//! two exits — so each GPU exit lies within `E + δ` of its primitive's surface and agrees with
//! the CPU's within `(E_gpu + E_cpu + 2δ)/(γ·|d|)` or at such a near-touch.

use crate::{bound32, link_of, ov};
use tubecast::{Ray, V3};
use tubecast_gpu::{Gpu, GpuScene};
use tubecast_oracle::sweep_dist;
use tubecast_render::accel::{first_component, Tracer, WideBvh};
use tubecast_render::scene::generate::Rng;
use tubecast_render::scene::{Model, Scene};

#[test]
fn first_piece_matches_the_cpu() {
    let Some(gpu) = crate::gpu("first_piece_matches_the_cpu") else { return };
    let scene = crate::fur();
    let bvh = WideBvh::from_scene(&scene, Model::Links).unwrap();
    let (both, near_touch) = compare_first_pieces(&gpu, &scene, &bvh, 3000, 21, "links");
    eprintln!("first piece: {both} of 3000 rays hit on both; {near_touch} boundaries at near-touches");
    assert!(both > 500, "{both}");
}

/// The GPU's first components of `bvh` (built over `scene`) against the CPU's on `n` rays near
/// the scene's nodes, from outside and (every third) from inside, by the band in the module
/// docs; a one-sided hit must lie within the band of a graze (the line's gap to its primitive,
/// [`crate::gap`]) or at `t_max`. A link boundary is also held to its surface by the
/// independent sweep distance (the oracle has no point distance for a spline piece). Returns
/// the rays hit on both sides and the boundaries that differ at a near-touch.
pub(crate) fn compare_first_pieces(
    gpu: &Gpu,
    scene: &Scene,
    bvh: &WideBvh,
    n: usize,
    seed: u64,
    name: &str,
) -> (usize, usize) {
    let gs = GpuScene::upload(gpu, bvh).unwrap();
    let delta = gs.band();
    let mut rng = Rng::new(seed);
    let rays: Vec<Ray<f64>> = (0..n)
        .map(|k| {
            let p = crate::near_node(&mut rng, scene);
            let d = V3::from(rng.unit());
            // From outside, and from inside (a ray starting in a tube: entry before t_min).
            let o = if k % 3 == 0 { p } else { p - d * 30.0 };
            Ray::with_range(o, d, 0.0, 50.0)
        })
        .collect();
    let got = gs.first_pieces(&rays).unwrap();
    let (mut both, mut near_touch) = (0, 0);
    for (k, ray) in rays.iter().enumerate() {
        let cpu = first_component(bvh, ray);
        match (got[k], cpu) {
            (None, None) => {}
            (Some((e, _)), None) | (None, Some((e, _))) => {
                let p = bvh.prim(e.id);
                let tol = 2.0 * bound32(&p, ray) + delta;
                let line = tubecast_oracle::Line { o: ov(ray.o), d: ov(ray.d) };
                let gap = crate::gap(&p, &line);
                let at_end = (e.t - ray.t_max).abs() <= tol;
                assert!(
                    gap.abs() <= tol || at_end,
                    "{name} ray {k}: GPU {:?} CPU {cpu:?}: gap {gap:e} > {tol:e}",
                    got[k]
                );
            }
            (Some((ge, gx)), Some((ce, cx))) => {
                both += 1;
                for (g, c) in [(ge, ce), (gx, cx)] {
                    let pg = bvh.prim(g.id);
                    let eg = bound32(&pg, ray) + delta;
                    if pg.quad().is_none() {
                        let (sd, _) = sweep_dist(&link_of(&pg), ov(ray.at(g.t)));
                        assert!(
                            sd.abs() <= eg + 1e-12,
                            "{name} ray {k}: GPU boundary {sd:e} off its surface (E + δ = {eg:e})"
                        );
                    }
                    let e = eg + bound32(&bvh.prim(c.id), ray) + delta;
                    let gamma = c.n.dot(ray.d).abs().max(1e-12);
                    if (g.t - c.t).abs() * gamma > e {
                        // A near-touch: between the two boundaries (within the band), one line
                        // interval ends within the band of where another begins, so that one
                        // side merged the two and the other saw a gap. (An entry of the CPU's
                        // alone explains nothing: every boundary is some interval's entry or exit.)
                        let mut ivs = Vec::new();
                        bvh.line_intervals(ray, &mut ivs);
                        let tol = 4.0 * e / gamma;
                        let (early, late) = (g.t.min(c.t) - tol, g.t.max(c.t) + tol);
                        let touch = ivs.iter().enumerate().any(|(i, a)| {
                            (early..=late).contains(&a.iv.exit.t)
                                && ivs
                                    .iter()
                                    .enumerate()
                                    .any(|(j, b)| j != i && (b.iv.entry.t - a.iv.exit.t).abs() <= tol)
                        });
                        assert!(touch, "{name} ray {k}: GPU {g:?} CPU {c:?}");
                        near_touch += 1;
                    }
                }
            }
        }
    }
    // The table's rows are these pieces, in hit_table's columns.
    let rows = tubecast_gpu::piece_table_gpu(&gs, bvh, &rays).unwrap();
    for (row, p) in rows.iter().zip(&got) {
        match p {
            Some((e, x)) => assert_eq!((row[0], row[1], row[5]), (e.t, x.t, f64::from(bvh.prim(e.id).link))),
            None => assert_eq!(*row, tubecast_render::accel::MISS_ROW),
        }
    }
    (both, near_touch)
}

/// A ray starting inside a tube, along it: the first component's entry lies behind the origin
/// (`first_component`'s contract: the component of the union over the whole line), at the
/// tube's far cap, reached through links that lie wholly behind the origin. The GPU's entry and
/// exit equal the CPU's within the band of [`compare_first_pieces`] (`(E_gpu + E_cpu + 2δ)/γ`).
/// (Links: the spline scenes' rays from inside are `spline::first_piece_matches_the_cpu_with_splines`'s,
/// and each spline module costs a long shader compile on lavapipe.)
#[test]
fn first_piece_of_a_ray_starting_inside_reaches_behind_it() {
    use tubecast_render::io::Polyline;
    let Some(gpu) = crate::gpu("first_piece_of_a_ray_starting_inside_reaches_behind_it") else { return };
    // Nine nodes a unit apart, radius 0.1: eight links, each overlapping the next at its node.
    let points: Vec<[f64; 3]> = (0..9).map(|i| [f64::from(i), 0.02 * f64::from(i % 2), 0.0]).collect();
    let scene = Scene::from_polylines(&[Polyline { points, radii: vec![] }], 0.1, "chain").unwrap();
    for model in [Model::Links] {
        let bvh = WideBvh::from_scene(&scene, model).unwrap();
        let gs = GpuScene::upload(&gpu, &bvh).unwrap();
        let delta = gs.band();
        let d = V3::new(1.0, 0.001, 0.0005);
        let d = d * (1.0 / d.length());
        // From the middle, forwards and backwards: the component reaches 3.6 or 4.6 behind.
        let rays = [
            Ray::with_range(V3::new(4.5, 0.01, 0.0), d, 0.0, 50.0),
            Ray::with_range(V3::new(4.5, 0.01, 0.0), -d, 0.0, 50.0),
        ];
        let got = gs.first_pieces(&rays).unwrap();
        for (k, ray) in rays.iter().enumerate() {
            let (ce, cx) = first_component(&bvh, ray).expect("the ray starts inside");
            assert!(ce.t < -3.0 && cx.t > 3.0, "{model:?} ray {k}: CPU component {ce:?} {cx:?}");
            let (ge, gx) = got[k].unwrap_or_else(|| panic!("{model:?} ray {k}: no GPU component"));
            for (g, c) in [(ge, ce), (gx, cx)] {
                let e = bound32(&bvh.prim(g.id), ray) + bound32(&bvh.prim(c.id), ray) + 2.0 * delta;
                let gamma = c.n.dot(ray.d).abs().max(1e-12);
                assert!(
                    (g.t - c.t).abs() * gamma <= e,
                    "{model:?} ray {k}: GPU {g:?} CPU {c:?}, apart {:e} > {e:e}",
                    (g.t - c.t).abs() * gamma
                );
            }
        }
    }
}
