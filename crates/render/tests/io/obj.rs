//! OBJ polyline reader: round trip with and without radii, relative indices, malformed cases.

use tubecast_render::io::obj::{read, write};
use tubecast_render::io::{Location, Polyline};

#[test]
fn round_trip_with_and_without_radii() {
    let lines = vec![
        Polyline { points: vec![[0.1, 0.2, 0.3], [1.0, -2.0, 1e-9]], radii: vec![0.5, 0.25] },
        Polyline { points: vec![[3.0, 3.0, 3.0], [4.0, 4.0, 4.0], [5.0, 5.0, 6.0]], radii: vec![] },
    ];
    assert_eq!(read(write(&lines).as_bytes(), "t.obj").unwrap(), lines);
}

#[test]
fn relative_indices_slashes_and_ignored_statements() {
    let text = "o thing\nv 0 0 0\nv 1 0 0\nvn 0 0 1\nv 2 0 0 0.5\nf 1 2 3\nl -3/1 2/2\nl 2 3 # tail\n";
    let t = read(text.as_bytes(), "t.obj").unwrap();
    assert_eq!(t[0].points, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    assert!(t[0].radii.is_empty());
    assert_eq!(t[1].points, vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]);
    // Vertex 2 has no radius, so the polyline has none.
    assert!(t[1].radii.is_empty());
}

#[test]
fn malformed_files_are_errors() {
    let cases: &[(&str, Location, &str)] = &[
        ("", Location::File, "no line elements"),
        ("v 0 0 0\nv 1 1 1\n", Location::File, "no line elements"),
        ("v 0 0\n", Location::Line(1), "found 2 values"),
        ("v 0 0 0 1 2\n", Location::Line(1), "found 5 values"),
        ("v 0 nan 0\n", Location::Line(1), "not a finite number"),
        ("v 0 0 0 -1\n", Location::Line(1), "radius -1 is negative"),
        ("v 0 0 0\nv 1 1 1\nl 1\n", Location::Line(3), "at least 2"),
        ("v 0 0 0\nv 1 1 1\nl 1 3\n", Location::Line(3), "index 3 is out of range"),
        ("v 0 0 0\nv 1 1 1\nl 0 1\n", Location::Line(3), "index 0"),
        ("v 0 0 0\nv 1 1 1\nl -3 1\n", Location::Line(3), "index -3"),
        ("v 0 0 0\nv 1 1 1\nl 1 x\n", Location::Line(3), "not an integer"),
    ];
    for (text, at, what) in cases {
        let e = read(text.as_bytes(), "bad.obj").expect_err(what);
        assert_eq!(e.at, *at, "{e}");
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
    let e = read(&[b'v', b' ', 0xff], "bad.obj").unwrap_err();
    assert!(e.to_string().contains("not UTF-8"), "{e}");
}
