//! Occupancy (Kraaijeveld Alg. 2 and 3, `tubecast::voxel::{clipped_sdf, occupancy}`) against
//! sampled volume fractions, with the bounds derived in `src/kernel/voxel/occupancy.rs`.

use tubecast::voxel::{clipped_sdf, occupancy};
use tubecast::{RoundCone, V3};
use tubecast_oracle::{sweep_dist, Link, Vec3};

type V = V3<f64>;

/// Fraction of the unit voxel at `corner` inside the link, by the oracle's exact distance at
/// `n³` stratified points.
fn sampled_fraction(l: &RoundCone<f64>, corner: [f64; 3], n: usize) -> f64 {
    let ol = Link { a: Vec3::new(l.a.x, l.a.y, l.a.z), ra: l.ra, b: Vec3::new(l.b.x, l.b.y, l.b.z), rb: l.rb };
    let mut inside = 0;
    for i in 0..n * n * n {
        let q = [i % n, (i / n) % n, i / (n * n)].map(|k| (k as f64 + 0.5) / n as f64);
        let x = Vec3::new(corner[0] + q[0], corner[1] + q[1], corner[2] + q[2]);
        inside += (sweep_dist(&ol, x).0 <= 0.0) as usize;
    }
    inside as f64 / (n * n * n) as f64
}

/// `s(c) ≥ √3/2`: empty voxel, estimate 0; `s(c) ≤ −√3/2`: full voxel, estimate 1 (the
/// 1-Lipschitz argument); checked against sampled fractions on random links.
#[test]
fn estimate_is_exact_where_the_sdf_decides_the_voxel() {
    let half_diag = 3f64.sqrt() / 2.0;
    let (mut empty, mut full) = (0, 0);
    for k in 0..12 {
        let f = k as f64;
        let a = V::new(5.0 + 0.37 * f, 5.0 + 0.11 * f, 5.0 - 0.23 * f);
        let b = a + V::new(4.0 - 0.5 * f, 1.0 + 0.3 * f, 2.5 - 0.1 * f);
        let l = RoundCone { a, ra: 1.0 + 0.2 * f, b, rb: 0.5 + 0.1 * f };
        for i in 0..13 * 13 * 13 {
            let corner = [i % 13, (i / 13) % 13, i / 169].map(|x| x as f64);
            let c = V::new(corner[0] + 0.5, corner[1] + 0.5, corner[2] + 0.5);
            let s = clipped_sdf(c, &l, None, None);
            let occ = occupancy(c, &l, None, None, 0.0);
            if s >= half_diag {
                assert_eq!((occ, sampled_fraction(&l, corner, 4)), (0.0, 0.0), "voxel {corner:?} should be empty");
                empty += 1;
            } else if s <= -half_diag {
                assert_eq!((occ, sampled_fraction(&l, corner, 4)), (1.0, 1.0), "voxel {corner:?} should be full");
                full += 1;
            }
        }
    }
    assert!(empty > 1000 && full > 100, "{empty} empty, {full} full voxels: too few to be a test");
}

/// Occupancy of one voxel layer (z centre 20.5) of a straight tube of radius `r` along z,
/// averaged over `n²` midpoint offsets of its axis in the unit square.
fn layer_mass(r: f64, r_min: f64, n: usize) -> f64 {
    let mut mass = 0.0;
    for i in 0..n * n {
        let o = [(i % n) as f64 + 0.5, (i / n) as f64 + 0.5].map(|x| x / n as f64);
        let (a, b) = (V::new(10.0 + o[0], 10.0 + o[1], 0.0), V::new(10.0 + o[0], 10.0 + o[1], 40.0));
        let l = RoundCone { a, ra: r, b, rb: r };
        for j in 0..20 * 20 {
            let c = V::new((j % 20) as f64 + 0.5, (j / 20) as f64 + 0.5, 20.5);
            mass += occupancy(c, &l, None, None, r_min);
        }
    }
    mass / (n * n) as f64
}

/// One layer of a straight tube along z, averaged over the tube's position against the
/// lattice (128² midpoint offsets in the unit square), sums to `π r²(1 + 1/(12 r_c²))` with
/// PWAA (`r_c = max(r, r_min)`, module docs). Averaging error: the layer sum `F(o)` of the
/// offset `o` is Lipschitz with `|∇F| ≤ (r/r_c)²·π·4·r_c·(½ + √2/2)` (the voxel centres that
/// can be on the ramp's ring, grown by a voxel's half-diagonal), and the midpoint rule on
/// cells of side `h` errs by at most `|∇F|·0.383·h` (mean distance to the cell centre).
#[test]
fn layer_mass_matches_the_derived_ramp_integral() {
    let n = 128;
    for (r, r_min) in [(0.1, 1.0), (0.3, 1.0), (0.7, 1.0), (1.5, 1.0), (3.0, 1.0), (0.1, 2.0)] {
        let rc: f64 = f64::max(r, r_min);
        let mass = layer_mass(r, r_min, n);
        let pi = std::f64::consts::PI;
        let expected = pi * r * r * (1.0 + 1.0 / (12.0 * rc * rc));
        let bound = (r / rc).powi(2) * pi * 4.0 * rc * (0.5 + 2f64.sqrt() / 2.0) * 0.383 / n as f64;
        println!("r {r} r_min {r_min}: mass {mass:.6}, expected {expected:.6}, true area {:.6}", pi * r * r);
        assert!((mass - expected).abs() <= bound, "r {r}: mass {mass} vs {expected} ± {bound}");
    }
}

/// Without PWAA a sub-voxel tube's ramp covers a voxel-sized blob: `∫ clamp(r + ½ − ρ) dA =
/// π(r + ½)³/3` for `r < ½`, 7× the true area at `r = 0.1`; with it the estimate stays within
/// `1/(12 r_c²)` of the area (previous test).
#[test]
fn without_pwaa_thin_tubes_are_overestimated() {
    let r = 0.1;
    let mass = layer_mass(r, 0.0, 64);
    let pi = std::f64::consts::PI;
    let expected = pi * (r + 0.5f64).powi(3) / 3.0;
    assert!((mass - expected).abs() < 0.02 * expected, "{mass} vs {expected}");
    assert!(mass > 5.0 * pi * r * r);
}

/// Clipping planes from the central-difference tangent at a joint: the two clipped links
/// share no interior point, and the joint region's occupancy is no longer counted twice.
#[test]
fn clipped_links_do_not_overlap_at_a_joint() {
    let (v0, v1, v2) = (V::new(2.0, 2.0, 2.0), V::new(8.0, 5.0, 3.0), V::new(12.0, 11.0, 4.0));
    let n1 = (v2 - v0).normalize_or_zero();
    let la = RoundCone { a: v0, ra: 1.2, b: v1, rb: 1.2 };
    let lb = RoundCone { a: v1, ra: 1.2, b: v2, rb: 1.2 };
    let (mut clipped, mut unclipped, mut both) = (0.0, 0.0, 0);
    for i in 0..16 * 16 * 16 {
        let c = V::new((i % 16) as f64 + 0.5, ((i / 16) % 16) as f64 + 0.5, (i / 256) as f64 + 0.5);
        let (sa, sb) = (clipped_sdf(c, &la, None, Some(n1)), clipped_sdf(c, &lb, Some(n1), None));
        both += (sa < 0.0 && sb < 0.0) as usize;
        clipped += occupancy(c, &la, None, Some(n1), 1.0) + occupancy(c, &lb, Some(n1), None, 1.0);
        unclipped += occupancy(c, &la, None, None, 1.0) + occupancy(c, &lb, None, None, 1.0);
        // A point of either clipped piece is a point of its link.
        assert!(sa >= clipped_sdf(c, &la, None, None) && sb >= clipped_sdf(c, &lb, None, None));
    }
    assert_eq!(both, 0, "clipped links overlap");
    // The joint sphere (radius 1.2, ≈ 7.2 voxels of volume) is no longer counted twice.
    assert!(unclipped - clipped > 3.0, "clipping removed only {} of overlap", unclipped - clipped);
}
