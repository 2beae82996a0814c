//! The link: a round cone, i.e. the convex hull of two spheres (= sphere ∪ tangent-cone stump
//! ∪ sphere, = the sphere sweep `S(p(u), r(u))` with `p`, `r` linear in `u ∈ [0, 1]`).
//!
//! Two formulations, both public, so the reports can chart them against each other:
//!
//! * **faithful** — Han et al. 2019: apex, unit-cone transform, quadratic, slab `[z_cap, 1]`,
//!   plus the two spheres; a textbook cylinder when the radii are exactly equal. With the
//!   transform precomputed ([`HanLink`], Han Table 1 option d) or built per call
//!   ([`RoundCone::intersect_han_on_the_fly`], option c).
//! * **stable** — [`RoundCone`] ([`Primitive`]): no apex. The cone is written with its half-angle,
//!   `sin θ = (r₁ − r₂)/L`, in coordinates centred on the link's midpoint, and the ray origin is
//!   first moved to the point of the line closest to that midpoint. The quadratic's
//!   coefficients are built from cross products (`|d × â|²`, `(o × â)·(d × â)`, …), so
//!   axis-parallel rays, equal radii and far origins lose no digits that the input did not
//!   already lose.
//!
//! Because the hull is convex and equals the union of its three pieces, the ray interval is
//! the earliest entry and the latest exit over the pieces.

use super::cone::{cylinder_line, quadric_in_slab_disc, slab, stump_line};
use super::cone::{TangentCone, UnitConeTransform};
use super::sphere::sphere_line;
use crate::primitive::Primitive;
use crate::ray::{Interval, Ray};
use crate::real::{Mask, Real, Scalar};

use crate::error::GeometryError;
use crate::vec::V3;

/// A round cone (link) between spheres `(a, ra)` and `(b, rb)`. The curve parameter `u` runs
/// from 0 at `a` to 1 at `b`.
///
/// Build scalar links with [`RoundCone::new`] (validated); lane links with
/// [`RoundCone::from_lanes`] from validated scalar links. Ray queries, the box and the
/// distance come from [`Primitive`]: the **stable** formulation (no apex: the cone by its
/// half-angle in coordinates centred on the link, the ray origin moved to the point of the
/// line closest to it; derivation in `src/kernel/link.rs`). [`HanLink`] is the faithful one.
///
/// ```
/// use tubecast::{Primitive, Ray, RoundCone, V3};
/// let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let iv = link.intersect(&Ray::new(V3::new(0.0, 0.0, -5.0), V3::new(0.0, 0.0, 1.0)));
/// assert_eq!((iv.t_in, iv.t_out, iv.u_in), (4.0, 6.0, 0.0)); // through the centre of sphere a
/// assert!(link.sdf(V3::new(2.0, 0.0, 0.0)) < 0.0);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundCone<T> {
    /// First centre.
    pub a: V3<T>,
    /// First radius.
    pub ra: T,
    /// Second centre.
    pub b: V3<T>,
    /// Second radius.
    pub rb: T,
}

/// What a link degenerates to, by the classification the kernels use.
///
/// ```
/// use tubecast::{LinkShape, RoundCone, V3};
/// let o = V3::new(0.0, 0.0, 0.0);
/// let x = V3::new(1.0, 0.0, 0.0);
/// assert_eq!(RoundCone::new(o, 0.5, x, 0.5)?.shape(), LinkShape::Cylinder);
/// assert_eq!(RoundCone::new(o, 0.5, x, 0.2)?.shape(), LinkShape::Cone);
/// assert_eq!(RoundCone::new(o, 2.0, x, 0.5)?.shape(), LinkShape::Sphere);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkShape {
    /// Distinct radii with `|ra − rb| < L`: a tangent cone stump between two spheres.
    Cone,
    /// Equal radii and `L > 0`: a cylinder between two spheres.
    Cylinder,
    /// `|ra − rb| ≥ L` (one sphere inside the other, or zero length): the larger sphere.
    Sphere,
}

impl<T: Scalar> RoundCone<T> {
    /// A validated link. Errors: non-finite coordinates or radii, a negative radius, or both
    /// radii zero (no volume). One sphere inside the other and zero length are valid: the
    /// link is the larger sphere ([`LinkShape::Sphere`]).
    pub fn new(a: V3<T>, ra: T, b: V3<T>, rb: T) -> Result<Self, GeometryError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(GeometryError::NonFinite { what: "link centre" });
        }
        if !ra.is_finite() || !rb.is_finite() {
            return Err(GeometryError::NonFinite { what: "link radius" });
        }
        if ra < T::zero() || rb < T::zero() {
            return Err(GeometryError::NegativeRadius);
        }
        if ra == T::zero() && rb == T::zero() {
            return Err(GeometryError::ZeroRadius);
        }
        // Kernels square radii and form differences of squares: a non-zero radius whose square
        // is within a factor 1/ε of underflow loses its digits in subnormal arithmetic.
        let tiny = |r: T| r > T::zero() && r * r < T::MIN_POSITIVE / T::EPS;
        if tiny(ra) || tiny(rb) {
            return Err(GeometryError::TooSmall { what: "link radius (its square underflows)" });
        }
        // Squared length must not overflow, or every kernel sees L = ∞.
        let e = (b - a).max_abs().max(ra).max(rb);
        if !(e * e * T::cst(4.0)).is_finite() {
            return Err(GeometryError::NonFinite { what: "link extent (overflows when squared)" });
        }
        Ok(Self { a, ra, b, rb })
    }
    /// How the kernels classify this link.
    pub fn shape(&self) -> LinkShape {
        let l = (self.b - self.a).length();
        let dr = (self.ra - self.rb).abs();
        if dr >= l {
            LinkShape::Sphere
        } else if dr == T::zero() {
            LinkShape::Cylinder
        } else {
            LinkShape::Cone
        }
    }
    /// Convert the precision.
    pub fn cast<U: Scalar>(&self) -> RoundCone<U> {
        RoundCone {
            a: self.a.cast(),
            ra: U::from_f64(self.ra.to_f64()),
            b: self.b.cast(),
            rb: U::from_f64(self.rb.to_f64()),
        }
    }
}

impl<T: Real> RoundCone<T> {
    /// Lanes from validated scalar links (one per lane).
    pub fn from_lanes(f: impl Fn(usize) -> RoundCone<T::Elem>) -> Self {
        Self {
            a: V3::from_fn(|i| f(i).a),
            ra: T::from_fn(|i| f(i).ra),
            b: V3::from_fn(|i| f(i).b),
            rb: T::from_fn(|i| f(i).rb),
        }
    }
    /// Every lane the same link.
    pub fn splat(l: RoundCone<T::Elem>) -> Self {
        Self { a: V3::splat(l.a), ra: T::splat(l.ra), b: V3::splat(l.b), rb: T::splat(l.rb) }
    }

    /// The tangent-cone stump alone (no end spheres), stable form.
    #[inline(always)]
    pub fn intersect_stump_stable(&self, ray: &Ray<T>) -> Interval<T> {
        self.stable_line(ray, false).clip(ray)
    }

    /// The stable kernel on the ray's whole line. All pieces (two spheres, the stump) are
    /// solved in one local frame, combined by `t` (the hull is convex and equals their union,
    /// so its interval is the earliest entry and the latest exit), and only then are the
    /// normals and curve parameters of the two winning crossings computed.
    #[inline(always)]
    pub(crate) fn stable_line(&self, ray: &Ray<T>, spheres: bool) -> Interval<T> {
        let zero = T::zero();
        let one = T::one();
        let half = T::cst(0.5);
        let no = T::Mask::splat(false);
        let v = self.b - self.a;
        let len = v.length();
        let dr = self.ra - self.rb;
        let len_s = T::select(len.gt(zero), len, one);
        let s = (dr / len_s).clamp(-one, one); // sin θ
        let c2 = (one - s) * (one + s); // cos² θ, without 1 − s² cancellation
                                        // s carries a relative rounding error ≈ 2ε, so c² = (1 − s)(1 + s) is known to ≈ 4ε
                                        // absolutely. Below 64ε it is mostly noise, and so is the stump (its radius is e/c with
                                        // e = r·c² buried under e's rounding error ε·r). There the stump is dropped: with one
                                        // sphere almost inside the other, the hull exceeds the union of the two spheres by at
                                        // most L − |ra − rb| = L·(1 − |s|) ≤ L·c² < 64ε·L, within the kernel's error bound.
        let has_cone = dr.abs().lt(len) & c2.ge(T::epsilon() * T::cst(64.0));
        let axis = v * (one / len_s);
        let s = T::select(has_cone, s, zero);
        let c2 = T::select(has_cone, c2, one);
        let mid = (self.a + self.b) * half;
        let hl = len_s * half;

        // Local frame. Work with the unit direction (t = τ/|d| at the end): nothing over- or
        // underflows because |d| is far from 1. 1) The ray's closest approach to the axis line
        // (to the midpoint if parallel); 2) its axial position clamped into the segment gives a
        // local centre c0 on the axis; 3) the new origin o is the ray's closest point to c0.
        // Near a crossing, o is then as short as the ray–axis distance, so every coefficient
        // below is formed from numbers of the size of the radius, not of L or |o − m|.
        let dl = ray.d.length();
        let dn = ray.d * (one / dl);
        let zd = dn.dot(axis);
        let q = dn.cross(axis);
        let q2 = q.length2();
        let w = mid - ray.o;
        let skew = q2.gt(T::cst(1e-12));
        let t_ax = (w.dot(dn) - w.dot(axis) * zd) / T::select(skew, q2, one);
        let t_ax = T::select(skew, t_ax, w.dot(dn));
        let z0 = (ray.o + dn * t_ax - mid).dot(axis).clamp(-hl, hl);
        let c0 = mid + axis * z0;
        let tc = (c0 - ray.o).dot(dn);
        let o = ray.o + dn * tc - c0;
        // End-sphere centres in the local frame.
        let ca = axis * (-hl - z0);
        let cb = axis * (hl - z0);

        // Spheres: closest point to the centre, then the half chord (no far-origin cancellation).
        let sphere = |c: V3<T>, r: T| {
            let f = o - c;
            let tcs = -f.dot(dn);
            let l = f + dn * tcs;
            let disc = r * r - l.length2();
            let ok = disc.ge(zero) & r.gt(zero);
            let h = disc.max(zero).sqrt();
            (tcs - h, tcs + h, ok)
        };
        let inf = T::infinity();
        let (mut t_in, mut t_out) = (inf, -inf);
        let (mut in_a, mut in_b, mut out_a, mut out_b) = (no, no, no, no);
        if spheres {
            let (a0, a1, oka) = sphere(ca, self.ra);
            let (b0, b1, okb) = sphere(cb, self.rb);
            (in_a, out_a) = widen(&mut t_in, &mut t_out, a0, a1, oka);
            let (bi, bo) = widen(&mut t_in, &mut t_out, b0, b1, okb);
            in_a = in_a & !bi;
            out_a = out_a & !bo;
            in_b = bi;
            out_b = bo;
        }

        // Cone side: c·ρ + s·z = rm in midpoint-centred coordinates; at c0 it reads
        // c·ρ + s·z' = rm − s·z0 with z' = z − z0.
        let rm = (self.ra + self.rb) * half - s * z0;
        let zo = o.dot(axis);
        let p = o.cross(axis);
        let e = rm - s * zo;
        let (mut cone_in, mut cone_out, mut side_in, mut side_out) = (no, no, no, no);
        if has_cone.any() {
            // F(τ) = c²|y × â|² − (rm − s·(y·â))², y = o + τ·d̂;  F = Aτ² + 2Bτ + C.
            let qa = c2 * q2 - s * s * zd * zd;
            let qb = c2 * p.dot(q) + s * zd * e;
            let qc = c2 * p.length2() - e * e;
            // Slab between the tangent circles: z ∈ [ra·s − L/2, L/2 + rb·s] (midpoint frame).
            let (lo, hi) = slab(zo, zd, self.ra * s - hl - z0, hl + self.rb * s - z0);
            // B² − AC expanded and regrouped (P = o×â, Q = d̂×â, both ⊥ â):
            //   B² − AC = c²·(|e·Q + s·zd·P|² − c²·|P×Q|²).
            // The e²-sized terms of B² and AC cancel exactly in this form; formed directly they
            // cancel in rounding, which loses every digit when the ray runs along a long link
            // (e ≫ |P|) — the discriminant is then c²s²zd²|P|², tiny against e².
            let eq = q * e + p * (s * zd);
            let disc = c2 * (eq.length2() - c2 * p.cross(q).length2());
            let (k0, k1, q0, q1, ok) = quadric_in_slab_disc(qa, qb, qc, disc, lo, hi);
            // F squares the distance-like g(τ) = c·|p + τq| − (e − s·zd·τ) (zero on the side,
            // |∇g| = 1): near a thin end seen from a far c0, F's root loses digits that g keeps.
            // One safeguarded Newton step on g restores them.
            let cc = c2.sqrt();
            let polish = |k: T, root: T::Mask| {
                let pq = p + q * k;
                let rho = pq.length();
                let g = cc * rho - (e - s * zd * k);
                let dg = cc * pq.dot(q) / T::select(rho.gt(zero), rho, one) + s * zd;
                let step = g / T::select(dg.abs().gt(zero), dg, one);
                // Safeguard: a quadratic's root is never worse than ≈ √ε relative (double
                // root), so a larger step means g's linearisation is not trustworthy here.
                let scale = k.abs() + hl + self.ra.max(self.rb) + rho;
                let lim = T::epsilon().sqrt() * T::cst(8.0) * scale;
                // Ends that are roots are polished. So are cap ends lying outside the cone
                // (g > 0): a cap disc is inside the cone, so such an end is a root lost to the
                // near-double root F has where a line passes close to an apex (a zero-radius
                // tip), where F's two nappes meet.
                let cap_out = ok & !root & g.gt(T::zero());
                let good = (root | cap_out) & dg.abs().gt(T::epsilon().sqrt()) & step.abs().le(lim);
                // A posteriori check: at a real crossing g ≈ 0 (|g| ≲ √ε·scale even at a double
                // root, where the quadratic's root is √ε-accurate). When A = c²|Q|² − s²zd² is
                // pure rounding (a ray parallel to a generator, far from the axis) the roots
                // are noise and g there is of the size of the ray–axis distance: not a crossing.
                let real = !(root | cap_out) | g.abs().le(lim);
                // The polished root stays a crossing of the stump: clamp it into the slab.
                (T::select(good, (k - step).clamp(lo, hi), k), real, root | (good & cap_out))
            };
            let (k0, real0, q0) = polish(k0, q0 & ok);
            let (k1, real1, q1) = polish(k1, q1 & ok);
            let ok = ok & real0 & real1;
            let ok = ok & has_cone & k0.le(k1);
            let (ci, co) = widen(&mut t_in, &mut t_out, k0, k1, ok);
            in_a = in_a & !ci;
            in_b = in_b & !ci;
            out_a = out_a & !co;
            out_b = out_b & !co;
            cone_in = ci;
            cone_out = co;
            side_in = ci & q0;
            side_out = co & q1;
        }
        let hit = in_a | in_b | cone_in;

        // Normals and u of the two winners only. A crossing of a cap plane lies in the adjacent
        // end sphere (the cap disc is inside it); it is exposed only when rounding loses that
        // sphere's grazing interval, and then the sphere's normal is the right one.
        let cc = c2.sqrt();
        let perp = super::cone::orthonormal_basis(axis).0;
        let inv = one / (len_s * c2);
        let finish = |k: T, on_a: T::Mask, on_b: T::Mask, cone: T::Mask, side: T::Mask| {
            let y = o + dn * k;
            let z = y.dot(axis);
            let radial = (y - axis * z).normalize_or_zero();
            // A point computed exactly on the axis (only by rounding) has no radial direction:
            // any perpendicular keeps the normal a unit vector.
            let radial = V3::select(radial.length2().gt(zero), radial, perp);
            let side_n = radial * cc + axis * s;
            let cap_b = cone & !side & (z + z0).gt((self.ra + self.rb) * s * half);
            let use_b = on_b | cap_b;
            let use_a = on_a | (cone & !side & !cap_b);
            let to_end = y - V3::select(use_b, cb, ca);
            // (At the tip of a zero-radius end there is no sphere: keep the side's normal.)
            let sph = use_a | use_b;
            let n = V3::select(sph & to_end.length2().gt(zero), to_end, side_n).normalize_or_zero();
            let u_side = ((z + z0 + hl - self.ra * s) * inv).clamp(zero, one);
            let u = T::select(use_b, one, T::select(use_a, zero, u_side));
            (n, u)
        };
        let (n_in, u_in) = finish(t_in, in_a, in_b, cone_in, side_in);
        let (n_out, u_out) = finish(t_out, out_a, out_b, cone_out, side_out);
        let inv_dl = one / dl;
        let (t_in, t_out) = ((t_in + tc) * inv_dl, (t_out + tc) * inv_dl);
        Interval { t_in, t_out, n_in, n_out, u_in, u_out, hit }.masked(hit)
    }

    /// Faithful Han et al. round cone, tangent cone and transform built per call
    /// (Han Table 1 option c).
    #[inline(always)]
    pub fn intersect_han_on_the_fly(&self, ray: &Ray<T>) -> Interval<T> {
        HanLink::new(self).intersect(ray)
    }
}

/// Widen the running hull `[t_in, t_out]` by a piece `[k0, k1]` (lanes where `ok`); returns which
/// lanes took the piece's entry and exit.
#[inline(always)]
fn widen<T: Real>(t_in: &mut T, t_out: &mut T, k0: T, k1: T, ok: T::Mask) -> (T::Mask, T::Mask) {
    let took_in = ok & k0.lt(*t_in);
    let took_out = ok & k1.gt(*t_out);
    *t_in = T::select(took_in, k0, *t_in);
    *t_out = T::select(took_out, k1, *t_out);
    (took_in, took_out)
}

/// A link with Han's tangent cone and unit-cone transform precomputed (Han Table 1 option d):
/// the faithful formulation of the same solid as its [`RoundCone`].
///
/// ```
/// use tubecast::{HanLink, Primitive, Ray, RoundCone, V3};
/// let link = RoundCone::new(V3::new(0.0f64, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
/// let (stable, han) = (link.intersect(&ray), HanLink::new(&link).intersect(&ray));
/// assert!(han.hit && (han.t_in - stable.t_in).abs() < 1e-12);
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
