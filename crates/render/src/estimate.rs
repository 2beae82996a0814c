//! The memory a scene will need, known before it is loaded: counts from the file's header and
//! size ([`probe`]), bytes per link measured on a sample built the same way ([`PerLink`]), and
//! the memory there is ([`available`]). The command line refuses, before allocating, a scene
//! that would not fit ([`check`]), naming the figures and the options that help.
//!
//! # The model
//! Peak bytes ≈ `links × (scene + tracer + build) + BASE_BYTES`, with `scene` and `tracer`
//! the bytes per link of [`crate::scene::Scene::memory_bytes`] and
//! [`crate::accel::Tracer::memory_bytes`] measured on a sample of the file (so they follow
//! any change of the layouts), and `build` what the tracer's build holds on top of both at
//! its peak (the primitives before reordering, their boxes, the builder's own tree):
//! `max(BUILD_OVERHEAD × tracer, BUILD_BYTES_PER_LINK)`, both measured (see the constants).
//! The builder's buffers are per tree item, not a share of the finished tree: the compact
//! tree (33 B per link) is built through the same ≈ 250 B per link as a tree of whole
//! primitives (92 B per link).

use crate::io::stream::{open, Selection};
use crate::io::{self, IoError};
use std::fmt;
use std::io::BufRead;
use std::path::Path;

/// Extra bytes a tracer's build holds at its peak, as a share of the finished tracer's
/// [`crate::accel::Tracer::memory_bytes`] (the primitives before reordering, their boxes,
/// obvhs's binary tree before it is collapsed to 8 wide). Measured with
/// `TUBECAST_PEAK_RSS=1 tubecast info FILE` on `generate bundle` scenes (peak resident set
/// after the build, `VmHWM`): 10⁶ links (`--count 11905 --segments 84`, release build):
/// 389 MB peak, 48.4 B scene + 92 B tree per link → 2.5; 5·10⁵ links (`--count 5000
/// --segments 100`, test profile): 247 MB → 3.45. The larger, rounded up.
pub const BUILD_OVERHEAD: f64 = 3.5;

/// Least bytes per link a build holds at its peak on top of the finished scene and tracer
/// (obvhs's PLOC buffers and binary tree, one box per tree item). Measured with
/// `TUBECAST_PEAK_RSS=1 tubecast info --radius 0.12 FILE` on `generate bundle --count N
/// --segments 84` scenes (release build, `VmHWM` after the build, the compact tree), as
/// `(peak − BASE_BYTES)/links − scene − tracer`: 10⁵ links 48.2 MB → 244 B, 10⁶ 342 MB →
/// 252 B, 10⁷ 3.36 GB → 261 B (main at f8636be: 48.5 B scene, 32.8–34.5 B tracer). Rounded
/// up to 280.
pub const BUILD_BYTES_PER_LINK: f64 = 280.0;

/// Bytes a process needs whatever the scene (code, thread stacks, buffers).
pub const BASE_BYTES: u64 = 16 << 20;

/// What a file holds, from its header and size, without reading its body.
///
/// ```
/// use tubecast_render::estimate::{check, Counts, PerLink};
/// use tubecast_render::io::stream::Selection;
/// let c = Counts { streamlines: Some(10), points: 1010 };
/// assert_eq!(c.links(&Selection::default(), None), 1000);
/// let per_link = PerLink { scene: 48.0, tracer: 90.0 };
/// let e = check("big.trk", (100_000_000, Some(10)), per_link, (8 << 30, "MemAvailable".into())).unwrap_err();
/// assert!(e.to_string().contains("--subsample"));
/// assert!(e.needed > 8 << 30);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Counts {
    /// Streamlines, when the header says (`None`: SWC, OBJ, a `.trk` with `n_count` 0, a
    /// `.tck` whose `count` does not fit its size).
    pub streamlines: Option<u64>,
    /// Points (nodes): exact for `.trk` with `n_count` and `.trx`, an upper bound otherwise.
    pub points: u64,
}

impl Counts {
    /// Links of the streamlines `sel` keeps: `(points − streamlines) × share` (an SWC tree or
    /// unknown streamlines: `points × share`), with `avg_points` (points per streamline of a
    /// sample) standing in for an unknown streamline count.
    pub fn links(&self, sel: &Selection, avg_points: Option<f64>) -> u64 {
        let lines = self.lines(avg_points);
        let share = sel.fraction(lines.unwrap_or(0));
        (self.points.saturating_sub(lines.unwrap_or(0)) as f64 * share).ceil() as u64
    }

    /// Streamlines: the header's count, or points / `avg_points` (a sample's points per
    /// streamline); `None` when neither is known.
    pub fn lines(&self, avg_points: Option<f64>) -> Option<u64> {
        let guess = || avg_points.filter(|&a| a >= 1.0).map(|a| (self.points as f64 / a) as u64);
        self.streamlines.or_else(guess)
    }

    /// Streamlines `sel` keeps ([`Self::lines`] × its share), when known.
    pub fn kept_lines(&self, sel: &Selection, avg_points: Option<f64>) -> Option<u64> {
        self.lines(avg_points).map(|n| (n as f64 * sel.fraction(n)).round() as u64)
    }
}

/// The counts of the file at `path` (by extension), from its header and length; SWC and OBJ
/// files are read line by line (nothing kept) to count their nodes / vertices.
pub fn probe(path: &Path) -> Result<Counts, IoError> {
    let name = path.display().to_string();
    let (mut r, len) = open(path)?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    Ok(match ext.as_str() {
        "trk" => {
            let info = io::trk::read_info(&mut r, &name)?;
            let per_point = 4 * (3 + info.header.n_scalars as u64);
            let n = info.n_count as u64;
            let fixed = 1000 + n * info.streamline_bytes(0);
            Counts { streamlines: (n > 0).then_some(n), points: len.saturating_sub(fixed) / per_point }
        }
        "tck" => {
            let info = io::tck::read_info(&mut r, &name, Some(len))?;
            let triplets = len.saturating_sub(info.offset) / 12;
            // Each streamline: its points and a NaN triplet; then one Inf triplet.
            match info.count.filter(|&c| c > 0 && 2 * c < triplets) {
                Some(c) => Counts { streamlines: Some(c), points: triplets - c - 1 },
                None => Counts { streamlines: None, points: triplets },
            }
        }
        "trx" => {
            let (ns, nv) = io::trx::read_counts(r, &name)?;
            Counts { streamlines: Some(ns as u64), points: nv as u64 }
        }
        _ => {
            let tag: &[u8] = if ext == "obj" { b"v " } else { b"" };
            Counts { streamlines: None, points: count_lines(r, &name, tag)? }
        }
    })
}

/// Lines of `r` that are not blank or comments (`#`) and start with `tag`.
fn count_lines(mut r: impl BufRead, name: &str, tag: &[u8]) -> Result<u64, IoError> {
    let (mut n, mut buf) = (0, Vec::new());
    loop {
        buf.clear();
        let got = r.read_until(b'\n', &mut buf).map_err(|e| IoError::file(name, format!("cannot read: {e}")))?;
        if got == 0 {
            return Ok(n);
        }
        let t = buf.trim_ascii_start();
        n += (!t.is_empty() && t[0] != b'#' && t.starts_with(tag)) as u64;
    }
}

/// Bytes per link measured on a sample: of the scene, and of the tracer over its primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerLink {
    /// [`crate::scene::Scene::memory_bytes`] per link.
    pub scene: f64,
    /// [`crate::accel::Tracer::memory_bytes`] per link.
    pub tracer: f64,
}

impl PerLink {
    /// Peak bytes per link of loading and building ([module docs](self)).
    pub fn peak(&self) -> f64 {
        self.scene + self.tracer + self.build()
    }

    /// Bytes per link the build holds on top of the scene and the tracer at its peak
    /// ([module docs](self)).
    pub fn build(&self) -> f64 {
        (self.tracer * BUILD_OVERHEAD).max(BUILD_BYTES_PER_LINK)
    }
}

/// A scene too large for the memory there is.
#[derive(Clone, Debug, PartialEq)]
pub struct TooLarge {
    /// The input file.
    pub file: String,
    /// Links the load would keep.
    pub links: u64,
    /// Streamlines it would keep, when known.
    pub streamlines: Option<u64>,
    /// Bytes per link (scene, tracer).
    pub per_link: PerLink,
    /// Estimated peak bytes.
    pub needed: u64,
    /// The bytes there are, and where that figure comes from.
    pub available: (u64, String),
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        // The share of the links that fits, with a tenth to spare (at least 0.001).
        let room = self.available.0.saturating_sub(BASE_BYTES) as f64;
        let share = (room / self.needed.saturating_sub(BASE_BYTES).max(1) as f64 * 0.9).clamp(0.001, 1.0);
        let share = (share * 1000.0).floor() / 1000.0;
        let n = match self.streamlines {
            Some(s) => format!("N ≤ {}", (s as f64 * share) as u64),
            None => "N".to_string(),
        };
        write!(
            f,
            "{}: the scene needs about {:.2} GiB ({} links × {:.0} B: scene {:.1} B + primitives and tree \
             {:.1} B, built with {:.0} B more at the peak), more than the {:.2} GiB available ({}); \
             load a part of it with --subsample F (F ≤ {share}) or --max-streamlines {n}, \
             or set --memory-limit BYTES",
            self.file,
            gib(self.needed),
            self.links,
            self.per_link.peak(),
            self.per_link.scene,
            self.per_link.tracer,
            self.per_link.build(),
            gib(self.available.0),
            self.available.1,
        )
    }
}

impl std::error::Error for TooLarge {}

/// Refuse `(links, streamlines)` (the streamlines kept, when known) at `per_link` when the
/// estimated peak exceeds `available`; the estimate in bytes otherwise.
pub fn check(
    file: &str,
    (links, streamlines): (u64, Option<u64>),
    per_link: PerLink,
    available: (u64, String),
) -> Result<u64, TooLarge> {
    let needed = (links as f64 * per_link.peak()) as u64 + BASE_BYTES;
    if needed > available.0 {
        return Err(TooLarge { file: file.to_string(), links, streamlines, per_link, needed, available });
    }
    Ok(needed)
}

/// The memory this process may still use: `MemAvailable` of `/proc/meminfo`, lowered to the
/// cgroup's `memory.max − memory.current` where a (v2) limit is set; `None` where neither is
/// readable (not Linux).
pub fn available() -> Option<(u64, String)> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let meminfo = read("/proc/meminfo")?;
    let kib = meminfo.lines().find_map(|l| l.strip_prefix("MemAvailable:"))?;
    let mut best = (kib.trim().trim_end_matches("kB").trim().parse::<u64>().ok()? * 1024, "MemAvailable".to_string());
    let num = |p: &str| read(p).and_then(|s| s.trim().parse::<u64>().ok());
    if let (Some(max), Some(cur)) = (num("/sys/fs/cgroup/memory.max"), num("/sys/fs/cgroup/memory.current")) {
        if max.saturating_sub(cur) < best.0 {
            best = (max.saturating_sub(cur), "cgroup memory.max − memory.current".to_string());
        }
    }
    Some(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_covers_a_measured_compact_tree_build() {
        // `generate bundle --count 119048 --segments 84`, `TUBECAST_PEAK_RSS=1 tubecast info
        // --radius 0.12` (release, main at f8636be): 10⁷ links (1.0000032·10⁷), 48.5 B scene +
        // 32.8 B tracer per link, peak 3 356 436 kB. The old model, scene + 4.5 × tracer =
        // 196 B per link, said 1.98 GB: 41 % under what the build took. The estimate must not
        // be under it (a refusal is better than running out of memory), nor more than a quarter
        // over it (a needless refusal).
        let links = 10_000_032u64;
        let measured = 3_356_436.0 * 1024.0;
        let p = PerLink { scene: 48.5, tracer: 32.8 };
        let est = links as f64 * p.peak() + BASE_BYTES as f64;
        assert!(est >= measured && est <= 1.25 * measured, "{est:e} against {measured:e}");
        // A tree of whole primitives (the old Bvh, 92 B per link) still scales with its size.
        assert_eq!(PerLink { scene: 48.5, tracer: 92.0 }.build(), 92.0 * BUILD_OVERHEAD);
    }
}
