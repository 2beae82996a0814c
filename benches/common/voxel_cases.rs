// The voxelization cases shared by `benches/voxel.rs` and the lab's `voxel-timing` report
// (`include!`d by both): 64 links of length `len` along `dir` (normalised), radius 0.5 voxel,
// spread over sub-voxel offsets.
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

/// Voxels `m` visits for all of `ls`.
fn visited(m: Method, ls: &[RoundCone<f64>]) -> usize {
    let mut count = 0usize;
    for l in ls {
        m(l, DIMS, &mut |_| count += 1);
    }
    count
}

/// One timed pass of `m` over `ls` (a checksum of the voxels, so none is optimised away).
fn sweep(m: Method, ls: &[RoundCone<f64>]) -> u32 {
    let mut acc = 0u32;
    for l in ls {
        m(std::hint::black_box(l), DIMS, &mut |c| acc = acc.wrapping_add(c[0] ^ c[1] ^ c[2]));
    }
    acc
}
