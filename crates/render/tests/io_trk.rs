//! TrackVis .trk reader: voxmm → RAS+ with the half-voxel shift, both byte orders, scalars
//! and properties, and malformed cases.

use tubecast_render::io::trk::{read, write, TrkHeader};
use tubecast_render::io::Polyline;

fn header() -> TrkHeader {
    TrkHeader {
        dim: [10, 20, 30],
        voxel_size: [2.0, 2.0, 2.5],
        // LAS: x flipped, translation (90, -126, -72).
        vox_to_ras: [[-2.0, 0.0, 0.0, 90.0], [0.0, 2.0, 0.0, -126.0], [0.0, 0.0, 2.5, -72.0], [0.0, 0.0, 0.0, 1.0]],
        n_scalars: 2,
        n_properties: 1,
        voxel_order: *b"LAS",
    }
}

#[test]
fn half_voxel_shift_and_affine() {
    // A point stored at voxmm (1, 1, 1.25) = ½·voxel size is the centre of voxel (0, 0, 0) (corner origin),
    // which the affine maps to its translation column: hand-computed expectation.
    let h = header();
    let mut d = write(&h, &[], false);
    d[988..992].copy_from_slice(&1i32.to_le_bytes());
    d.extend_from_slice(&1i32.to_le_bytes());
    for v in [1.0f32, 1.0, 1.25, 7.0, 8.0, 9.0] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    let (_, t) = read(&d, "t.trk").unwrap();
    assert_eq!(t[0].points, vec![[90.0, -126.0, -72.0]]);
    // voxmm (5, 1, 1.25) → voxel (2, 0, 0) → RAS (90 − 4, −126, −72).
    let off = 1004;
    d[off..off + 4].copy_from_slice(&5.0f32.to_le_bytes());
    assert_eq!(read(&d, "t.trk").unwrap().1[0].points, vec![[86.0, -126.0, -72.0]]);
}

#[test]
fn round_trip_both_endians_with_scalars_and_properties() {
    // RAS points chosen so every voxmm value is exact in f32 (multiples of 1/4 here).
    let lines = vec![
        Polyline { points: vec![[90.0, -126.0, -72.0], [80.0, -100.0, -47.0]], radii: vec![] },
        Polyline { points: vec![[0.0, 0.0, 0.0]], radii: vec![] },
        Polyline { points: vec![], radii: vec![] },
    ];
    for big in [false, true] {
        let d = write(&header(), &lines, big);
        let (h, t) = read(&d, "t.trk").unwrap();
        assert_eq!(h, header());
        assert_eq!(t, lines);
    }
}

#[test]
fn unset_matrix_reads_as_identity() {
    let mut h = header();
    h.vox_to_ras = [[0.0; 4]; 4];
    let mut d = write(&TrkHeader { vox_to_ras: TrkHeader::default().vox_to_ras, ..h }, &[], false);
    d[440..504].fill(0);
    d[988..992].copy_from_slice(&1i32.to_le_bytes());
    d.extend_from_slice(&1i32.to_le_bytes());
    for v in [3.0f32, 3.0, 3.75, 0.0, 0.0, 0.0] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    // voxmm / voxel size − ½ = (1, 1, 1).
    assert_eq!(read(&d, "t.trk").unwrap().1[0].points, vec![[1.0, 1.0, 1.0]]);
}

#[test]
fn malformed_files_are_errors() {
    let good = write(&header(), &[Polyline { points: vec![[0.0; 3]; 2], radii: vec![] }], false);
    let patch = |at: usize, bytes: &[u8]| {
        let mut d = good.clone();
        d[at..at + bytes.len()].copy_from_slice(bytes);
        d
    };
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (vec![], "empty file"),
        (good[..500].to_vec(), "truncated header"),
        (patch(0, b"TRICK"), "magic"),
        (patch(996, &7i32.to_le_bytes()), "hdr_size"),
        (patch(12, &0f32.to_le_bytes()), "voxel size 0"),
        (patch(16, &f32::NAN.to_le_bytes()), "voxel size NaN"),
        (patch(36, &11i16.to_le_bytes()), "n_scalars 11"),
        (patch(238, &(-1i16).to_le_bytes()), "n_properties -1"),
        (patch(440, &0f32.to_le_bytes()), "singular"),
        (patch(444, &f32::INFINITY.to_le_bytes()), "NaN or infinite"),
        (patch(948, b"RAS"), "disagrees"),
        (patch(988, &(-2i32).to_le_bytes()), "n_count -2"),
        (patch(988, &2i32.to_le_bytes()), "header says 2"),
        (patch(1000, &(-1i32).to_le_bytes()), "point count -1"),
        (patch(1000, &1000i32.to_le_bytes()), "truncated streamline"),
        (patch(1004, &f32::NAN.to_le_bytes()), "NaN or infinite coordinates"),
        ([&good[..], &[0u8; 3]].concat(), "3 bytes after"),
        (good[..good.len() - 2].to_vec(), "truncated"),
    ];
    for (d, what) in cases {
        let e = read(&d, "bad.trk").expect_err(what);
        assert!(e.to_string().starts_with("bad.trk: "), "{e}");
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
}
