//! Ray queries on the grid: the DDA walk with a closest hit accepted inside the current
//! voxel's `t` range (module docs), any hit, and every line interval for the CSG union.

use super::Grid;
use crate::accel::Hit;
use tubecast::csg::Tagged;
use tubecast::{voxel, Ray, V3};

/// The last few primitives tested on a walk, so a primitive listed in consecutive voxels is
/// tested once there (a check, not a guarantee: older ones may be tested again, harmlessly).
struct Mailbox {
    ids: [u32; 8],
    next: usize,
}

impl Mailbox {
    fn new() -> Self {
        Self { ids: [u32::MAX; 8], next: 0 }
    }
    /// True when `id` is new (and remember it).
    #[inline]
    fn fresh(&mut self, id: u32) -> bool {
        if self.ids.contains(&id) {
            return false;
        }
        self.ids[self.next] = id;
        self.next = (self.next + 1) % self.ids.len();
        true
    }
}

impl Grid {
    /// Walk the voxels of `ray`'s line over `[t_lo, t_hi]` (ray parameter), skipping empty
    /// cells of the coarse levels, handing each voxel's list and exit `t` to `f` until it
    /// returns false.
    #[inline]
    fn walk(&self, ray: &Ray<f64>, t_lo: f64, t_hi: f64, mut f: impl FnMut(&[u32], f64) -> bool) {
        if self.prims.is_empty() {
            return;
        }
        let o = self.to_grid(ray.o);
        let d = ray.d * self.inv_h;
        self.walk_level(self.skip.len(), o, d, t_lo, t_hi, &mut f);
    }

    /// The walk over `[t0, t1]` at skip level `k` (0: the voxels); false once `f` stopped it.
    #[inline]
    fn walk_level<F: FnMut(&[u32], f64) -> bool>(
        &self,
        k: usize,
        o: V3<f64>,
        d: V3<f64>,
        t0: f64,
        t1: f64,
        f: &mut F,
    ) -> bool {
        let mut go = true;
        if k == 0 {
            voxel::dda(o, d, t0, t1, self.dims, |c, _, tc| {
                go = f(self.list(c), tc);
                go
            });
            return go;
        }
        let level = &self.skip[k - 1];
        let s = 1.0 / level.side as f64;
        voxel::dda(o * s, d * s, t0, t1, level.dims, |c, a, b| {
            if level.occupied[level.index(c)] {
                go = self.walk_level(k - 1, o, d, a, b, f);
            }
            go
        });
        go
    }

    /// The closest surface crossing in `[t_min, t_max]`; equal `t` decided by
    /// [`tubecast::Hit::closer`], as in every tracer.
    pub(super) fn closest(&self, ray: &Ray<f64>) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut seen = Mailbox::new();
        self.walk(ray, ray.t_min, ray.t_max, |list, t1| {
            for &id in list {
                if !seen.fresh(id) {
                    continue;
                }
                let p = &self.prims[id as usize];
                if let Some(h) = p.first_hit(ray) {
                    Hit { id, ..h }.keep_closer(&mut best);
                }
            }
            best.map_or(true, |b| b.t > t1)
        });
        best
    }

    /// True when any primitive meets `[t_min, t_max]` of the ray.
    pub(super) fn any(&self, ray: &Ray<f64>) -> bool {
        let mut found = false;
        let mut seen = Mailbox::new();
        self.walk(ray, ray.t_min, ray.t_max, |list, _| {
            found = list.iter().any(|&id| seen.fresh(id) && self.prims[id as usize].meets(ray));
            !found
        });
        found
    }

    /// Every primitive's intervals with the ray's whole line (each primitive once).
    pub(super) fn intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        let mut ids = Vec::new();
        let mut seen = Mailbox::new();
        self.walk(ray, f64::NEG_INFINITY, f64::INFINITY, |list, _| {
            ids.extend(list.iter().filter(|&&id| seen.fresh(id)));
            true
        });
        ids.sort_unstable();
        ids.dedup();
        let line = Ray::with_range(ray.o, ray.d, f64::NEG_INFINITY, f64::INFINITY);
        for id in ids {
            self.prims[id as usize].pieces(&line, |iv| out.push(Tagged { iv, id }));
        }
    }
}
