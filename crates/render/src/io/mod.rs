//! File readers and writers: SWC, TrackVis .trk, MRtrix .tck, OBJ polylines, .npy.
//!
//! Every reader takes the file's bytes plus a name used in error messages, and returns either
//! the data or an [`IoError`] that names the file, the line or byte offset, and the problem.
//! The readers of `.trk`, `.tck`/`.tsf`, `.trx` and `.swc` also stream from any reader
//! ([`stream`]), which is how scenes are loaded: a file is never copied into memory whole.
//! Readers never panic and never return NaN or infinite coordinates. Each format has a writer
//! too, so the tests can round-trip.

pub mod data;
pub mod npy;
pub mod obj;
mod orient;
pub mod stream;
pub mod swc;
pub mod tck;
pub mod trk;
pub mod trx;

use std::fmt;
use std::path::Path;

/// Where in a file an error was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// The whole file (e.g. it is empty).
    File,
    /// A 1-based line number (text formats).
    Line(usize),
    /// A 0-based byte offset (binary formats).
    Offset(u64),
}

/// A malformed, truncated or empty file, or a file that could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IoError {
    /// The file name as given by the caller.
    pub file: String,
    /// Where the problem is.
    pub at: Location,
    /// What is wrong, in words.
    pub problem: String,
}

impl IoError {
    /// An error at `at` in `file`.
    pub fn new(file: &str, at: Location, problem: impl Into<String>) -> Self {
        Self { file: file.to_string(), at, problem: problem.into() }
    }
    /// An error on 1-based line `line`.
    pub fn line(file: &str, line: usize, problem: impl Into<String>) -> Self {
        Self::new(file, Location::Line(line), problem)
    }
    /// An error at byte offset `off`.
    pub fn offset(file: &str, off: u64, problem: impl Into<String>) -> Self {
        Self::new(file, Location::Offset(off), problem)
    }
    /// An error about the whole file.
    pub fn file(file: &str, problem: impl Into<String>) -> Self {
        Self::new(file, Location::File, problem)
    }
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            Location::File => write!(f, "{}: {}", self.file, self.problem),
            Location::Line(n) => write!(f, "{}: line {}: {}", self.file, n, self.problem),
            Location::Offset(o) => write!(f, "{}: byte offset {}: {}", self.file, o, self.problem),
        }
    }
}

impl std::error::Error for IoError {}

/// Read a whole file, mapping OS errors to [`IoError`].
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, IoError> {
    std::fs::read(path).map_err(|e| IoError::file(&path.display().to_string(), format!("cannot read: {e}")))
}

/// Write a whole file, mapping OS errors to [`IoError`].
pub fn write_bytes(path: &Path, data: &[u8]) -> Result<(), IoError> {
    std::fs::write(path, data).map_err(|e| IoError::file(&path.display().to_string(), format!("cannot write: {e}")))
}

/// A streamline / polyline: points in order, with an optional radius per point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polyline {
    /// Points (finite).
    pub points: Vec<[f64; 3]>,
    /// One radius per point, or empty when the format carries none.
    pub radii: Vec<f64>,
}

/// Parse a finite `f64` from a text token.
pub(crate) fn parse_finite(tok: &str) -> Option<f64> {
    tok.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// A little-endian or big-endian byte cursor with offsets for error messages.
pub(crate) struct Cursor<'a> {
    pub data: &'a [u8],
    pub pos: usize,
    pub big: bool,
    pub name: &'a str,
}

impl<'a> Cursor<'a> {
    pub fn new(data: &'a [u8], name: &'a str, big: bool) -> Self {
        Self { data, pos: 0, big, name }
    }
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], IoError> {
        if self.remaining() < n {
            return Err(IoError::offset(
                self.name,
                self.pos as u64,
                format!("truncated: need {n} bytes for {what}, {} left", self.remaining()),
            ));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    pub fn u32_bytes(&mut self, what: &str) -> Result<[u8; 4], IoError> {
        let s = self.take(4, what)?;
        Ok([s[0], s[1], s[2], s[3]])
    }
    pub fn i32(&mut self, what: &str) -> Result<i32, IoError> {
        let b = self.u32_bytes(what)?;
        Ok(if self.big { i32::from_be_bytes(b) } else { i32::from_le_bytes(b) })
    }
    pub fn f32(&mut self, what: &str) -> Result<f32, IoError> {
        let b = self.u32_bytes(what)?;
        Ok(if self.big { f32::from_be_bytes(b) } else { f32::from_le_bytes(b) })
    }
    pub fn i16(&mut self, what: &str) -> Result<i16, IoError> {
        let s = self.take(2, what)?;
        let b = [s[0], s[1]];
        Ok(if self.big { i16::from_be_bytes(b) } else { i16::from_le_bytes(b) })
    }
}

/// Write polylines to `path` in the format its extension names: `.swc` (each polyline a chain
/// of type-0 nodes; points without a radius get 0.2), `.tck`, `.obj` or `.trk` (default header).
pub fn write_polylines(path: &Path, lines: &[Polyline]) -> Result<(), IoError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let bytes = match ext.as_str() {
        "swc" => swc::write(&swc::from_polylines(lines, 0.2)).into_bytes(),
        "tck" => tck::write(lines, false),
        "obj" => obj::write(lines).into_bytes(),
        "trk" => trk::write(&trk::TrkHeader::default(), lines, false),
        _ => {
            let problem = format!("unknown extension {ext:?} (use .swc, .tck, .obj or .trk)");
            return Err(IoError::file(&path.display().to_string(), problem));
        }
    };
    write_bytes(path, &bytes)
}
