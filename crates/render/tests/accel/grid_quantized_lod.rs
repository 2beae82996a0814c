//! Kanzler's LoD over quantized lines (`tubecast_render::quantized::Lod`): what each level must
//! conserve, checked against sums taken independently from the segments; and the joining of
//! representative lines across shared faces (`quantized::lod` module docs): where two non-empty
//! voxels share a face and each one's representative line has exactly one end on it, both ends
//! sit at the centre of the face bin of their average, so the lines meet. Checked against the
//! unjoined LoD (`Lod::build_with(.., false)`), with faces and bins recomputed from coordinates.

use std::collections::HashMap;
use tubecast_render::quantized::{Lod, LodLevel, QuantizedLines, RepLine};
use tubecast_render::scene::generate;

const Q: u32 = 16;

/// A bundle of 12 lines quantized with `Q` bins on 16³ voxels around it (a power of two: every
/// coarse voxel has all 8 children, so the mean opacity is conserved exactly up to f32
/// rounding: ≤ 1e-5 relative over 4 levels of 8-term sums), and the grid corner.
fn bundle_quantized() -> (QuantizedLines, [f64; 3]) {
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
    (QuantizedLines::new(&lines, lo, h, [16; 3], Q), lo)
}

#[test]
fn lod_levels_conserve_lines_length_and_mean_opacity() {
    let (q, lo) = bundle_quantized();
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

/// Local coordinates of `p` in voxel `c` of `level`.
fn local(p: [f64; 3], lo: [f64; 3], level: &LodLevel, c: [u32; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (p[i] - lo[i]) / level.h - c[i] as f64)
}

/// The one end of `l` on its voxel's face `axis`/`side` (and on no other face), if exactly one.
fn end_on(l: &RepLine, lo: [f64; 3], level: &LodLevel, axis: usize, side: f64) -> Option<[f64; 3]> {
    let on = |p: [f64; 3]| {
        let u = local(p, lo, level, l.voxel);
        let faces = (0..3).flat_map(|i| [u[i].abs(), (u[i] - 1.0).abs()]).filter(|d| *d <= 1e-9).count();
        (u[axis] - side).abs() <= 1e-9 && faces == 1
    };
    match (on(l.a), on(l.b)) {
        (true, false) => Some(l.a),
        (false, true) => Some(l.b),
        _ => None,
    }
}

/// Pairs of face-neighbour voxels `(c, c + e_axis, axis)` that both hold a line.
fn neighbours(level: &LodLevel) -> Vec<(usize, usize, usize)> {
    let at: HashMap<[u32; 3], usize> = level.lines.iter().enumerate().map(|(k, l)| (l.voxel, k)).collect();
    let mut out = Vec::new();
    for (k, l) in level.lines.iter().enumerate() {
        for axis in 0..3 {
            let mut c = l.voxel;
            c[axis] += 1;
            if let Some(&j) = at.get(&c) {
                out.push((k, j, axis));
            }
        }
    }
    out
}

#[test]
fn joined_representative_lines_meet_on_shared_faces_and_conserve_the_lod() {
    let (q, lo) = bundle_quantized();
    let (apart, joined) = (Lod::build_with(&q, 0.12, false), Lod::build(&q, 0.12));
    let (mut joins, mut moved) = (0, 0);
    for (k, level) in joined.levels.iter().enumerate() {
        for (a, b, axis) in neighbours(level) {
            let (la, lb) = (&level.lines[a], &level.lines[b]);
            let (Some(pa), Some(pb)) = (end_on(la, lo, level, axis, 1.0), end_on(lb, lo, level, axis, 0.0)) else {
                continue;
            };
            joins += 1;
            assert_eq!(pa, pb, "level {k}: voxels {:?} and {:?} do not meet on their face", la.voxel, lb.voxel);
            if k > 0 {
                continue;
            }
            // Level 0: the centre of the bin of the mean of the unjoined ends (same voxels,
            // same order: both levels list the non-empty voxels by index).
            let ua = end_on(&apart.levels[0].lines[a], lo, level, axis, 1.0).expect("unjoined end on the face");
            let ub = end_on(&apart.levels[0].lines[b], lo, level, axis, 0.0).expect("unjoined end on the face");
            moved += (ua != ub) as usize;
            let mean: [f64; 3] = std::array::from_fn(|i| 0.5 * (ua[i] + ub[i]));
            let u = local(mean, lo, level, la.voxel);
            let want: [f64; 3] = std::array::from_fn(|i| {
                let v = if i == axis { 1.0 } else { ((u[i] * Q as f64).floor().min(Q as f64 - 1.0) + 0.5) / Q as f64 };
                lo[i] + (la.voxel[i] as f64 + v) * level.h
            });
            for i in 0..3 {
                assert!((pa[i] - want[i]).abs() <= 1e-9 * level.h, "level 0: joined at {pa:?}, bin centre {want:?}");
            }
        }
        // Joining moves ends only: the represented count and length and the opacities are
        // those of the unjoined LoD, voxel by voxel, and radii keep their bounds.
        let ap = &apart.levels[k];
        assert_eq!(level.opacity, ap.opacity, "level {k}: opacities changed");
        assert_eq!(level.lines.len(), ap.lines.len());
        for (l, m) in level.lines.iter().zip(&ap.lines) {
            assert_eq!((l.voxel, l.count), (m.voxel, m.count), "level {k}");
            assert!((l.length - m.length).abs() <= 1e-9 * m.length, "level {k}: length {} vs {}", l.length, m.length);
            assert!(l.radius >= 0.12 && l.radius <= (level.h / 2.0).max(0.12), "level {k}: radius {}", l.radius);
        }
    }
    // Not vacuous: many faces are joined, and at level 0 some ends had to move to meet.
    assert!(joins > 50 && moved > 0, "{joins} joins, {moved} moved");
    println!("{joins} joined faces over all levels; {moved} at level 0 had to move");
}
