//! MRtrix `.tck` streamlines: an ASCII header (`mrtrix tracks`, `key: value` lines, `END`),
//! then `float32` triplets from the byte offset given by `file: . OFFSET`. A NaN triplet ends
//! each streamline and an Inf triplet ends the data. `datatype` must be `Float32LE` or
//! `Float32BE` (missing: `Float32LE`, as nibabel assumes). The header's `count` is often wrong or zero-padded (writers fill it in at the
//! end); it is ignored and the triplets are authoritative. Coordinates are scanner-space mm.

use super::{Cursor, IoError, Polyline};

/// The `key: value` lines of a `.tck` header (nibabel's `_read_header`): a line without a
/// colon continues the previous key's value (joined with a newline). Returns the entries with
/// the line of their first appearance, and the byte offset just after `END`.
/// A header entry: key, value (continuation lines joined by newlines), line of the key.
type Entry = (String, String, usize);

fn header_lines(data: &[u8], name: &str, magic: &str) -> Result<(Vec<Entry>, usize), IoError> {
    if data.is_empty() {
        return Err(IoError::file(name, "empty file"));
    }
    if !(data.starts_with(magic.as_bytes()) && data.get(magic.len()) == Some(&b'\n')) {
        return Err(IoError::line(name, 1, format!("first line is not {magic:?}")));
    }
    let mut pos = magic.len() + 1;
    let mut line_no = 1;
    let mut entries: Vec<Entry> = Vec::new();
    let mut last: Option<usize> = None;
    loop {
        line_no += 1;
        if pos >= data.len() {
            return Err(IoError::line(name, line_no, "header ends without an END line"));
        }
        let nl = data[pos..].iter().position(|&b| b == b'\n').unwrap_or(data.len() - pos);
        let raw = &data[pos..pos + nl];
        pos = (pos + nl + 1).min(data.len());
        let line =
            std::str::from_utf8(raw).map_err(|_| IoError::line(name, line_no, "header line is not UTF-8 text"))?.trim();
        if line == "END" {
            return Ok((entries, pos));
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

/// The header of a `.tck` file: the data's byte order (`true`: big endian) and offset. As in
/// nibabel, a missing `datatype` means `Float32LE` and a missing `file` entry means the data
/// start right after `END`.
fn read_header(data: &[u8], name: &str, magic: &str) -> Result<(bool, usize), IoError> {
    let (entries, header_end) = header_lines(data, name, magic)?;
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
            off.parse::<usize>()
                .map_err(|_| IoError::line(name, *line, format!("file offset {off:?} is not a byte count")))?
        }
    };
    if off < header_end {
        return Err(IoError::offset(
            name,
            off as u64,
            format!("data offset {off} lies inside the header (which ends at {header_end})"),
        ));
    }
    if off > data.len() {
        return Err(IoError::offset(
            name,
            off as u64,
            format!("data offset {off} is beyond the end of the file ({} bytes)", data.len()),
        ));
    }
    Ok((big, off))
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
pub fn read(data: &[u8], name: &str) -> Result<Vec<Polyline>, IoError> {
    let (big, off) = read_header(data, name, "mrtrix tracks")?;
    let mut c = Cursor::new(data, name, big);
    c.pos = off;
    let mut out = Vec::new();
    let mut cur = Polyline::default();
    loop {
        let at = c.pos as u64;
        if c.remaining() == 0 {
            return Err(IoError::offset(name, at, "truncated: data ends without the Inf end marker"));
        }
        let x = c.f32("a point")?;
        let y = c.f32("a point")?;
        let z = c.f32("a point")?;
        let v = [x, y, z];
        if v.iter().all(|a| a.is_finite()) {
            cur.points.push([x as f64, y as f64, z as f64]);
        } else if v.iter().all(|a| a.is_nan()) {
            if !cur.points.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
        } else if v.iter().all(|a| a.is_infinite()) {
            if !cur.points.is_empty() {
                let problem = "the last streamline has no NaN triplet before the Inf end marker";
                return Err(IoError::offset(name, at, problem));
            }
            if c.remaining() > 0 {
                return Err(IoError::offset(
                    name,
                    c.pos as u64,
                    format!("{} bytes after the Inf end marker", c.remaining()),
                ));
            }
            break;
        } else {
            return Err(IoError::offset(name, at, format!("point ({x}, {y}, {z}) mixes finite and NaN/Inf values")));
        }
    }
    Ok(out)
}

/// Parse an MRtrix track scalar file (`.tsf`, the per-point values beside a `.tck`): the same
/// header (first line `mrtrix track scalars`), then one `float32` per point, a NaN after each
/// streamline and an Inf at the end, with the same rules as [`read`]. Returns the values per
/// streamline.
pub fn read_tsf(data: &[u8], name: &str) -> Result<Vec<Vec<f64>>, IoError> {
    let (big, off) = read_header(data, name, "mrtrix track scalars")?;
    let mut c = Cursor::new(data, name, big);
    c.pos = off;
    let (mut out, mut cur) = (Vec::new(), Vec::new());
    loop {
        let at = c.pos as u64;
        if c.remaining() == 0 {
            return Err(IoError::offset(name, at, "truncated: data ends without the Inf end marker"));
        }
        let v = c.f32("a value")?;
        if v.is_nan() {
            // Empty streamlines are skipped, as `read` skips them.
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
        } else if v.is_infinite() {
            if !cur.is_empty() || c.remaining() > 0 {
                return Err(IoError::offset(name, at, "the Inf end marker must follow a NaN and end the file"));
            }
            return Ok(out);
        } else {
            cur.push(v as f64);
        }
    }
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
