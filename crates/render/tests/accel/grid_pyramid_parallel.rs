//! The occupancy pyramid is built in parallel (rayon): its values must be the same bits on one
//! thread and on several, since contributions are added in link order whatever the schedule.

use tubecast_render::accel::grid::Pyramid;
use tubecast_render::scene::{generate, Scene};

fn build_on(threads: usize, scene: &Scene, lo: [f64; 3], h: f64, dims: [u32; 3]) -> Pyramid {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| Pyramid::build(scene, lo, h, dims, 0.5 * h))
}

#[test]
fn parallel_pyramid_equals_single_thread_bit_for_bit() {
    // 4,200 links: more than one 4,096-link chunk, so the chunked accumulation is exercised.
    let scene = Scene::from_polylines(&generate::bundle(50, 84, 7), 0.12, "bundle").unwrap();
    let (lo, hi) = scene.stats().bounds;
    let h = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max) / 24.0;
    let lo = lo.map(|x| x - h);
    let dims = [0, 1, 2].map(|i| ((hi[i] - lo[i]) / h).ceil() as u32 + 2);
    let one = build_on(1, &scene, lo, h, dims);
    let total: f64 = one.levels[0].values.iter().map(|&v| v as f64).sum();
    assert!(total > 0.0, "the bundle occupies some voxels");
    for threads in [2, 3] {
        let many = build_on(threads, &scene, lo, h, dims);
        assert_eq!(many.levels.len(), one.levels.len());
        for (a, b) in many.levels.iter().zip(&one.levels) {
            assert_eq!(a.dims, b.dims);
            let same = a.values.iter().zip(&b.values).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same, "level {:?} differs on {threads} threads", a.dims);
        }
    }
}
