//! Empty tractograms and morphologies are valid: a TrackVis file with `n_count` 0 and no
//! records, an MRtrix file holding only the Inf end marker (both as nibabel writes and reads
//! them, see nibabel/tests/data/empty.{trk,tck}), and an SWC file without nodes (navis and
//! NeuroM read it as an empty morphology) load as the empty scene, whose stats are zeros with
//! finite bounds, which every ray misses and which renders as the background.

use tubecast::{Ray, V3};
use tubecast_render::accel::{hit_table, Bvh};
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{Model, Scene};

/// nibabel's own `empty.trk` and `empty.tck` test files (committed under `reference/readers/`,
/// MIT; see the COPYING there).
fn nibabel_file(name: &str) -> Vec<u8> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/readers/nibabel").join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn nibabel_empty_trk() -> Vec<u8> {
    nibabel_file("empty.trk")
}

fn nibabel_empty_tck() -> Vec<u8> {
    nibabel_file("empty.tck")
}

#[test]
fn empty_files_read_as_no_streamlines() {
    let (h, lines) = tubecast_render::io::trk::read(&nibabel_empty_trk(), "empty.trk").unwrap();
    assert!(lines.is_empty());
    assert_eq!(h.voxel_order, *b"RAS");
    // Big endian too (hdr_size read in the other byte order).
    let mut be = nibabel_empty_trk();
    for o in [6, 8, 10] {
        be.swap(o, o + 1);
    }
    for o in (12..24).step_by(4).chain((440..504).step_by(4)).chain([992, 996]) {
        be[o..o + 4].reverse();
    }
    assert!(tubecast_render::io::trk::read(&be, "be.trk").unwrap().1.is_empty());
    assert!(tubecast_render::io::tck::read(&nibabel_empty_tck(), "empty.tck").unwrap().is_empty());
    assert!(tubecast_render::io::swc::read(b"", "empty.swc").unwrap().is_empty());
    let header = b"# ORIGINAL_SOURCE NeuronStudio\n# SCALE 1.0 1.0 1.0\n\n   \n# id type x y z r parent\n";
    assert!(tubecast_render::io::swc::read(header, "comments.swc").unwrap().is_empty());
}

#[test]
fn an_empty_file_is_still_refused_when_it_is_malformed() {
    // nibabel refuses a .tck without the Inf end marker ("Cannot find a streamline
    // delimiter"), and a .trk whose n_count promises streamlines it does not hold.
    let tck = nibabel_empty_tck();
    let e = tubecast_render::io::tck::read(&tck[..67], "cut.tck").unwrap_err();
    assert!(e.to_string().contains("without the Inf end marker"), "{e}");
    let mut trk = nibabel_empty_trk();
    trk[988..992].copy_from_slice(&1i32.to_le_bytes());
    let e = tubecast_render::io::trk::read(&trk, "cut.trk").unwrap_err();
    assert!(e.to_string().contains("header says 1 streamlines, file holds 0"), "{e}");
}

#[test]
fn empty_files_load_as_the_empty_scene_with_zero_stats() {
    let dir = std::env::temp_dir().join(format!("tubecast-empty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: [(&str, Vec<u8>); 3] =
        [("e.trk", nibabel_empty_trk()), ("e.tck", nibabel_empty_tck()), ("e.swc", b"# no nodes here\n".to_vec())];
    for (name, bytes) in files {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        let s = Scene::load(&p, 0.2).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(s.nodes.is_empty() && s.links.is_empty(), "{name}");
        for model in [Model::Links, Model::Splines] {
            let prims = s.model_primitives(model).unwrap();
            assert!(prims.is_empty(), "{name}");
            for st in [s.stats(), s.stats_of(&prims)] {
                assert!(st.is_empty());
                assert_eq!((st.nodes, st.links, st.cylinders, st.cones, st.spheres, st.splines), (0, 0, 0, 0, 0, 0));
                assert_eq!(st.bounds, ([0.0; 3], [0.0; 3]), "{name}: finite bounds, not ±inf");
            }
        }
    }
    // Building from nothing directly gives the same scene.
    assert_eq!(Scene::from_polylines(&[], 0.5, "none").unwrap(), Scene::default());
    assert_eq!(Scene::from_swc(&[], "none").unwrap(), Scene::default());
    // Streamlines of zero points (a .trk can hold them) add no nodes.
    let zero = tubecast_render::io::Polyline::default();
    assert_eq!(Scene::from_polylines(&[zero.clone(), zero], 0.5, "zeros").unwrap(), Scene::default());
}

#[test]
fn every_ray_misses_the_empty_scene() {
    let bvh = Bvh::build(Scene::default().primitives());
    let ray = Ray::new(V3::new(0.0, 0.0, -5.0), V3::new(0.0, 0.0, 1.0));
    assert!(bvh.closest_hit(&ray).is_none());
    let rows = hit_table(&bvh, &[ray, Ray::new(V3::zero(), V3::new(1.0, 0.0, 0.0))]);
    for r in rows {
        assert_eq!(r, [f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0]);
    }
}

#[test]
fn the_empty_scene_renders_as_the_background() {
    let scene = Scene::default();
    let bvh = Bvh::build(scene.primitives());
    let cam = Camera::fit([-1.0; 3], [1.0; 3], 40.0, 6, 4).unwrap();
    let bg = [0.25f32, 0.5, 0.75];
    for opacity in [1.0, 0.5] {
        let opts = Options { background: bg, opacity, ao: 4, shadows: true, ..Options::default() };
        let img = render(&scene, &bvh, &cam, &opts).unwrap();
        assert_eq!((img.width, img.height), (6, 4));
        assert!(img.rgb.iter().all(|c| *c == bg), "opacity {opacity}: {:?}", img.rgb);
        assert!(img.depth.iter().all(|d| *d == f64::INFINITY));
    }
}
