//! TRX reader: archives built here with the zip crate's writer (hand-chosen arrays, expected
//! values written out), and malformed archives refused with a clear error.
//! (Agreement with trx-python's own files: io_reference_readers.rs.)

use std::io::Write;
use tubecast_render::io::trx::read;

fn le<T: Copy, const N: usize>(v: &[T], f: fn(T) -> [u8; N]) -> Vec<u8> {
    v.iter().flat_map(|&x| f(x)).collect()
}

fn archive(entries: &[(&str, Vec<u8>)], deflate: bool) -> Vec<u8> {
    let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let method = if deflate { zip::CompressionMethod::Deflated } else { zip::CompressionMethod::Stored };
    let opts = zip::write::SimpleFileOptions::default().compression_method(method);
    for (name, data) in entries {
        w.start_file(*name, opts).unwrap();
        w.write_all(data).unwrap();
    }
    w.finish().unwrap().into_inner()
}

fn header(ns: usize, nv: usize) -> Vec<u8> {
    format!(
        r#"{{"NB_STREAMLINES": {ns}, "NB_VERTICES": {nv}, "DIMENSIONS": [1, 1, 1],
        "VOXEL_TO_RASMM": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}"#
    )
    .into_bytes()
}

fn good(deflate: bool) -> Vec<u8> {
    archive(
        &[
            ("header.json", header(2, 3)),
            ("positions.3.float32", le(&[0.0f32, 0.0, 0.0, 1.0, 0.5, 0.25, -2.0, 3.0, 4.0], f32::to_le_bytes)),
            ("offsets.uint64", le(&[0u64, 2, 3], u64::to_le_bytes)),
            ("dpv/fa.float32", le(&[0.1f32, 0.2, 0.3], f32::to_le_bytes)),
            ("dps/len.1.float64", le(&[2.5f64, 7.0], f64::to_le_bytes)),
            ("groups/g.uint32", le(&[1u32], u32::to_le_bytes)),
            ("dpg/g/w.float32", le(&[1.0f32], f32::to_le_bytes)),
        ],
        deflate,
    )
}

#[test]
fn reads_positions_offsets_dpv_dps_groups_stored_and_deflated() {
    for deflate in [false, true] {
        let t = read(&good(deflate), "g.trx").unwrap();
        assert_eq!(t.lines.len(), 2);
        assert_eq!(t.lines[0].points, vec![[0.0, 0.0, 0.0], [1.0, 0.5, 0.25]]);
        assert_eq!(t.lines[1].points, vec![[-2.0, 3.0, 4.0]]);
        assert_eq!(t.point_field("fa").unwrap().values, vec![0.1f32 as f64, 0.2f32 as f64, 0.3f32 as f64]);
        assert_eq!(t.line_field("len").unwrap().values, vec![2.5, 7.0]);
        assert_eq!(t.groups, vec![("g".to_string(), vec![1])]);
    }
}

#[test]
fn malformed_archives_are_errors() {
    let pos = le(&[0.0f32; 9], f32::to_le_bytes);
    let off = le(&[0u32, 2, 3], u32::to_le_bytes);
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (b"PK not really".to_vec(), "zip archive"),
        (archive(&[("positions.3.float32", pos.clone())], false), "no header.json"),
        (archive(&[("header.json", b"{".to_vec())], false), "header.json"),
        (archive(&[("header.json", br#"{"NB_STREAMLINES": -1, "NB_VERTICES": 3}"#.to_vec())], false), "NB_STREAMLINES"),
        (archive(&[("header.json", header(2, 3)), ("offsets.uint32", off.clone())], false), "missing positions"),
        (archive(&[("header.json", header(2, 3)), ("positions.3.float32", pos[..32].to_vec())], false), "positions"),
        (archive(&[("header.json", header(2, 3)), ("positions.3.float32", pos[..30].to_vec())], false), "whole number"),
        (
            archive(
                &[
                    ("header.json", header(2, 3)),
                    ("positions.3.float32", pos.clone()),
                    ("offsets.uint32", le(&[0u32, 3, 2], u32::to_le_bytes)),
                ],
                false,
            ),
            "offsets must rise",
        ),
        (
            archive(
                &[
                    ("header.json", header(2, 3)),
                    ("positions.3.float32", pos.clone()),
                    ("offsets.uint32", off.clone()),
                    ("dpv/fa.float32", vec![0; 8]),
                ],
                false,
            ),
            "dpv",
        ),
        (
            archive(
                &[
                    ("header.json", header(2, 3)),
                    ("positions.3.float32", pos.clone()),
                    ("offsets.uint32", off.clone()),
                    ("groups/g.uint32", le(&[2u32], u32::to_le_bytes)),
                ],
                false,
            ),
            "outside 0..2",
        ),
        (
            archive(
                &[
                    ("header.json", header(2, 3)),
                    ("positions.3.float32", le(&[f32::NAN; 9], f32::to_le_bytes)),
                    ("offsets.uint32", off.clone()),
                ],
                false,
            ),
            "NaN",
        ),
        (archive(&[("header.json", header(2, 3)), ("a.b.c.float32", vec![0; 4])], false), "NAME[.DIM].DTYPE"),
    ];
    for (d, what) in cases {
        let e = read(&d, "bad.trx").expect_err(what);
        assert!(e.to_string().starts_with("bad.trx: "), "{e}");
        assert!(e.to_string().contains(what), "expected {what:?} in {e}");
    }
    // Empty (as trx-python): zero streamlines read as the empty tractogram.
    assert!(read(&archive(&[("header.json", header(0, 0))], false), "e.trx").unwrap().lines.is_empty());
}

/// A scene streamed from a TRX file with a selection: `--max-streamlines 1` keeps the first
/// streamline, with its own per-vertex and per-streamline values; without data fields the
/// dpv/dps arrays are not needed (a corrupt group is then not read either).
#[test]
fn streamed_scene_with_a_selection_keeps_its_own_values() {
    use tubecast_render::io::stream::Selection;
    use tubecast_render::scene::{LoadOptions, Scene};
    let dir = std::env::temp_dir().join(format!("tubecast-io-trx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("g.trx");
    std::fs::write(&p, good(true)).unwrap();
    let hidden = indicatif::ProgressBar::hidden();
    let first = Selection { max_streamlines: Some(1), subsample: None };
    let (s, _, fields) = Scene::load_selected(&p, &LoadOptions::default(), &first, true, &hidden).unwrap();
    assert_eq!(s.nodes.iter().map(|n| n.pos).collect::<Vec<_>>(), vec![[0.0, 0.0, 0.0], [1.0, 0.5, 0.25]]);
    let get = |k: &str| fields.iter().find(|f| f.name == k).unwrap().values.clone();
    assert_eq!(get("scalar:fa"), vec![0.1f32 as f64, 0.2f32 as f64]);
    assert_eq!(get("property:len"), vec![2.5, 2.5]);
    let (all, _, _) = Scene::load_selected(&p, &LoadOptions::default(), &Selection::default(), true, &hidden).unwrap();
    assert_eq!(all.nodes.len(), 3);
    // A group index out of range: an error when the data are read, not needed without them.
    let bad = archive(
        &[
            ("header.json", header(2, 3)),
            ("positions.3.float32", le(&[0.0f32, 0.0, 0.0, 1.0, 0.5, 0.25, -2.0, 3.0, 4.0], f32::to_le_bytes)),
            ("offsets.uint64", le(&[0u64, 2, 3], u64::to_le_bytes)),
            ("groups/g.uint32", le(&[5u32], u32::to_le_bytes)),
        ],
        false,
    );
    std::fs::write(&p, bad).unwrap();
    assert!(Scene::load_selected(&p, &LoadOptions::default(), &Selection::default(), true, &hidden).is_err());
    let (s, _, _) = Scene::load_selected(&p, &LoadOptions::default(), &Selection::default(), false, &hidden).unwrap();
    assert_eq!(s.nodes.len(), 3);
}

/// Fuzz finding (trx target, seed 1701 on f8636be): a stored `offsets.uint32` entry whose zip
/// directory record says 16 bytes (4 offsets for 3 streamlines, so its size check passed) but
/// whose data are 0 bytes long (compressed size 0; Python's `zipfile` reads it as b"" too).
/// The reader decoded an empty array and indexed it: a panic. The decoded length must be the
/// declared one, so this is a clear error naming the entry and both sizes.
#[test]
fn an_entry_shorter_than_its_directory_record_is_an_error() {
    let d = include_bytes!("../../../../fuzz/corpus/trx/regression-entry-shorter-than-directory.trx");
    let e = read(d, "short.trx").expect_err("the offsets entry holds no data");
    assert!(
        e.problem.contains("offsets") && e.problem.contains("holds 0 bytes where the zip directory says 16"),
        "{e}"
    );
}

/// A reader over shared bytes that counts every byte read through any of its clones.
#[derive(Clone)]
struct Counting {
    c: std::io::Cursor<std::sync::Arc<[u8]>>,
    n: std::rc::Rc<std::cell::Cell<u64>>,
}

impl std::io::Read for Counting {
    fn read(&mut self, b: &mut [u8]) -> std::io::Result<usize> {
        let k = self.c.read(b)?;
        self.n.set(self.n.get() + k as u64);
        Ok(k)
    }
}

impl std::io::Seek for Counting {
    fn seek(&mut self, p: std::io::SeekFrom) -> std::io::Result<u64> {
        self.c.seek(p)
    }
}

/// The readers stream: the `dpv`/`dps` arrays are read streamline by streamline beside
/// the positions, not whole. Two streamlines of 1 and 262,143 vertices, stored (trx-python's
/// default) with a 1 MiB per-vertex array; the consumer stops after the first streamline. Read
/// whole, the per-vertex array alone is 1 MiB of reads; streamed, the first streamline needs
/// 12 + 4 + 8 bytes of data beside the archive's directory (read once per view: three views
/// here, ~0.3 KB each) and whatever the zip reader reads ahead: far below 1 MiB.
#[test]
fn data_arrays_are_read_as_the_streamlines_go() {
    use tubecast_render::io::stream::Flow;
    let nv = 1usize << 18;
    let pos: Vec<f32> = (0..3 * nv).map(|i| i as f32).collect();
    let fa: Vec<f32> = (0..nv).map(|i| i as f32 * 0.5).collect();
    let bytes = archive(
        &[
            ("header.json", header(2, nv)),
            ("positions.3.float32", le(&pos, f32::to_le_bytes)),
            ("offsets.uint64", le(&[0u64, 1, nv as u64], u64::to_le_bytes)),
            ("dpv/fa.float32", le(&fa, f32::to_le_bytes)),
            ("dps/len.float64", le(&[2.5f64, 7.0], f64::to_le_bytes)),
        ],
        false,
    );
    let r = Counting { c: std::io::Cursor::new(bytes.clone().into()), n: Default::default() };
    let n = r.n.clone();
    let mut seen = Vec::new();
    let info = tubecast_render::io::trx::stream(r, "s.trx", true, &mut |l| {
        seen.push((l.points.to_vec(), l.scalars.to_vec(), l.properties.to_vec()));
        Flow::Stop
    })
    .unwrap();
    assert_eq!(info.scalars, vec![("fa".to_string(), 0, 1)]);
    assert_eq!(seen, vec![(vec![[0.0, 1.0, 2.0]], vec![0.0], vec![2.5])]);
    assert!(n.get() < 1 << 18, "{} bytes read for one streamline of one vertex", n.get());

    // Read to the end, every value arrives with its streamline (the streamed columns line up).
    let t = read(&bytes, "s.trx").unwrap();
    assert_eq!(t.lines[1].points.len(), nv - 1);
    assert_eq!(t.lines[1].points[nv - 2], [pos[3 * nv - 3] as f64, pos[3 * nv - 2] as f64, pos[3 * nv - 1] as f64]);
    let fa64: Vec<f64> = fa.iter().map(|&x| x as f64).collect();
    assert_eq!(t.point_field("fa").unwrap().values, fa64);
    assert_eq!(t.line_field("len").unwrap().values, vec![2.5, 7.0]);
}
