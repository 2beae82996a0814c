//! Wavefront OBJ polylines: `v x y z [radius]` vertices and `l i j k ...` line elements
//! (1-based indices, negative ones relative to the last vertex, `i/t` forms accepted).
//!
//! The optional fourth `v` value is read as the vertex **radius** (this is what [`write()`]
//! writes; the OBJ specification calls it a weight `w`, which line geometry does not use).
//! Faces, normals, texture coordinates, groups and materials are ignored; `v` and `l` lines
//! must be well formed.

use super::{parse_finite, IoError, Polyline};

/// Parse OBJ text into polylines. A polyline's `radii` is filled when every vertex it uses
/// has a radius, and is empty otherwise.
///
/// Errors name the line: a `v` with fewer than 3 or more than 4 numbers, a non-finite or
/// negative value, an `l` with fewer than 2 indices, an index that is 0, not an integer, or
/// out of range; and a file with no `l` elements.
pub fn read(data: &[u8], name: &str) -> Result<Vec<Polyline>, IoError> {
    let text = std::str::from_utf8(data)
        .map_err(|e| IoError::offset(name, e.valid_up_to() as u64, "not UTF-8 text (is this an OBJ file?)"))?;
    let mut verts: Vec<([f64; 3], Option<f64>)> = Vec::new();
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let ln = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let toks: Vec<&str> = it.collect();
                if !(3..=4).contains(&toks.len()) {
                    return Err(IoError::line(
                        name,
                        ln,
                        format!("v needs 3 coordinates and an optional radius, found {} values", toks.len()),
                    ));
                }
                let mut v = [0.0; 4];
                for (k, t) in toks.iter().enumerate() {
                    v[k] = parse_finite(t)
                        .ok_or_else(|| IoError::line(name, ln, format!("{t:?} is not a finite number")))?;
                }
                let r = if toks.len() == 4 {
                    if v[3] < 0.0 {
                        return Err(IoError::line(name, ln, format!("radius {} is negative", v[3])));
                    }
                    Some(v[3])
                } else {
                    None
                };
                verts.push(([v[0], v[1], v[2]], r));
            }
            Some("l") => {
                let mut idx = Vec::new();
                for t in it {
                    let s = t.split('/').next().unwrap_or("");
                    let k: i64 =
                        s.parse().map_err(|_| IoError::line(name, ln, format!("index {t:?} is not an integer")))?;
                    let n = verts.len() as i64;
                    let j = if k > 0 {
                        k - 1
                    } else if k < 0 {
                        n + k
                    } else {
                        -1
                    };
                    if k == 0 || j < 0 || j >= n {
                        return Err(IoError::line(
                            name,
                            ln,
                            format!("index {k} is out of range (1..={n} or -{n}..=-1 so far)"),
                        ));
                    }
                    idx.push(j as usize);
                }
                if idx.len() < 2 {
                    return Err(IoError::line(name, ln, "l needs at least 2 vertex indices"));
                }
                let points = idx.iter().map(|&j| verts[j].0).collect();
                let radii: Option<Vec<f64>> = idx.iter().map(|&j| verts[j].1).collect();
                out.push(Polyline { points, radii: radii.unwrap_or_default() });
            }
            _ => {} // comments, blank lines, vn/vt/f/o/g/s/usemtl/mtllib: not line geometry.
        }
    }
    if out.is_empty() {
        return Err(IoError::file(name, "no line elements (l) found"));
    }
    Ok(out)
}

/// Write polylines as OBJ text; radii (when present) go in the fourth `v` column.
pub fn write(lines: &[Polyline]) -> String {
    let mut s = String::from("# written by tubecast: v x y z [radius], l i j ...\n");
    let mut base = 1usize;
    for l in lines {
        for (k, p) in l.points.iter().enumerate() {
            match l.radii.get(k) {
                Some(r) => s.push_str(&format!("v {:?} {:?} {:?} {:?}\n", p[0], p[1], p[2], r)),
                None => s.push_str(&format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2])),
            }
        }
        s.push('l');
        for k in 0..l.points.len() {
            s.push_str(&format!(" {}", base + k));
        }
        s.push('\n');
        base += l.points.len();
    }
    s
}
