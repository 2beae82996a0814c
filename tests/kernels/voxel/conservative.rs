//! Conservative voxelization of round cones (`tubecast::voxel`), judged by an independent test:
//! a voxel's closed box `B` meets the link `⋃ B(p(u), r(u))` iff
//! `g = min_{u∈[0,1]} dist(B, p(u)) − r(u) ≤ 0`. `u ↦ dist(B, p(u))` is convex (the distance
//! to a convex set along an affine path) and `r` is linear, so `g` is a convex function of `u`
//! and the oracle's golden-section search finds its minimum value to rounding (its argmin only
//! to `√ε`, which does not matter for the value). Rounding of `g` is `≲ 4ε·M` (`M` the
//! coordinate size), below the kernel's own outward margin `32ε·M`, so "every voxel with
//! `g ≤ 0` is visited" is a claim the kernel can meet exactly and a missed voxel is a defect.
//!
//! Regions: random, axis-parallel on integer planes (faces touching voxel faces), diagonal
//! `(±1, ±1, ±1)`, long and thin, sub-voxel, strongly tapered, far from the origin (2²⁰ grid,
//! coordinates near 5·10⁵), each in `f64` and in `f32` (the `f32` link, exact in `f64`, is what
//! the oracle judges).

use std::collections::HashSet;
use tubecast::baseline;
use tubecast::voxel::{self, Dims};
use tubecast::{RoundCone, Scalar, V3};
use tubecast_oracle::golden_min;

/// Splitmix-style seeded stream (the test's own; uniform in `[0, 1)`).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn dir(&mut self) -> [f64; 3] {
        loop {
            let v = [self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0)];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Region {
    Random,
    AxisOnPlanes,
    Diagonal,
    LongThin,
    SubVoxel,
    Tapered,
    Far,
}
const REGIONS: [Region; 7] = [
    Region::Random,
    Region::AxisOnPlanes,
    Region::Diagonal,
    Region::LongThin,
    Region::SubVoxel,
    Region::Tapered,
    Region::Far,
];

/// A link `(a, ra, b, rb)` in grid coordinates and the grid it lives in.
fn case(rng: &mut Rng, region: Region) -> ([f64; 3], f64, [f64; 3], f64, Dims) {
    let small: Dims = [32, 32, 32];
    let centre = |rng: &mut Rng| [rng.range(6.0, 26.0), rng.range(6.0, 26.0), rng.range(6.0, 26.0)];
    let along = |a: [f64; 3], d: [f64; 3], l: f64| std::array::from_fn(|i| a[i] + d[i] * l);
    match region {
        Region::Random => {
            let a = centre(rng);
            let d = rng.dir();
            let (l, ra, rb) = (rng.range(0.1, 12.0), rng.range(0.0, 2.5), rng.range(0.0, 2.5));
            (a, ra, along(a, d, l), rb, small)
        }
        Region::AxisOnPlanes => {
            let a = centre(rng).map(|x| (2.0 * x).round() / 2.0);
            let mut b = a;
            let axis = (rng.next() * 3.0) as usize;
            b[axis] += (rng.range(-10.0, 10.0)).round();
            let r = (rng.range(0.0, 3.0) * 2.0).round() / 2.0; // 0, 0.5, 1, …: faces on planes
            let rb = if rng.next() < 0.5 { r } else { (rng.range(0.0, 3.0) * 2.0).round() / 2.0 };
            (a, r, b, rb, small)
        }
        Region::Diagonal => {
            let a = centre(rng);
            let s = [0, 1, 2].map(|_| if rng.next() < 0.5 { -1.0 } else { 1.0 });
            let l = rng.range(1.0, 8.0);
            let r = rng.range(0.05, 1.5);
            (a, r, along(a, s, l), r * rng.range(0.5, 1.0), small)
        }
        Region::LongThin => {
            let a = [rng.range(2.0, 6.0), rng.range(2.0, 6.0), rng.range(2.0, 6.0)];
            let d = rng.dir().map(f64::abs);
            (a, rng.range(0.0, 0.05), along(a, d, rng.range(18.0, 24.0)), rng.range(0.0, 0.05), small)
        }
        Region::SubVoxel => {
            let a = centre(rng);
            let d = rng.dir();
            (a, rng.range(0.0, 0.3), along(a, d, rng.range(0.0, 0.5)), rng.range(0.0, 0.3), small)
        }
        Region::Tapered => {
            let a = centre(rng);
            let d = rng.dir();
            let l = rng.range(2.0, 8.0);
            (a, rng.range(1.0, 0.9 * l + 1.0), along(a, d, l), rng.range(0.0, 0.2), small)
        }
        Region::Far => {
            let a = [5e5 + rng.range(0.0, 8.0), 5e5 + rng.range(0.0, 8.0), 5e5 + rng.range(0.0, 8.0)];
            let d = rng.dir();
            let far: Dims = [1 << 20, 1 << 20, 1 << 20];
            (a, rng.range(0.0, 1.5), along(a, d, rng.range(0.5, 8.0)), rng.range(0.0, 1.5), far)
        }
    }
}

/// `g = min_u dist(box(c), p(u)) − r(u)`: ≤ 0 iff the voxel `c` meets the link.
fn gap(l: &RoundCone<f64>, c: [u32; 3]) -> f64 {
    let (a, b) = (l.a.to_array(), l.b.to_array());
    let f = |u: f64| {
        let mut s = 0.0;
        for i in 0..3 {
            let x = a[i] + (b[i] - a[i]) * u;
            let lo = c[i] as f64;
            let e = (lo - x).max(x - (lo + 1.0)).max(0.0);
            s += e * e;
        }
        s.sqrt() - (l.ra + (l.rb - l.ra) * u)
    };
    golden_min(f, 0.0, 1.0).1
}

/// Tallies of one method against the oracle.
#[derive(Default, Debug)]
struct Tally {
    meeting: usize,
    visited: usize,
    missed: usize,
    duplicates: usize,
}

/// The voxels near the link (its box grown by two voxels), clamped to the grid.
fn nearby(l: &RoundCone<f64>, dims: Dims, mut f: impl FnMut([u32; 3])) {
    let r = l.ra.max(l.rb) + 2.0;
    let (a, b) = (l.a.to_array(), l.b.to_array());
    let lo: [u32; 3] = std::array::from_fn(|i| (a[i].min(b[i]) - r).floor().max(0.0) as u32);
    let hi: [u32; 3] = std::array::from_fn(|i| ((a[i].max(b[i]) + r).floor() as u32).min(dims[i] - 1));
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                f([x, y, z]);
            }
        }
    }
}

fn judge<T: Scalar>(l: &RoundCone<T>, dims: Dims, method: Method<T>, t: &mut Tally) {
    let mut seen = HashSet::new();
    method(l, dims, &mut |c| {
        assert!(c.iter().zip(dims).all(|(&x, n)| x < n), "voxel {c:?} outside the grid");
        if !seen.insert(c) {
            t.duplicates += 1;
        }
    });
    t.visited += seen.len();
    let l64 = RoundCone { a: l.a.cast::<f64>(), ra: l.ra.to_f64(), b: l.b.cast::<f64>(), rb: l.rb.to_f64() };
    nearby(&l64, dims, |c| {
        if gap(&l64, c) <= 0.0 {
            t.meeting += 1;
            if !seen.contains(&c) {
                t.missed += 1;
            }
        }
    });
}

type Method<T> = fn(&RoundCone<T>, Dims, &mut dyn FnMut([u32; 3]));

fn methods<T: Scalar>() -> [(&'static str, Method<T>); 4] {
    [
        ("round_cone", |l, d, f| voxel::voxelize_round_cone(l, d, f)),
        ("aabb", |l, d, f| baseline::voxel::voxelize_aabb(l, d, f)),
        ("dda", |l, d, f| baseline::voxel::voxelize_dda(l, d, f)),
        ("eq1", |l, d, f| baseline::voxel::voxelize_capsule_eq1(l, d, f)),
    ]
}

/// Per region and method, the tallies over `n` links in precision `T`.
fn sweep<T: Scalar>(n: usize, seed: u64) -> Vec<(Region, [Tally; 4])> {
    let mut out = Vec::new();
    for (k, region) in REGIONS.into_iter().enumerate() {
        let mut rng = Rng(seed + 1000 * k as u64);
        let mut tallies: [Tally; 4] = Default::default();
        for _ in 0..n {
            let (a, ra, b, rb, dims) = case(&mut rng, region);
            let f = |x: f64| T::from_f64(x);
            let l = RoundCone {
                a: V3::new(f(a[0]), f(a[1]), f(a[2])),
                ra: f(ra),
                b: V3::new(f(b[0]), f(b[1]), f(b[2])),
                rb: f(rb),
            };
            for (m, t) in methods::<T>().iter().zip(tallies.iter_mut()) {
                judge(&l, dims, m.1, t);
            }
        }
        out.push((region, tallies));
    }
    out
}

fn check<T: Scalar>(name: &str, seed: u64) {
    let (mut dda_missed, mut eq1_missed) = (0, 0);
    for (region, [ours, aabb, dda, eq1]) in sweep::<T>(30, seed) {
        println!("{name} {region:?}: ours {ours:?}\n  aabb {aabb:?}\n  dda {dda:?}\n  eq1 {eq1:?}");
        assert_eq!(ours.missed, 0, "{name} {region:?}: Algorithm 1 (two radii) missed voxels");
        assert_eq!(aabb.missed, 0, "{name} {region:?}: AABB voxelization missed voxels");
        assert_eq!((ours.duplicates, aabb.duplicates), (0, 0), "{name} {region:?}: a voxel visited twice");
        assert!(ours.meeting > 0 && ours.visited >= ours.meeting);
        assert!(aabb.visited >= ours.visited, "{name} {region:?}: AABB visits fewer ({aabb:?} vs {ours:?})");
        if matches!(region, Region::Diagonal | Region::LongThin) {
            assert!(aabb.visited > 2 * ours.visited, "{name} {region:?}: AABB should visit far more");
        }
        dda_missed += dda.missed;
        eq1_missed += eq1.missed;
        if !matches!(region, Region::SubVoxel) {
            assert!(dda.missed > 0, "{name} {region:?}: DDA is expected to miss voxels of thick links");
        }
    }
    println!("{name}: DDA missed {dda_missed} voxels, Eq. 1 missed {eq1_missed}");
    assert!(eq1_missed > 0, "{name}: Eq. 1's projected radii were expected to miss voxels");
}

#[test]
fn round_cone_voxelization_is_conservative_f64() {
    check::<f64>("f64", 11);
}

#[test]
fn round_cone_voxelization_is_conservative_f32() {
    check::<f32>("f32", 12);
}

/// Zero-radius, zero-length, NaN and off-grid links: no panic, nothing outside the grid.
#[test]
fn degenerate_links_stay_in_the_grid() {
    let dims = [4, 4, 4];
    let p = |x: f64, y: f64, z: f64| V3::new(x, y, z);
    let cases = [
        RoundCone { a: p(1.5, 1.5, 1.5), ra: 0.0, b: p(1.5, 1.5, 1.5), rb: 0.0 },
        RoundCone { a: p(-10.0, -10.0, -10.0), ra: 1.0, b: p(-9.0, -9.0, -9.0), rb: 1.0 },
        RoundCone { a: p(f64::NAN, 0.0, 0.0), ra: 1.0, b: p(1.0, 1.0, 1.0), rb: 1.0 },
        RoundCone { a: p(-100.0, 2.0, 2.0), ra: 0.5, b: p(100.0, 2.0, 2.0), rb: 0.5 },
    ];
    let mut counts = Vec::new();
    for l in &cases {
        let mut n = 0;
        for m in methods::<f64>() {
            (m.1)(l, dims, &mut |c| {
                assert!(c.iter().all(|&x| x < 4));
                n += 1;
            });
        }
        counts.push(n);
    }
    // The point link: the one voxel it sits in, by all four methods; the off-grid and the NaN
    // link: nothing; the long one through the grid: 4 voxels along x by DDA, a band by the rest.
    assert_eq!(&counts[..3], &[4, 0, 0]);
    assert!(counts[3] >= 4 + 3 * 4 * 4);
}
