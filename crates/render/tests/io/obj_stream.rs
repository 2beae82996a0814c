//! The OBJ reader streams: line by line from any `BufRead` (a reader that yields one byte at a
//! time reads the same polylines), stops where asked, and a truncated or malformed file is an
//! error naming its line; the streaming writer writes what `write` does.

use std::io::{BufReader, Read};
use tubecast_render::io::obj::{read, read_from, stream, write, Writer};
use tubecast_render::io::stream::Flow;
use tubecast_render::io::{Location, Polyline};

/// Hands out one byte per `read` call.
struct OneByte<'a>(&'a [u8]);

impl Read for OneByte<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match (self.0.split_first(), buf.is_empty()) {
            (Some((&b, rest)), false) => {
                buf[0] = b;
                self.0 = rest;
                Ok(1)
            }
            _ => Ok(0),
        }
    }
}

const TEXT: &str = "# a comment\r\no thing\nv 0 0 0\nv 1 0 0\nvn 0 0 1\nv 2 0 0 0.5\nf 1 2 3\n\
                    l -3/1 2/2\nl 2 3 # tail\nv 4 5 6 0.25\r\nv 7 8 9 0.125\nl 3 4 5";

/// The polylines of `TEXT`, worked out by hand: vertices 1..5 are (0,0,0), (1,0,0),
/// (2,0,0; r 0.5), (4,5,6; r 0.25), (7,8,9; r 0.125); `-3` is vertex 1 when 3 exist.
fn expected() -> Vec<Polyline> {
    vec![
        Polyline { points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], radii: vec![] },
        Polyline { points: vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], radii: vec![] },
        Polyline { points: vec![[2.0, 0.0, 0.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]], radii: vec![0.5, 0.25, 0.125] },
    ]
}

#[test]
fn one_byte_at_a_time_reads_the_same_polylines() {
    assert_eq!(read(TEXT.as_bytes(), "t.obj").unwrap(), expected());
    let slow = BufReader::with_capacity(1, OneByte(TEXT.as_bytes()));
    assert_eq!(read_from(slow, "t.obj").unwrap(), expected());
    // And a file written by `write`, with and without radii.
    let text = write(&expected());
    let slow = BufReader::with_capacity(1, OneByte(text.as_bytes()));
    assert_eq!(read_from(slow, "t.obj").unwrap(), expected());
}

#[test]
fn a_stop_ends_the_reading() {
    let mut got = Vec::new();
    let n = stream(TEXT.as_bytes(), "t.obj", &mut |l| {
        got.push(l);
        Flow::Stop
    })
    .unwrap();
    assert_eq!((n, got), (1, vec![expected()[0].clone()]));
    // A stop before a malformed line never reads it.
    let bad = "v 0 0 0\nv 1 1 1\nl 1 2\nv oops\n";
    assert!(read(bad.as_bytes(), "b.obj").is_err());
    assert_eq!(stream(bad.as_bytes(), "b.obj", &mut |_| Flow::Stop).unwrap(), 1);
}

#[test]
fn truncated_and_malformed_files_name_the_line() {
    let full = "v 0 0 0\nv 1 1 1 0.5\nl 1 2\n";
    // Cut inside the second `v` (after "v 1 1"), inside the `l` (after "l 1"), before any `l`.
    let cases: &[(&str, Location, &str)] = &[
        (&full[..13], Location::Line(2), "found 2 values"),
        (&full[..23], Location::Line(3), "at least 2"),
        (&full[..20], Location::File, "no line elements"),
        ("v 0 0 0\nv 1 1 1\nl 1 2\nl 2 9\n", Location::Line(4), "index 9 is out of range (1..=2"),
        ("v 0 0 0\r\nv 1 1 1\r\nl 1 2 x\r\n", Location::Line(3), "\"x\" is not an integer"),
    ];
    for &(text, at, what) in cases {
        for slow in [false, true] {
            let e = match slow {
                false => read(text.as_bytes(), "bad.obj").unwrap_err(),
                true => read_from(BufReader::with_capacity(1, OneByte(text.as_bytes())), "bad.obj").unwrap_err(),
            };
            assert_eq!(e.at, at, "{text:?}: {e}");
            assert!(e.to_string().contains(what), "{text:?}: expected {what:?} in {e}");
        }
    }
    // Not UTF-8 on line 2: the offset of the bad byte (8 bytes of line 1, then "v ").
    let e = read(b"v 0 0 0\nv \xff 0 0\nl 1 2\n", "bad.obj").unwrap_err();
    assert_eq!(e.at, Location::Offset(10), "{e}");
    assert!(e.to_string().contains("not UTF-8"), "{e}");
}

#[test]
fn the_streaming_writer_writes_what_write_does() {
    let lines = expected();
    let mut w = Writer::new(Vec::new()).unwrap();
    lines.iter().for_each(|l| w.push(l).unwrap());
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    assert_eq!(text, write(&lines));
    // The text itself, by hand: vertices numbered on from 1 across polylines.
    assert!(text.ends_with("v 2.0 0.0 0.0 0.5\nv 4.0 5.0 6.0 0.25\nv 7.0 8.0 9.0 0.125\nl 5 6 7\n"), "{text}");
    assert!(text.contains("v 0.0 0.0 0.0\nv 1.0 0.0 0.0\nl 1 2\n"), "{text}");
}
