//! The Polynomial solver's previous candidates (main up to 09f0319), kept as a **test oracle**
//! for `isolate.rs`: all roots of `P` by the derivative cascade on two power-basis expansions,
//! in powers of `t` and of `t − tv`, merged. `tests` compare the kernel's answers with this
//! path's on every generator region.

use super::ray_space::RaySpace;
use super::QuadTube;
use crate::math::bezier::bernstein2;
use crate::math::roots::{poly_breakpoints, poly_mul, Bracket};
use crate::ray::{Interval, Ray};
use crate::real::Real;
use crate::vec::V3;

/// `h` and `g` (ascending powers of the parameter) from the power-basis position
/// `q = qa x² + qb x + qc` and radius `ra x² + rb x + rc`.
fn ray_polys<T: Real>(q: [V3<T>; 3], r: [T; 3], dhat: V3<T>) -> ([T; 3], [T; 5]) {
    let ([qa, qb, qc], [ra, rb, rc]) = (q, r);
    let two = T::cst(2.0);
    let h = [qc.dot(dhat), qb.dot(dhat), qa.dot(dhat)];
    let (wa, wb, wc) = (qa.cross(dhat), qb.cross(dhat), qc.cross(dhat));
    let w2 = [wc.dot(wc), two * wc.dot(wb), wb.dot(wb) + two * wc.dot(wa), two * wb.dot(wa), wa.dot(wa)];
    let r2 = [rc * rc, two * rc * rb, rb * rb + two * rc * ra, two * rb * ra, ra * ra];
    let g = [r2[0] - w2[0], r2[1] - w2[1], r2[2] - w2[2], r2[3] - w2[3], r2[4] - w2[4]];
    (h, g)
}

/// `P = 4h'²g − g'²` from `h`, `g` in powers of one variable.
fn p_of<T: Real>(h: &[T; 3], g: &[T; 5]) -> [T; 7] {
    let two = T::cst(2.0);
    let h1 = [h[1], two * h[2]];
    let g1 = [g[1], two * g[2], T::cst(3.0) * g[3], T::cst(4.0) * g[4]];
    let h1s: [T; 3] = poly_mul(&h1, &h1);
    let a: [T; 7] = poly_mul(&h1s, g);
    let b: [T; 7] = poly_mul(&g1, &g1);
    let mut p = [T::zero(); 7];
    for i in 0..7 {
        p[i] = T::cst(4.0) * a[i] - b[i];
    }
    p
}

/// The old breakpoints: roots of `P` in powers of `t` and of `t − tv`, sorted, 16 entries.
pub(super) fn p_breakpoints_cascade<T: Real>(rs: &RaySpace<T>) -> [T; 16] {
    let two = T::cst(2.0);
    let ([c0, c1, c2], [r0, r1, r2], tv) = (rs.c, rs.rr, rs.tv);
    let (qa, qb, qc) = (c0 - c1 * two + c2, (c1 - c0) * two, c0);
    let (ra, rb, rc) = (r0 - r1 * two + r2, (r1 - r0) * two, r0);
    let (h, g) = ray_polys([qa, qb, qc], [ra, rb, rc], rs.dhat);
    let sv = T::one() - tv;
    let [wv0, wv1, wv2] = bernstein2(tv);
    let qcv = c0 * wv0 + c1 * wv1 + c2 * wv2;
    let qbv = ((c1 - c0) * sv + (c2 - c1) * tv) * two;
    let rcv = r0 * wv0 + r1 * wv1 + r2 * wv2;
    let rbv = ((r1 - r0) * sv + (r2 - r1) * tv) * two;
    let (hv, gv) = ray_polys([qa, qbv, qcv], [ra, rbv, rcv], rs.dhat);
    let (lo, hi) = (-tv, T::one() - tv);
    let (bt, _) = poly_breakpoints(&p_of(&h, &g), T::zero(), T::one(), Bracket::Newton);
    let (bv, _) = poly_breakpoints(&p_of(&hv, &gv), lo, hi, Bracket::Newton);
    let mut out = [T::one(); 16];
    out[..8].copy_from_slice(&bt);
    for i in 0..8 {
        let t = (tv + bv[i]).clamp(T::zero(), T::one());
        out[8 + i] = T::select(bv[i].le(lo), T::zero(), T::select(bv[i].ge(hi), T::one(), t));
    }
    out
}

impl<T: Real> QuadTube<T> {
    /// The Polynomial solver's line interval with the old candidates (the oracle; the same
    /// filters, decisions and polish as [`QuadTube::line_interval_with`]).
    pub(super) fn line_interval_cascade(&self, ray: &Ray<T>) -> Interval<T> {
        let far = super::capsule::capsule_misses(self, ray);
        let Some(rs) = RaySpace::new(self, ray) else {
            return Interval::miss();
        };
        super::polynomial_line(&rs, ray, |rs| (p_breakpoints_cascade(rs), 16)).masked(!far)
    }
}
