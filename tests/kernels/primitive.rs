//! The `Primitive` trait over `Sphere`, `RoundCone`, `HanLink` and `QuadTube`:
//! * bit-for-bit pins of every method against the functions it replaced (fingerprints
//!   recorded from them before the change; correctness itself is the business of the oracle
//!   tests, these only say "nothing moved by a bit"), in f32, f64 and both lane types, and
//!   lanes equal to scalar calls;
//! * the line interval ignores the ray's range and `intersect` applies it;
//! * boxes contain sampled points of each solid, `RoundCone::obb` is conservative and tight;
//! * the signed distance vanishes at hit points.
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tubecast::baseline::HanLink;
use tubecast::{
    Aabb, Interval, Primitive, QuadTube, Ray, Real, RoundCone, Scalar, Solver, Sphere, WideF32x8, WideF64x4, V3,
};
use tubecast_oracle::Quad;

struct Case {
    link: RoundCone<f64>,
    quad: QuadTube<f64>,
    ray: Ray<f64>,
    p: V3<f64>,
}

fn cases(n: usize) -> Vec<Case> {
    let mut rng = StdRng::seed_from_u64(9);
    let mut out = Vec::new();
    while out.len() < n {
        let mut v = |s: f64| V3::new(rng.gen_range(-s..s), rng.gen_range(-s..s), rng.gen_range(-s..s));
        let a = v(2.0);
        let b = a + v(3.0);
        let (q0, q1, q2) = (v(2.0), v(2.0), v(2.0));
        let target = (a + b) * 0.5 + v(1.5);
        let o = v(8.0);
        let p = target + v(1.0);
        let ra = rng.gen_range(0.05..1.0);
        let rb = match rng.gen_range(0..4) {
            0 => ra,
            1 => 0.0,
            _ => rng.gen_range(0.0..1.0),
        };
        let r = [rng.gen_range(0.05..0.8), rng.gen_range(0.05..0.8), rng.gen_range(0.05..0.8)];
        let t_min = [0.0, -f64::INFINITY, rng.gen_range(-1.0..1.0)][rng.gen_range(0..3)];
        let t_max = [f64::INFINITY, rng.gen_range(1.0..2.0)][rng.gen_range(0..2)];
        let d = (target - o) * rng.gen_range(0.01..10.0);
        let (Ok(link), Ok(quad)) = (RoundCone::new(a, ra, b, rb), QuadTube::new([q0, q1, q2], r)) else { continue };
        out.push(Case { link, quad, ray: Ray::with_range(o, d, t_min, t_max), p });
    }
    out
}

fn cast_ray<U: Scalar>(r: &Ray<f64>) -> Ray<U> {
    Ray::with_range(r.o.cast(), r.d.cast(), U::from_f64(r.t_min), U::from_f64(r.t_max))
}

/// FNV-1a over the bits of every lane of every output.
struct Fnv(u64);

impl Fnv {
    fn bits(&mut self, x: u64) {
        for b in x.to_le_bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn real<T: Real>(&mut self, x: T) {
        for i in 0..T::LANES {
            self.bits(x.lane(i).to_f64().to_bits());
        }
    }
    fn v3<T: Real>(&mut self, v: V3<T>) {
        self.real(v.x);
        self.real(v.y);
        self.real(v.z);
    }
    fn iv<T: Real>(&mut self, iv: &Interval<T>) {
        for i in 0..T::LANES {
            let l = iv.lane(i);
            for x in [
                l.entry.t,
                l.exit.t,
                l.entry.n.x,
                l.entry.n.y,
                l.entry.n.z,
                l.exit.n.x,
                l.exit.n.y,
                l.exit.n.z,
                l.entry.u,
                l.exit.u,
            ] {
                self.bits(x.to_f64().to_bits());
            }
            self.bits(l.hit as u64);
        }
    }
}

/// Fingerprints `[sphere, link, han, quad]` of the intersections and boxes of `cases` in lane
/// type `T` (`T::LANES` consecutive cases per lane group).
fn fingerprint<T: Real>(cs: &[Case]) -> [u64; 4] {
    let mut h = [FNV0; 4].map(Fnv);
    for g in cs.chunks_exact(T::LANES) {
        let link = RoundCone::<T>::from_lanes(|i| g[i].link.cast());
        let quad = QuadTube::<T>::from_lanes(|i| g[i].quad.cast());
        let ray = Ray::<T>::from_fn(|i| cast_ray(&g[i].ray));
        // Was `intersect_sphere(&ray, link.a, link.ra, 0)`.
        h[0].iv(&Sphere { c: link.a, r: link.ra }.intersect(&ray));
        h[1].iv(&link.intersect(&ray));
        h[2].iv(&HanLink::new(&link).intersect(&ray));
        h[3].iv(&quad.intersect(&ray));
        // Was `Obb::aabb(&quad)`, an identity-frame Obb, moved to world coordinates.
        let bx = quad.aabb();
        h[3].v3(bx.min);
        h[3].v3(bx.max);
        let o = quad.obb();
        for v in [o.origin, o.axes[0], o.axes[1], o.axes[2], o.lo, o.hi] {
            h[3].v3(v);
        }
    }
    h.map(|f| f.0)
}

/// Scalar pins: the link's box (was `RoundCone::aabb -> (min, max)`, scalar only) and the
/// distances (were `sdf::sphere`, `sdf::round_cone`, `spline::quadratic_tube`).
fn fingerprint_scalar<T: Scalar>(cs: &[Case]) -> [u64; 4] {
    let mut h = [FNV0; 4].map(Fnv);
    for c in cs {
        let link: RoundCone<T> = c.link.cast();
        let quad: QuadTube<T> = c.quad.cast();
        let p: V3<T> = c.p.cast();
        h[0].real(Sphere { c: link.a, r: link.ra }.sdf(p));
        let bx = link.aabb();
        h[1].v3(bx.min);
        h[1].v3(bx.max);
        h[1].real(link.sdf(p));
        h[2].real(HanLink::new(&link).sdf(p));
        h[3].real(quad.sdf(p));
    }
    h.map(|f| f.0)
}

const FNV0: u64 = 0xcbf2_9ce4_8422_2325;

#[test]
fn bit_identical_to_the_replaced_functions() {
    let cs = cases(256);
    // Fingerprints of every answer (intervals, normals, curve parameters) of the four kernels
    // (slot 0 sphere, 1 stable link, 2 Han's link, 3 spline piece) on the same cases, so that
    // any change of rounding fails here. A slot is re-recorded only when a kernel's arithmetic
    // is changed on purpose and its answers are shown within the derived band E by the accuracy
    // tests (tests/splines/conditioning.rs, tests/kernels/link/far_from_world.rs); each
    // such change and its reason is in CHANGELOG.md. Slots 0 and 2 hold the answers of the
    // functions these replaced.
    assert_eq!(
        fingerprint::<f64>(&cs),
        [0xba79df740085b444, 0x20be78c5e185ac86, 0x403afd8b99b02e6f, 0xbabb30bcf6f17bb8]
    );
    assert_eq!(
        fingerprint::<f32>(&cs),
        [0x5b4698ba48087a8e, 0xb024259242bc31bd, 0x77b75045ede7a321, 0x0d44ac20817a3503]
    );
    assert_eq!(
        fingerprint::<WideF32x8>(&cs),
        [0x5b4698ba48087a8e, 0xb024259242bc31bd, 0x77b75045ede7a321, 0x07a82c2fee93a65b]
    );
    assert_eq!(
        fingerprint::<WideF64x4>(&cs),
        [0xba79df740085b444, 0x20be78c5e185ac86, 0x403afd8b99b02e6f, 0x019237f4527216a0]
    );
    assert_eq!(
        fingerprint_scalar::<f64>(&cs),
        [0x53bca9c9d5e6a5e9, 0xc3213ffa503b2dc3, 0x9c17b928b1891f62, 0x863109bcab403f76]
    );
    assert_eq!(
        fingerprint_scalar::<f32>(&cs),
        [0xc626ac8edec4aad9, 0x9a09fabd930cb445, 0x2f31aa94fa900b23, 0x77cac46c15db7293]
    );
}

/// `QuadTube`'s trait interval is `intersect_with(Solver::Polynomial)`, bit for bit.
#[test]
fn quad_tube_default_solver() {
    for c in cases(64) {
        assert_eq!(c.quad.intersect(&c.ray), c.quad.intersect_with(&c.ray, Solver::Polynomial));
    }
}

/// Every lane of every method equals the scalar call on that lane's data.
fn lanes_equal_scalar<T: Real>(cs: &[Case])
where
    T::Elem: Scalar,
{
    for g in cs.chunks_exact(T::LANES) {
        let one = |i: usize| (g[i].link.cast::<T::Elem>(), g[i].quad.cast::<T::Elem>(), cast_ray::<T::Elem>(&g[i].ray));
        let link = RoundCone::<T>::from_lanes(|i| one(i).0);
        let quad = QuadTube::<T>::from_lanes(|i| one(i).1);
        let ray = Ray::<T>::from_fn(|i| one(i).2);
        let ball = Sphere::<T>::from_lanes(|i| Sphere { c: one(i).0.b, r: one(i).0.ra });
        let han = HanLink::new(&link);
        let p = V3::<T>::from_fn(|i| g[i].p.cast());
        for i in 0..T::LANES {
            let (l, q, r) = one(i);
            let b = Sphere { c: l.b, r: l.ra };
            let hl = HanLink::new(&l);
            let pi = p.lane(i);
            assert_eq!(ball.line_interval(&ray).lane(i), b.line_interval(&r));
            assert_eq!(ball.intersect(&ray).lane(i), b.intersect(&r));
            assert_eq!(link.line_interval(&ray).lane(i), l.line_interval(&r));
            assert_eq!(link.intersect(&ray).lane(i), l.intersect(&r));
            assert_eq!(han.line_interval(&ray).lane(i), hl.line_interval(&r));
            assert_eq!(han.intersect(&ray).lane(i), hl.intersect(&r));
            assert_eq!(quad.line_interval(&ray).lane(i), q.line_interval(&r));
            assert_eq!(quad.intersect(&ray).lane(i), q.intersect(&r));
            assert_eq!(ball.aabb().lane(i), b.aabb());
            assert_eq!(link.aabb().lane(i), l.aabb());
            assert_eq!(han.aabb().lane(i), hl.aabb());
            assert_eq!(quad.aabb().lane(i), q.aabb());
            assert_eq!(ball.sdf(p).lane(i), b.sdf(pi));
            assert_eq!(link.sdf(p).lane(i), l.sdf(pi));
            assert_eq!(han.sdf(p).lane(i), hl.sdf(pi));
            assert_eq!(quad.sdf(p).lane(i), q.sdf(pi));
            let (ol, oq) = (link.obb(), quad.obb());
            let (sl, sq) = (l.obb(), q.obb());
            assert_eq!([ol.origin.lane(i), ol.lo.lane(i), ol.hi.lane(i)], [sl.origin, sl.lo, sl.hi]);
            assert_eq!([oq.origin.lane(i), oq.lo.lane(i), oq.hi.lane(i)], [sq.origin, sq.lo, sq.hi]);
            assert_eq!(ol.axes.map(|a| a.lane(i)), sl.axes);
            assert_eq!(oq.axes.map(|a| a.lane(i)), sq.axes);
        }
    }
}

#[test]
fn lanes_equal_scalar_calls() {
    let cs = cases(64);
    lanes_equal_scalar::<WideF32x8>(&cs);
    lanes_equal_scalar::<WideF64x4>(&cs);
}

/// The four primitives of a case as trait objects.
fn prims(c: &Case) -> [(&'static str, Box<dyn Primitive<f64>>); 4] {
    let l = c.link;
    [
        ("sphere", Box::new(Sphere::new(l.a, l.ra).unwrap())),
        ("link", Box::new(l)),
        ("han", Box::new(HanLink::new(&l))),
        ("quad", Box::new(c.quad)),
    ]
}

/// The line interval does not depend on the ray's range; `intersect` keeps it (unchanged)
/// exactly where it overlaps the range.
#[test]
fn line_interval_ignores_the_range() {
    let mut hits = 0;
    for c in cases(128) {
        for (name, p) in prims(&c) {
            let full = Ray::with_range(c.ray.o, c.ray.d, -f64::INFINITY, f64::INFINITY);
            let line = p.line_interval(&full);
            assert_eq!(p.intersect(&full), line, "{name}");
            if !line.hit {
                continue;
            }
            hits += 1;
            let (ti, to) = (line.entry.t, line.exit.t);
            let ranges =
                [(to + 1.0, to + 2.0, false), (ti - 2.0, ti - 1.0, false), (ti - 1.0, ti, true), (to, to + 1.0, true)];
            for (t0, t1, overlaps) in ranges {
                let r = Ray::with_range(c.ray.o, c.ray.d, t0, t1);
                assert_eq!(p.line_interval(&r), line, "{name}");
                let iv = p.intersect(&r);
                if overlaps {
                    assert_eq!(iv, line, "{name}");
                } else {
                    assert!(!iv.hit && iv == Interval::miss(), "{name}: {iv:?}");
                }
            }
        }
    }
    assert!(hits > 100, "only {hits} hits");
}

/// Points of the solid: spheres `S(p(u), r(u))` of the sweep sampled on a grid of
/// directions, computed in f64 from the primitive's own (already rounded) data.
fn solid_samples(centre_radius: impl Fn(f64) -> (V3<f64>, f64)) -> Vec<V3<f64>> {
    let mut out = Vec::new();
    for k in 0..=32 {
        let (p, r) = centre_radius(k as f64 / 32.0);
        for i in 0..12 {
            for j in 0..=6 {
                let (th, ph) = (std::f64::consts::PI * j as f64 / 6.0, std::f64::consts::TAU * i as f64 / 12.0);
                out.push(p + V3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()) * r);
            }
        }
    }
    out
}

/// Boxes contain the sampled points of each solid, to a margin: a box coordinate is formed
/// with at most 1 rounding (`c ± r`, sphere and link) or, for the tube, the Obb extents
/// (≤ 16ε·S, the bound of tests/splines/obb.rs) plus moving them to world coordinates (ε·S),
/// where S is the largest coordinate or radius magnitude; the samples' own f64 rounding is
/// ≤ 4ε₆₄·S. So 32ε·S (ε of the box's precision) bounds it.
fn check_boxes<T: Scalar>(cs: &[Case]) {
    for c in cs {
        let l: RoundCone<T> = c.link.cast();
        let q: QuadTube<T> = c.quad.cast();
        let (lf, qf) = (l.cast::<f64>(), q.cast::<f64>());
        let lerp = |u: f64| (lf.a + (lf.b - lf.a) * u, lf.ra + (lf.rb - lf.ra) * u);
        let quad = |t: f64| {
            let q = Quad::new(qf.b.map(|v| v.to_array()), qf.r);
            (V3::from(q.point(t).to_array()), q.radius(t))
        };
        let ball = Sphere { c: l.a, r: l.ra };
        let sets: [Samples<T>; 4] = [
            ("sphere", ball.aabb(), solid_samples(|_| (lf.a, lf.ra)), lf.a.max_abs() + lf.ra),
            ("link", l.aabb(), solid_samples(lerp), lf.a.max_abs().max(lf.b.max_abs()) + lf.ra.max(lf.rb)),
            (
                "han",
                HanLink::new(&l).aabb(),
                solid_samples(lerp),
                lf.a.max_abs().max(lf.b.max_abs()) + lf.ra.max(lf.rb),
            ),
            (
                "quad",
                q.aabb(),
                solid_samples(quad),
                qf.b.iter().fold(0.0, |m, v| v.max_abs().max(m)) + qf.r.iter().fold(0.0, |m, r| r.max(m)),
            ),
        ];
        for (name, bx, pts, s) in sets {
            let m = 32.0 * T::EPS.to_f64() * s;
            let (lo, hi) = (bx.min.cast::<f64>() - V3::new(m, m, m), bx.max.cast::<f64>() + V3::new(m, m, m));
            let grown = Aabb::new(lo, hi);
            for x in pts {
                assert!(grown.contains(x), "{name}: {x:?} outside {bx:?}");
            }
        }
    }
}

/// Name, box, sample points, size S.
type Samples<T> = (&'static str, Aabb<T>, Vec<V3<f64>>, f64);

#[test]
fn boxes_contain_the_solids() {
    let cs = cases(64);
    check_boxes::<f64>(&cs);
    check_boxes::<f32>(&cs);
}

/// `RoundCone::obb` contains the solid and each face touches it: along a unit axis `a` the
/// hull of two spheres reaches `max(a·A + ra, a·B + rb)` (closed form); the box is formed
/// from a few dot products of size-S numbers (≤ 16εS, as in tests/splines/obb.rs).
#[test]
fn round_cone_obb_conservative_and_tight() {
    for c in cases(64) {
        let l = c.link;
        let o = l.obb();
        let s = l.a.max_abs().max(l.b.max_abs()) + l.ra.max(l.rb) + 1.0;
        let tol = 16.0 * f64::EPSILON * s;
        let lerp = |u: f64| (l.a + (l.b - l.a) * u, l.ra + (l.rb - l.ra) * u);
        for x in solid_samples(lerp) {
            let y = o.local(x);
            assert!(y.x >= o.lo.x - tol && y.x <= o.hi.x + tol, "{x:?} {o:?}");
            assert!(y.y >= o.lo.y - tol && y.y <= o.hi.y + tol, "{x:?} {o:?}");
            assert!(y.z >= o.lo.z - tol && y.z <= o.hi.z + tol, "{x:?} {o:?}");
        }
        for (k, a) in o.axes.iter().enumerate() {
            let sup = |sign: f64| (sign * (l.a - o.origin).dot(*a) + l.ra).max(sign * (l.b - o.origin).dot(*a) + l.rb);
            assert!((o.hi.to_array()[k] - sup(1.0)).abs() <= tol, "axis {k}: {o:?}");
            assert!((o.lo.to_array()[k] + sup(-1.0)).abs() <= tol, "axis {k}: {o:?}");
        }
    }
}

/// The signed distance vanishes at hit points (f64), within each kernel's derived bound:
/// * sphere: 16ε(|o − c| + r) (fuzz/checks/sphere.rs);
/// * stable link: E = 64ε(S + D), S = max(L, ra, rb), D = |o − m| (tests/kernels/link/properties.rs),
///   for links without a pointed end or a nearly flat stump (the cases here: radii ≥ 0.05,
///   `c² = 1 − s² ≥ 0.01`, else skipped);
/// * faithful link: 64ε·D'·max(D'/r_min, 1), D' = D + 100S (tests/kernels/link/properties.rs);
/// * tube: √(64ε)·S + 8εS + 8εS, S = scale + 2 (tests/splines/kernel.rs);
///
/// plus forming `x = o + t·d` in absolute coordinates: 4ε(|o| + |t·d| + S).
#[test]
fn sdf_vanishes_at_hits() {
    let eps = f64::EPSILON;
    let mut n = 0;
    for c in cases(256) {
        let (l, ray) = (c.link, c.ray);
        let len = (l.b - l.a).length();
        let (s, d) = (len.max(l.ra).max(l.rb), (ray.o - (l.a + l.b) * 0.5).length());
        let sin = (l.ra - l.rb) / len.max(1e-300);
        let plain = l.ra.min(l.rb) >= 0.05 && 1.0 - sin * sin >= 0.01;
        let dd = d + 100.0 * s;
        let qs = crate::spline_common::scale(&c.quad.b.map(|v| v.to_array()), &c.quad.r) + 2.0;
        let bounds = [
            16.0 * eps * ((ray.o - l.a).length() + l.ra),
            if plain { 64.0 * eps * (s + d) } else { f64::NAN },
            if plain { 64.0 * eps * dd * (dd / l.ra.min(l.rb)).max(1.0) } else { f64::NAN },
            (64.0 * eps).sqrt() * qs + 16.0 * eps * qs,
        ];
        for ((name, p), e) in prims(&c).into_iter().zip(bounds) {
            let iv = p.intersect(&ray);
            if !iv.hit || e.is_nan() {
                continue;
            }
            for t in [iv.entry.t, iv.exit.t].into_iter().filter(|t| t.is_finite()) {
                let x = ray.at(t);
                let fx = 4.0 * eps * (ray.o.length() + (t * ray.d.length()).abs() + s + qs);
                let f = p.sdf(x);
                assert!(f.abs() <= e + fx, "{name}: sdf {f:e} at t = {t} (bound {e:e} + {fx:e})");
                n += 1;
            }
        }
    }
    assert!(n > 200, "only {n} hit points");
}
