//! Kanzler's quantized lines (`tubecast_render::quantized`): the measured Hausdorff distance of
//! every quantized segment to the exact piece it replaces stays within the derived bound
//! (module docs: `D + max(e_A, e_B)`), shrinks like `1/Q`, and an end takes `3 + 2·log₂ Q` bits.

use tubecast_render::io::Polyline;
use tubecast_render::quantized::QuantizedLines;
use tubecast_render::scene::generate;

/// A grid of side `h` over the lines' box.
fn grid(lines: &[Polyline], h: f64) -> ([f64; 3], [u32; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in lines.iter().flat_map(|l| &l.points) {
        lo = std::array::from_fn(|i| lo[i].min(p[i]));
        hi = std::array::from_fn(|i| hi[i].max(p[i]));
    }
    let lo = lo.map(|x| x - 0.5 * h);
    (lo, std::array::from_fn(|i| ((hi[i] + 0.5 * h - lo[i]) / h).ceil() as u32))
}

#[test]
fn hausdorff_distance_is_within_the_derived_bound_and_shrinks_with_q() {
    for (name, lines, h) in [
        ("bundle", generate::bundle(20, 84, 1), 1.0),
        ("furball", generate::furball(100, 78, 2), 0.5),
        ("helix", generate::helix(200), 0.7),
    ] {
        let (lo, dims) = grid(&lines, h);
        let mut prev = f64::INFINITY;
        for q in [8, 16, 32, 64] {
            let ql = QuantizedLines::new(&lines, lo, h, dims, q);
            let e = ql.hausdorff(&lines);
            let exact_bytes = 6 * 4; // two f32 points
            println!(
                "{name} Q={q}: {} segments, Hausdorff max {:.3e} (bound max {:.3e}, worst measured/bound {:.3}), \
                 {} bits per end vs {} bytes per exact segment",
                ql.segments.len(),
                e.max,
                e.max_bound,
                e.worst_ratio,
                ql.bits_per_end(),
                exact_bytes
            );
            assert!(e.worst_ratio <= 1.0, "{name} Q={q}: a segment exceeds its bound ({e:?})");
            assert!(e.worst_ratio > 0.3, "{name} Q={q}: the bound is far from tight ({e:?})");
            // Bundle fibres are nearly straight within a voxel (D ≪ h/Q): the error is the
            // quantization's and halves with Q. Furball hairs and the helix bend within a
            // voxel: D dominates, which no Q removes (it is in the bound, and measured).
            if name == "bundle" {
                assert!(e.max < 0.6 * prev, "{name} Q={q}: error did not shrink like 1/Q");
            }
            prev = e.max;
        }
    }
}

#[test]
fn ends_decode_onto_their_voxel_faces() {
    let lines = generate::furball(30, 40, 3);
    let (lo, dims) = grid(&lines, 0.4);
    let ql = QuantizedLines::new(&lines, lo, 0.4, dims, 16);
    assert_eq!((ql.bits_per_end(), QuantizedLines::new(&lines, lo, 0.4, dims, 64).bits_per_end()), (11, 15));
    let mut faces = 0;
    for s in &ql.segments {
        for &code in &s.ends {
            let p = ql.decode(code, s.voxel);
            let local: Vec<f64> = (0..3).map(|i| (p[i] - lo[i]) / 0.4 - s.voxel[i] as f64).collect();
            assert!(local.iter().all(|&x| (-1e-9..=1.0 + 1e-9).contains(&x)), "end outside its voxel: {local:?}");
            if code & 7 != 6 {
                let axis = (code & 7) as usize / 2;
                assert!((local[axis] - (code & 1) as f64).abs() < 1e-9, "face end off its face");
                faces += 1;
            }
        }
    }
    // Every piece but a polyline's first and last has both ends on faces.
    assert!(faces + 2 * lines.len() >= 2 * ql.segments.len());
}
