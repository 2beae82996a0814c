//! Streaming readers and the selection of streamlines: reading a byte at a time gives what
//! reading the whole file gives; `--subsample` keeps exactly the streamlines its documented
//! rule names, in order, the same in every format; `--max-streamlines` stops reading (a
//! corrupt tail after the last kept streamline is never seen); the header counts the memory
//! estimate starts from.

use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use std::io::Read;
use std::path::PathBuf;
use tubecast_render::estimate::{self, Counts, PerLink};
use tubecast_render::io::stream::{Flow, Selection};
use tubecast_render::io::{tck, trk, Polyline};
use tubecast_render::scene::{LoadOptions, Scene};

/// `n` streamlines of 1 to 5 points, every coordinate a multiple of 1/4 (exact in f32, and
/// through the TrackVis voxmm shift of ½), streamline `i` starting at x = i (tells them apart).
fn lines(n: usize) -> Vec<Polyline> {
    let line = |i: usize| Polyline {
        points: (0..i % 5 + 1).map(|k| [i as f64, 0.5 * k as f64, 0.25 * ((i * k) % 7) as f64]).collect(),
        radii: vec![],
    };
    (0..n).map(line).collect()
}

/// A reader handing over one byte per call.
struct Trickle<'a>(&'a [u8]);

impl Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match (self.0.split_first(), buf.is_empty()) {
            (Some((b, rest)), false) => {
                buf[0] = *b;
                self.0 = rest;
                Ok(1)
            }
            _ => Ok(0),
        }
    }
}

fn tmp(name: &str, data: &[u8]) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tubecast-io-stream-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, data).unwrap();
    p
}

#[test]
fn a_byte_at_a_time_reads_what_the_file_holds() {
    let want = lines(40);
    for big in [false, true] {
        let data = trk::write(&trk::TrkHeader::default(), &want, big);
        let mut got = Vec::new();
        trk::stream(Trickle(&data), "t.trk", &mut |l| {
            got.push(Polyline { points: l.points.to_vec(), radii: vec![] });
            Flow::Continue
        })
        .unwrap();
        assert_eq!(got, want, "trk big={big}");
        let data = tck::write(&want, big);
        let mut r =
            tck::Records::new(std::io::BufReader::with_capacity(1, Trickle(&data)), "t.tck", None, false).unwrap();
        let mut got = Vec::new();
        while let Some(l) = r.next_line().unwrap() {
            got.push(Polyline { points: l.points.to_vec(), radii: vec![] });
        }
        assert_eq!(got, want, "tck big={big}");
    }
    // A cut file read a byte at a time fails as the whole file does, at the same offset.
    let data = trk::write(&trk::TrkHeader::default(), &want, false);
    let cut = &data[..data.len() - 6];
    let whole = trk::read(cut, "t.trk").unwrap_err();
    let streamed = trk::stream(Trickle(cut), "t.trk", &mut |_| Flow::Continue).unwrap_err();
    assert_eq!(streamed, whole);
    assert!(whole.problem.contains("truncated"), "{whole}");
}

/// The points of the streamlines the documented rule keeps (SplitMix64 seeded with the
/// index, below F·2⁶⁴), first `max` of them.
fn expected(all: &[Polyline], f: f64, max: usize) -> Vec<[f64; 3]> {
    let keep = |i: usize| (rand_xoshiro::SplitMix64::seed_from_u64(i as u64).next_u64() as f64) < f * 2f64.powi(64);
    let kept = all.iter().enumerate().filter(|(i, _)| keep(*i)).take(max);
    kept.flat_map(|(_, l)| l.points.iter().copied()).collect()
}

fn load(path: &std::path::Path, sel: &Selection) -> Scene {
    let hidden = indicatif::ProgressBar::hidden();
    Scene::load_selected(path, &LoadOptions::default(), sel, false, &hidden).unwrap().0
}

#[test]
fn subsample_keeps_what_its_rule_says_in_every_format() {
    let all = lines(3000);
    let files =
        [tmp("s.trk", &trk::write(&trk::TrkHeader::default(), &all, false)), tmp("s.tck", &tck::write(&all, true))];
    let sel = Selection { max_streamlines: None, subsample: Some(0.3) };
    let want = expected(&all, 0.3, usize::MAX);
    // About 0.3 of them: 900 ± 5σ, σ = √(3000·0.3·0.7) ≈ 25.1 (the rule draws like a fair coin).
    let kept = all.iter().filter(|l| want.contains(&l.points[0])).count();
    assert!((774..=1026).contains(&kept), "{kept} kept");
    for p in &files {
        let s = load(p, &sel);
        assert_eq!(s.nodes.iter().map(|n| n.pos).collect::<Vec<_>>(), want, "{}", p.display());
        assert_eq!(load(p, &sel), s, "deterministic");
        let first = load(p, &Selection { max_streamlines: Some(7), subsample: Some(0.3) });
        assert_eq!(first.nodes.iter().map(|n| n.pos).collect::<Vec<_>>(), expected(&all, 0.3, 7));
    }
    let swc = tmp("s.swc", "1 1 0 0 0 1 -1\n2 3 1 0 0 1 1\n".as_bytes());
    let hidden = indicatif::ProgressBar::hidden();
    let e = Scene::load_selected(&swc, &LoadOptions::default(), &sel, false, &hidden).unwrap_err().to_string();
    assert!(e.contains("SWC") && e.contains("--subsample"), "{e}");
    assert_eq!(load(&swc, &Selection::default()).nodes.len(), 2);
}

#[test]
fn max_streamlines_stops_before_a_corrupt_tail() {
    let all = lines(20);
    let mut data = tck::write(&all, false);
    // Replace the Inf end marker by a triplet mixing finite and NaN values.
    let n = data.len();
    data[n - 12..n - 8].copy_from_slice(&1.0f32.to_le_bytes());
    let p = tmp("tail.tck", &data);
    let hidden = indicatif::ProgressBar::hidden();
    let e = Scene::load_selected(&p, &LoadOptions::default(), &Selection::default(), false, &hidden).unwrap_err();
    assert!(e.to_string().contains("mixes"), "{e}");
    let s = load(&p, &Selection { max_streamlines: Some(5), subsample: None });
    let want: Vec<[f64; 3]> = all[..5].iter().flat_map(|l| l.points.iter().copied()).collect();
    assert_eq!(s.nodes.iter().map(|n| n.pos).collect::<Vec<_>>(), want);
    // Zero streamlines: the empty scene.
    assert!(load(&p, &Selection { max_streamlines: Some(0), subsample: None }).nodes.is_empty());
}

#[test]
fn tsf_values_follow_the_kept_streamlines() {
    let all = lines(30);
    let values: Vec<Vec<f64>> = all.iter().map(|l| l.points.iter().map(|p| p[0] + p[1]).collect()).collect();
    let p = tmp("v.tck", &tck::write(&all, false));
    std::fs::write(p.with_extension("tsf"), tck::write_tsf(&values)).unwrap();
    let sel = Selection { max_streamlines: Some(9), subsample: Some(0.5) };
    let hidden = indicatif::ProgressBar::hidden();
    let (s, _, fields) = Scene::load_selected(&p, &LoadOptions::default(), &sel, true, &hidden).unwrap();
    let f = fields.iter().find(|f| f.name == "scalar:tsf").expect("tsf field");
    let want: Vec<f64> = s.nodes.iter().map(|n| n.pos[0] + n.pos[1]).collect();
    assert_eq!(f.values, want);
    assert_eq!(s.nodes.len(), expected(&all, 0.5, 9).len());
}

#[test]
fn header_counts() {
    let all = lines(101);
    let points: u64 = all.iter().map(|l| l.points.len() as u64).sum();
    let links = points - all.len() as u64;
    let p = tmp("c.trk", &trk::write(&trk::TrkHeader::default(), &all, false));
    let c = estimate::probe(&p).unwrap();
    assert_eq!(c, Counts { streamlines: Some(101), points });
    assert_eq!(c.links(&Selection::default(), None), links);
    // The writer zero-pads `count`: exact too. Without a count, the points are an upper
    // bound (each NaN separator and the end marker counted as a point).
    let p = tmp("c.tck", &tck::write(&all, false));
    assert_eq!(estimate::probe(&p).unwrap(), Counts { streamlines: Some(101), points });
    let mut data = tck::write(&all, false);
    let at = data.windows(17).position(|w| w == b"count: 0000000101").expect("the writer's count");
    data[at..at + 17].copy_from_slice(b"count: 0000000000");
    let p = tmp("c0.tck", &data);
    assert_eq!(estimate::probe(&p).unwrap(), Counts { streamlines: None, points: points + 102 });
    // A selection: half of them, or the first 10 of 101 (10/101 of the links).
    let half = Selection { max_streamlines: None, subsample: Some(0.5) };
    assert_eq!(c.links(&half, None), (links as f64 * 0.5).ceil() as u64);
    let ten = Selection { max_streamlines: Some(10), subsample: None };
    assert_eq!(c.links(&ten, None), (links as f64 * 10.0 / 101.0).ceil() as u64);
}

#[test]
fn too_large_names_the_figures_and_the_way_out() {
    let per_link = PerLink { scene: 48.0, tracer: 100.0 };
    // Peak per link 48 + 100·(1 + BUILD_OVERHEAD), plus the builder's bytes for each link (10⁶
    // links are built at once: fewer than BUILD_ITEMS), plus the base.
    const { assert!(estimate::BUILD_ITEMS >= 1_000_000) };
    let peak = 48.0 + 100.0 * (1.0 + estimate::BUILD_OVERHEAD) + estimate::BUILD_BYTES_PER_ITEM;
    let need = (1e6 * peak) as u64 + estimate::BASE_BYTES;
    let kept = (1_000_000, Some(10_000));
    assert_eq!(estimate::check("f.trk", kept, per_link, (need, "test".into())), Ok(need));
    let e = estimate::check("f.trk", kept, per_link, (need - 1, "test".into())).unwrap_err();
    let m = e.to_string();
    // What fits, with a tenth to spare: (need − 1 − base)/(need − base)·0.9 ≈ 0.899 → 0.899 of
    // the streamlines, 8990 of 10⁴.
    let parts = ["f.trk", "1000000 links", "--subsample F (F ≤ 0.899)", "--max-streamlines N ≤ 8990", "test"];
    for part in parts.into_iter().chain(["--memory-limit", "GiB"]) {
        assert!(m.contains(part), "{part:?} missing in {m}");
    }
    assert_eq!(e.needed, need);
}
