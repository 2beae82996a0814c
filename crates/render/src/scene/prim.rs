//! Renderer primitives: `f32` geometry relative to an `f64` local origin.

use tubecast::QuadTube;
use tubecast::Solver;
use tubecast::{Crossing, Hit, Interval, Ray};
use tubecast::{GeometryError, LinkShape, Primitive, Sphere, V3};
use tubecast::{PendingInterval, RoundCone};

/// Which exact shape a primitive is (the tag of [`Shape`], for counting and comparing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimKind {
    /// A sphere ([`Shape::Sphere`]).
    Sphere,
    /// A cylinder link (equal radii).
    Cylinder,
    /// A tangent-cone link (different radii).
    Cone,
    /// A quadratic sphere-swept spline sub-segment ([`Shape::Spline`]).
    Spline,
}

/// The geometry of a primitive, in `f32` relative to its [`Prim::origin`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere centred at the local origin.
    Sphere {
        /// Radius.
        r: f32,
    },
    /// A cylinder link (equal radii), centres relative to the local origin.
    Cylinder(RoundCone<f32>),
    /// A tangent-cone link (different radii), centres relative to the local origin.
    Cone(RoundCone<f32>),
    /// A quadratic sphere-swept spline sub-segment: one half of a cubic Hermite segment
    /// ([`tubecast::HermiteSegment::split`]). Its middle control radius may be
    /// negative as long as the radius curve is not ([`QuadTube`]).
    Spline {
        /// Control points relative to the local origin, and control radii.
        quad: QuadTube<f32>,
        /// Which half of its link's Hermite segment it is (0: from the link's first node,
        /// 1: to its second).
        half: u8,
    },
}

/// A primitive stored for rendering: its [`Shape`] in `f32` relative to an `f64` local origin
/// (a link's or a spline sub-segment's midpoint, a sphere's centre).
///
/// Why: a coordinate near `1e6` has an `f32` spacing of `0.0625`, so storing world
/// coordinates in `f32` moves a thin tube by a good fraction of its radius. Relative to the
/// midpoint, the stored offsets are at most half the link length, so their rounding error is
/// `2⁻²⁴` of the link's own size wherever the link is. Rays are moved the same way in `f64`
/// (to the point of the line nearest the origin) before the `f32` kernel runs.
///
/// ```
/// use tubecast::{RoundCone, V3};
/// use tubecast_render::scene::{Prim, PrimKind};
///
/// let link = RoundCone::new(V3::new(1e6, 0.0, 0.0), 0.5, V3::new(1e6 + 4.0, 0.0, 0.0), 0.5).unwrap();
/// let p = Prim::from_link(&link, 0);
/// assert_eq!((p.kind(), p.origin), (PrimKind::Cylinder, [1e6 + 2.0, 0.0, 0.0]));
/// let ray = tubecast::Ray::new(V3::new(1e6 + 2.0, 0.0, -10.0), V3::new(0.0, 0.0, 1.0));
/// assert_eq!(p.first_hit(&ray).map(|h| h.t), Some(9.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prim {
    /// Local origin (world coordinates).
    pub origin: [f64; 3],
    /// Index of the scene link this primitive models (a spline sub-segment: the link whose
    /// Hermite segment it is half of).
    pub link: u32,
    /// The geometry relative to `origin`.
    pub shape: Shape,
}

/// True only where the stable link kernel surely misses the local `f32` line `o + τ·d` (`d`
/// unit to `f32` rounding): the line passes the link's axis segment `[a, b]` farther than
/// `R = max(ra, rb)` plus a margin `M = 2⁻¹²·(L₁ + R + |o − m|₁) + 2⁻¹⁶·(|o|₁ + |m|₁)` (`L₁`,
/// `|·|₁`: 1-norms, upper bounds of the Euclidean ones; `m` the link's midpoint, `≈ 0` for a
/// [`Prim::from_link`] primitive, up to a cluster's extent for links sharing a cluster's origin).
/// A static filter, as in robust predicates: it runs before the kernel and never changes a hit.
///
/// Why it is safe: the solid lies within distance `R` of the segment, and the kernel reports
/// only crossings it has checked against the solid to its own `ε`-sized error. A stump crossing
/// stands only where the distance-like residual after the Newton settle is
/// `|g| ≤ 64ε·min(scale, S + D)` (`StumpSide::polish`, `ε = 2⁻²³` in `f32`, `S + D =
/// max(L, ra, rb) + |o − m| ≤ L₁ + R + |o − m|₁`), or at a cap end inside the cone (`g ≤ 0`, a point
/// of the solid); its sphere chords err by a few `ε` of the same sizes. So every crossing it
/// accepts lies within `E = 64ε·(L₁ + R + |o − m|₁)` plus a few `ε` of that size of the solid,
/// and on the line: the line passes the segment within `R + E`. Forming the midpoint, the
/// frame and this distance in `f32` from coordinates relative to the local origin adds a few
/// `ε·(|o| + |m|)`, which the second term of `M` covers 32 times over; the first term is 32
/// times `64ε = 2⁻¹⁷`. A rejected line is therefore a kernel miss (the test
/// `filter_rejects_only_kernel_misses` below compares filtered and unfiltered answers bit for
/// bit on lines passing at `R·(1 + δ)`, `δ` down to `10⁻⁶`, also for links stored in a
/// cluster's frame).
#[inline(always)]
pub(crate) fn link_surely_misses(c: &RoundCone<f32>, o: V3<f32>, d: V3<f32>) -> bool {
    let v = c.b - c.a;
    let w = c.a - o;
    // Components perpendicular to the line: the distance at axis parameter s is |w⊥ + s·v⊥|.
    let wp = w - d * w.dot(d);
    let vp = v - d * v.dot(d);
    let vp2 = vp.length2();
    let s = if vp2 > 0.0 { (-wp.dot(vp) / vp2).clamp(0.0, 1.0) } else { 0.0 };
    let dist2 = (wp + vp * s).length2();
    let r = c.ra.max(c.rb);
    let n1 = |x: V3<f32>| x.x.abs() + x.y.abs() + x.z.abs();
    let m = (c.a + c.b) * 0.5;
    let reach = r + (n1(v) + r + n1(o - m)) * (1.0 / 4096.0) + (n1(o) + n1(m)) * (1.0 / 65536.0);
    // NaN compares false: no rejection.
    dist2 > reach * reach
}

/// The point of the line `o + s·dn` (`dn` unit, `f64`) nearest the local origin `origin`,
/// relative to it and rounded to `f32`, and its distance `s = tc` along `dn`: every local ray
/// of a primitive (or of a cluster of links sharing one origin) is made by these operations.
#[inline(always)]
pub(crate) fn local_origin(origin: [f64; 3], o: V3<f64>, dn: V3<f64>) -> (V3<f32>, f64) {
    let org = V3::from(origin);
    let tc = (org - o).dot(dn); // distance along dn to the nearest point
    ((o + dn * tc - org).cast::<f32>(), tc)
}

/// A link's interval with the world ray `ray`, given its local `f32` ray `rl` (unit direction,
/// made by [`local_origin`], `tc` and `len = |d|` as [`Prim::intersect_unit`] takes them):
/// [`link_surely_misses`], then the stable kernel, mapped back by [`Prim::to_world`].
#[inline(always)]
pub(crate) fn link_interval(c: &RoundCone<f32>, rl: &Ray<f32>, tc: f64, len: f64, ray: &Ray<f64>) -> Interval<f64> {
    if link_surely_misses(c, rl.o, rl.d) {
        return Interval::miss();
    }
    Prim::to_world(&c.intersect(rl), tc, len, ray)
}

/// A link's first crossing within the ray's range, found by exactly the arithmetic of
/// [`link_interval`] then [`Interval::first_hit`] (so its `t`, and once finished its normal and
/// curve parameter, equal theirs bit for bit) but with the normal and curve parameter left to
/// [`PendingHit::finish`]: a closest-hit search finishes only the crossing it keeps.
#[derive(Clone, Copy)]
pub(crate) struct PendingHit {
    /// The crossing's `t` along the world ray.
    pub t: f64,
    /// The exit `t` of the link's interval (that of `Prim::intersect`).
    pub t_out: f64,
    /// The hit's primitive id.
    pub id: u32,
    entering: bool,
    cone: RoundCone<f32>,
    line: PendingInterval<f32>,
}

impl PendingHit {
    /// The link's first crossing of `ray` within its range (`rl`, `tc`, `len` as
    /// [`link_interval`] takes them), if any.
    #[inline(always)]
    pub fn of_link(c: &RoundCone<f32>, rl: &Ray<f32>, tc: f64, len: f64, ray: &Ray<f64>, id: u32) -> Option<Self> {
        if link_surely_misses(c, rl.o, rl.d) {
            return None;
        }
        // `Primitive::intersect`, `Prim::to_world`, then `Interval::first_hit`.
        let line = c.pending_line(rl).clip(rl);
        if !line.hit {
            return None;
        }
        let (t_in, t_out) = Prim::world_range(line.t_in, line.t_out, tc, len, ray)?;
        let entering = Interval::first_end(t_in, t_out, ray.t_min, ray.t_max)?;
        let t = if entering { t_in } else { t_out };
        Some(Self { t, t_out, id, entering, cone: *c, line })
    }

    /// The hit, with the normal and curve parameter of its crossing.
    #[inline]
    pub fn finish(&self) -> Hit<f64> {
        let c = if self.entering { self.line.entry(&self.cone) } else { self.line.exit(&self.cone) };
        Hit::new(Crossing { t: self.t, ..c.to_f64() }, self.id, self.entering)
    }
}

/// The closest hit of a search so far: finished (a whole primitive's, with the exit `t` of its
/// interval) or pending (a link's).
#[derive(Clone, Copy, Default)]
pub(crate) enum Best {
    #[default]
    None,
    Done(Hit<f64>, f64),
    Pending(PendingHit),
}

impl Best {
    /// `t` of the hit held (`None` when none).
    #[inline(always)]
    pub fn t(&self) -> Option<f64> {
        match self {
            Best::None => None,
            Best::Done(h, _) => Some(h.t),
            Best::Pending(p) => Some(p.t),
        }
    }

    /// The hit held, finished, and the exit `t` of its primitive's interval.
    #[inline]
    pub fn finish(&self) -> Option<(Hit<f64>, f64)> {
        match self {
            Best::None => None,
            Best::Done(h, x) => Some((*h, *x)),
            Best::Pending(p) => Some((p.finish(), p.t_out)),
        }
    }

    /// Keep `cand` where it is closer than the hit held, by [`Hit::closer`]: decided on `t`
    /// alone where the two differ, on the finished hits where they are equal.
    #[inline(always)]
    pub fn keep(&mut self, cand: Best) {
        let (Some(tc), Some(tb)) = (cand.t(), self.t()) else {
            if self.t().is_none() {
                *self = cand;
            }
            return;
        };
        if tc < tb {
            *self = cand;
        } else if tc.partial_cmp(&tb) != Some(std::cmp::Ordering::Greater) {
            if let (Some((c, _)), Some((b, _))) = (cand.finish(), self.finish()) {
                if c.closer(&b) {
                    *self = cand;
                }
            }
        }
    }
}

/// A sphere of radius `r` at the local origin as a (degenerate) round cone.
fn sphere_cone(r: f32) -> RoundCone<f32> {
    RoundCone { a: V3::zero(), ra: r, b: V3::zero(), rb: r }
}

/// Whether [`Prim::from_link`] stores the link as a sphere (its larger end sphere): where one end
/// sphere contains the other ([`LinkShape::Sphere`]), and where the link is shorter than
/// [`super::SHORT_LINK`] (its `f32` squared length would be subnormal) and than `2⁻¹⁸` of its
/// larger radius (so the sphere is within half the kernels' band of it; derivation at
/// [`super::MIN_RADIUS`]). In a scene (radii `≥ MIN_RADIUS`) the second condition follows
/// from the first; it leaves primitives built beyond the scene's limits as they were.
#[inline]
pub(crate) fn stored_as_sphere(l: &RoundCone<f64>) -> bool {
    let len = (l.b - l.a).length();
    l.shape() == LinkShape::Sphere || (len < super::SHORT_LINK && len * 262_144.0 <= l.ra.max(l.rb))
}

impl Prim {
    /// The cheapest exact primitive for a validated link: a sphere where `stored_as_sphere`
    /// (one end sphere contains the other, or the link is shorter than [`super::SHORT_LINK`] and
    /// than `2⁻¹⁸` of its radius), else a cylinder or a tangent-cone link.
    pub fn from_link(l: &RoundCone<f64>, link: u32) -> Self {
        let shape = l.shape();
        if stored_as_sphere(l) {
            // The larger sphere contains the link.
            let (c, r) = if l.ra >= l.rb { (l.a, l.ra) } else { (l.b, l.rb) };
            return Self { origin: c.to_array(), link, shape: Shape::Sphere { r: r as f32 } };
        }
        let mid = (l.a + l.b) * 0.5;
        let cone = RoundCone { a: (l.a - mid).cast(), ra: l.ra as f32, b: (l.b - mid).cast(), rb: l.rb as f32 };
        let shape = if shape == LinkShape::Cylinder { Shape::Cylinder(cone) } else { Shape::Cone(cone) };
        Self { origin: mid.to_array(), link, shape }
    }

    /// A spline sub-segment primitive from a validated `f64` quadratic segment: control
    /// points stored in `f32` relative to the curve's midpoint `p(½)` (in `f64`), radii in
    /// `f32`. Errors when the rounded segment is not a valid `f32` [`QuadTube`] (an extent
    /// whose square overflows `f32` in the kernel, beyond ≈ 2·10¹⁸; the segments of scenes
    /// within [`super::MAX_COORD`] stay below it, so this is a guard, not an expected outcome).
    pub fn from_quad(q: &QuadTube<f64>, link: u32, half: u8) -> Result<Self, GeometryError> {
        let mid = q.point(0.5);
        let [b0, b1, b2] = q.b;
        let c: [V3<f32>; 3] = [(b0 - mid).cast(), (b1 - mid).cast(), (b2 - mid).cast()];
        let quad = QuadTube::new(c, q.r.map(|x| x as f32))?;
        Ok(Self { origin: mid.to_array(), link, shape: Shape::Spline { quad, half } })
    }

    /// Which exact shape the primitive is.
    pub fn kind(&self) -> PrimKind {
        match self.shape {
            Shape::Sphere { .. } => PrimKind::Sphere,
            Shape::Cylinder(_) => PrimKind::Cylinder,
            Shape::Cone(_) => PrimKind::Cone,
            Shape::Spline { .. } => PrimKind::Spline,
        }
    }

    /// Which half of its link's Hermite segment a spline sub-segment is; 0 for the others.
    pub fn half(&self) -> u8 {
        match self.shape {
            Shape::Spline { half, .. } => half,
            _ => 0,
        }
    }

    /// The round cone of a link or sphere primitive relative to `origin` (a sphere: both
    /// ends at the origin with its radius); `None` for a spline sub-segment.
    #[inline]
    pub fn round_cone(&self) -> Option<RoundCone<f32>> {
        match self.shape {
            Shape::Sphere { r } => Some(sphere_cone(r)),
            Shape::Cylinder(c) | Shape::Cone(c) => Some(c),
            Shape::Spline { .. } => None,
        }
    }

    /// The stored spline sub-segment relative to `origin`; `None` for links and spheres.
    #[inline]
    pub fn quad(&self) -> Option<QuadTube<f32>> {
        match self.shape {
            Shape::Spline { quad, .. } => Some(quad),
            _ => None,
        }
    }

    /// Largest control radius (the size of the primitive's cross-section).
    pub fn max_radius(&self) -> f32 {
        match self.shape {
            Shape::Sphere { r } => r,
            Shape::Cylinder(c) | Shape::Cone(c) => c.ra.max(c.rb),
            Shape::Spline { quad: QuadTube { r, .. }, .. } => r[0].max(r[2]).max(r[1]),
        }
    }

    /// World-space bounding box `(min, max)` of the stored (rounded) primitive, in `f64`.
    ///
    /// For a spline sub-segment this is [`QuadTube`]'s [`Primitive::aabb`] of the stored control data evaluated
    /// in `f64` (exact extents up to a few `f64` roundings, far below the BVH's padding).
    pub fn aabb(&self) -> ([f64; 3], [f64; 3]) {
        let cone_box = |rc: RoundCone<f32>| {
            let b = rc.aabb();
            (b.min.cast::<f64>().to_array(), b.max.cast::<f64>().to_array())
        };
        let (lo, hi) = match self.shape {
            Shape::Sphere { r } => cone_box(sphere_cone(r)),
            Shape::Cylinder(c) | Shape::Cone(c) => cone_box(c),
            Shape::Spline { quad, .. } => {
                let b = quad.cast::<f64>().aabb();
                (b.min.to_array(), b.max.to_array())
            }
        };
        (std::array::from_fn(|i| self.origin[i] + lo[i]), std::array::from_fn(|i| self.origin[i] + hi[i]))
    }

    /// The interval of the ray's **line** with this primitive, in the ray's own parameter,
    /// with the hit mask set when it is non-empty and overlaps `[t_min, t_max]`.
    ///
    /// The ray is moved in `f64` to the point of its line nearest the local origin and its
    /// direction normalised, then the `f32` kernel runs ([`Primitive::intersect`] of [`RoundCone`], stable, or
    /// of [`Sphere`]) and `t` is mapped back in `f64`.
    ///
    /// A spline sub-segment returns the **hull** `[first entry, last exit]` of its line
    /// pieces ([`QuadTube::intersect_with`], [`Solver::Polynomial`]): its entry is the exact first
    /// entry, but a strongly bent segment may be crossed more than once, so the hull can
    /// cover gaps; [`Self::pieces`] gives the exact pieces.
    #[inline]
    pub fn intersect(&self, ray: &Ray<f64>) -> Interval<f64> {
        let len = ray.d.length();
        self.intersect_unit(ray, ray.d * (1.0 / len), len)
    }

    /// [`Self::intersect`] given the ray's unit direction `dn = d·(1/|d|)` and `len = |d|`,
    /// computed exactly so (a tracer computes them once per ray; the result is bit-identical).
    /// A link first goes through [`link_surely_misses`], which rejects only lines the kernel
    /// misses anyway.
    #[inline]
    pub(crate) fn intersect_unit(&self, ray: &Ray<f64>, dn: V3<f64>, len: f64) -> Interval<f64> {
        let (o, tc) = self.local_origin(ray.o, dn);
        let rl = Ray::with_range(o, dn.cast::<f32>(), f32::NEG_INFINITY, f32::INFINITY);
        let iv = match &self.shape {
            Shape::Sphere { r } => Sphere { c: V3::zero(), r: *r }.intersect(&rl),
            Shape::Cylinder(c) | Shape::Cone(c) => return link_interval(c, &rl, tc, len, ray),
            Shape::Spline { quad, .. } => quad.intersect_with(&rl, Solver::Polynomial),
        };
        Self::to_world(&iv, tc, len, ray)
    }

    /// The exact intervals of the ray's **line** with the primitive, one per connected piece
    /// (a link has one; a bent spline sub-segment up to three), each with the hit mask set
    /// when it is non-empty and overlaps `[t_min, t_max]`; passed to `emit` in no particular
    /// order. Spline pieces come from [`QuadTube::intersect_pieces`] ([`Solver::Polynomial`]).
    #[inline]
    pub fn pieces(&self, ray: &Ray<f64>, mut emit: impl FnMut(Interval<f64>)) {
        let Shape::Spline { quad, .. } = &self.shape else {
            let iv = self.intersect(ray);
            if iv.hit {
                emit(iv);
            }
            return;
        };
        let (rl, tc, len) = self.local_ray(ray);
        for iv in quad.intersect_pieces(&rl, Solver::Polynomial) {
            let iv = Self::to_world(&iv, tc, len, ray);
            if iv.hit {
                emit(iv);
            }
        }
    }

    /// The first surface crossing in `[t_min, t_max]`, as a [`Hit`] whose `id` is the
    /// primitive's link. Exact for every kind: a spline's hull entry is used when it lies in the
    /// range (it is the first entry of the pieces), otherwise the pieces are searched (a ray
    /// starting inside the hull, e.g. a shadow ray leaving a bent segment, may be in a gap
    /// between pieces).
    #[inline]
    pub fn first_hit(&self, ray: &Ray<f64>) -> Option<Hit<f64>> {
        let len = ray.d.length();
        self.first_hit_unit(ray, ray.d * (1.0 / len), len)
    }

    /// [`Self::first_hit`] given `dn` and `len` as [`Self::intersect_unit`] takes them.
    #[inline]
    pub(crate) fn first_hit_unit(&self, ray: &Ray<f64>, dn: V3<f64>, len: f64) -> Option<Hit<f64>> {
        self.first_hit_exit_unit(ray, dn, len).map(|(h, _)| h)
    }

    /// [`Self::first_hit_unit`] and the exit `t` of the primitive's own interval (that of
    /// [`Self::intersect`]).
    #[inline]
    pub(crate) fn first_hit_exit_unit(&self, ray: &Ray<f64>, dn: V3<f64>, len: f64) -> Option<(Hit<f64>, f64)> {
        let iv = self.intersect_unit(ray, dn, len);
        if !iv.hit {
            return None;
        }
        let own = |h: Hit<f64>| (Hit { id: self.link, ..h }, iv.exit.t);
        if self.kind() != PrimKind::Spline || (iv.entry.t >= ray.t_min && iv.entry.t <= ray.t_max) {
            return iv.first_hit(ray.t_min, ray.t_max).map(own);
        }
        let mut best: Option<Hit<f64>> = None;
        self.pieces(ray, |p| {
            if let Some(h) = p.first_hit(ray.t_min, ray.t_max) {
                h.keep_closer(&mut best);
            }
        });
        best.map(own)
    }

    /// True when the primitive's surface or interior meets `[t_min, t_max]` of the ray.
    #[inline]
    pub fn meets(&self, ray: &Ray<f64>) -> bool {
        let len = ray.d.length();
        self.meets_unit(ray, ray.d * (1.0 / len), len)
    }

    /// [`Self::meets`] given `dn` and `len` as [`Self::intersect_unit`] takes them.
    #[inline]
    pub(crate) fn meets_unit(&self, ray: &Ray<f64>, dn: V3<f64>, len: f64) -> bool {
        let iv = self.intersect_unit(ray, dn, len);
        if !iv.hit {
            return false;
        }
        if self.kind() != PrimKind::Spline || iv.entry.t >= ray.t_min {
            return true;
        }
        let mut any = false;
        self.pieces(ray, |_| any = true);
        any
    }

    /// The ray moved in `f64` to the point of its line nearest the local origin, with a unit
    /// direction, in `f32`; and `(tc, |d|)` to map distances back.
    #[inline]
    fn local_ray(&self, ray: &Ray<f64>) -> (Ray<f32>, f64, f64) {
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let (o, tc) = self.local_origin(ray.o, dn);
        (Ray::with_range(o, dn.cast::<f32>(), f32::NEG_INFINITY, f32::INFINITY), tc, len)
    }

    /// The local ray's origin in `f32` and its distance `tc` along the unit direction `dn`
    /// (`dn = d/|d|` in `f64`) from the world origin `o`: the part of [`Self::local_ray`] that
    /// depends on the primitive, shared with the lane-packet path so both see the same bits.
    #[inline(always)]
    pub(crate) fn local_origin(&self, o: V3<f64>, dn: V3<f64>) -> (V3<f32>, f64) {
        local_origin(self.origin, o, dn)
    }

    /// A local `f32` line interval mapped back to the world ray, with the hit mask clipped
    /// to the ray's range.
    #[inline]
    pub(crate) fn to_world(iv: &Interval<f32>, tc: f64, len: f64, ray: &Ray<f64>) -> Interval<f64> {
        if !iv.hit {
            return Interval::miss();
        }
        let Some((t_in, t_out)) = Self::world_range(iv.entry.t, iv.exit.t, tc, len, ray) else {
            return Interval::miss();
        };
        let (entry, exit) = (iv.entry.to_f64(), iv.exit.to_f64());
        Interval::new(Crossing { t: t_in, ..entry }, Crossing { t: t_out, ..exit }, true)
    }

    /// A local `f32` interval's ends as world `t` (`(tc + τ)/len`), where it is non-empty and
    /// overlaps the ray's range.
    #[inline(always)]
    pub(crate) fn world_range(t_in: f32, t_out: f32, tc: f64, len: f64, ray: &Ray<f64>) -> Option<(f64, f64)> {
        let t_in = (tc + t_in as f64) / len;
        let t_out = (tc + t_out as f64) / len;
        (t_in <= t_out && t_out >= ray.t_min && t_in <= ray.t_max).then_some((t_in, t_out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::generate::Rng;

    /// The unfiltered answer: the same arithmetic as [`Prim::intersect_unit`] without
    /// [`link_surely_misses`].
    fn unfiltered(p: &Prim, ray: &Ray<f64>) -> Interval<f64> {
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let (o, tc) = p.local_origin(ray.o, dn);
        let rl = Ray::with_range(o, dn.cast::<f32>(), f32::NEG_INFINITY, f32::INFINITY);
        Prim::to_world(&p.round_cone().unwrap().intersect(&rl), tc, len, ray)
    }

    /// Where the filter rejects, the kernel misses: filtered and unfiltered intervals are equal
    /// (bit for bit, hits included) over links from stubby to needle-thin (L/r from 10⁻² to
    /// 10⁴), near-degenerate cones (|ra − rb| → L, ra → rb, a zero-radius tip), scales 10⁻³…10³
    /// and far offsets, and rays passing the axis at r·(1 + δ) for δ from −10⁻³ to 10³ —
    /// grazing, parallel to the axis and along a generator included.
    #[test]
    fn filter_rejects_only_kernel_misses() {
        let mut rng = Rng::new(14);
        let (mut rejected, mut near_kept) = (0, 0);
        for k in 0..20_000 {
            let scale = 10f64.powf(rng.range(-3.0, 3.0));
            let ratio = 10f64.powf(rng.range(-2.0, 4.0));
            let r = scale;
            let len = r * ratio;
            let rb = match k % 5 {
                0 => r,                                 // cylinder
                1 => r * rng.uniform(),                 // cone
                2 => 0.0,                               // zero-radius tip
                3 => (r - len * (1.0 - 1e-6)).max(0.0), // |ra − rb| just under L
                _ => r * (1.0 - 1e-7),                  // almost a cylinder
            };
            let off = V3::from(rng.unit()) * (scale * 10f64.powf(rng.range(0.0, 6.0)));
            let axis = V3::from(rng.unit());
            let Ok(link) = RoundCone::new(off, r, off + axis * len, rb) else { continue };
            let p = Prim::from_link(&link, 0);
            let Some(c) = p.round_cone().filter(|_| p.kind() != PrimKind::Sphere) else { continue };
            // One in four: stored as in a cluster of links sharing one origin, up to 4·(L + R)
            // away from the link (the accel cluster module's limit).
            let p = if k % 4 == 3 {
                let sh = V3::from(rng.unit()) * (4.0 * (len + r) * rng.uniform());
                let m = |x: V3<f32>| (x.cast::<f64>() + sh).cast::<f32>();
                let c = RoundCone { a: m(c.a), b: m(c.b), ..c };
                Prim { origin: (V3::from(p.origin) - sh).to_array(), shape: Shape::Cone(c), ..p }
            } else {
                p
            };
            // A point on the axis, a direction, and the ray's distance from the axis point.
            let at = off + axis * (len * rng.range(-0.2, 1.2));
            let dir = match k % 7 {
                0 => axis,                                                     // parallel
                1 => (axis + V3::from(rng.unit()) * 1e-4).normalize_or_zero(), // almost parallel
                _ => V3::from(rng.unit()),
            };
            let side = dir.cross(V3::from(rng.unit())).normalize_or_zero();
            let delta = [-1e-3, 0.0, 1e-6, 1e-3, 1e-2, 0.1, 1.0, 10.0, 1e3][k % 9];
            // One in three: beside the axis by up to the link's length; one in three (when
            // not so): at the filter's margin, about 2⁻¹¹·L₁ for these lines, on both sides.
            let reach = r.max(rb) * (1.0 + delta)
                + match k % 3 {
                    0 => len * rng.uniform(),
                    1 => len * [0.0, 2f64.powi(-12), 2f64.powi(-11), 2f64.powi(-10)][(k / 3) % 4],
                    _ => 0.0,
                };
            let o = at + side * reach - dir * (scale * 50.0);
            let ray = Ray::new(o, dir);
            let (f, u) = (p.intersect(&ray), unfiltered(&p, &ray));
            assert_eq!(f, u, "case {k}: link {link:?} ray {ray:?}");
            let len_d = ray.d.length();
            let (lo, _) = p.local_origin(ray.o, ray.d * (1.0 / len_d));
            let c = p.round_cone().unwrap();
            if link_surely_misses(&c, lo, (ray.d * (1.0 / len_d)).cast()) {
                rejected += 1;
            } else if delta.abs() <= 1e-2 {
                near_kept += 1;
            }
        }
        assert!(rejected > 4000 && near_kept > 4000, "rejected {rejected}, kept near the surface {near_kept}");
    }
}
