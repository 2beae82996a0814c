//! MRtrix `.tck` streamlines: an ASCII header (`mrtrix tracks`, `key: value` lines, `END`),
//! then `float32` triplets from the byte offset given by `file: . OFFSET`. A NaN triplet ends
//! each streamline and an Inf triplet ends the data. `datatype` must be `Float32LE` or
//! `Float32BE` (missing: `Float32LE`, as nibabel assumes). The header's `count` is often wrong or zero-padded (writers fill it in at the
//! end); it is ignored and the triplets are authoritative. Coordinates are scanner-space mm.

use super::stream::{Line, Src};
use super::{IoError, Polyline};
use std::io::BufRead;

/// A header entry: key, value (continuation lines joined by newlines), line of the key.
type Entry = (String, String, usize);

/// The `key: value` lines of a `.tck` header (nibabel's `_read_header`): a line without a
/// colon continues the previous key's value (joined with a newline). Returns the entries with
/// the line of their first appearance; `src` is left just after `END`.
fn header_lines<R: BufRead>(src: &mut Src<'_, R>, magic: &str) -> Result<Vec<Entry>, IoError> {
    let name = src.name;
    let mut raw = vec![0u8; magic.len() + 1];
    let first = src.fill(&mut raw)?;
    if first == 0 {
        return Err(IoError::file(name, "empty file"));
    }
    if !(raw.starts_with(magic.as_bytes()) && raw.get(magic.len()) == Some(&b'\n')) {
        return Err(IoError::line(name, 1, format!("first line is not {magic:?}")));
    }
    let mut line_no = 1;
    let mut entries: Vec<Entry> = Vec::new();
    let mut last: Option<usize> = None;
    loop {
        line_no += 1;
        if src.line(&mut raw, line_no)? == 0 {
            return Err(IoError::line(name, line_no, "header ends without an END line"));
        }
        let text = raw.strip_suffix(b"\n").unwrap_or(&raw);
        let line = std::str::from_utf8(text)
            .map_err(|_| IoError::line(name, line_no, "header line is not UTF-8 text"))?
            .trim();
        if line == "END" {
            return Ok(entries);
        }
        if line.is_empty() {
            continue;
        }
        let (key, value) = match (line.split_once(':'), last) {
            (Some((k, v)), _) => (k.trim().to_string(), v.trim()),
            (None, Some(i)) => (entries[i].0.clone(), line),
            (None, None) => {
                return Err(IoError::line(name, line_no, format!("expected \"key: value\", found {line:?}")));
            }
        };
        match entries.iter().position(|e| e.0 == key) {
            Some(i) => {
                entries[i].1.push('\n');
                entries[i].1.push_str(value);
                last = Some(i);
            }
            None => {
                entries.push((key, value.to_string(), line_no));
                last = Some(entries.len() - 1);
            }
        }
    }
}

/// What a `.tck` / `.tsf` header says: the data's byte order, offset, and `count` if any.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TckInfo {
    /// Big-endian data (`Float32BE`).
    pub big: bool,
    /// Byte offset of the data.
    pub offset: u64,
    /// The header's `count` when it is a number (writers often leave it 0 or wrong).
    pub count: Option<u64>,
}

/// The header of a `.tck` file read from `src` (left at the data offset; `len`: the file's
/// length when known). As in nibabel, a missing `datatype` means `Float32LE` and a missing
/// `file` entry means the data start right after `END`.
fn read_header<R: BufRead>(src: &mut Src<'_, R>, magic: &str, len: Option<u64>) -> Result<TckInfo, IoError> {
    let name = src.name;
    let entries = header_lines(src, magic)?;
    let header_end = src.pos;
    let get = |k: &str| entries.iter().find(|e| e.0 == k);
    let big = match get("datatype") {
        None => false,
        Some((_, v, line)) => {
            if !v.starts_with("Float32") {
                let problem = format!("datatype {v:?} unsupported (Float32LE or Float32BE)");
                return Err(IoError::line(name, *line, problem));
            }
            v.ends_with("BE")
        }
    };
    let off = match get("file") {
        None => header_end,
        Some((_, value, line)) => {
            let mut it = value.split_whitespace();
            let (Some("."), Some(off)) = (it.next(), it.next()) else {
                return Err(IoError::line(
                    name,
                    *line,
                    format!("file entry {value:?} is not \". OFFSET\" (separate data files are unsupported)"),
                ));
            };
            off.parse::<u64>()
                .map_err(|_| IoError::line(name, *line, format!("file offset {off:?} is not a byte count")))?
        }
    };
    if off < header_end {
        return Err(IoError::offset(
            name,
            off,
            format!("data offset {off} lies inside the header (which ends at {header_end})"),
        ));
    }
    let beyond =
        |len: u64| IoError::offset(name, off, format!("data offset {off} is beyond the end of the file ({len} bytes)"));
    if let Some(len) = len.filter(|&l| off > l) {
        return Err(beyond(len));
    }
    let skipped = src.chunk(off - header_end, &mut Vec::new())? as u64;
    if skipped < off - header_end {
        return Err(beyond(src.pos));
    }
    let count = get("count").and_then(|e| e.1.trim().parse::<u64>().ok());
    Ok(TckInfo { big, offset: off, count })
}

/// Read the header of a `.tck` file from `r` (`len`: the file's length when known).
pub fn read_info(r: impl BufRead, name: &str, len: Option<u64>) -> Result<TckInfo, IoError> {
    read_header(&mut Src::new(r, name), "mrtrix tracks", len)
}

/// A streaming reader of a `.tck` file ([`Self::next_line`]: points) or `.tsf` file
/// ([`Self::next_values`]: values), one streamline at a time, from any [`BufRead`].
///
/// ```
/// use tubecast_render::io::{tck, Polyline};
/// let lines = vec![Polyline { points: vec![[0.0; 3], [1.0, 2.0, 3.0]], radii: vec![] }];
/// let bytes = tck::write(&lines, false);
/// let mut r = tck::Records::new(&bytes[..], "t.tck", None, false).unwrap();
/// assert_eq!(r.next_line().unwrap().unwrap().points, &lines[0].points[..]);
/// assert!(r.next_line().unwrap().is_none());
/// assert_eq!(tck::read_info(&bytes[..], "t.tck", None).unwrap().count, Some(1));
/// ```
pub struct Records<'n, R> {
    src: Src<'n, R>,
    width: usize,
    values: Vec<f64>,
    points: Vec<[f64; 3]>,
    index: usize,
    done: bool,
}

impl<'n, R: BufRead> Records<'n, R> {
    /// Read the header of a `.tck` file (`tsf: false`) or `.tsf` file (`tsf: true`) from `r`.
    pub fn new(r: R, name: &'n str, len: Option<u64>, tsf: bool) -> Result<Self, IoError> {
        let mut src = Src::new(r, name);
        let magic = if tsf { "mrtrix track scalars" } else { "mrtrix tracks" };
        src.big = read_header(&mut src, magic, len)?.big;
        let width = if tsf { 1 } else { 3 };
        Ok(Self { src, width, values: Vec::new(), points: Vec::new(), index: 0, done: false })
    }

    /// The next streamline's values (`.tsf`), `None` after the end marker.
    pub fn next_values(&mut self) -> Result<Option<&[f64]>, IoError> {
        Ok(if self.advance()? { Some(&self.values) } else { None })
    }

    /// The next streamline (`.tck`; no scalars or properties), `None` after the end marker.
    pub fn next_line(&mut self) -> Result<Option<Line<'_>>, IoError> {
        if !self.advance()? {
            return Ok(None);
        }
        let index = self.index - 1;
        Ok(Some(Line { index, points: &self.points, scalars: &[], properties: &[] }))
    }

    /// Read up to and including the NaN record ending the next non-empty streamline (empty
    /// ones are skipped, as nibabel does); false at the Inf end marker.
    fn advance(&mut self) -> Result<bool, IoError> {
        let (name, w) = (self.src.name, self.width);
        let what = if w == 3 { "a point" } else { "a value" };
        self.values.clear();
        self.points.clear();
        let mut rec = [0u8; 12];
        loop {
            if self.done {
                return Ok(false);
            }
            let at = self.src.pos;
            let got = self.src.fill(&mut rec[..4 * w])?;
            if got == 0 {
                return Err(IoError::offset(name, at, "truncated: data ends without the Inf end marker"));
            }
            if got < 4 * w {
                let problem = format!("truncated: need 4 bytes for {what}, {} left", got % 4);
                return Err(IoError::offset(name, at + 4 * (got / 4) as u64, problem));
            }
            let v: [f32; 3] = std::array::from_fn(|k| if k < w { self.src.f32_at(&rec[4 * k..]) } else { 0.0 });
            let v = &v[..w];
            if v.iter().all(|a| a.is_finite()) {
                match w {
                    3 => self.points.push([v[0] as f64, v[1] as f64, v[2] as f64]),
                    _ => self.values.push(v[0] as f64),
                }
            } else if v.iter().all(|a| a.is_nan()) {
                if !(self.points.is_empty() && self.values.is_empty()) {
                    self.index += 1;
                    return Ok(true);
                }
            } else if v.iter().all(|a| a.is_infinite()) {
                return self.end(at).map(|_| false);
            } else {
                let problem = format!("point ({}, {}, {}) mixes finite and NaN/Inf values", v[0], v[1], v[2]);
                return Err(IoError::offset(name, at, problem));
            }
        }
    }

    /// The Inf end marker at `at`: it must follow a NaN (no open streamline) and end the file.
    fn end(&mut self, at: u64) -> Result<(), IoError> {
        let name = self.src.name;
        let open = !(self.points.is_empty() && self.values.is_empty());
        if self.width == 1 {
            if open || self.src.rest()? > 0 {
                return Err(IoError::offset(name, at, "the Inf end marker must follow a NaN and end the file"));
            }
        } else {
            if open {
                let problem = "the last streamline has no NaN triplet before the Inf end marker";
                return Err(IoError::offset(name, at, problem));
            }
            let pos = self.src.pos;
            let rest = self.src.rest()?;
            if rest > 0 {
                return Err(IoError::offset(name, pos, format!("{rest} bytes after the Inf end marker")));
            }
        }
        self.done = true;
        Ok(())
    }
}

/// Parse a `.tck` file into streamlines (no radii).
///
/// As nibabel: every streamline ends with a NaN triplet and the data end with one Inf triplet
/// (right after a NaN triplet or at the start), nothing after it.
///
/// Errors: missing magic line, header without `END`, a `datatype` other than float32, a bad
/// `file:` entry, an offset beyond the end or inside the header, a triplet cut short, a
/// triplet mixing finite and non-finite values, no Inf end marker (truncated file), a last
/// streamline without its NaN triplet, or bytes after the Inf end marker.
/// ([`Records`] reads the same streamline by streamline.)
pub fn read(data: &[u8], name: &str) -> Result<Vec<Polyline>, IoError> {
    let mut r = Records::new(data, name, Some(data.len() as u64), false)?;
    let mut out = Vec::new();
    while let Some(l) = r.next_line()? {
        out.push(Polyline { points: l.points.to_vec(), radii: Vec::new() });
    }
    Ok(out)
}

/// Parse an MRtrix track scalar file (`.tsf`, the per-point values beside a `.tck`): the same
/// header (first line `mrtrix track scalars`), then one `float32` per point, a NaN after each
/// streamline and an Inf at the end, with the same rules as [`read`]. Returns the values per
/// streamline.
pub fn read_tsf(data: &[u8], name: &str) -> Result<Vec<Vec<f64>>, IoError> {
    let mut r = Records::new(data, name, Some(data.len() as u64), true)?;
    let mut out = Vec::new();
    while let Some(v) = r.next_values()? {
        out.push(v.to_vec());
    }
    Ok(out)
}

/// Write per-point values as a little-endian `.tsf` file (inverse of [`read_tsf`]).
pub fn write_tsf(values: &[Vec<f64>]) -> Vec<u8> {
    let head = |off: usize| format!("mrtrix track scalars\ndatatype: Float32LE\nfile: . {off:08}\nEND\n");
    let off = head(0).len();
    let mut out = head(off).into_bytes();
    for l in values {
        for &v in l {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
        out.extend_from_slice(&f32::NAN.to_le_bytes());
    }
    out.extend_from_slice(&f32::INFINITY.to_le_bytes());
    out
}

/// Write streamlines as a little-endian (`big = false`) or big-endian `.tck` file with a
/// zero-padded `count`.
pub fn write(lines: &[Polyline], big: bool) -> Vec<u8> {
    let dt = if big { "Float32BE" } else { "Float32LE" };
    // Fixed-width offset field so the header length does not depend on the offset itself.
    let head =
        |off: usize| format!("mrtrix tracks\ndatatype: {dt}\ncount: {:010}\nfile: . {off:08}\nEND\n", lines.len());
    let off = head(0).len();
    let mut out = head(off).into_bytes();
    let put = |v: f32, out: &mut Vec<u8>| out.extend_from_slice(&if big { v.to_be_bytes() } else { v.to_le_bytes() });
    for l in lines {
        for p in &l.points {
            for &x in p {
                put(x as f32, &mut out);
            }
        }
        for _ in 0..3 {
            put(f32::NAN, &mut out);
        }
    }
    for _ in 0..3 {
        put(f32::INFINITY, &mut out);
    }
    out
}
