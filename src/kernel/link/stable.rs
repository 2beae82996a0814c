//! The stable round-cone kernel ([`RoundCone::stable_line`]): no apex; the cone written with
//! its half-angle in a frame centred on the link's axis near the ray (see the parent module).

use super::RoundCone;
use crate::math::frame::orthonormal_basis;
use crate::math::quadric::{quadric_in_slab_disc, slab, sphere_chord, Chord};
use crate::ray::{in_range, Crossing, Interval, Ray};
use crate::real::{Mask, Real};
use crate::vec::V3;

impl<T: Real> RoundCone<T> {
    /// The stable kernel on the ray's whole line. All pieces (two spheres, the stump) are
    /// solved in one local frame ([`StableFrame`]), combined by `t` (the hull is convex and
    /// equals their union, so its interval is the earliest entry and the latest exit:
    /// [`PieceHull`]), and only then are the normals and curve parameters of the two winning
    /// crossings computed ([`StableFrame::finish`]).
    #[inline(always)]
    pub(crate) fn stable_line(&self, ray: &Ray<T>, spheres: bool) -> Interval<T> {
        let p = self.pending_line_with(ray, spheres);
        // A miss in every lane needs no normals: the same answer as `masked` gives.
        if p.hit.none() {
            return Interval::miss();
        }
        p.interval(self)
    }

    /// The line's interval with the link ([`Primitive::line_interval`](crate::Primitive)'s
    /// `t` and hit mask, bit for bit) before the normals and curve parameters of its ends are
    /// formed: a closest-hit search finishes only the crossing it keeps
    /// ([`PendingInterval::entry`], [`PendingInterval::exit`]), and those equal the ends of
    /// [`Primitive::line_interval`](crate::Primitive), bit for bit.
    ///
    /// ```
    /// use tubecast::{Primitive, Ray, RoundCone, V3};
    /// let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
    /// let ray = Ray::new(V3::new(2.0, 5.0, 0.0), V3::new(0.0, -1.0, 0.0));
    /// let p = link.pending_line(&ray);
    /// let iv = link.line_interval(&ray);
    /// assert!(p.hit && iv.hit);
    /// assert_eq!((p.t_in, p.t_out), (iv.entry.t, iv.exit.t));
    /// assert_eq!((p.entry(&link), p.exit(&link)), (iv.entry, iv.exit));
    /// ```
    #[inline(always)]
    pub fn pending_line(&self, ray: &Ray<T>) -> PendingInterval<T> {
        self.pending_line_with(ray, true)
    }

    #[inline(always)]
    fn pending_line_with(&self, ray: &Ray<T>, spheres: bool) -> PendingInterval<T> {
        let f = StableFrame::new(self, ray);
        let mut hull = PieceHull::empty();
        if spheres {
            let a = sphere_chord(f.o, f.dn, f.ca, self.ra);
            let b = sphere_chord(f.o, f.dn, f.cb, self.rb);
            hull.add_spheres(a, b);
        }
        if f.has_cone.any() {
            hull.add_stump(f.stump_crossings(self));
        }
        let hit = hull.in_a | hull.in_b | hull.cone_in;
        let inv_dl = T::one() / f.dl;
        let (t_in, t_out) = ((hull.t_in + f.tc) * inv_dl, (hull.t_out + f.tc) * inv_dl);
        PendingInterval { t_in, t_out, hit, f, hull }
    }
}

/// A link's line interval whose ends have their `t` but not yet their normal and curve
/// parameter ([`RoundCone::pending_line`]).
#[derive(Clone, Copy)]
pub struct PendingInterval<T: Real> {
    /// Entry `t` along the ray (meaningful where `hit`).
    pub t_in: T,
    /// Exit `t` along the ray (meaningful where `hit`).
    pub t_out: T,
    /// Lanes where the line meets the link.
    pub hit: T::Mask,
    f: StableFrame<T>,
    hull: PieceHull<T>,
}

impl<T: Real> PendingInterval<T> {
    /// The entry crossing of `link` (the link this was computed for).
    #[inline(always)]
    pub fn entry(&self, link: &RoundCone<T>) -> Crossing<T> {
        let h = &self.hull;
        let (n, u) = self.f.finish(link, h.t_in, h.in_a, h.in_b, h.cone_in, h.side_in);
        Crossing { t: self.t_in, n, u }
    }

    /// The exit crossing of `link` (the link this was computed for).
    #[inline(always)]
    pub fn exit(&self, link: &RoundCone<T>) -> Crossing<T> {
        let h = &self.hull;
        let (n, u) = self.f.finish(link, h.t_out, h.out_a, h.out_b, h.cone_out, h.side_out);
        Crossing { t: self.t_out, n, u }
    }

    /// The lanes whose interval overlaps the ray's range keep `hit`, as
    /// [`Interval::clip`] does (the step from a line interval to an `intersect`).
    #[inline(always)]
    pub fn clip(mut self, ray: &Ray<T>) -> Self {
        self.hit = self.hit & in_range(ray, self.t_in, self.t_out);
        self
    }

    /// The whole line interval, as [`Primitive::line_interval`](crate::Primitive) gives it.
    #[inline(always)]
    pub fn interval(&self, link: &RoundCone<T>) -> Interval<T> {
        Interval::new(self.entry(link), self.exit(link), self.hit).masked(self.hit)
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

/// The stable kernel's local frame for one ray (see [`RoundCone::stable_line`]).
///
/// Work with the unit direction (t = τ/|d| at the end): nothing over- or underflows because
/// |d| is far from 1. 1) The ray's closest approach to the axis line (to the midpoint if
/// parallel); 2) its axial position clamped into the segment gives a local centre c0 on the
/// axis; 3) the new origin o is the ray's closest point to c0. Near a crossing, o is then as
/// short as the ray–axis distance, so every coefficient is formed from numbers of the size
/// of the radius, not of L or |o − m|.
#[derive(Clone, Copy)]
struct StableFrame<T: Real> {
    /// Link length, or 1 for a zero-length link.
    len_s: T,
    /// Half of `len_s`.
    hl: T,
    /// Unit axis `a → b`.
    axis: V3<T>,
    /// `sin θ = (ra − rb)/L` (0 where there is no stump).
    s: T,
    /// `cos² θ` (1 where there is no stump).
    c2: T,
    /// Lanes with a stump (see [`StableFrame::new`] for when it is dropped).
    has_cone: T::Mask,
    /// `|d|` and the unit direction `d̂`.
    dl: T,
    dn: V3<T>,
    /// `d̂·â` and `d̂ × â`, `|d̂ × â|²`.
    zd: T,
    q: V3<T>,
    q2: T,
    /// Axial position of the local centre c0 (midpoint frame).
    z0: T,
    /// Ray parameter τ of the new origin, and the new origin relative to c0.
    tc: T,
    o: V3<T>,
    /// End-sphere centres relative to c0.
    ca: V3<T>,
    cb: V3<T>,
    /// `S + D`: the link's size `max(L, ra, rb)` plus the ray origin's distance to the
    /// midpoint, the scale of the kernel's error bound `E = 64ε(S + D) + …` (`tests/kernels/link/properties.rs`).
    sd: T,
}

impl<T: Real> StableFrame<T> {
    /// The frame of `ray` for the link `l`.
    #[inline(always)]
    fn new(l: &RoundCone<T>, ray: &Ray<T>) -> Self {
        let zero = T::zero();
        let one = T::one();
        let half = T::cst(0.5);
        let v = l.b - l.a;
        let len = v.length();
        let dr = l.ra - l.rb;
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
        let hl = len_s * half;

        let dl = ray.d.length();
        let dn = ray.d * (one / dl);
        let zd = dn.dot(axis);
        let q = dn.cross(axis);
        let q2 = q.length2();
        // Everything is formed relative to the end `a`, never in world coordinates: the ray
        // origin `o − a` (one rounding of size ε·|o − a| ≤ ε·(D + S)) and the midpoint `v/2`.
        // Forming the midpoint, the local centre or the new origin in world coordinates would
        // round each to ε·|a| — for a link far from the world origin (|a| ≫ S + D) a move of
        // the geometry far beyond E = 64ε(S + D) (a fuzz finding of the differential target: an
        // f32 link 2e-3 long at 32.5 from the world origin, exit 1.7 E off).
        let oa = ray.o - l.a;
        let mid = v * half;
        let w = mid - oa;
        let skew = q2.gt(T::cst(1e-12));
        let t_ax = (w.dot(dn) - w.dot(axis) * zd) / T::select(skew, q2, one);
        let t_ax = T::select(skew, t_ax, w.dot(dn));
        let z0 = (oa + dn * t_ax - mid).dot(axis).clamp(-hl, hl);
        let c0 = mid + axis * z0;
        let tc = (c0 - oa).dot(dn);
        let o = oa + dn * tc - c0;
        // End-sphere centres in the local frame.
        let ca = axis * (-hl - z0);
        let cb = axis * (hl - z0);
        let sd = len.max(l.ra).max(l.rb) + w.length();
        Self { len_s, hl, axis, s, c2, has_cone, dl, dn, zd, q, q2, z0, tc, o, ca, cb, sd }
    }

    /// The stump's crossings `[k0, k1]` (ray-space τ about the new origin), each polished
    /// ([`StumpSide::polish`]).
    #[inline(always)]
    fn stump_crossings(&self, l: &RoundCone<T>) -> StumpCrossings<T> {
        let half = T::cst(0.5);
        let (s, c2, zd, q, q2, z0, hl, o, axis) =
            (self.s, self.c2, self.zd, self.q, self.q2, self.z0, self.hl, self.o, self.axis);
        // Cone side: c·ρ + s·z = rm in midpoint-centred coordinates; at c0 it reads
        // c·ρ + s·z' = rm − s·z0 with z' = z − z0.
        let rm = (l.ra + l.rb) * half - s * z0;
        let zo = o.dot(axis);
        let p = o.cross(axis);
        let e = rm - s * zo;
        // F(τ) = c²|y × â|² − (rm − s·(y·â))², y = o + τ·d̂;  F = Aτ² + 2Bτ + C.
        let qa = c2 * q2 - s * s * zd * zd;
        let qb = c2 * p.dot(q) + s * zd * e;
        let qc = c2 * p.length2() - e * e;
        // Slab between the tangent circles: z ∈ [ra·s − L/2, L/2 + rb·s] (midpoint frame).
        let (lo, hi) = slab(zo, zd, l.ra * s - hl - z0, hl + l.rb * s - z0);
        // B² − AC expanded and regrouped (P = o×â, Q = d̂×â, both ⊥ â):
        //   B² − AC = c²·(|e·Q + s·zd·P|² − c²·|P×Q|²).
        // The e²-sized terms of B² and AC cancel exactly in this form; formed directly they
        // cancel in rounding, which loses every digit when the ray runs along a long link
        // (e ≫ |P|) — the discriminant is then c²s²zd²|P|², tiny against e².
        let eq = q * e + p * (s * zd);
        let disc = c2 * (eq.length2() - c2 * p.cross(q).length2());
        let hits = quadric_in_slab_disc(qa, qb, qc, disc, lo, hi);
        let side = StumpSide {
            p,
            q,
            e,
            cc: c2.sqrt(),
            szd: s * zd,
            hl,
            r_big: l.ra.max(l.rb),
            sd: self.sd,
            lo,
            hi,
            ok: hits.ok,
        };
        let (k0, real0, q0) = side.polish(hits.t0, hits.root0 & hits.ok);
        let (k1, real1, q1) = side.polish(hits.t1, hits.root1 & hits.ok);
        let ok = hits.ok & real0 & real1;
        let ok = ok & self.has_cone & k0.le(k1);
        StumpCrossings { k0, k1, side0: q0, side1: q1, ok }
    }

    /// Normal and curve parameter of the winning crossing at τ = `k`, given which piece won it.
    ///
    /// A crossing of a cap plane lies in the adjacent end sphere (the cap disc is inside it);
    /// it is exposed only when rounding loses that sphere's grazing interval, and then the
    /// sphere's normal is the right one.
    #[inline(always)]
    fn finish(&self, l: &RoundCone<T>, k: T, on_a: T::Mask, on_b: T::Mask, cone: T::Mask, side: T::Mask) -> (V3<T>, T) {
        let zero = T::zero();
        let one = T::one();
        let half = T::cst(0.5);
        let (s, axis, z0, hl) = (self.s, self.axis, self.z0, self.hl);
        let cc = self.c2.sqrt();
        let perp = orthonormal_basis(axis).0;
        let inv = one / (self.len_s * self.c2);
        let y = self.o + self.dn * k;
        let z = y.dot(axis);
        let radial = (y - axis * z).normalize_or_zero();
        // A point computed exactly on the axis (only by rounding) has no radial direction:
        // any perpendicular keeps the normal a unit vector.
        let radial = V3::select(radial.length2().gt(zero), radial, perp);
        let side_n = radial * cc + axis * s;
        let cap_b = cone & !side & (z + z0).gt((l.ra + l.rb) * s * half);
        let use_b = on_b | cap_b;
        let use_a = on_a | (cone & !side & !cap_b);
        let to_end = y - V3::select(use_b, self.cb, self.ca);
        // (At the tip of a zero-radius end there is no sphere: keep the side's normal.)
        let sph = use_a | use_b;
        let n = V3::select(sph & to_end.length2().gt(zero), to_end, side_n).normalize_or_zero();
        let u_side = ((z + z0 + hl - l.ra * s) * inv).clamp(zero, one);
        let u = T::select(use_b, one, T::select(use_a, zero, u_side));
        (n, u)
    }
}

/// The stump's side in the local frame, for [`StumpSide::polish`]: `g(τ) = c·|p + τq| −
/// (e − s·zd·τ)` is zero on the side and distance-like (`|∇g| = 1`).
struct StumpSide<T: Real> {
    p: V3<T>,
    q: V3<T>,
    e: T,
    /// `c = cos θ`.
    cc: T,
    /// `s·zd`.
    szd: T,
    /// `L/2` and `max(ra, rb)`: the size of the link about its midpoint is their sum.
    hl: T,
    r_big: T,
    /// [`StableFrame`]'s `S + D`.
    sd: T,
    /// The slab `[lo, hi]` of τ between the tangent circles.
    lo: T,
    hi: T,
    /// Lanes where the quadratic's interval is non-empty.
    ok: T::Mask,
}

impl<T: Real> StumpSide<T> {
    /// F squares the distance-like g: near a thin end seen from a far c0, F's root loses
    /// digits that g keeps. One safeguarded Newton step on g restores them. Returns the
    /// polished `k`, whether the end is a real crossing, and whether it is on the side.
    #[inline(always)]
    fn polish(&self, k: T, root: T::Mask) -> (T, T::Mask, T::Mask) {
        let (zero, one) = (T::zero(), T::one());
        let (p, q, cc, ok) = (self.p, self.q, self.cc, self.ok);
        let pq = p + q * k;
        let rho = pq.length();
        let g = cc * rho - (self.e - self.szd * k);
        let dg = cc * pq.dot(q) / T::select(rho.gt(zero), rho, one) + self.szd;
        let step = g / T::select(dg.abs().gt(zero), dg, one);
        // Safeguard: a quadratic's root is never worse than ≈ √ε relative (double
        // root), so a larger step means g's linearisation is not trustworthy here.
        let scale = k.abs() + self.hl + self.r_big + rho;
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
        // The polished root stays a crossing of the stump: clamp it into the slab.
        let kp = T::select(good, (k - step).clamp(self.lo, self.hi), k);
        // A cap end outside the cone is a crossing only if the step reached the side: g is
        // convex along the line, so a line that never enters the cone (parallel to a generator
        // and offset from it, where F's coefficients are rounding noise and claim the whole
        // slab) keeps g > 0 there. Its g is checked after the step, to the kernel's ε-sized
        // error (fuzz finding regression-generator-tangent: a line 4.6e-36 = 1.4e-8·L beside a
        // generator through a zero-radius tip; the step from the cap at the tip left g at
        // 1.35e-36, accepted by the √ε-sized `lim` of 6.7e-35, far above E = 1.2e-41).
        //
        // That error is at most the kernel's bound `E = 64ε(S + D)`, so the tolerance is
        // `64ε·min(scale, S + D)`: `scale` alone reaches ~3(S + D) (`|k|` counts from the new
        // origin), and accepted points off the side by more than E (differential fuzz finding
        // regression-generator-parallel-f32: an f32 line parallel to a generator 5.8e-4 outside
        // a 46-long link, where A is noise and g = 5.8e-4 passed 64ε·scale = 7.9e-4; E = 5.7e-4,
        // 64ε(S + D) = 4.8e-4). g's rounding at a real crossing is a few ε·scale, well inside.
        let tight = T::epsilon() * T::cst(64.0) * scale.min(self.sd);
        let (kp, gp) = self.settle(kp, root | cap_out, tight);
        // A root is a crossing only if it lies on the side to the kernel's own ε-sized error as
        // well: the √ε window alone let a root of F's noise stand 4.8e-41 off the side where
        // E = 1.2e-41 (fuzz finding regression-generator-offset: the same line beside a
        // generator through a tip, but offset 7.3e-38 at the far end too, so it passes
        // 8e-48 outside sphere b and never enters).
        let real = !(root | cap_out) | ((root & g.abs().le(lim) | cap_out) & gp.abs().le(tight));
        (kp, real, root | (good & cap_out))
    }

    /// `g` at `k`, and then Newton steps on `g` for the lanes in `todo` whose `|g|` is still
    /// above `tight`, at most three, each clamped into the slab. Returns the settled `k` and
    /// its `g`.
    ///
    /// g is convex along the line, so from a point outside the cone (g > 0) Newton steps
    /// move monotonically toward the nearer crossing without passing it, and from a point
    /// inside (g < 0) the first step lands outside and the next ones converge from there: a
    /// real crossing left slightly off by F's rounding settles within `tight`. A line that
    /// never enters the cone has no crossing to settle on and keeps g > `tight`. The steps
    /// run only while some lane still needs them (none, when the first polish settled every
    /// lane: the common case, which then costs one evaluation of g as before).
    #[inline(always)]
    fn settle(&self, mut k: T, todo: T::Mask, tight: T) -> (T, T) {
        let (zero, one) = (T::zero(), T::one());
        let (p, q, cc, szd) = (self.p, self.q, self.cc, self.szd);
        let g_at = |k: T| cc * (p + q * k).length() - (self.e - szd * k);
        let mut g = g_at(k);
        for _ in 0..3 {
            let open = todo & g.abs().gt(tight);
            if open.none() {
                break;
            }
            let pq = p + q * k;
            let rho = pq.length();
            let dg = cc * pq.dot(q) / T::select(rho.gt(zero), rho, one) + szd;
            let open = open & dg.abs().gt(T::epsilon().sqrt());
            if open.none() {
                break; // no lane can step: further rounds would change nothing
            }
            let next = (k - g / T::select(open, dg, one)).clamp(self.lo, self.hi);
            k = T::select(open, next, k);
            g = T::select(open, g_at(k), g);
        }
        (k, g)
    }
}

/// The stump's polished crossings ([`StableFrame::stump_crossings`]).
struct StumpCrossings<T: Real> {
    /// Entry and exit τ.
    k0: T,
    k1: T,
    /// Lanes whose entry / exit is on the curved side (not a cap plane).
    side0: T::Mask,
    side1: T::Mask,
    /// Lanes where the stump is crossed.
    ok: T::Mask,
}

/// The running hull `[t_in, t_out]` over the link's pieces, and which piece gave each end.
#[derive(Clone, Copy)]
struct PieceHull<T: Real> {
    t_in: T,
    t_out: T,
    /// Entry from sphere a / sphere b / the stump; the stump's entry on its side.
    in_a: T::Mask,
    in_b: T::Mask,
    cone_in: T::Mask,
    side_in: T::Mask,
    /// The same for the exit.
    out_a: T::Mask,
    out_b: T::Mask,
    cone_out: T::Mask,
    side_out: T::Mask,
}

impl<T: Real> PieceHull<T> {
    /// No piece yet: `[+∞, −∞]`.
    #[inline(always)]
    fn empty() -> Self {
        let no = T::Mask::splat(false);
        let inf = T::infinity();
        Self {
            t_in: inf,
            t_out: -inf,
            in_a: no,
            in_b: no,
            cone_in: no,
            side_in: no,
            out_a: no,
            out_b: no,
            cone_out: no,
            side_out: no,
        }
    }

    /// Widen by the two end spheres' chords.
    #[inline(always)]
    fn add_spheres(&mut self, a: Chord<T>, b: Chord<T>) {
        let (ai, ao) = widen(&mut self.t_in, &mut self.t_out, a.tc - a.h, a.tc + a.h, a.ok);
        let (bi, bo) = widen(&mut self.t_in, &mut self.t_out, b.tc - b.h, b.tc + b.h, b.ok);
        self.in_a = ai & !bi;
        self.out_a = ao & !bo;
        self.in_b = bi;
        self.out_b = bo;
    }

    /// Widen by the stump's crossings.
    #[inline(always)]
    fn add_stump(&mut self, c: StumpCrossings<T>) {
        let (ci, co) = widen(&mut self.t_in, &mut self.t_out, c.k0, c.k1, c.ok);
        self.in_a = self.in_a & !ci;
        self.in_b = self.in_b & !ci;
        self.out_a = self.out_a & !co;
        self.out_b = self.out_b & !co;
        self.cone_in = ci;
        self.cone_out = co;
        self.side_in = ci & c.side0;
        self.side_out = co & c.side1;
    }
}
