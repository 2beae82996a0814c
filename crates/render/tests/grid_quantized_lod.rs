//! Kanzler's LoD over quantized lines (`tubecast_render::quantized::Lod`): what each level must
//! conserve, checked against sums taken independently from the segments.

use tubecast_render::quantized::{Lod, QuantizedLines};
use tubecast_render::scene::generate;

#[test]
fn lod_levels_conserve_lines_length_and_mean_opacity() {
    // 16³ voxels (a power of two: every coarse voxel has all 8 children, so the mean opacity
    // is conserved exactly up to f32 rounding: ≤ 1e-5 relative over 4 levels of 8-term sums).
    let lines = generate::bundle(12, 84, 3);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in lines.iter().flat_map(|l| &l.points) {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    let h = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max) / 15.0;
    let lo = lo.map(|x| x - h / 2.0);
    let q = QuantizedLines::new(&lines, lo, h, [16; 3], 16);
    let r = 0.12;
    let lod = Lod::build(&q, r);
    assert_eq!(lod.levels.len(), 5, "16, 8, 4, 2, 1 voxels per side");
    // Independent sums from the segments.
    let seg_len: f64 = q
        .segments
        .iter()
        .map(|s| {
            let (a, b) = (q.decode(s.ends[0], s.voxel), q.decode(s.ends[1], s.voxel));
            (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt()
        })
        .sum();
    let mean0 = lod.levels[0].opacity.iter().map(|&o| o as f64).sum::<f64>() / 4096.0;
    assert!(mean0 > 0.0);
    for (k, level) in lod.levels.iter().enumerate() {
        let count: u32 = level.lines.iter().map(|l| l.count).sum();
        let length: f64 = level.lines.iter().map(|l| l.length).sum();
        assert_eq!(count as usize, q.segments.len(), "level {k}: every segment represented once");
        assert!((length - seg_len).abs() <= 1e-9 * seg_len, "level {k}: length {length} vs {seg_len}");
        let mean = level.opacity.iter().map(|&o| o as f64).sum::<f64>() / level.opacity.len() as f64;
        assert!((mean - mean0).abs() <= 1e-5 * mean0, "level {k}: mean opacity {mean} vs {mean0}");
        // Representative ends lie on a face of their voxel (snapped), and thick lines stay
        // within half a voxel.
        for l in &level.lines {
            for p in [l.a, l.b] {
                let u: Vec<f64> = (0..3).map(|i| (p[i] - lo[i]) / level.h - l.voxel[i] as f64).collect();
                assert!(u.iter().all(|&x| (-1e-9..=1.0 + 1e-9).contains(&x)), "level {k}: {u:?} outside");
                assert!(u.iter().any(|&x| x.abs() < 1e-9 || (x - 1.0).abs() < 1e-9), "level {k}: {u:?} not on a face");
            }
            assert!(l.radius >= r && l.radius <= (level.h / 2.0).max(r), "level {k}: radius {}", l.radius);
        }
    }
}
