//! SWC files as found in the field: placeholder radii (0 or negative) are refused with an
//! error that names the line and points to the minimum-radius fallback, which replaces them
//! and counts the replacements; several roots, unsorted and non-contiguous ids, comment
//! headers, CRLF line ends and tabs keep working.

use std::path::PathBuf;
use tubecast_render::io::swc::{read, read_with, SwcNode};
use tubecast_render::io::Location;
use tubecast_render::scene::{LoadOptions, LoadReport, Scene, SceneError};

fn file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tubecast-swc-wild-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn strict() -> LoadOptions {
    LoadOptions { default_radius: 0.2, min_radius: None }
}

fn with_min(r: f64) -> LoadOptions {
    LoadOptions { default_radius: 0.2, min_radius: Some(r) }
}

/// A NeuroMorpho-style file: a header of comments, CRLF line ends, tabs, ids that are
/// neither contiguous nor sorted (children before parents), two roots.
const FIELD: &str = "# ORIGINAL_SOURCE Neurolucida\r\n# CREATURE mouse\r\n# SCALE 1.0 1.0 1.0\r\n\
                     #\r\n# id type x y z radius parent\r\n\
                     500\t3\t0\t3\t0\t0.5\t40\r\n\
                     40 3 0 2 0 0.75 7\r\n\
                     7 1 0 0 0 2 -1\r\n\
                     9001 2 10 0 0 0.25 -1 # a second tree\r\n\
                     12 2 11 0 0 0.25 9001\r\n";

#[test]
fn field_files_read_with_lines_and_link_child_to_parent() {
    let f = read_with(FIELD.as_bytes(), "field.swc", None).unwrap();
    let ids: Vec<i64> = f.nodes.iter().map(|n| n.id).collect();
    assert_eq!(ids, vec![500, 40, 7, 9001, 12]);
    assert_eq!(f.lines, vec![6, 7, 8, 9, 10]);
    assert_eq!((f.replaced, f.placeholders), (0, 0));
    assert_eq!(f.nodes[0], SwcNode { id: 500, kind: 3, pos: [0.0, 3.0, 0.0], radius: 0.5, parent: 40 });
    let (s, rep) = Scene::load_with(&file("field.swc", FIELD), &strict()).unwrap();
    assert_eq!(rep, LoadReport::default());
    // Links (parent index, child index) in file order: 40→500, 7→40, 9001→12.
    assert_eq!(s.links, vec![[1, 0], [2, 1], [3, 4]]);
    assert_eq!(s.radius(2), 2.0);
}

#[test]
fn negative_placeholder_radius_is_refused_at_its_line_with_the_hint() {
    let text = "# header\n1 1 0 0 0 1 -1\n2 3 1 0 0 -1 1\n";
    let e = read(text.as_bytes(), "neg.swc").unwrap_err();
    assert_eq!(e.at, Location::Line(3));
    let msg = e.to_string();
    assert!(msg.starts_with("neg.swc: line 3: radius -1 is negative"), "{msg}");
    assert!(msg.contains("--min-radius"), "{msg}");
    let e = Scene::load_with(&file("neg.swc", text), &strict()).unwrap_err();
    assert!(matches!(&e, SceneError::Io(io) if io.at == Location::Line(3)), "{e}");
}

#[test]
fn zero_radius_links_without_volume_are_refused_at_their_line() {
    // All radii 0 (the commonest placeholder): the first child of a zero-radius parent.
    let all_zero = "# all placeholders\n1 1 0 0 0 0 -1\n2 3 1 0 0 0 1\n3 3 2 0 0 0 2\n";
    let e = Scene::load_with(&file("zero.swc", all_zero), &strict()).unwrap_err();
    assert_eq!(
        e,
        SceneError::ZeroRadius {
            file: file("zero.swc", all_zero).display().to_string(),
            line: 3,
            node: 2,
            parent: Some((1, 2))
        }
    );
    let msg = e.to_string();
    assert!(msg.contains("zero.swc: line 3: node 2 and its parent 1 (line 2) both have radius 0"), "{msg}");
    assert!(msg.contains("--min-radius"), "{msg}");
    // An isolated node of radius 0 (no parent, no children).
    let lone = "1 1 0 0 0 1 -1\n2 3 1 0 0 1 1\n\n7 1 5 5 5 0 -1\n";
    let e = Scene::load_with(&file("lone.swc", lone), &strict()).unwrap_err();
    assert!(matches!(e, SceneError::ZeroRadius { line: 4, node: 7, parent: None, .. }), "{e}");
    assert!(e.to_string().contains("line 4: node 7 has radius 0 and no links"), "{e}");
    // A tapering tip (radius 0 next to a positive radius) is a cone to a point: kept.
    let tip = "1 1 0 0 0 1 -1\n2 3 1 0 0 0 1\n";
    let (s, rep) = Scene::load_with(&file("tip.swc", tip), &strict()).unwrap();
    assert_eq!((s.radius(1), rep), (0.0, LoadReport::default()));
}

#[test]
fn min_radius_replaces_placeholders_and_small_radii_and_counts_them() {
    let text = "1 1 0 0 0 0 -1\n2 3 1 0 0 -1 1\n3 3 2 0 0 0.05 2\n4 3 3 0 0 0.5 3\n5 3 4 0 0 0.1 4\n";
    let f = read_with(text.as_bytes(), "m.swc", Some(0.1)).unwrap();
    // 0 and −1 (placeholders) and 0.05 are below 0.1; 0.1 itself and 0.5 are kept.
    assert_eq!(f.nodes.iter().map(|n| n.radius).collect::<Vec<_>>(), vec![0.1, 0.1, 0.1, 0.5, 0.1]);
    assert_eq!((f.replaced, f.placeholders), (3, 2));
    let (s, rep) = Scene::load_with(&file("m.swc", text), &with_min(0.1)).unwrap();
    assert_eq!(rep, LoadReport { replaced: 3, placeholders: 2 });
    assert!((0..s.nodes.len()).all(|i| s.radius(i) >= 0.1));
    assert_eq!(s.links.len(), 4);
    // The same file without the option: refused at the negative radius.
    assert!(Scene::load_with(&file("m.swc", text), &strict()).is_err());
    // A minimum radius must be a positive finite number.
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = read_with(text.as_bytes(), "m.swc", Some(r)).unwrap_err();
        assert_eq!(e.at, Location::File);
        assert!(e.to_string().contains("minimum radius"), "{e}");
        let e = Scene::load_with(&file("m.swc", text), &with_min(r)).unwrap_err();
        assert!(matches!(e, SceneError::MinRadius(_)), "{e}");
    }
}

#[test]
fn min_radius_applies_to_every_format() {
    // A polyline file's radii (OBJ) and default radii (.tck) are raised as well.
    let obj = "v 0 0 0 0\nv 1 0 0 0.5\nv 2 0 0 0\nl 1 2 3\n";
    let (s, rep) = Scene::load_with(&file("r.obj", obj), &with_min(0.25)).unwrap();
    assert_eq!(rep, LoadReport { replaced: 2, placeholders: 2 });
    assert_eq!((0..s.nodes.len()).map(|i| s.radius(i)).collect::<Vec<_>>(), vec![0.25, 0.5, 0.25]);
    let tck = tubecast_render::io::tck::write(
        &[tubecast_render::io::Polyline { points: vec![[0.0; 3], [1.0, 0.0, 0.0]], radii: vec![] }],
        false,
    );
    let p = std::env::temp_dir().join(format!("tubecast-swc-wild-{}", std::process::id())).join("d.tck");
    std::fs::write(&p, tck).unwrap();
    let (s, rep) = Scene::load_with(&p, &LoadOptions { default_radius: 0.2, min_radius: Some(0.3) }).unwrap();
    assert_eq!(rep, LoadReport { replaced: 2, placeholders: 0 });
    assert!((0..s.nodes.len()).all(|i| s.radius(i) == 0.3));
    // Radii at or above the minimum are untouched.
    let (s, rep) = Scene::load_with(&p, &LoadOptions { default_radius: 0.2, min_radius: Some(0.2) }).unwrap();
    assert_eq!(rep, LoadReport::default());
    assert!((0..s.nodes.len()).all(|i| s.radius(i) == 0.2));
}
