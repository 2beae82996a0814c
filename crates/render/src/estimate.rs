//! The memory a scene will need, known before it is loaded: counts from the file's header and
//! size ([`probe`]), bytes per link measured on a sample built the same way ([`PerLink`]), and
//! the memory there is ([`available`]). The command line refuses, before allocating, a scene
//! that would not fit ([`check`]), naming the figures and the options that help.
//!
//! # The model
//! Peak bytes ≈ `links × (scene + tracer × (1 + BUILD_OVERHEAD)) + min(links, BUILD_ITEMS) ×
//! BUILD_BYTES_PER_ITEM + BASE_BYTES`, with `scene` and `tracer` the bytes per link of
//! [`crate::scene::Scene::memory_bytes`] and [`crate::accel::Tracer::memory_bytes`] measured on
//! a sample of the file (so they follow any change of the layouts), [`BUILD_OVERHEAD`] the
//! share of the tracer's size its build holds on top of it (tables in item order, the clusters
//! before reordering), and [`BUILD_BYTES_PER_ITEM`] the tree builder's buffers for each item it
//! builds at once: at most [`BUILD_ITEMS`], as the compact tree is built in chunks.

use crate::io::stream::{open, Selection};
use crate::io::{self, IoError};
use std::fmt;
use std::io::BufRead;
use std::path::Path;

/// Extra bytes a tracer's build holds at its peak, as a share of the finished tracer's
/// [`crate::accel::Tracer::memory_bytes`] (its item table, Morton keys and leaf order, the
/// clusters before they are reordered), besides the builder's buffers
/// ([`BUILD_BYTES_PER_ITEM`]). Fitted with it to the peaks of `TUBECAST_PEAK_RSS=1 tubecast
/// info FILE --radius 0.12` on `generate bundle --segments 84` scenes (plain release build,
/// `VmHWM`; 48.5 B scene and 33 B tree per link): 341.5 MB at 10⁶ links and 1534 MB at 10⁷
/// give 0.75 and 218 B; both rounded up (the model is 26 % and 16 % above those peaks).
pub const BUILD_OVERHEAD: f64 = 1.0;

/// Bytes the tree builder holds per item it builds at once (obvhs's PLOC arrays, its binary
/// tree, the 8-wide conversion's cost table, the items' boxes): fitted as 218 B (see
/// [`BUILD_OVERHEAD`]), rounded up.
pub const BUILD_BYTES_PER_ITEM: f64 = 300.0;

/// Items the compact tree's builder holds at once at most: [`crate::accel::CHUNKS_AT_ONCE`]
/// chunks of [`crate::accel::CHUNK`] (one item per link).
pub const BUILD_ITEMS: u64 = (crate::accel::CHUNK * crate::accel::CHUNKS_AT_ONCE) as u64;

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
    /// Peak bytes per link of loading and building, the builder's buffers aside ([module
    /// docs](self)).
    pub fn peak(&self) -> f64 {
        self.scene + self.tracer * (1.0 + BUILD_OVERHEAD)
    }

    /// Peak bytes of loading and building `links` links, the base aside ([module docs](self)).
    pub fn needed(&self, links: u64) -> f64 {
        links as f64 * self.peak() + links.min(BUILD_ITEMS) as f64 * BUILD_BYTES_PER_ITEM
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
             {:.1} B, built with {:.0}% more and {:.0} B per link built at once), more than the {:.2} GiB available ({}); \
             load a part of it with --subsample F (F ≤ {share}) or --max-streamlines {n}, \
             or set --memory-limit BYTES",
            self.file,
            gib(self.needed),
            self.links,
            self.per_link.peak(),
            self.per_link.scene,
            self.per_link.tracer,
            100.0 * BUILD_OVERHEAD,
            BUILD_BYTES_PER_ITEM,
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
    let needed = per_link.needed(links) as u64 + BASE_BYTES;
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
    fn the_estimate_covers_measured_chunked_builds() {
        // `generate bundle --segments 84` scenes, `TUBECAST_PEAK_RSS=1 tubecast info --radius
        // 0.12` (release build, chunked compact tree, 48.5 B scene + 33.2/32.8/32.9 B tracer
        // per link, peak `VmHWM` in kB): 10⁶ links 341 500 kB, 10⁷ links 1 534 000 kB, 10⁸
        // links (two 5·10⁷ bundles joined) 10 520 000 kB. main's model before the chunked
        // build, scene + 4.5 × tracer, said 198 B per link at 10⁶: 42 % under the measured
        // peak. The estimate must not be under a measured peak (a refusal is better than
        // running out of memory), nor more than 30 % over it (a needless refusal); the
        // builder's term is what keeps small scenes above their peak.
        for (links, tracer, kb) in
            [(1_000_020u64, 33.2, 341_500.0), (10_000_032, 32.8, 1_534_000.0), (99_999_984, 32.9, 10_520_000.0)]
        {
            let measured = kb * 1024.0;
            let est = PerLink { scene: 48.5, tracer }.needed(links) + BASE_BYTES as f64;
            assert!(est >= measured && est <= 1.3 * measured, "{links}: {est:e} against {measured:e}");
        }
    }
}
