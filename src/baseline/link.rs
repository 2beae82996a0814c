//! Han et al. 2019's round cone, faithful to the paper: the two spheres plus the tangent-cone
//! stump of [`super::cone`] (apex, unit-cone transform, slab), or the textbook cylinder for
//! equal radii. The same solid as the stable [`RoundCone`]; the stability report charts the
//! two against each other.

use super::cone::{cylinder_line, stump_line, TangentCone, UnitConeTransform};
use crate::kernel::link::RoundCone;
use crate::kernel::sphere::sphere_line;
use crate::primitive::Primitive;
use crate::ray::{Interval, Ray};
use crate::real::{Mask, Real};

/// A link with Han's tangent cone and unit-cone transform precomputed (Han Table 1 option d):
/// the faithful formulation of the same solid as its [`RoundCone`].
///
/// ```
/// use tubecast::baseline::HanLink;
/// use tubecast::{Primitive, Ray, RoundCone, V3};
/// let link = RoundCone::new(V3::new(0.0f64, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
/// let (stable, han) = (link.intersect(&ray), HanLink::new(&link).intersect(&ray));
/// assert!(han.hit && (han.entry.t - stable.entry.t).abs() < 1e-12);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct HanLink<T: Real> {
    /// The link.
    pub link: RoundCone<T>,
    /// Its tangent cone (Han §3.2.2).
    pub cone: TangentCone<T>,
    /// The unit-cone transform (Han §4.1).
    pub xf: UnitConeTransform<T>,
}

impl<T: Real> HanLink<T> {
    /// Precompute the cone and the transform.
    #[inline(always)]
    pub fn new(link: &RoundCone<T>) -> Self {
        let cone = TangentCone::new(link.a, link.ra, link.b, link.rb);
        let xf = UnitConeTransform::new(&cone);
        Self { link: *link, cone, xf }
    }
    /// The line interval: spheres ∪ (cone stump, or the textbook cylinder for equal radii).
    #[inline(always)]
    pub(crate) fn line(&self, ray: &Ray<T>) -> Interval<T> {
        let l = &self.link;
        let s1 = sphere_line(ray, l.a, l.ra, T::zero());
        let s2 = sphere_line(ray, l.b, l.rb, T::one());
        let mut iv = s1.hull(s2);
        if self.cone.is_cone.any() {
            iv = iv.hull(stump_line(ray, &self.cone, &self.xf));
        }
        if self.cone.is_cylinder.any() {
            let cyl = cylinder_line(ray, l.a, l.b, l.ra).masked(self.cone.is_cylinder);
            iv = iv.hull(cyl);
        }
        iv
    }
}

impl<T: Real> RoundCone<T> {
    /// Baseline: the faithful Han et al. round cone with the tangent cone and its transform
    /// built per call (Han Table 1 option c), i.e. `HanLink::new(self).intersect(ray)`. Use
    /// [`Primitive::intersect`] for the stable kernel.
    #[inline(always)]
    pub fn intersect_han_on_the_fly(&self, ray: &Ray<T>) -> Interval<T> {
        HanLink::new(self).intersect(ray)
    }
}
