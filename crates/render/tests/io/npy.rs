//! .npy reader/writer: round trip, byte order, Fortran order, header versions, malformed.

use tubecast_render::io::npy::{read, write, Array2};

fn arr() -> Array2 {
    Array2 { rows: 2, cols: 3, data: vec![1.0, -2.5, f64::INFINITY, 1e-300, 0.0, 7.0] }
}

/// A hand-built .npy (version `ver`) with the given header dict and body.
fn build(ver: u8, dict: &str, body: &[u8]) -> Vec<u8> {
    let mut d = b"\x93NUMPY".to_vec();
    d.push(ver);
    d.push(0);
    let h = format!("{dict}\n");
    if ver == 1 {
        d.extend_from_slice(&(h.len() as u16).to_le_bytes());
    } else {
        d.extend_from_slice(&(h.len() as u32).to_le_bytes());
    }
    d.extend_from_slice(h.as_bytes());
    d.extend_from_slice(body);
    d
}

#[test]
fn round_trip_and_alignment() {
    let d = write(&arr());
    assert_eq!((d.len() - 6 * 8) % 64, 0, "data starts 64-byte aligned");
    assert_eq!(read(&d, "a.npy", Some(3)).unwrap(), arr());
}

#[test]
fn big_endian_fortran_and_version_2() {
    // Fortran order stores columns: (1, 1e-300), (-2.5, 0), (inf, 7).
    let vals = [1.0, 1e-300, -2.5, 0.0, f64::INFINITY, 7.0];
    let body: Vec<u8> = vals.iter().flat_map(|v: &f64| v.to_be_bytes()).collect();
    let d = build(2, "{'descr': '>f8', 'fortran_order': True, 'shape': (2, 3), }", &body);
    assert_eq!(read(&d, "f.npy", None).unwrap(), arr());
}

#[test]
fn malformed_files_are_errors() {
    let body = vec![0u8; 48];
    let ok = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (vec![], "empty file"),
        (b"PK\x03\x04 not npy".to_vec(), "magic"),
        (build(9, ok, &body), "version 9"),
        // float32 is read (float32_in_both_orders); an integer dtype is not.
        (build(1, &ok.replace("<f8", "<i8"), &body), "not float32 or float64"),
        (build(1, &ok.replace("False", "Maybe"), &body), "fortran_order"),
        (build(1, &ok.replace("(2, 3)", "(6,)"), &body), "1-D"),
        (build(1, &ok.replace("(2, 3)", "(2, x)"), &body), "unparsable (could not parse Python expression"),
        (build(1, "{'descr': '<f8'}", &body), "missing key 'fortran_order'"),
        (build(1, ok, &body[..40]), "data is 40 bytes"),
        (build(1, ok, &[body.clone(), vec![0; 8]].concat()), "data is 56 bytes"),
        (build(1, &ok.replace("(2, 3)", "(99999999999, 99999999999)"), &body), "overflows"),
    ];
    for (d, what) in cases {
        let e = read(&d, "bad.npy", None).expect_err(what);
        assert!(e.to_string().starts_with("bad.npy: "), "{e}");
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
    let mut short = build(1, ok, &body);
    short.truncate(20);
    assert!(read(&short, "bad.npy", None).unwrap_err().to_string().contains("truncated header"));
    let e = read(&build(1, ok, &body), "bad.npy", Some(6)).unwrap_err();
    assert!(e.to_string().contains("3 columns, expected 6"), "{e}");
}

#[test]
fn rays_from_rows() {
    // Rows are origin, direction; each ray is validated.
    let a = Array2::from_rows(&[[1.0, 2.0, 3.0, 0.0, 0.0, -2.0], [0.0; 6]]);
    assert_eq!((a.rows, a.cols, a.row(0)), (2, 6, &[1.0, 2.0, 3.0, 0.0, 0.0, -2.0][..]));
    let e = a.rays("r.npy").unwrap_err().to_string();
    assert!(e.starts_with("r.npy: row 1: ") && e.contains("zero"), "{e}");
    let one = Array2::from_rows(&[[1.0, 2.0, 3.0, 0.0, 0.0, -2.0]]).rays("r.npy").unwrap();
    assert_eq!((one[0].o.to_array(), one[0].d.to_array()), ([1.0, 2.0, 3.0], [0.0, 0.0, -2.0]));
    let e = arr().rays("r.npy").unwrap_err().to_string();
    assert!(e.contains("3 columns, expected 6"), "{e}");
}

#[test]
fn float32_in_both_orders() {
    // The 2×3 array [[1, 2, 3], [4, 5, 6]] as float32, C order and Fortran order (columns
    // first), little and big endian: the same f64 values (float32 → f64 is exact).
    let want = Array2 { rows: 2, cols: 3, data: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0] };
    for (order, vals) in [("False", [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0]), ("True", [1.0, 4.0, 2.0, 5.0, 3.0, 6.0])] {
        for big in [false, true] {
            let descr = if big { ">f4" } else { "<f4" };
            let body: Vec<u8> = vals.iter().flat_map(|v| if big { v.to_be_bytes() } else { v.to_le_bytes() }).collect();
            let d = build(1, &format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': (2, 3), }}"), &body);
            assert_eq!(read(&d, "f4.npy", None).unwrap(), want, "{descr} fortran={order}");
        }
    }
    // A non-representable float32 value keeps its float32 value exactly.
    let d = build(1, "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1), }", &0.1f32.to_le_bytes());
    assert_eq!(read(&d, "x.npy", None).unwrap().data, vec![0.1f32 as f64]);
}

/// The npy campaigns' slow inputs (kept as fuzz/corpus/npy/regression-*): seed 2001's 118-byte
/// header with 40 unbalanced `[`, and seed 2003's 392- and 278-byte headers of unterminated
/// quotes and braces two deep, on which npyz's PEG header parser backtracked for minutes. A plain
/// float32/float64 header is a flat dict of strings, `True`/`False` and one integer tuple, so
/// anything else is refused before npyz parses it, in one linear pass: the slow inputs, and a
/// structured dtype (a list of tuples); plain headers keep parsing (numpy's own in the
/// io_reference_readers fixtures, and the ones here in either quote style).
#[test]
fn headers_other_than_a_plain_dict_are_refused_before_parsing() {
    let slow: [&[u8]; 3] = [
        include_bytes!("../../../../fuzz/corpus/npy/regression-nested-brackets"),
        include_bytes!("../../../../fuzz/corpus/npy/regression-quote-maze"),
        include_bytes!("../../../../fuzz/corpus/npy/regression-quote-maze-slow"),
    ];
    for d in slow {
        let e = read(d, "slow.npy", None).unwrap_err().to_string();
        assert!(e.contains("not a plain dict"), "{e}");
    }
    let structured =
        build(1, "{'descr': [('x', '<f8'), ('y', '<f8')], 'fortran_order': False, 'shape': (1, 2), }", &[0; 32]);
    let e = read(&structured, "s.npy", None).unwrap_err().to_string();
    assert!(e.contains("not a plain dict") && e.contains("structured"), "{e}");
    let body: Vec<u8> = [1.0f64, 2.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    for dict in [
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), }",
        "{\"descr\":\"<f8\",\"shape\":(1,2),\"fortran_order\":False}",
    ] {
        let plain = build(1, dict, &body);
        assert_eq!(read(&plain, "p.npy", Some(2)).unwrap().data, vec![1.0, 2.0], "{dict}");
    }
}
