//! Criterion bench of the three round-cone voxelizations: conservative Algorithm 1 (two radii,
//! `tubecast::voxel`), the AABB baseline and the DDA baseline (centre line only, not
//! conservative; both `tubecast::baseline::voxel`), against link length (1…64 voxels) and
//! orientation (axis, face diagonal, space diagonal), radius 0.5 voxel — the shape of
//! Kraaijeveld et al.'s Fig. 6. Time is per link; the voxels each method visits are printed
//! once per case (`voxels …` lines).
//!
//!     cargo bench --bench voxel
use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use tubecast::baseline;
use tubecast::voxel::{self, Dims};
use tubecast::{RoundCone, V3};

const DIMS: Dims = [256, 256, 256];

include!("common/voxel_cases.rs");

fn bench(c: &mut Criterion) {
    let methods: [(&str, Method); 3] = [
        ("round_cone", |l, d, f| voxel::voxelize_round_cone(l, d, f)),
        ("aabb", |l, d, f| baseline::voxel::voxelize_aabb(l, d, f)),
        ("dda", |l, d, f| baseline::voxel::voxelize_dda(l, d, f)),
    ];
    let dirs = [("axis", [1.0, 0.0, 0.0]), ("face", [1.0, 1.0, 0.0]), ("diagonal", [1.0, 1.0, 1.0])];
    for (dname, dir) in dirs {
        let mut g = c.benchmark_group(format!("voxelize/{dname}"));
        g.throughput(Throughput::Elements(64));
        for len in [1.0, 4.0, 16.0, 64.0] {
            let ls = links(dir, len);
            for (mname, m) in methods {
                let count = visited(m, &ls);
                println!("voxels {dname} len {len} {mname}: {:.1} per link", count as f64 / 64.0);
                g.bench_with_input(BenchmarkId::new(mname, len), &ls, |b, ls| b.iter(|| sweep(m, black_box(ls))));
            }
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
