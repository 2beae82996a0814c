//! Wavefront OBJ polylines: `v x y z [radius]` vertices and `l i j k ...` line elements
//! (1-based indices, negative ones relative to the last vertex, `i/t` forms accepted).
//!
//! The optional fourth `v` value is read as the vertex **radius** (this is what [`write()`]
//! writes; the OBJ specification calls it a weight `w`, which line geometry does not use).
//! Faces, normals, texture coordinates, groups and materials are ignored; `v` and `l` lines
//! must be well formed.

use super::stream::{Flow, Src};
use super::{parse_finite, IoError, Polyline};
use std::io::{BufRead, Write};

/// Parse OBJ text into polylines ([`read_from`] over the bytes).
///
/// ```
/// use tubecast_render::io::obj::read;
/// let lines = read(b"v 0 0 0\nv 1 0 0 0.5\nl 1 2\n", "t.obj").unwrap();
/// assert_eq!(lines[0].points, vec![[0.0; 3], [1.0, 0.0, 0.0]]);
/// assert!(lines[0].radii.is_empty()); // vertex 1 has no radius
/// ```
pub fn read(data: &[u8], name: &str) -> Result<Vec<Polyline>, IoError> {
    read_from(data, name)
}

/// Read OBJ text from `r` into polylines, line by line (the text is never held whole). A
/// polyline's `radii` is filled when every vertex it uses has a radius, and is empty
/// otherwise.
///
/// Errors name the line: a `v` with fewer than 3 or more than 4 numbers, a non-finite or
/// negative value, an `l` with fewer than 2 indices, an index that is 0, not an integer, or
/// out of range, a line that is not UTF-8 (the error names its byte offset) or longer than
/// 16 MiB; and a file with no `l` elements.
pub fn read_from(r: impl BufRead, name: &str) -> Result<Vec<Polyline>, IoError> {
    let mut out = Vec::new();
    stream(r, name, &mut |l| {
        out.push(l);
        Flow::Continue
    })?;
    Ok(out)
}

/// Stream OBJ text from `r`: each polyline goes to `each` as soon as its `l` line is read,
/// until the end or [`Flow::Stop`]. The vertices read so far are kept (an `l` may use any
/// earlier vertex), nothing else. Returns the number of polylines handed over; the errors of
/// [`read_from`] (no `l` elements: only when the whole text was read).
pub fn stream(r: impl BufRead, name: &str, each: &mut dyn FnMut(Polyline) -> Flow) -> Result<usize, IoError> {
    let mut src = Src::new(r, name);
    let (mut verts, mut buf, mut count) = (Vec::new(), Vec::new(), 0);
    for ln in 1.. {
        let at = src.pos;
        if src.line(&mut buf, ln)? == 0 {
            break;
        }
        let text = std::str::from_utf8(&buf)
            .map_err(|e| IoError::offset(name, at + e.valid_up_to() as u64, "not UTF-8 text (is this an OBJ file?)"))?;
        if let Some(l) = statement(text, ln, name, &mut verts)? {
            count += 1;
            if each(l) == Flow::Stop {
                return Ok(count);
            }
        }
    }
    if count == 0 {
        return Err(IoError::file(name, "no line elements (l) found"));
    }
    Ok(count)
}

/// One line of OBJ text (line number `ln`): a `v` joins `verts`, an `l` is returned as a
/// polyline, anything else is skipped.
fn statement(
    raw: &str,
    ln: usize,
    name: &str,
    verts: &mut Vec<([f64; 3], Option<f64>)>,
) -> Result<Option<Polyline>, IoError> {
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
                v[k] =
                    parse_finite(t).ok_or_else(|| IoError::line(name, ln, format!("{t:?} is not a finite number")))?;
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
            Ok(None)
        }
        Some("l") => {
            let mut idx = Vec::new();
            for t in it {
                let s = t.split('/').next().unwrap_or("");
                let k: i64 =
                    s.parse().map_err(|_| IoError::line(name, ln, format!("index {t:?} is not an integer")))?;
                let n = verts.len() as i64;
                let j = match k {
                    1.. => k - 1,
                    ..=-1 => n + k,
                    0 => -1,
                };
                if j < 0 || j >= n {
                    let problem = format!("index {k} is out of range (1..={n} or -{n}..=-1 so far)");
                    return Err(IoError::line(name, ln, problem));
                }
                idx.push(j as usize);
            }
            if idx.len() < 2 {
                return Err(IoError::line(name, ln, "l needs at least 2 vertex indices"));
            }
            let points = idx.iter().map(|&j| verts[j].0).collect();
            let radii: Option<Vec<f64>> = idx.iter().map(|&j| verts[j].1).collect();
            Ok(Some(Polyline { points, radii: radii.unwrap_or_default() }))
        }
        _ => Ok(None), // comments, blank lines, vn/vt/f/o/g/s/usemtl/mtllib: not line geometry.
    }
}

/// Write polylines as OBJ text; radii (when present) go in the fourth `v` column.
pub fn write(lines: &[Polyline]) -> String {
    let mut w = Writer::new(Vec::new()).expect("writing to memory does not fail");
    for l in lines {
        w.push(l).expect("writing to memory does not fail");
    }
    String::from_utf8(w.finish().expect("writing to memory does not fail")).expect("OBJ text is UTF-8")
}

/// Writes OBJ text polyline by polyline ([`write()`] as a stream): the vertices of each, then
/// its `l` element.
///
/// ```
/// use tubecast_render::io::{obj, Polyline};
/// let l = Polyline { points: vec![[0.0; 3], [1.0, 2.0, 3.0]], radii: vec![] };
/// let mut w = obj::Writer::new(Vec::new()).unwrap();
/// w.push(&l).unwrap();
/// assert_eq!(w.finish().unwrap(), obj::write(&[l]).into_bytes());
/// ```
pub struct Writer<W: Write> {
    out: W,
    /// 1-based index of the next vertex.
    base: usize,
}

impl<W: Write> Writer<W> {
    /// Start the text (a comment line naming the columns).
    pub fn new(mut out: W) -> std::io::Result<Self> {
        out.write_all(b"# written by tubecast: v x y z [radius], l i j ...\n")?;
        Ok(Self { out, base: 1 })
    }

    /// Write one polyline.
    pub fn push(&mut self, l: &Polyline) -> std::io::Result<()> {
        for (k, p) in l.points.iter().enumerate() {
            match l.radii.get(k) {
                Some(r) => writeln!(self.out, "v {:?} {:?} {:?} {:?}", p[0], p[1], p[2], r)?,
                None => writeln!(self.out, "v {:?} {:?} {:?}", p[0], p[1], p[2])?,
            }
        }
        write!(self.out, "l")?;
        for k in 0..l.points.len() {
            write!(self.out, " {}", self.base + k)?;
        }
        writeln!(self.out)?;
        self.base += l.points.len();
        Ok(())
    }

    /// Flush and hand back the output.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}
