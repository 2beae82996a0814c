//! Streaming input: the readers of `.trk`, `.tck` (and `.tsf`), `.trx` and `.swc` read from any
//! [`Read`] a piece at a time and hand each streamline over as it is read ([`Line`]), in a
//! buffer they reuse, so reading a file costs what its consumer keeps (plus a buffer of
//! one streamline) rather than a copy of the whole file. [`Selection`] says which streamlines
//! a consumer keeps (`--max-streamlines`, `--subsample`).

use super::IoError;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use std::io::{BufRead, Read};

/// One streamline as a streaming reader hands it over (valid until the next one is read).
///
/// ```
/// use tubecast_render::io::stream::{Flow, Line};
/// let pts = [[0.0; 3], [1.0, 0.0, 0.0]];
/// let l = Line { index: 0, points: &pts, scalars: &[], properties: &[] };
/// let mut stop_after_first = |l: Line<'_>| if l.index == 0 { Flow::Stop } else { Flow::Continue };
/// assert_eq!(stop_after_first(l), Flow::Stop);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Line<'a> {
    /// 0-based index of the streamline in the file.
    pub index: usize,
    /// Its points, in the file's world space (RAS+ mm for TrackVis, MRtrix and TRX).
    pub points: &'a [[f64; 3]],
    /// Per-point data (`points.len() × width` values, point after point), or empty.
    pub scalars: &'a [f64],
    /// Per-streamline data, or empty.
    pub properties: &'a [f64],
}

/// What a consumer of [`Line`]s answers: read on, or stop (the rest of the file is not read).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Read the next streamline.
    Continue,
    /// Stop reading.
    Stop,
}

/// Which streamlines of a file to keep: `--subsample F` then `--max-streamlines N`.
///
/// `subsample: Some(F)` (`0 < F ≤ 1`) keeps streamline `i` (0-based, file order) when
/// SplitMix64 seeded with `i` draws a value below `F·2⁶⁴`: a deterministic pseudo-random
/// choice of about `F` of the streamlines, the same on every run and machine, that does not
/// alias a periodic order of the file (interleaved bundles) as a stride would.
/// `max_streamlines: Some(N)` then keeps the first `N` of those and stops reading.
///
/// ```
/// use tubecast_render::io::stream::Selection;
/// let half = Selection { max_streamlines: None, subsample: Some(0.5) };
/// let kept = (0..10_000).filter(|&i| half.keeps(i)).count();
/// assert!((4_800..5_200).contains(&kept));
/// assert!(Selection::default().keeps(7));
/// assert!(Selection { max_streamlines: Some(0), subsample: None }.check().is_ok());
/// assert!(Selection { max_streamlines: None, subsample: Some(0.0) }.check().is_err());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Selection {
    /// Keep at most this many streamlines (the first ones the subsample keeps).
    pub max_streamlines: Option<usize>,
    /// Keep about this fraction of the streamlines, `0 < F ≤ 1`.
    pub subsample: Option<f64>,
}

impl Selection {
    /// True when nothing is dropped.
    pub fn is_all(&self) -> bool {
        self.max_streamlines.is_none() && !matches!(self.subsample, Some(f) if f < 1.0)
    }

    /// An error in words when `subsample` is not in `(0, 1]`.
    pub fn check(&self) -> Result<(), String> {
        match self.subsample {
            Some(f) if !(f > 0.0 && f <= 1.0) => Err(format!("--subsample {f} must be in (0, 1]")),
            _ => Ok(()),
        }
    }

    /// Whether the subsample keeps streamline `i` (the first `max_streamlines` of those kept
    /// are taken by the consumer, which counts them).
    pub fn keeps(&self, i: u64) -> bool {
        match self.subsample {
            None => true,
            Some(f) if f >= 1.0 => true,
            Some(f) => {
                let draw = rand_xoshiro::SplitMix64::seed_from_u64(i).next_u64();
                (draw as f64) < f * 18_446_744_073_709_551_616.0
            }
        }
    }

    /// The fraction of streamlines expected to be kept out of `total` (for estimates).
    pub fn fraction(&self, total: u64) -> f64 {
        let f = self.subsample.unwrap_or(1.0).min(1.0);
        match self.max_streamlines {
            Some(n) if total > 0 => f.min(n as f64 / total as f64),
            _ => f,
        }
    }
}

/// A byte source with its offset, for binary readers: reads exactly what is asked, and a short
/// read is an error naming the offset, what was being read and how many bytes were left.
pub(crate) struct Src<'n, R> {
    r: R,
    /// Offset of the next byte.
    pub pos: u64,
    pub name: &'n str,
    pub big: bool,
}

impl<'n, R: Read> Src<'n, R> {
    pub fn new(r: R, name: &'n str) -> Self {
        Self { r, pos: 0, name, big: false }
    }

    /// Read up to `buf.len()` bytes, fewer only at the end of the input; the count.
    pub fn fill(&mut self, buf: &mut [u8]) -> Result<usize, IoError> {
        let mut got = 0;
        while got < buf.len() {
            match self.r.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(IoError::offset(self.name, self.pos + got as u64, format!("cannot read: {e}"))),
            }
        }
        self.pos += got as u64;
        Ok(got)
    }

    /// Read up to `n` bytes into `out` (cleared first), growing it only as data arrive (a
    /// count from a corrupt header allocates nothing it cannot fill); the count read.
    pub fn chunk(&mut self, n: u64, out: &mut Vec<u8>) -> Result<usize, IoError> {
        out.clear();
        let at = self.pos;
        let got = (&mut self.r)
            .take(n)
            .read_to_end(out)
            .map_err(|e| IoError::offset(self.name, at, format!("cannot read: {e}")))?;
        self.pos += got as u64;
        Ok(got)
    }

    /// Skip and count every byte left.
    pub fn rest(&mut self) -> Result<u64, IoError> {
        let n = std::io::copy(&mut self.r, &mut std::io::sink())
            .map_err(|e| IoError::offset(self.name, self.pos, format!("cannot read: {e}")))?;
        self.pos += n;
        Ok(n)
    }

    /// The 4 bytes at the start of `b` as a `u32` in the source's byte order.
    fn u32_at(&self, b: &[u8]) -> u32 {
        let a = [b[0], b[1], b[2], b[3]];
        if self.big {
            u32::from_be_bytes(a)
        } else {
            u32::from_le_bytes(a)
        }
    }
    /// ... as an `f32`.
    pub fn f32_at(&self, b: &[u8]) -> f32 {
        f32::from_bits(self.u32_at(b))
    }
    /// ... as an `i32`.
    pub fn i32_at(&self, b: &[u8]) -> i32 {
        self.u32_at(b) as i32
    }
}

/// Longest text line a reader accepts (a binary file read as text ends here, not in memory).
pub(crate) const MAX_LINE: u64 = 1 << 24;

impl<R: BufRead> Src<'_, R> {
    /// Read line `line_no` into `out` (with its `\n`, if any); its length, 0 at the end.
    pub fn line(&mut self, out: &mut Vec<u8>, line_no: usize) -> Result<usize, IoError> {
        out.clear();
        let at = self.pos;
        let n = (&mut self.r)
            .take(MAX_LINE)
            .read_until(b'\n', out)
            .map_err(|e| IoError::offset(self.name, at, format!("cannot read: {e}")))?;
        self.pos += n as u64;
        if n as u64 == MAX_LINE && out.last() != Some(&b'\n') {
            return Err(IoError::line(self.name, line_no, format!("line longer than {MAX_LINE} bytes")));
        }
        Ok(n)
    }
}

/// Open `path` for streaming: a buffered reader and the file's length.
pub fn open(path: &std::path::Path) -> Result<(std::io::BufReader<std::fs::File>, u64), IoError> {
    let name = path.display().to_string();
    let f = std::fs::File::open(path).map_err(|e| IoError::file(&name, format!("cannot read: {e}")))?;
    let len = f.metadata().map_err(|e| IoError::file(&name, format!("cannot read: {e}")))?.len();
    Ok((std::io::BufReader::with_capacity(1 << 16, f), len))
}
