//! Criterion bench of the three round-cone voxelizations (`tubecast::voxel`): conservative
//! Algorithm 1 (two radii), the AABB baseline and the DDA baseline (centre line only, not
//! conservative), against link length (1…64 voxels) and orientation (axis, face diagonal,
//! space diagonal), radius 0.5 voxel — the shape of Kraaijeveld et al.'s Fig. 6. Time is per
//! link; the voxels each method visits are printed once per case (`voxels …` lines).
//!
//!     cargo bench --bench voxel
use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use tubecast::voxel::{self, Dims};
use tubecast::{RoundCone, V3};

const DIMS: Dims = [256, 256, 256];

/// 64 links of length `len` along `dir` (normalised), spread over sub-voxel offsets.
fn links(dir: [f64; 3], len: f64) -> Vec<RoundCone<f64>> {
    let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
    let d = V3::new(dir[0] / n, dir[1] / n, dir[2] / n);
    (0..64)
        .map(|k| {
            let f = k as f64 / 64.0;
            let a = V3::new(100.0 + f, 100.0 + 0.37 * f, 100.0 + 0.71 * f);
            RoundCone { a, ra: 0.5, b: a + d * len, rb: 0.5 }
        })
        .collect()
}

type Method = fn(&RoundCone<f64>, Dims, &mut dyn FnMut([u32; 3]));

fn bench(c: &mut Criterion) {
    let methods: [(&str, Method); 3] = [
        ("round_cone", |l, d, f| voxel::voxelize_round_cone(l, d, f)),
        ("aabb", |l, d, f| voxel::voxelize_aabb(l, d, f)),
        ("dda", |l, d, f| voxel::voxelize_dda(l, d, f)),
    ];
    let dirs = [("axis", [1.0, 0.0, 0.0]), ("face", [1.0, 1.0, 0.0]), ("diagonal", [1.0, 1.0, 1.0])];
    for (dname, dir) in dirs {
        let mut g = c.benchmark_group(format!("voxelize/{dname}"));
        g.throughput(Throughput::Elements(64));
        for len in [1.0, 4.0, 16.0, 64.0] {
            let ls = links(dir, len);
            for (mname, m) in methods {
                let mut count = 0usize;
                for l in &ls {
                    m(l, DIMS, &mut |_| count += 1);
                }
                println!("voxels {dname} len {len} {mname}: {:.1} per link", count as f64 / 64.0);
                g.bench_with_input(BenchmarkId::new(mname, len), &ls, |b, ls| {
                    b.iter(|| {
                        let mut acc = 0u32;
                        for l in ls {
                            m(black_box(l), DIMS, &mut |c| acc = acc.wrapping_add(c[0] ^ c[1] ^ c[2]));
                        }
                        acc
                    })
                });
            }
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
