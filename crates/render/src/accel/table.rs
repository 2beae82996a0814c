//! Per-ray answer tables for `tubecast intersect`, one row of [`HIT_COLUMNS`] `f64` per answer,
//! computed in parallel (rayon; the caller's thread pool decides how many threads) through any
//! [`Tracer`]:
//!
//! * [`closest_table`] (`--query hit`, the default): the closest surface crossing, by the same
//!   [`Tracer::closest_hit`] fast path the renderer uses — no union, no list of intervals;
//! * [`hit_table`] (`--query piece`): the first solid piece (entry and exit of the first
//!   component of the CSG union along the line);
//! * [`crossings_table`] (`--query all`): every exterior boundary of the union in `[t_min, t_max]`.

use super::{first_component, Tracer, HIT_COLUMNS};
use rayon::prelude::*;
use tubecast::csg::{union, Tagged};
use tubecast::Ray;

/// A miss row of [`closest_table`] and [`hit_table`].
pub const MISS_ROW: [f64; HIT_COLUMNS] = [f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0];

/// The closest-hit table of `rays`: per ray `t`, the exit `t` of the hit primitive's own
/// interval, the unit outward normal at `t` (x, y, z), the scene link, its curve parameter `u`
/// at `t`, and a flag: 1 for an entry, −1 when the ray starts inside a tube (`t` is then the
/// exit from the primitive it starts in), 0 for a miss ([`MISS_ROW`]). Rows in ray order.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::{closest_table, Bvh};
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
///
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let bvh = Bvh::build(Scene::from_polylines(&[line], 0.5, "tube").unwrap().primitives());
/// let rows = closest_table(&bvh, &[Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0))]);
/// assert_eq!(rows[0], [2.5, 3.5, 0.0, 1.0, 0.0, 0.0, 0.5, 1.0]);
/// ```
pub fn closest_table(tracer: &dyn Tracer, rays: &[Ray<f64>]) -> Vec<[f64; HIT_COLUMNS]> {
    let mut rows = vec![MISS_ROW; rays.len()];
    closest_rows(tracer, rays, &mut rows);
    rows
}

/// [`closest_table`] into `rows` (one per ray, `rows.len() == rays.len()`), for a caller that
/// streams the table in chunks through one buffer.
pub fn closest_rows(tracer: &dyn Tracer, rays: &[Ray<f64>], rows: &mut [[f64; HIT_COLUMNS]]) {
    fill(rays, rows, |ray| match tracer.closest_hit_exit(ray) {
        Some((h, exit)) => {
            let p = tracer.prim(h.id);
            let flag = if h.entering { 1.0 } else { -1.0 };
            [h.t, exit, h.n.x, h.n.y, h.n.z, p.link as f64, h.u, flag]
        }
        None => MISS_ROW,
    });
}

/// `rows[k] = row(&rays[k])` for every ray, in parallel.
fn fill(rays: &[Ray<f64>], rows: &mut [[f64; HIT_COLUMNS]], row: impl Fn(&Ray<f64>) -> [f64; HIT_COLUMNS] + Sync) {
    assert_eq!(rays.len(), rows.len(), "one row per ray");
    rows.par_iter_mut().zip(rays.par_iter()).for_each(|(r, ray)| *r = row(ray));
}

/// The `--query piece` table of `rays`: `t_in`, `t_out` of the first component of the union
/// ([`first_component`]), the entry normal (x, y, z), the entry's scene link, its curve
/// parameter `u`, and 1; a miss is [`MISS_ROW`]. Rows in ray order.
pub fn hit_table(tracer: &dyn Tracer, rays: &[Ray<f64>]) -> Vec<[f64; HIT_COLUMNS]> {
    let mut rows = vec![MISS_ROW; rays.len()];
    hit_rows(tracer, rays, &mut rows);
    rows
}

/// [`hit_table`] into `rows` (one per ray, `rows.len() == rays.len()`).
pub fn hit_rows(tracer: &dyn Tracer, rays: &[Ray<f64>], rows: &mut [[f64; HIT_COLUMNS]]) {
    fill(rays, rows, |ray| match first_component(tracer, ray) {
        Some((e, x)) => [e.t, x.t, e.n.x, e.n.y, e.n.z, tracer.prim(e.id).link as f64, e.u, 1.0],
        None => MISS_ROW,
    });
}

/// The `--query all` table of `rays`: one row per exterior boundary of the union of all tubes
/// within each ray's `[t_min, t_max]`, in ray order and increasing `t`: the ray's index, `t`,
/// the unit outward normal (x, y, z), the scene link, its curve parameter `u`, and 1 for an
/// entry or −1 for an exit. A ray that misses has no row.
pub fn crossings_table(tracer: &dyn Tracer, rays: &[Ray<f64>]) -> Vec<[f64; HIT_COLUMNS]> {
    let per_ray: Vec<Vec<[f64; HIT_COLUMNS]>> = rays
        .par_iter()
        .enumerate()
        .map(|(k, ray)| {
            let mut ivs: Vec<Tagged<f64>> = Vec::new();
            tracer.line_intervals(ray, &mut ivs);
            let mut rows = Vec::new();
            union(&mut ivs, ray.t_min, ray.t_max, |b| {
                let link = tracer.prim(b.id).link as f64;
                rows.push([k as f64, b.t, b.n.x, b.n.y, b.n.z, link, b.u, if b.entering { 1.0 } else { -1.0 }]);
            });
            rows
        })
        .collect();
    per_ray.concat()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Bvh;
    use crate::scene::generate::{self, Rng};
    use crate::scene::Scene;
    use tubecast::V3;

    /// Rays from outside the scene box start outside every tube, so the first component's
    /// entry is the smallest entry `t ≥ 0` over all primitive intervals — the closest hit. Both
    /// paths compute each interval by the same [`crate::scene::Prim::intersect`] arithmetic
    /// (lane packets are bit-identical to it), so `t` must agree bit for bit; the link may differ
    /// only where two primitives enter at exactly the same `t`.
    #[test]
    fn closest_hit_equals_the_first_component_entry_from_outside() {
        let scene = Scene::from_polylines(&generate::bundle(40, 30, 3), 0.05, "bundle").unwrap();
        let bvh = Bvh::build(scene.primitives());
        let (lo, hi) = scene.stats().bounds;
        let (c, r) = ((V3::from(lo) + V3::from(hi)) * 0.5, (V3::from(hi) - V3::from(lo)).length());
        let mut rng = Rng::new(7);
        let rays: Vec<Ray<f64>> = (0..3000)
            .map(|_| {
                let dir = V3::from(rng.unit()).normalize_or_zero();
                let o = c - dir * r;
                // Aim at a random point of the inner third of the box: most rays hit.
                let aim = c + V3::from(rng.unit()) * (0.1 * r);
                Ray::new(o, aim - o)
            })
            .collect();
        let (fast, piece) = (closest_table(&bvh, &rays), hit_table(&bvh, &rays));
        let mut hits = 0;
        for (k, (f, p)) in fast.iter().zip(&piece).enumerate() {
            assert_eq!(f[0].to_bits(), p[0].to_bits(), "ray {k}: closest {f:?} vs piece {p:?}");
            assert_eq!(f[7] == 0.0, p[7] == 0.0, "ray {k}: hit/miss {f:?} vs {p:?}");
            if f[7] != 0.0 {
                hits += 1;
                assert_eq!(f[7], 1.0, "ray {k} starts outside: an entry");
                if f[5] != p[5] {
                    let other =
                        bvh.prims.iter().filter(|q| q.link as f64 == p[5]).filter_map(|q| q.first_hit(&rays[k]));
                    assert!(other.map(|h| h.t).any(|t| t == f[0]), "ray {k}: links differ without a tie");
                }
            }
        }
        assert!(hits > 300, "only {hits} of 3000 rays hit: the test says little");
    }

    #[test]
    fn all_crossings_pair_up_and_start_with_the_piece_entry() {
        let scene = Scene::from_polylines(&generate::furball(400, 20, 5), 0.05, "furball").unwrap();
        let bvh = Bvh::build(scene.primitives());
        let (lo, hi) = scene.stats().bounds;
        let (lo, hi) = (V3::from(lo), V3::from(hi));
        let at = |i: usize| lo.y + (hi.y - lo.y) * (i % 20) as f64 / 20.0;
        let rays: Vec<Ray<f64>> = (0..400)
            .map(|i| Ray::new(V3::new(lo.x - 1.0, at(i), at(i / 20) - lo.y + lo.z), V3::new(1.0, 0.0, 0.0)))
            .collect();
        let all = crossings_table(&bvh, &rays);
        let piece = hit_table(&bvh, &rays);
        for (k, p) in piece.iter().enumerate() {
            let rows: Vec<_> = all.iter().filter(|r| r[0] == k as f64).collect();
            assert_eq!(rows.len() % 2, 0, "ray {k} starts outside: entries and exits pair up");
            assert!(rows.windows(2).all(|w| w[0][1] <= w[1][1] && w[0][7] == -w[1][7]), "ray {k}: {rows:?}");
            match rows.first() {
                Some(r) => assert_eq!((r[1], r[7], rows[1][1]), (p[0], 1.0, p[1]), "ray {k}"),
                None => assert_eq!(p[7], 0.0, "ray {k}"),
            }
        }
        assert!(all.len() > 100, "only {} crossings: the test says little", all.len());
    }
}
