//! The WGSL link and sphere kernels against the CPU's `f32` kernels on the link-accuracy
//! generators (every region: thin/long, far origin, grazing, nearly flat, zero-radius tips,
//! axis-parallel, rays from inside), both judged by the oracle.
//!
//! Error analysis: the WGSL is the Rust kernel's arithmetic, operation for operation, without
//! fused multiply-adds, so an IEEE adapter (lavapipe) gives the same bits; an adapter whose
//! division or square root is a few ulps off (Vulkan allows 2.5 ulps for division and sqrt as
//! `1/inversesqrt`) perturbs each operation by a few ε, which the kernel's derived bound
//! `E = 64ε(S + D) + …` (`tubecast_oracle::link_error_bound`, ε = 2⁻²³) covers with the same
//! margin it leaves the CPU. So each GPU answer is checked as the CPU kernel's are: a hit point
//! within `E + E₆₄` of the exact surface; a hit where the line passes more than `E` inside, a
//! miss where it passes more than `E` outside; and hit/miss as the CPU's wherever the line's
//! gap to the surface exceeds `E`.

use tubecast::{Interval, Primitive, Ray, RoundCone, V3};
use tubecast_gpu::kernel::{Local, Pairs};
use tubecast_oracle::{line_gap, link_case, link_error_bound, sweep_dist, LinkRegion, Vec3, LINK_REGIONS};

const SEEDS: u64 = 1500;

fn v32(v: Vec3) -> V3<f32> {
    V3::new(v.x as f32, v.y as f32, v.z as f32)
}

#[test]
fn link_kernel_matches_the_cpu_on_every_generator_region() {
    let Some(gpu) = crate::gpu("link_kernel_matches_the_cpu_on_every_generator_region") else { return };
    let pairs = Pairs::new(&gpu).unwrap();
    let mut regions = LINK_REGIONS.to_vec();
    regions.push(LinkRegion::ZeroLength);
    let (mut total, mut same_bits) = (0usize, 0usize);
    for region in regions {
        let mut cases = Vec::new();
        let mut prims = Vec::new();
        let mut rays = Vec::new();
        for seed in 0..SEEDS {
            let c = link_case(seed, region);
            let l = &c.link;
            let Ok(link) = RoundCone::new(v32(l.a), l.ra as f32, v32(l.b), l.rb as f32) else { continue };
            cases.push((c, link));
            prims.push(Local::Link(link));
            rays.push(Ray::new(v32(c.ray.o), v32(c.ray.d)));
        }
        let got = pairs.line_intervals(&gpu, &prims, &rays).unwrap();
        for (((c, link), ray), g) in cases.iter().zip(&rays).zip(&got) {
            let cpu: Interval<f32> = link.line_interval(ray);
            total += 1;
            same_bits += usize::from(bits(&cpu) == bits(g));
            let e = link_error_bound(&c.link, c.ray.o, c.size, f64::from(f32::EPSILON));
            let e64 = link_error_bound(&c.link, c.ray.o, c.size, f64::EPSILON);
            let (gap, _) = line_gap(&c.link, &c.ray);
            let what = format!("{} seed case {c:?}: gpu {g:?} cpu {cpu:?}", region.name());
            if gap < -e {
                assert!(g.hit, "false miss, gap {gap:e} < -E {e:e}: {what}");
            }
            if gap > e {
                assert!(!g.hit, "false hit, gap {gap:e} > E {e:e}: {what}");
            }
            if g.hit != cpu.hit {
                assert!(gap.abs() <= e, "hit/miss differs outside the band, gap {gap:e}, E {e:e}: {what}");
            }
            if g.hit {
                assert!(g.entry.t <= g.exit.t, "{what}");
                for t in [g.entry.t, g.exit.t] {
                    let (sd, _) = sweep_dist(&c.link, c.ray.at(f64::from(t)));
                    assert!(sd.abs() <= e + e64, "hit point {sd:e} off the surface (E {e:e}): {what}");
                }
            }
        }
    }
    eprintln!("link kernel: {same_bits} of {total} GPU intervals bit-identical to the CPU's");
    assert!(total > 10_000, "{total} cases");
}

#[test]
fn sphere_kernel_matches_the_cpu() {
    let Some(gpu) = crate::gpu("sphere_kernel_matches_the_cpu") else { return };
    let pairs = Pairs::new(&gpu).unwrap();
    let mut prims = Vec::new();
    let mut rays = Vec::new();
    for seed in 0..4000 {
        // Spheres of radius 1e-3 … 1e3, rays from 2 to 1e4 radii away aimed within 1.5 radii.
        let c = link_case(seed, LinkRegion::ZeroLength);
        let r = c.link.ra as f32;
        let off = c.ray.o - c.link.a;
        prims.push(Local::Sphere(r));
        rays.push(Ray::new(v32(off), v32(c.ray.d)));
    }
    let got = pairs.line_intervals(&gpu, &prims, &rays).unwrap();
    let mut same = 0;
    for ((p, ray), g) in prims.iter().zip(&rays).zip(&got) {
        let Local::Sphere(r) = *p else { unreachable!() };
        let cpu = tubecast::Sphere { c: V3::zero(), r }.line_interval(ray);
        assert_eq!(g.hit, cpu.hit, "{ray:?} r {r}: gpu {g:?} cpu {cpu:?}");
        if g.hit {
            // Two f32 evaluations of the same formulas: within a few ε of the chord's scale.
            let tol = 8.0 * f32::EPSILON * (ray.o.length() + r) / ray.d.length();
            assert!((g.entry.t - cpu.entry.t).abs() <= tol && (g.exit.t - cpu.exit.t).abs() <= tol, "{g:?} {cpu:?}");
        }
        same += usize::from(bits(&cpu) == bits(g));
    }
    eprintln!("sphere kernel: {same} of {} bit-identical", prims.len());
}

/// The bits of an interval (hit flag, both `t`).
fn bits(iv: &Interval<f32>) -> (bool, u32, u32) {
    (iv.hit, iv.entry.t.to_bits(), iv.exit.t.to_bits())
}
