//! CSG union of intervals along one ray (Han et al. 2019 §4.3): keep only the exterior
//! boundaries, i.e. the 0→1 and 1→0 transitions of the count of overlapping intervals.
//!
//! This is what transparent rendering needs: the interior surfaces where links, spheres and
//! bifurcations overlap are dropped. Rays that start inside a tube are handled by passing the
//! full line intervals (the kernels return them unclipped) and a `t_min`: the union is formed
//! over the whole line and only boundaries in `[t_min, t_max]` are reported, so a ray starting
//! inside sees its first exit and nothing of the surfaces behind its origin.

use crate::ray::{Hit, Interval};
use crate::real::Scalar;

/// One primitive's interval along a ray, tagged with the primitive's id.
///
/// ```
/// use tubecast::{Primitive, Ray, Sphere, Tagged, V3};
/// let ray = Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0));
/// let ball = Sphere::new(V3::new(5.0, 0.0, 0.0), 1.0)?;
/// let t = Tagged { iv: ball.line_interval(&ray), id: 7 };
/// assert!(t.iv.hit && t.id == 7);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tagged<T: Scalar> {
    /// The line interval (a kernel's output; entries with `hit == false` are ignored).
    pub iv: Interval<T>,
    /// Caller's primitive id (e.g. link index).
    pub id: u32,
}

/// Union of `intervals` along the ray; calls `emit` for each exterior boundary (a [`Hit`]:
/// `entering` for a 0 → 1 transition, its `id` the owning primitive's) with
/// `t ∈ [t_min, t_max]`, in increasing `t`. Returns the number emitted.
///
/// Sorts `intervals` in place by entry (no allocation). Intervals that touch (`entry ==
/// previous exit`) merge: a surface shared exactly by two primitives is interior.
///
/// ```
/// use tubecast::{union, Primitive, Ray, Sphere, Tagged, V3};
/// // Two overlapping balls on the x axis: [4, 6] ∪ [5.5, 7.5] has one entry and one exit.
/// let ray = Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0));
/// let balls = [Sphere::new(V3::new(5.0, 0.0, 0.0), 1.0)?, Sphere::new(V3::new(6.5, 0.0, 0.0), 1.0)?];
/// let mut ivs: Vec<_> = balls.iter().zip(0..).map(|(b, id)| Tagged { iv: b.line_interval(&ray), id }).collect();
/// let mut out = Vec::new();
/// assert_eq!(union(&mut ivs, ray.t_min, ray.t_max, |b| out.push((b.t, b.id, b.entering))), 2);
/// assert_eq!(out, [(4.0, 0, true), (7.5, 1, false)]);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
pub fn union<T: Scalar>(intervals: &mut [Tagged<T>], t_min: T, t_max: T, mut emit: impl FnMut(Hit<T>)) -> usize {
    // By entry under the one `closer` rule (misses last), so that the owner of a boundary is
    // the same whatever order the intervals arrive in.
    intervals.sort_unstable_by(|a, b| match (a.iv.hit, b.iv.hit) {
        (true, true) => Hit::new(a.iv.entry, a.id, true).cmp_closer(&Hit::new(b.iv.entry, b.id, true)),
        (x, y) => y.cmp(&x),
    });
    let mut n = 0;
    let mut cur: Option<(Tagged<T>, Tagged<T>)> = None; // (owner of entry, owner of exit)
    let mut flush = |entry: &Tagged<T>, exit: &Tagged<T>, n: &mut usize| {
        let (ti, to) = (entry.iv.entry.t, exit.iv.exit.t);
        if ti >= t_min && ti <= t_max {
            emit(Hit::new(entry.iv.entry, entry.id, true));
            *n += 1;
        }
        if to >= t_min && to <= t_max {
            emit(Hit::new(exit.iv.exit, exit.id, false));
            *n += 1;
        }
    };
    for iv in intervals.iter() {
        if !iv.iv.hit {
            break;
        }
        match cur {
            Some((e, x)) if iv.iv.entry.t <= x.iv.exit.t => {
                if iv.iv.exit.t > x.iv.exit.t {
                    cur = Some((e, *iv));
                }
            }
            Some((e, x)) => {
                flush(&e, &x, &mut n);
                cur = Some((*iv, *iv));
            }
            None => cur = Some((*iv, *iv)),
        }
    }
    if let Some((e, x)) = cur {
        flush(&e, &x, &mut n);
    }
    n
}
