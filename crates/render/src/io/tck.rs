//! MRtrix `.tck` streamlines: an ASCII header (`mrtrix tracks`, `key: value` lines, `END`),
//! then `float32` triplets from the byte offset given by `file: . OFFSET`. A NaN triplet ends
//! each streamline and an Inf triplet ends the data. `datatype` must be `Float32LE` or
//! `Float32BE`. The header's `count` is often wrong or zero-padded (writers fill it in at the
//! end); it is ignored and the triplets are authoritative. Coordinates are scanner-space mm.

use super::{Cursor, IoError, Polyline};

/// The header of a `.tck` file: the data's byte order (`true`: big endian) and offset.
fn read_header(data: &[u8], name: &str) -> Result<(bool, usize), IoError> {
    const MAGIC: &[u8] = b"mrtrix tracks\n";
    if data.is_empty() {
        return Err(IoError::file(name, "empty file"));
    }
    if !data.starts_with(MAGIC) {
        return Err(IoError::line(name, 1, "first line is not \"mrtrix tracks\""));
    }
    // Header: lines up to "END".
    let mut pos = MAGIC.len();
    let mut line_no = 1;
    let mut datatype: Option<(bool, usize)> = None; // (big endian, line)
    let mut offset: Option<usize> = None;
    let header_end;
    loop {
        line_no += 1;
        let Some(nl) = data[pos..].iter().position(|&b| b == b'\n') else {
            return Err(IoError::line(name, line_no, "header ends without an END line"));
        };
        let raw = &data[pos..pos + nl];
        pos += nl + 1;
        let line =
            std::str::from_utf8(raw).map_err(|_| IoError::line(name, line_no, "header line is not UTF-8 text"))?.trim();
        if line == "END" {
            header_end = pos;
            break;
        }
        if line.is_empty() {
            continue;
        }
        let Some((key, value)) = line.split_once(':') else {
            return Err(IoError::line(name, line_no, format!("expected \"key: value\", found {line:?}")));
        };
        let value = value.trim();
        match key.trim() {
            "datatype" => {
                let big = match value {
                    "Float32LE" => false,
                    "Float32BE" => true,
                    other => {
                        return Err(IoError::line(
                            name,
                            line_no,
                            format!("datatype {other:?} unsupported (Float32LE or Float32BE)"),
                        ))
                    }
                };
                datatype = Some((big, line_no));
            }
            "file" => {
                let mut it = value.split_whitespace();
                let (Some("."), Some(off), None) = (it.next(), it.next(), it.next()) else {
                    return Err(IoError::line(
                        name,
                        line_no,
                        format!("file entry {value:?} is not \". OFFSET\" (separate data files are unsupported)"),
                    ));
                };
                let off = off
                    .parse::<usize>()
                    .map_err(|_| IoError::line(name, line_no, format!("file offset {off:?} is not a byte count")))?;
                offset = Some(off);
            }
            _ => {} // count, total_count, timestamp, step_size, ...: informational.
        }
    }
    let Some((big, _)) = datatype else {
        return Err(IoError::file(name, "header has no datatype entry"));
    };
    let Some(off) = offset else {
        return Err(IoError::file(name, "header has no \"file: . OFFSET\" entry"));
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
/// Errors: missing magic line, header without `END`, missing or unknown `datatype`, missing or
/// bad `file:` entry, an offset beyond the end or inside the header, a triplet cut short, a
/// triplet mixing finite and non-finite values, or no Inf end marker (truncated file).
pub fn read(data: &[u8], name: &str) -> Result<Vec<Polyline>, IoError> {
    let (big, off) = read_header(data, name)?;
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
                // Tolerated: a last streamline not closed by a NaN triplet.
                out.push(std::mem::take(&mut cur));
            }
            break;
        } else {
            return Err(IoError::offset(name, at, format!("point ({x}, {y}, {z}) mixes finite and NaN/Inf values")));
        }
    }
    Ok(out)
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
