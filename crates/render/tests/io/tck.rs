//! MRtrix .tck reader: round trip in both byte orders, padded/wrong counts, malformed cases.

use tubecast_render::io::tck::{read, write};
use tubecast_render::io::{Location, Polyline};

fn lines() -> Vec<Polyline> {
    // Values exactly representable in f32, so the f64 → f32 → f64 round trip is exact.
    vec![
        Polyline { points: vec![[0.5, 1.0, -2.0], [1.5, 1.25, -2.0], [2.5, 1.5, 3.0]], radii: vec![] },
        Polyline { points: vec![[-100.0, 0.0, 0.125]], radii: vec![] },
    ]
}

#[test]
fn round_trip_both_endians() {
    for big in [false, true] {
        let data = write(&lines(), big);
        assert_eq!(read(&data, "t.tck").unwrap(), lines());
    }
}

fn raw(header: &str, body: &[f32], big: bool) -> Vec<u8> {
    // "OFF" is replaced by a 3-digit offset, so the header keeps its length.
    let off = header.len();
    let mut d = header.replace("OFF", &format!("{off:03}")).into_bytes();
    assert_eq!(d.len(), off);
    for v in body {
        d.extend_from_slice(&if big { v.to_be_bytes() } else { v.to_le_bytes() });
    }
    d
}

#[test]
fn wrong_or_padded_count_is_ignored() {
    let (n, i) = (f32::NAN, f32::INFINITY);
    let body = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, n, n, n, 7.0, 8.0, 9.0, n, n, n, i, i, i];
    for count in ["count: 0000000002", "count: 17", "count: 0"] {
        let h = format!("mrtrix tracks\ndatatype: Float32LE\n{count}\nfile: . OFF\nEND\n");
        let d = raw(&h, &body, false);
        let t = read(&d, "t.tck").unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t[0].points, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        assert_eq!(t[1].points, vec![[7.0, 8.0, 9.0]]);
    }
}

#[test]
fn data_offset_after_padding_is_honoured() {
    let i = f32::INFINITY;
    let h = "mrtrix tracks\ndatatype: Float32BE\nfile: . 064\nEND\n";
    let mut d = h.as_bytes().to_vec();
    d.resize(64, b' ');
    let n = f32::NAN;
    for v in [1.0f32, 2.0, 3.0, n, n, n, i, i, i] {
        d.extend_from_slice(&v.to_be_bytes());
    }
    assert_eq!(read(&d, "p.tck").unwrap()[0].points, vec![[1.0, 2.0, 3.0]]);
}

#[test]
fn malformed_files_are_errors() {
    let ok_head = "mrtrix tracks\ndatatype: Float32LE\nfile: . OFF\nEND\n";
    let n = f32::NAN;
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (vec![], "empty file"),
        (b"not tracks\n".to_vec(), "mrtrix tracks"),
        (b"mrtrix tracks\ndatatype: Float32LE\n".to_vec(), "without an END"),
        // (A missing datatype or file entry is accepted as nibabel accepts it: see
        // nibabel_header_defaults below and reference/readers/variants/no_{datatype,file}.tck.)
        (b"mrtrix tracks\ndatatype: Float32LE\nfile: .\nEND\n".to_vec(), "is not \". OFFSET\""),
        (raw(ok_head, &[1.0, 2.0, 3.0, f32::INFINITY, f32::INFINITY, f32::INFINITY], false), "no NaN triplet"),
        (raw(ok_head, &[n, n, n, f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0], false), "after the Inf end marker"),
        (b"mrtrix tracks\ndatatype: Float64LE\nfile: . 50\nEND\n".to_vec(), "unsupported"),
        (b"mrtrix tracks\ndatatype: Float32LE\nfile: other.dat 0\nEND\n".to_vec(), "separate data files"),
        (b"mrtrix tracks\ndatatype: Float32LE\nfile: . xx\nEND\n".to_vec(), "not a byte count"),
        (b"mrtrix tracks\ndatatype: Float32LE\nfile: . 5\nEND\n".to_vec(), "inside the header"),
        (b"mrtrix tracks\ndatatype: Float32LE\nfile: . 5000\nEND\n".to_vec(), "beyond the end"),
        (b"mrtrix tracks\nno colon here\nEND\n".to_vec(), "key: value"),
        (raw(ok_head, &[1.0, 2.0, 3.0], false), "without the Inf end marker"),
        (raw(ok_head, &[1.0, 2.0], false), "truncated"),
        (raw(ok_head, &[1.0, n, 3.0], false), "mixes finite"),
    ];
    for (d, what) in cases {
        let e = read(&d, "bad.tck").expect_err(what);
        assert!(e.to_string().starts_with("bad.tck: "), "{e}");
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
    let e = read(&raw(ok_head, &[1.0, 2.0, 3.0, 4.0], false), "bad.tck").unwrap_err();
    assert!(matches!(e.at, Location::Offset(o) if o > 40), "{e:?}");
}

#[test]
fn nibabel_header_defaults() {
    // nibabel reads a header without `datatype` as Float32LE and, without `file`, takes the data
    // to start right after END; a line without a colon continues the previous key's value.
    let (n, i) = (f32::NAN, f32::INFINITY);
    let body = [1.0, 2.0, 3.0, n, n, n, i, i, i];
    let no_dt = raw("mrtrix tracks\nfile: . OFF\nEND\n", &body, false);
    assert_eq!(read(&no_dt, "a.tck").unwrap()[0].points, vec![[1.0, 2.0, 3.0]]);
    let no_file = raw("mrtrix tracks\ndatatype: Float32BE\nEND\n", &body, true);
    assert_eq!(read(&no_file, "b.tck").unwrap()[0].points, vec![[1.0, 2.0, 3.0]]);
    let multi = raw("mrtrix tracks\ncommand: tckgen\n  -seed x\ndatatype: Float32LE\nfile: . OFF\nEND\n", &body, false);
    assert_eq!(read(&multi, "c.tck").unwrap()[0].points, vec![[1.0, 2.0, 3.0]]);
}
