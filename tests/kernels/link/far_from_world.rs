//! The stable link kernel on links far from the world origin (a fuzz finding of the
//! `differential` target).
//!
//! The error analysis of `tests/kernels/link/properties.rs` bounds a hit point's distance from the surface by
//! `E = 64·ε·(S + D)`: the link's size `S` and the ray origin's distance `D` from the link's
//! midpoint, and nothing else. So the link's distance from the *world* origin, `|m|`, must not
//! enter: every quantity the kernel forms is a difference of inputs (`o − a`, `b − a`), each
//! rounded once to `ε·(D + S)`, never a world-coordinate sum such as `(a + b)/2` or `o + τ·d̂`
//! (each rounded to `ε·|m|`). The kernel once formed its local frame in world coordinates: an
//! `f32` link 2·10⁻³ long at 32.5 from the world origin (`|m|/S ≈ 1.7·10⁴`) had its exit 1.7·E
//! off (`fuzz/corpus/differential/regression-far-from-world-origin`).
//!
//! The generators of `tests/kernels/common` place links within a few sizes of the world origin, so these
//! properties move every region's case by `10^k` sizes (`k ∈ [1, 7]`, a random direction) and
//! hold the kernel to the same `E` in `f32` and `f64`, lanes included. The `f32` problem is the
//! translated one rounded to `f32` (the oracle sees exactly that problem, its size recomputed).

use crate::common::check::*;
use crate::common::*;
use proptest::prelude::*;
use tubecast::{Primitive, Ray, RoundCone, WideF32x8, WideF64x4, V3};

fn region() -> impl Strategy<Value = Region> {
    proptest::sample::select(REGIONS.to_vec())
}

/// `c` moved by `10^k` of its sizes along the unit vector `dir`.
fn moved(c: &Case, dir: V3<f64>, k: f64) -> Case {
    let t = dir * (c.size * 10f64.powf(k));
    Case { link: RoundCone { a: c.link.a + t, b: c.link.b + t, ..c.link }, ray: Ray { o: c.ray.o + t, ..c.ray }, ..*c }
}

/// The far case moved back by its own end `a`, for the oracle: the kernel's `t` is a ray
/// parameter, the same for both. The test must not judge in world coordinates — forming a hit
/// point `o + t·d` there rounds to `ε·|m|`, the very term the kernel must not have. For `f32`
/// inputs the differences are exact in `f64` (two `f32` values within a factor 2⁻²⁹ of each
/// other's magnitude differ by a 24-bit multiple of the smaller ulp); for `f64` inputs each is
/// within `ε·(D + S)`, inside the `2ε·(2D + 2S)` that `tests/kernels/link/properties.rs` budgets for forming
/// the hit point.
fn back(c: &Case) -> Case {
    let r = c.link.a;
    let link = RoundCone { a: c.link.a - r, b: c.link.b - r, ..c.link };
    let size = (link.b - link.a).length().max(link.ra).max(link.rb);
    Case { link, ray: Ray { o: c.ray.o - r, ..c.ray }, size, ..*c }
}

/// The case rounded to `f32`, with its size recomputed from the rounded link; `None` when
/// rounding made the link invalid.
fn rounded(c: &Case) -> Option<Case> {
    let r = round_case_f32(c);
    RoundCone::new(r.link.a, r.link.ra, r.link.b, r.link.rb).ok()?;
    let size = (r.link.b - r.link.a).length().max(r.link.ra).max(r.link.rb);
    Some(Case { size, ..r })
}

fn unit_dir(x: f64, y: f64, z: f64) -> V3<f64> {
    let v = V3::new(x, y, z);
    let l = v.length();
    if l > 1e-3 {
        v * (1.0 / l)
    } else {
        V3::new(1.0, 0.0, 0.0)
    }
}

fn f32_run(c: &Case) -> tubecast::Interval<f64> {
    let l32: RoundCone<f32> = c.link.cast();
    let r32 = Ray { o: c.ray.o.cast(), d: c.ray.d.cast(), t_min: c.ray.t_min as f32, t_max: f32::INFINITY };
    iv64(l32.intersect(&r32))
}

proptest! {
    #[test]
    fn stable_far_from_world_matches_oracle(
        seed in any::<u64>(), region in region(), k in 1.0f64..7.0,
        x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0,
    ) {
        let c = moved(&make_case(seed, region), unit_dir(x, y, z), k);
        check_against_oracle(&back(&c), c.link.intersect(&c.ray), f64::EPSILON, "stable f64, far from the world origin")?;
        let Some(c32) = rounded(&c) else { return Ok(()) };
        check_against_oracle(&back(&c32), f32_run(&c32), f32::EPSILON as f64, "stable f32, far from the world origin")?;
    }

    #[test]
    fn far_from_world_lanes_equal_scalar(
        seeds in proptest::array::uniform8(any::<u64>()), region in region(), k in 1.0f64..7.0,
    ) {
        // Lanes run the scalar kernel's IEEE operations in order: equal bit for bit.
        let cases: Vec<Case> = seeds.iter().enumerate().map(|(i, &s)| {
            let dir = unit_dir(1.0, i as f64 - 3.5, 0.5);
            moved(&make_case(s, region), dir, k)
        }).collect();
        let l8 = RoundCone::<WideF32x8>::from_lanes(|i| cases[i].link.cast());
        let r8 = Ray::<WideF32x8>::from_fn(|i| Ray::new(cases[i].ray.o.cast(), cases[i].ray.d.cast()));
        let s8 = l8.intersect(&r8);
        for (i, c) in cases.iter().enumerate() {
            let l: RoundCone<f32> = c.link.cast();
            prop_assert_eq!(s8.lane(i), l.intersect(&r8.lane(i)), "stable f32x8 lane {}", i);
        }
        let l4 = RoundCone::<WideF64x4>::from_lanes(|i| cases[i].link);
        let r4 = Ray::<WideF64x4>::from_fn(|i| cases[i].ray);
        let s4 = l4.intersect(&r4);
        for (i, c) in cases.iter().enumerate().take(4) {
            prop_assert_eq!(s4.lane(i), c.link.intersect(&c.ray), "stable f64x4 lane {}", i);
        }
    }
}

/// The fuzz finding itself (`fuzz/corpus/differential/regression-far-from-world-origin`): a cone
/// from a tip at `a` to a sphere of radius `rb ≈ 3.2·10⁻⁴` at `b`, 1.96·10⁻³ along `z`, both at
/// 32.5 from the world origin; the ray starts inside the sphere, 2.99·10⁻⁴ off the axis at `b`'s
/// height, and leaves nearly along `+z`. Its exit is through the sphere at `b`, so the right
/// answer is the larger root of `|p + t·d|² = rb²` with `p = o − b` (exact here: all inputs are
/// `f32` values a few ulps apart). Both precisions must put it within `E + E₆₄` of that root,
/// measured along the ray through the incidence cosine.
#[test]
fn f32_link_far_from_world_exits_where_the_sphere_does() {
    let a = V3::new(0.0, 32.50196075439453, 32.5);
    let b = V3::new(0.0, 32.50196075439453, 32.50196075439453);
    let rb = 0.000316217599902302;
    let link = RoundCone::new(a, 0.0, b, rb).unwrap();
    let o = V3::new(0.0002992746885865927, 32.50196075439453, 32.50196075439453);
    let d = V3::new(0.0002736598835326731, 0.00029285860364325345, 0.7090400457382202);
    let ray = Ray::new(o, d);
    // Every input is an f32 value.
    for x in [a.x, a.y, a.z, b.x, b.y, b.z, rb, o.x, o.y, o.z, d.x, d.y, d.z] {
        assert_eq!(x as f32 as f64, x);
    }
    let p = o - b; // exact (Sterbenz)
    let (dd, pd, c) = (d.dot(d), p.dot(d), p.dot(p) - rb * rb);
    let exit = (-pd + (pd * pd - dd * c).sqrt()) / dd;
    let x = p + d * exit;
    let gamma = (x * (1.0 / x.length())).dot(d) / d.length();
    let size = (b - a).length().max(rb);
    let m = (a + b) * 0.5;
    let e32 = tubecast_oracle::link_error_bound(&olink(&link), ov(o), size, f32::EPSILON as f64);
    let e64 = tubecast_oracle::link_error_bound(&olink(&link), ov(o), size, f64::EPSILON);
    // (The root itself is formed from numbers of size rb with a handful of roundings: its error
    // is far below E₆₄; 1e-12·t covers it.)
    let tol = |e: f64| (e + e64) / (gamma * d.length()) + 1e-12 * exit;
    assert!((o - m).length() < 2.0 * size, "the bound's D is small: only |m| is large");
    let t64 = link.intersect(&ray);
    assert!(t64.hit && (t64.exit.t - exit).abs() <= tol(e64), "f64 exit {} vs {exit}", t64.exit.t);
    let l32: RoundCone<f32> = link.cast();
    let t32 = l32.intersect(&Ray::new(o.cast::<f32>(), d.cast::<f32>()));
    assert!(t32.hit, "f32 misses");
    let err = (t32.exit.t as f64 - exit).abs();
    assert!(err <= tol(e32), "f32 exit {} vs {exit}: off by {err:e} > {:e}", t32.exit.t, tol(e32));
}
