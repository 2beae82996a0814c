//! `tubecast simplify`: merge consecutive links within a tolerance and write the same format.
//! The file formats hold nodes only, so quadratic spline pieces cannot be written; the command
//! prints what the automatic choice (`render`/`info --tolerance`) makes of the input at the
//! same tolerance, links only and with quadratic spline fits.
//!
//! # Streaming
//! `.trk`, `.tck` and `.obj` files are read streamline by streamline through the streaming
//! readers ([`tubecast_render::io::stream`], [`io::obj::stream`]) and each simplified
//! streamline is written as it comes ([`Out`]), so the command holds one streamline of each
//! (an OBJ file: its vertices too, which its `l` elements may index anywhere). The output
//! goes to a file beside `--out` that is renamed over it at the end (removed on an error), so
//! a malformed input leaves no partial output and the output may be the input itself. The
//! choice is then printed for the scene loaded again by the streaming loader (what it keeps:
//! the scene, no copy of the file). An SWC tree is read line by line and simplified whole.

use crate::args::SimplifyArgs;
use crate::error::CliError;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use tubecast_render::io::stream::{open, Flow, Selection};
use tubecast_render::io::{self, obj, tck, trk, IoError, Polyline};
use tubecast_render::scene::choice::{choose, choose_with, Tolerance};
use tubecast_render::scene::simplify::{simplify_polyline, simplify_swc};
use tubecast_render::scene::{LoadOptions, Scene};

/// The automatic choice on `scene` at `eps`, links only and with splines, as a line of text
/// or JSON.
fn choice(scene: &Scene, eps: f64, json: bool) -> String {
    let t = Tolerance::Absolute(eps);
    let (l, s) = (choose(scene, &t), choose_with(scene, &t, true));
    if json {
        return serde_json::json!({
            "links": scene.links.len(),
            "links_only": {"primitives": l.prims.len(), "worst": l.worst},
            "with_splines": {"primitives": s.prims.len(), "spline_pieces": s.splines, "merged": s.merged,
                             "fitted": s.fitted, "worst": s.worst},
        })
        .to_string();
    }
    format!(
        "choice at {eps:e}: {} links → {} primitives with links only (worst {:e}); {} with quadratic splines: \
         {} spline pieces, {} links merged, {} fitted (worst {:e}; render/info --tolerance only, not written)",
        scene.links.len(),
        l.prims.len(),
        l.worst,
        s.prims.len(),
        s.splines,
        s.merged,
        s.fitted,
        s.worst
    )
}

/// `tubecast simplify`.
pub fn simplify(a: &SimplifyArgs) -> Result<(), CliError> {
    crate::options::simplify(a)?;
    crate::progress::configure(a.run.progress, a.run.quiet);
    let eps = a.tolerance;
    let kind = crate::options::extension(&a.input);
    let (min, all) = (a.radius.min_radius, Selection::default());
    // The radius of formats without radii, at least --min-radius.
    let radius = crate::setup::resolve_radius(&a.input, a.radius.radius, min, &all)?.max(min.unwrap_or(0.0));
    let part = PathBuf::from(format!("{}.partial", a.out.display()));
    let done = crate::setup::with_threads(a.run.threads, || write_simplified(a, radius, &kind, &part))?;
    let renamed = done.and_then(|r| {
        let err = |e: std::io::Error| IoError::file(&a.out.display().to_string(), format!("cannot write: {e}"));
        std::fs::rename(&part, &a.out).map_err(err)?;
        Ok(r)
    });
    let (before, after, d, swc_scene) = renamed.inspect_err(|_| drop(std::fs::remove_file(&part)))?;
    let scene = swc_scene.or_else(|| {
        let opts = LoadOptions { default_radius: radius, min_radius: min };
        let hidden = indicatif::ProgressBar::hidden();
        Scene::load_selected(&a.input, &opts, &all, false, &hidden).ok().map(|s| s.0)
    });
    let choice = scene.map(|s| choice(&s, eps, a.json));
    if a.json {
        let choice: serde_json::Value = choice.and_then(|c| serde_json::from_str(&c).ok()).unwrap_or_default();
        let j = serde_json::json!({
            "file": a.out.display().to_string(), "nodes_before": before, "nodes_after": after,
            "largest_merge_bound": d, "tolerance": eps, "choice": choice,
        });
        println!("{j}");
        return Ok(());
    }
    println!("{}: {after} of {before} nodes kept, largest merge bound {d:e} (tolerance {eps:e})", a.out.display());
    if let Some(c) = choice {
        println!("{c}");
    }
    Ok(())
}

/// Nodes before and after, the largest merge bound, and (SWC) the input's scene.
type Counts = (usize, usize, f64, Option<Scene>);

/// Simplify the input (of extension `kind`) into `path`.
fn write_simplified(a: &SimplifyArgs, radius: f64, kind: &str, path: &Path) -> Result<Counts, IoError> {
    let name = a.input.display().to_string();
    let (r, len) = open(&a.input)?;
    let min = a.radius.min_radius;
    if kind == "swc" {
        let rows = io::swc::read_from(r, &name, min)?.nodes;
        let (out, d) = simplify_swc(&rows, a.tolerance);
        io::write_bytes(path, io::swc::write(&out).as_bytes())?;
        return Ok((rows.len(), out.len(), d, Scene::from_swc(&rows, &name).ok()));
    }
    let (mut out, out_name) = (Out::create(path, kind, &a.input)?, path.display().to_string());
    let (mut before, mut after, mut worst, mut failed) = (0, 0, 0.0f64, None);
    let mut each = |points: &[[f64; 3]], radii: Vec<f64>| {
        let radii = match min {
            Some(m) => radii.into_iter().map(|r| r.max(m)).collect(),
            None => radii,
        };
        let line = Polyline { points: points.to_vec(), radii };
        let (s, d) = simplify_polyline(&line, radius, a.tolerance);
        (before, after, worst) = (before + line.points.len(), after + s.points.len(), worst.max(d));
        match out.push(&s, &out_name) {
            Ok(()) => Flow::Continue,
            Err(e) => {
                failed = Some(e);
                Flow::Stop
            }
        }
    };
    match kind {
        "trk" => drop(trk::stream(r, &name, &mut |l| each(l.points, Vec::new()))?),
        "tck" => {
            let mut records = tck::Records::new(r, &name, Some(len), false)?;
            while let Some(l) = records.next_line()? {
                if each(l.points, Vec::new()) == Flow::Stop {
                    break;
                }
            }
        }
        _ => drop(obj::stream(r, &name, &mut |l| each(&l.points, l.radii))?),
    }
    if let Some(e) = failed {
        return Err(e);
    }
    out.finish(&out_name)?;
    Ok((before, after, worst, None))
}

/// `.tck`'s end marker: an Inf triplet (little-endian, as [`tck::write`] writes it).
const END: [u8; 12] = [0, 0, 0x80, 0x7f, 0, 0, 0x80, 0x7f, 0, 0, 0x80, 0x7f];

/// Streamlines written as they come, in the layout [`trk::write`], [`tck::write`] and
/// [`obj::write`] give the whole list: the header first, with a count of 0, then each record
/// (cut from what the writer gives for that one streamline), and at the end the count, written
/// over the header's fixed-width field (`.trk`: `n_count` at byte 988; `.tck`: the 10-digit
/// `count:`), and `.tck`'s end marker.
enum Out {
    Trk { w: BufWriter<File>, h: trk::TrkHeader, n: i32 },
    Tck { w: BufWriter<File>, head: Vec<u8>, n: usize },
    Obj(obj::Writer<BufWriter<File>>),
}

impl Out {
    /// Start `path` for `kind` (a `.trk`: with the header of `input`).
    fn create(path: &Path, kind: &str, input: &Path) -> Result<Self, IoError> {
        let err = |e: std::io::Error| IoError::file(&path.display().to_string(), format!("cannot write: {e}"));
        let mut w = BufWriter::new(File::create(path).map_err(err)?);
        Ok(match kind {
            "trk" => {
                let h = trk::read_info(open(input)?.0, &input.display().to_string())?.header;
                w.write_all(&trk::write(&h, &[], false)).map_err(err)?;
                Out::Trk { w, h, n: 0 }
            }
            "tck" => {
                let mut head = tck::write(&[], false);
                head.truncate(head.len() - END.len()); // the end marker, written at the end
                w.write_all(&head).map_err(err)?;
                Out::Tck { w, head, n: 0 }
            }
            _ => Out::Obj(obj::Writer::new(w).map_err(err)?),
        })
    }

    /// Append one streamline.
    fn push(&mut self, l: &Polyline, name: &str) -> Result<(), IoError> {
        let one = std::slice::from_ref(l);
        let done = match self {
            Out::Trk { w, h, n } => {
                *n += 1;
                w.write_all(&trk::write(h, one, false)[1000..])
            }
            Out::Tck { w, head, n } => {
                *n += 1;
                let rec = tck::write(one, false);
                w.write_all(&rec[head.len()..rec.len() - END.len()])
            }
            Out::Obj(w) => w.push(l),
        };
        done.map_err(|e| IoError::file(name, format!("cannot write: {e}")))
    }

    /// Write the counts and the end marker, and flush.
    fn finish(self, name: &str) -> Result<(), IoError> {
        let done = match self {
            Out::Trk { mut w, n, .. } => (|| {
                w.seek(SeekFrom::Start(988))?;
                w.write_all(&n.to_le_bytes())?;
                w.flush()
            })(),
            Out::Tck { mut w, head, n } => (|| {
                w.write_all(&END)?;
                let at = head.windows(7).position(|s| s == b"count: ").expect("tck::write writes a count") + 7;
                w.seek(SeekFrom::Start(at as u64))?;
                w.write_all(format!("{n:010}").as_bytes())?;
                w.flush()
            })(),
            Out::Obj(w) => w.finish().map(drop),
        };
        done.map_err(|e| IoError::file(name, format!("cannot write: {e}")))
    }
}
