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
    // voxel_order RAS, the orientation of the identity: no reorientation (the LAS case is
    // `voxel_order_differing_from_the_affine_reorients`).
    let mut h = TrkHeader { voxel_order: *b"RAS", ..header() };
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
        // More than 10 scalars is accepted as nibabel accepts it (unnamed columns: "scalars").
        (patch(36, &(-3i16).to_le_bytes()), "n_scalars -3"),
        (patch(238, &(-1i16).to_le_bytes()), "n_properties -1"),
        (patch(440, &0f32.to_le_bytes()), "singular"),
        (patch(444, &f32::INFINITY.to_le_bytes()), "NaN or infinite"),
        // A voxel_order differing from the affine's is reoriented as nibabel does (below); one
        // that names an axis twice is refused, as nibabel refuses it.
        (patch(948, b"RRS"), "voxel_order \"RRS\""),
        (patch(992, &7i32.to_le_bytes()), "version 7"),
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

#[test]
fn voxel_order_differing_from_the_affine_reorients() {
    // Identity vox_to_ras (RAS) but voxel_order LPS, dims (10, 20, 30), voxel size 1: nibabel
    // flips x and y as voxel indices, x ↦ dim − 1 − x (hand-computed, not from the reader):
    // voxmm (3.5, 2.5, 1.5) → voxel (3, 2, 1) → (10 − 1 − 3, 20 − 1 − 2, 1) = (6, 17, 1).
    let h = TrkHeader { dim: [10, 20, 30], voxel_order: *b"LPS", ..TrkHeader::default() };
    let mut d = write(&TrkHeader { voxel_order: *b"RAS", ..h }, &[], false);
    d[948..951].copy_from_slice(b"LPS");
    d[988..992].copy_from_slice(&1i32.to_le_bytes());
    d.extend_from_slice(&1i32.to_le_bytes());
    for v in [3.5f32, 2.5, 1.5] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    assert_eq!(read(&d, "lps.trk").unwrap().1[0].points, vec![[6.0, 17.0, 1.0]]);
    // Unset voxel_order means LPS (TrackVis's default): the same answer.
    d[948..952].fill(0);
    assert_eq!(read(&d, "unset.trk").unwrap().1[0].points, vec![[6.0, 17.0, 1.0]]);
    // Lower case is the same order.
    d[948..951].copy_from_slice(b"lps");
    assert_eq!(read(&d, "lower.trk").unwrap().1[0].points, vec![[6.0, 17.0, 1.0]]);
    // A permutation, voxel_order "ASR": nibabel's `inv_ornt_aff(ornt_transform(ASR, RAS))`
    // sets output axis i to input axis j where RAS axis j is the world axis of header axis i
    // (A → 1, S → 2, R → 0), no flips: (x₁, x₂, x₀) = (2, 1, 3). nibabel 5.4.2's
    // get_affine_trackvis_to_rasmm gives the same (2, 1, 3) for this header.
    d[948..951].copy_from_slice(b"ASR");
    assert_eq!(read(&d, "asr.trk").unwrap().1[0].points, vec![[2.0, 1.0, 3.0]]);
}

#[test]
fn scalars_and_properties_are_kept_with_their_names() {
    // Two named scalar groups, "fa" (1 column) and "t\02" (2 columns), and one property.
    let mut h = header();
    h.voxel_order = *b"LAS";
    let lines = vec![Polyline { points: vec![[90.0, -126.0, -72.0], [88.0, -126.0, -72.0]], radii: vec![] }];
    let mut h2 = h;
    h2.n_scalars = 3;
    let mut d = write(&h2, &lines, false);
    d[38..40].copy_from_slice(b"fa");
    d[58..62].copy_from_slice(b"t\x002\x00");
    d[240..244].copy_from_slice(b"len\x00");
    // Point values: x y z fa t0 t1 ; write() wrote zeros for the scalars: set them.
    let vals = [[0.25f32, 1.0, 2.0], [0.5, 3.0, 4.0]];
    for (p, v) in vals.iter().enumerate() {
        for (k, x) in v.iter().enumerate() {
            let at = 1004 + p * 24 + 12 + 4 * k;
            d[at..at + 4].copy_from_slice(&x.to_le_bytes());
        }
    }
    let at = 1004 + 2 * 24;
    d[at..at + 4].copy_from_slice(&7.5f32.to_le_bytes());
    let (_, t) = tubecast_render::io::trk::read_data(&d, "s.trk").unwrap();
    let fa = t.point_field("fa").unwrap();
    assert_eq!((fa.width, fa.values.clone()), (1, vec![0.25, 0.5]));
    let tt = t.point_field("t").unwrap();
    assert_eq!((tt.width, tt.values.clone()), (2, vec![1.0, 2.0, 3.0, 4.0]));
    let len = t.line_field("len").unwrap();
    assert_eq!((len.width, len.values.clone()), (1, vec![7.5]));
}
