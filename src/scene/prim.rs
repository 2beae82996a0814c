//! Renderer primitives: `f32` geometry relative to an `f64` local origin.

use crate::kernel::link::RoundCone;
use crate::kernel::sphere::intersect_sphere;
use crate::ray::{Interval, Ray};
use crate::{LinkShape, V3};

/// Which exact shape a primitive is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimKind {
    /// A sphere (centre `a`, radius `ra`).
    Sphere,
    /// A cylinder link (equal radii).
    Cylinder,
    /// A tangent-cone link (different radii).
    Cone,
}

/// A link stored for rendering: centres in `f32` relative to the `f64` local origin
/// (the link's midpoint), radii in `f32`.
///
/// Why: a coordinate near `1e6` has an `f32` spacing of `0.0625`, so storing world
/// coordinates in `f32` moves a thin tube by a good fraction of its radius. Relative to the
/// midpoint, the stored offsets are at most half the link length, so their rounding error is
/// `2⁻²⁴` of the link's own size wherever the link is. Rays are moved the same way in `f64`
/// (to the point of the line nearest the origin) before the `f32` kernel runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prim {
    /// Local origin (world coordinates).
    pub origin: [f64; 3],
    /// First centre relative to `origin`.
    pub a: V3<f32>,
    /// First radius.
    pub ra: f32,
    /// Second centre relative to `origin` (equal to `a` for a sphere).
    pub b: V3<f32>,
    /// Second radius.
    pub rb: f32,
    /// The shape.
    pub kind: PrimKind,
    /// Index of the scene link this primitive models.
    pub link: u32,
}

impl Prim {
    /// The cheapest exact primitive for a validated link.
    pub fn from_link(l: &RoundCone<f64>, link: u32) -> Self {
        let kind = match l.shape() {
            LinkShape::Sphere => PrimKind::Sphere,
            LinkShape::Cylinder => PrimKind::Cylinder,
            LinkShape::Cone => PrimKind::Cone,
        };
        if kind == PrimKind::Sphere {
            // The larger sphere contains the link.
            let (c, r) = if l.ra >= l.rb { (l.a, l.ra) } else { (l.b, l.rb) };
            return Self {
                origin: c.to_array(),
                a: V3::zero(),
                ra: r as f32,
                b: V3::zero(),
                rb: r as f32,
                kind,
                link,
            };
        }
        let mid = (l.a + l.b) * 0.5;
        Self {
            origin: mid.to_array(),
            a: (l.a - mid).cast(),
            ra: l.ra as f32,
            b: (l.b - mid).cast(),
            rb: l.rb as f32,
            kind,
            link,
        }
    }

    /// World-space bounding box `(min, max)` of the stored (rounded) primitive, in `f64`.
    pub fn aabb(&self) -> ([f64; 3], [f64; 3]) {
        let rc = RoundCone { a: self.a, ra: self.ra, b: self.b, rb: self.rb };
        let (lo, hi) = rc.aabb();
        let (lo, hi) = (lo.cast::<f64>().to_array(), hi.cast::<f64>().to_array());
        (
            std::array::from_fn(|i| self.origin[i] + lo[i]),
            std::array::from_fn(|i| self.origin[i] + hi[i]),
        )
    }

    /// The interval of the ray's **line** with this primitive, in the ray's own parameter,
    /// with the hit mask set when it is non-empty and overlaps `[t_min, t_max]`.
    ///
    /// The ray is moved in `f64` to the point of its line nearest the local origin and its
    /// direction normalised, then the `f32` kernel runs ([`RoundCone::intersect`], stable, or
    /// [`intersect_sphere`]) and `t` is mapped back in `f64`.
    #[inline]
    pub fn intersect(&self, ray: &Ray<f64>) -> Interval<f64> {
        let len = ray.d.length();
        let dn = ray.d * (1.0 / len);
        let org = V3::from(self.origin);
        let tc = (org - ray.o).dot(dn); // distance along dn to the nearest point
        let o = (ray.o + dn * tc - org).cast::<f32>();
        let rl = Ray::with_range(o, dn.cast::<f32>(), f32::NEG_INFINITY, f32::INFINITY);
        let iv = match self.kind {
            PrimKind::Sphere => intersect_sphere(&rl, self.a, self.ra, 0.0),
            _ => RoundCone { a: self.a, ra: self.ra, b: self.b, rb: self.rb }.intersect(&rl),
        };
        if !iv.hit {
            return Interval::miss();
        }
        let t_in = (tc + iv.t_in as f64) / len;
        let t_out = (tc + iv.t_out as f64) / len;
        let hit = t_in <= t_out && t_out >= ray.t_min && t_in <= ray.t_max;
        if !hit {
            return Interval::miss();
        }
        Interval {
            t_in,
            t_out,
            n_in: iv.n_in.cast(),
            n_out: iv.n_out.cast(),
            u_in: iv.u_in as f64,
            u_out: iv.u_out as f64,
            hit,
        }
    }
}
