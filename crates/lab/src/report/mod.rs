//! Accuracy, speed and stability reports (SVG charts + markdown).
//!
//! Each `run_*` function writes its charts and one markdown file into a folder, from seeded
//! case sets, and returns the paths. Every number in the markdown is computed by the run:
//!
//! * [`run_accuracy`] — error of `t` (max, p99; in radii and in ulps) against an independent
//!   `f64` oracle ([`oracle`]) versus nanoseconds per ray–primitive test, for every link kernel
//!   (stable, faithful precomputed/on-the-fly, link-as-spline) and every spline solver setting,
//!   in `f32`, `f64`, `f32x8` and `f64x4`, on the same ray sets;
//! * [`run_stability`] — false-miss and false-hit rates and error percentiles per failure region
//!   (grazing, near-equal radii, sphere inside sphere, long thin links, far origins, radius above
//!   curvature radius, cusps, rays starting inside, …);
//! * [`run_speed`] — BVH build and frame time and rays/s versus segment count (opaque and
//!   transparent/CSG) on generated scenes;
//! * [`run_thin`] — the spline kernel's length/radius sweep (`L/r = 10 … 10⁵`): max error in
//!   radii and false-hit / false-miss rates per solver and precision, with the kernel's band;
//! * [`run_mesh`] — the certified mesh path against the exact kernels (build, memory, frame,
//!   image difference) versus segment count;
//! * [`run_mesh_real`] — the same trade-off on real-world-like scenes (nibabel's `standard.trk`,
//!   a fibre bundle, the README's neuron assembly), frame time and memory against certified error;
//! * [`run_mesh_size`] — on the same scenes, triangles and bytes against certified error for the
//!   exact links, the simplified link model, the per-chain shells and the union mesh;
//! * [`run_spline_lanes`] — what a spline costs: the spline kernel against the link per call, in
//!   scalar and lanes, on the spline bench's rays, and the floor of any per-call lane kernel;
//! * `run_peers` (feature `embree`) — Embree 3's round linear curves on the same `f32` rays;
//! * `run_gpu` (features `gpu` and `embree`) — the GPU walk against the CPU path and Embree on
//!   the same rays, with the upload's bytes and time per link.
//!
//! The accuracy numbers (not the timings) are a pure function of [`ReportOptions`].

pub mod chart;
pub mod eval;
#[cfg(all(feature = "gpu", feature = "embree"))]
mod gpu;
mod mesh;
mod mesh_real;
mod mesh_size;
pub mod oracle;
#[cfg(feature = "embree")]
mod peers;
#[cfg(feature = "embree")]
mod peers_speed;
mod runs;
mod speed;
mod spline_lanes;
mod thin;
mod thin_render;
mod voxel;
mod voxel_ao;
mod voxel_clock;
mod voxel_lambda;
mod voxel_levels;
mod voxel_quantized;
mod voxel_timing;

#[cfg(all(feature = "gpu", feature = "embree"))]
pub use gpu::run_gpu;
pub use mesh::run_mesh;
pub use mesh_real::run_mesh_real;
pub use mesh_size::{measure_sizes, ply_bytes, run_mesh_size, size_table, union_estimate, SizeRow, KINDS, SIZE_EPS};
#[cfg(feature = "embree")]
pub use peers::run_peers;
pub use runs::{run_accuracy, run_stability};
pub use speed::run_speed;
pub use spline_lanes::{floor as spline_lane_floor, run_spline_lanes};
pub use thin::run_thin;
pub use voxel::run_voxel;
pub use voxel_ao::run_voxel_ao;
pub use voxel_quantized::run_voxel_quantized;
pub use voxel_timing::run_voxel_timing;

use std::path::{Path, PathBuf};

/// Settings of a report run.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportOptions {
    /// Seed of every case generator.
    pub seed: u64,
    /// Link cases per region (accuracy uses the `random` region; stability every region).
    pub link_cases: usize,
    /// Spline cases per region.
    pub spline_cases: usize,
    /// Timing budget per method, milliseconds (each method also runs at least 3 times; the
    /// best repetition is reported). Zero: no timing (ns columns are NaN).
    pub time_ms: u64,
    /// Speed report: largest scene in segments (10³, 10⁴, … up to this).
    pub max_segments: usize,
    /// Speed report: image width and height in pixels.
    pub image: u32,
    /// Speed report: worker threads (1 makes frame times comparable across machines).
    pub threads: usize,
    /// Show progress bars on stderr.
    pub progress: bool,
}

impl Default for ReportOptions {
    /// The settings of the committed `docs/report/`.
    fn default() -> Self {
        Self {
            seed: 1,
            link_cases: 2000,
            spline_cases: 400,
            time_ms: 150,
            max_segments: 100_000,
            image: 256,
            threads: 1,
            progress: true,
        }
    }
}

impl ReportOptions {
    /// A tiny run for tests and smoke checks (a few seconds).
    pub fn quick() -> Self {
        Self {
            seed: 7,
            link_cases: 120,
            spline_cases: 30,
            time_ms: 0,
            max_segments: 1000,
            image: 24,
            threads: 1,
            progress: false,
        }
    }

    /// Check the settings. Errors name the bad field.
    pub fn validate(&self) -> Result<(), ReportError> {
        let bad = |m: &str| Err(ReportError::Options(m.to_string()));
        if self.link_cases == 0 || self.link_cases > 10_000_000 {
            return bad("link_cases must be in 1..=10^7");
        }
        if self.spline_cases == 0 || self.spline_cases > 1_000_000 {
            return bad("spline_cases must be in 1..=10^6");
        }
        if self.time_ms > 600_000 {
            return bad("time_ms must be at most 600000");
        }
        if self.max_segments < 1000 || self.max_segments > 10_000_000 {
            return bad("max_segments must be in 1000..=10^7");
        }
        if self.image == 0 || self.image > 8192 {
            return bad("image must be in 1..=8192");
        }
        if self.threads == 0 || self.threads > 1024 {
            return bad("threads must be in 1..=1024");
        }
        Ok(())
    }
}

/// Why a report could not be written.
#[derive(Debug, Clone, PartialEq)]
pub enum ReportError {
    /// Bad [`ReportOptions`].
    Options(String),
    /// A file or folder could not be written.
    Io(String),
    /// A chart could not be drawn.
    Chart(String),
    /// A generated scene or the renderer failed.
    Render(String),
    /// The peer library failed.
    Peer(String),
}

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Options(s) => write!(f, "bad report options: {s}"),
            Self::Io(s) => write!(f, "cannot write report: {s}"),
            Self::Chart(s) => write!(f, "cannot draw chart: {s}"),
            Self::Render(s) => write!(f, "speed report: {s}"),
            Self::Peer(s) => write!(f, "peer: {s}"),
        }
    }
}

impl std::error::Error for ReportError {}

/// The files a report wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportFiles {
    /// The markdown summary.
    pub markdown: PathBuf,
    /// The SVG charts.
    pub charts: Vec<PathBuf>,
}

pub(crate) fn ensure_dir(out: &Path) -> Result<(), ReportError> {
    std::fs::create_dir_all(out).map_err(|e| ReportError::Io(format!("{}: {e}", out.display())))
}

pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), ReportError> {
    std::fs::write(path, text).map_err(|e| ReportError::Io(format!("{}: {e}", path.display())))?;
    if path.extension().is_some_and(|e| e == "md") {
        let json = serde_json::to_string_pretty(&tables_json(text)).expect("tables print as JSON");
        let jp = path.with_extension("tables.json");
        std::fs::write(&jp, json + "\n").map_err(|e| ReportError::Io(format!("{}: {e}", jp.display())))?;
    }
    Ok(())
}

/// Write `<name>.tables.json` beside every `<name>.md` in `dir` from its tables
/// ([`tables_json`]), measuring nothing: for reports committed before the JSON was written.
/// Returns the JSON files written.
pub fn write_tables_json(dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    let io = |p: &Path, e: std::io::Error| ReportError::Io(format!("{}: {e}", p.display()));
    let mut out = Vec::new();
    let mut mds: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "md") && !p.ends_with("README.md"))
        .collect();
    mds.sort();
    for p in mds {
        let md = std::fs::read_to_string(&p).map_err(|e| io(&p, e))?;
        if tables_json(&md).as_array().is_some_and(|a| a.is_empty()) {
            continue;
        }
        write_text(&p, &md)?;
        out.push(p.with_extension("tables.json"));
    }
    Ok(out)
}

/// Every markdown table of `markdown`, for machines: a JSON array of
/// `{"columns": [...], "rows": [[...], ...]}` in document order, cells as strings exactly as in
/// the table (numbers in the report's own formatting; `-` for no value). Written beside each
/// report as `<name>.tables.json`.
pub fn tables_json(markdown: &str) -> serde_json::Value {
    let cells = |l: &str| l.trim().trim_matches('|').split('|').map(|c| c.trim().to_string()).collect::<Vec<_>>();
    let lines: Vec<&str> = markdown.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i + 1 < lines.len() {
        let sep = lines[i + 1].trim();
        if lines[i].trim_start().starts_with('|') && sep.starts_with('|') && sep.contains("---") {
            let columns = cells(lines[i]);
            let mut rows = Vec::new();
            i += 2;
            while i < lines.len() && lines[i].trim_start().starts_with('|') {
                rows.push(cells(lines[i]));
                i += 1;
            }
            out.push(serde_json::json!({"columns": columns, "rows": rows}));
        } else {
            i += 1;
        }
    }
    serde_json::Value::Array(out)
}

pub(crate) fn progress(opts: &ReportOptions, len: u64, what: &str) -> indicatif::ProgressBar {
    if !opts.progress {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(st) = indicatif::ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} {elapsed}") {
        bar.set_style(st.progress_chars("=> "));
    }
    bar.set_message(what.to_string());
    bar
}

/// Format a number for the markdown tables (`-` for NaN, scientific otherwise).
pub fn fmt_num(x: f64) -> String {
    if x.is_nan() {
        "-".into()
    } else if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.3e}")
    }
}

/// Parse a number written by [`fmt_num`] (`-` is NaN).
pub fn parse_num(s: &str) -> Option<f64> {
    let s = s.trim();
    if s == "-" {
        Some(f64::NAN)
    } else {
        s.parse().ok()
    }
}

/// The rows of every markdown table whose header row starts with `| <first_header> |`, as
/// cells. Used by tests and tools to read numbers back from a report.
pub fn table_rows(markdown: &str, first_header: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let mut lines = markdown.lines().peekable();
    let cells = |l: &str| l.trim().trim_matches('|').split('|').map(|c| c.trim().to_string()).collect::<Vec<_>>();
    while let Some(l) = lines.next() {
        if l.starts_with('|') && cells(l).first().map(String::as_str) == Some(first_header) {
            lines.next(); // separator
            while let Some(r) = lines.peek() {
                if !r.starts_with('|') {
                    break;
                }
                rows.push(cells(r));
                lines.next();
            }
        }
    }
    rows
}

/// A short description of the machine for the report headers.
pub(crate) fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let simd = if cfg!(target_feature = "avx2") {
        "AVX2 enabled at compile time"
    } else {
        "no AVX2 at compile time (wide lanes use SSE halves)"
    };
    format!("{cpu}; {simd}; {} logical CPUs", std::thread::available_parallelism().map_or(1, |n| n.get()))
}
