//! TrackVis `.trk` streamlines: a 1000-byte header, then per streamline an `int32` point count,
//! `count × (3 + n_scalars)` `float32`s and `n_properties` `float32`s. Either byte order (the
//! header's `hdr_size` field, 1000, tells which).
//!
//! Points are stored in "voxmm" space (voxel index × voxel size, origin at the corner of the
//! first voxel). They are returned in RAS+ millimetres exactly as nibabel does:
//! `ras = vox_to_ras · (voxmm / voxel_size − ½)` — the `−½` moves the origin from the voxel's
//! corner to its centre. A header whose `vox_to_ras[3][3]` is 0 (old writers leave the matrix
//! unset, and version 1 has none) is read with the identity matrix, as nibabel does. When
//! `voxel_order` (LPS when unset, TrackVis's default) differs from the orientation of
//! `vox_to_ras`, the voxel axes are reoriented first, as nibabel does
//! (`get_affine_trackvis_to_rasmm`): a flipped axis maps index `x` to `dim − 1 − x`.
//! Per-point scalars and per-streamline properties are kept ([`read_data`]), grouped and named
//! by the header's name tables as nibabel groups them.

use super::data::{Field, Tractogram};
use super::orient::{self, io_orientation, Affine, Ornt};
use super::stream::{Flow, Line, Src};
use super::{Cursor, IoError, Polyline};
use std::io::Read;

/// The header fields the reader uses (and the writer writes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrkHeader {
    /// Volume dimensions in voxels.
    pub dim: [i16; 3],
    /// Voxel size in mm (each > 0).
    pub voxel_size: [f32; 3],
    /// Voxel (centre) index → RAS+ mm, row-major 4×4.
    pub vox_to_ras: [[f32; 4]; 4],
    /// Per-point scalars stored after each point (skipped by the reader).
    pub n_scalars: i16,
    /// Per-streamline properties stored after each streamline (skipped by the reader).
    pub n_properties: i16,
    /// Three-letter axis codes such as `b"LAS"` (or zeros when unset).
    pub voxel_order: [u8; 3],
}

impl Default for TrkHeader {
    fn default() -> Self {
        let mut m = [[0.0; 4]; 4];
        for (i, r) in m.iter_mut().enumerate() {
            r[i] = 1.0;
        }
        Self {
            dim: [1, 1, 1],
            voxel_size: [1.0; 3],
            vox_to_ras: m,
            n_scalars: 0,
            n_properties: 0,
            voxel_order: *b"RAS",
        }
    }
}

/// A TrackVis header as the streaming reader reads it: the fields, `n_count` (0: unknown),
/// the column groups of the scalars and properties, and the affine voxmm → RAS+ mm.
///
/// ```
/// use tubecast_render::io::stream::Flow;
/// use tubecast_render::io::{trk, Polyline};
/// let lines = vec![Polyline { points: vec![[0.5; 3], [1.5, 2.5, 3.5]], radii: vec![] }; 3];
/// let bytes = trk::write(&trk::TrkHeader::default(), &lines, false);
/// let mut seen = 0;
/// let info = trk::stream(&bytes[..], "t.trk", &mut |l| {
///     assert_eq!(l.points, &lines[l.index].points[..]);
///     seen += 1;
///     Flow::Continue
/// })
/// .unwrap();
/// assert_eq!((info.n_count, seen), (3, 3));
/// assert_eq!(info.streamline_bytes(2), 4 + 2 * 12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TrkInfo {
    /// The header fields.
    pub header: TrkHeader,
    /// Streamlines the header announces (0: unknown, read to the end of the file).
    pub n_count: usize,
    /// Per-point scalar groups `(name, first column, width)`, as nibabel names them.
    pub scalars: Vec<(String, usize, usize)>,
    /// Per-streamline property groups `(name, first column, width)`.
    pub properties: Vec<(String, usize, usize)>,
    /// The affine the reader applies, voxmm → RAS+ mm (row-major).
    pub affine: [[f64; 4]; 4],
    big: bool,
}

impl TrkInfo {
    /// Bytes of one streamline of `points` points (count, points with scalars, properties).
    pub fn streamline_bytes(&self, points: u64) -> u64 {
        4 + points * 4 * (3 + self.header.n_scalars as u64) + 4 * self.header.n_properties as u64
    }
}

/// Column groups named in the 10 × 20-byte name table at `at` (nibabel's
/// `decode_value_from_name`): `name` (one column) or `name\0COUNT` (COUNT columns), all-zero
/// entries skipped, columns taken in order and clipped to `n`; columns no name covers form one
/// group called `rest` (`"scalars"` / `"properties"`). Returns `(name, first column, width)`.
fn decode_names(
    data: &[u8],
    at: usize,
    n: usize,
    rest: &str,
    name: &str,
) -> Result<Vec<(String, usize, usize)>, IoError> {
    let mut out: Vec<(String, usize, usize)> = Vec::new();
    let mut cpt = 0usize;
    for k in 0..10 {
        let raw = &data[at + 20 * k..at + 20 * (k + 1)];
        let end = raw.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
        if end == 0 {
            continue;
        }
        let text: String = raw[..end].iter().map(|&b| b as char).collect();
        let parts: Vec<&str> = text.split('\0').collect();
        let count = match parts.as_slice() {
            [_] => 1,
            [_, v] => v.trim().parse::<usize>().map_err(|_| {
                IoError::offset(
                    name,
                    (at + 20 * k) as u64,
                    format!("column count {v:?} in name {:?} is not a number", parts[0]),
                )
            })?,
            _ => {
                let problem = format!("name {text:?} has bytes after its column count (unused bytes must be 0)");
                return Err(IoError::offset(name, (at + 20 * k) as u64, problem));
            }
        };
        if count == 0 {
            continue;
        }
        let (a, b) = (cpt.min(n), (cpt + count).min(n));
        let group = (parts[0].to_string(), a, b - a);
        match out.iter_mut().find(|g| g.0 == group.0) {
            Some(g) => *g = group,
            None => out.push(group),
        }
        cpt += count;
    }
    if cpt < n {
        out.push((rest.to_string(), cpt, n - cpt));
    }
    Ok(out)
}

/// The voxmm → RAS+ mm affine (nibabel's `get_affine_trackvis_to_rasmm`):
/// `vox_to_ras · R · (−½ shift) · diag(1/voxel_size)`, with `R` the reorientation from the
/// header's `voxel_order` to the orientation of `vox_to_ras` (identity when they agree).
fn voxmm_to_ras(h: &TrkHeader, order: &Ornt, name: &str) -> Result<Affine, IoError> {
    let v = h.vox_to_ras.map(|r| r.map(|x| x as f64));
    let Some(aff_ornt) = io_orientation(&v) else {
        return Err(IoError::offset(name, 440, "vox_to_ras is singular (no axis directions)"));
    };
    let mut scale = orient::eye();
    let mut shift = orient::eye();
    for k in 0..3 {
        scale[k][k] = 1.0 / h.voxel_size[k] as f64;
        shift[k][3] = -0.5;
    }
    let dims = h.dim.map(|d| d as f64);
    let m = orient::mul(&orient::reorient(order, &aff_ornt, dims), &orient::mul(&shift, &scale));
    Ok(orient::mul(&v, &m))
}

/// The validated header of a TrackVis file from its first (up to) 1000 bytes.
fn read_header(data: &[u8], name: &str) -> Result<TrkInfo, IoError> {
    if data.is_empty() {
        return Err(IoError::file(name, "empty file"));
    }
    if data.len() < 1000 {
        return Err(IoError::offset(
            name,
            data.len() as u64,
            format!("truncated header: {} of 1000 bytes", data.len()),
        ));
    }
    if &data[0..5] != b"TRACK" {
        return Err(IoError::offset(name, 0, "magic is not \"TRACK\" (not a TrackVis file)"));
    }
    let hs: [u8; 4] = [data[996], data[997], data[998], data[999]];
    let big = if i32::from_le_bytes(hs) == 1000 {
        false
    } else if i32::from_be_bytes(hs) == 1000 {
        true
    } else {
        return Err(IoError::offset(name, 996, "hdr_size is not 1000 in either byte order"));
    };
    let mut c = Cursor::new(data, name, big);
    c.pos = 992;
    let version = c.i32("version")?;
    if !(1..=3).contains(&version) {
        return Err(IoError::offset(name, 992, format!("version {version} is not a TrackVis version (1, 2 or 3)")));
    }
    c.pos = 6;
    let mut h = TrkHeader::default();
    for d in h.dim.iter_mut() {
        *d = c.i16("dim")?;
    }
    for k in 0..3 {
        let at = c.pos as u64;
        let v = c.f32("voxel_size")?;
        if !(v.is_finite() && v != 0.0) {
            return Err(IoError::offset(name, at, format!("voxel size {v} is zero or not finite")));
        }
        h.voxel_size[k] = v;
    }
    c.pos = 36;
    h.n_scalars = c.i16("n_scalars")?;
    if h.n_scalars < 0 {
        return Err(IoError::offset(name, 36, format!("n_scalars {} is negative", h.n_scalars)));
    }
    c.pos = 238;
    h.n_properties = c.i16("n_properties")?;
    if h.n_properties < 0 {
        return Err(IoError::offset(name, 238, format!("n_properties {} is negative", h.n_properties)));
    }
    c.pos = 440;
    for r in 0..4 {
        for k in 0..4 {
            h.vox_to_ras[r][k] = c.f32("vox_to_ras")?;
        }
    }
    // Version 1 has no matrix; a zero vox_to_ras[3][3] means "not recorded": identity.
    if version == 1 || h.vox_to_ras[3][3] == 0.0 {
        h.vox_to_ras = TrkHeader::default().vox_to_ras;
    }
    if h.vox_to_ras.iter().flatten().any(|v| !v.is_finite()) {
        return Err(IoError::offset(name, 440, "vox_to_ras has NaN or infinite entries"));
    }
    h.voxel_order.copy_from_slice(&data[948..951]);
    let raw = &data[948..952];
    let code = &raw[..raw.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1)];
    // TrackVis's default when unset is LPS (nibabel assumes it too).
    let code = if code.is_empty() { &b"LPS"[..] } else { code };
    let Some(order) = orient::parse_axcodes(code) else {
        let problem =
            format!("voxel_order {:?} is not three axis codes (R/L, A/P, S/I)", String::from_utf8_lossy(code));
        return Err(IoError::offset(name, 948, problem));
    };
    let affine = voxmm_to_ras(&h, &order, name)?;
    c.pos = 988;
    let n_count = c.i32("n_count")?;
    if n_count < 0 {
        return Err(IoError::offset(name, 988, format!("n_count {n_count} is negative")));
    }
    let scalars = decode_names(data, 38, h.n_scalars as usize, "scalars", name)?;
    let properties = decode_names(data, 240, h.n_properties as usize, "properties", name)?;
    Ok(TrkInfo { header: h, big, n_count: n_count as usize, scalars, properties, affine })
}

/// Read the header of a `.trk` file (its first 1000 bytes) from `r`.
pub fn read_info(r: impl Read, name: &str) -> Result<TrkInfo, IoError> {
    let mut head = [0u8; 1000];
    let got = Src::new(r, name).fill(&mut head)?;
    read_header(&head[..got], name)
}

/// Stream a `.trk` file from `r`: each streamline (points in RAS+ mm, per-point scalars
/// `n_scalars` per point, properties) goes to `each` as it is read, until the end of the file
/// or [`Flow::Stop`]; the header is returned. The same checks as [`read_data`] (which is this
/// plus collecting), except that after a stop the rest of the file is not read.
pub fn stream(r: impl Read, name: &str, each: &mut dyn FnMut(Line<'_>) -> Flow) -> Result<TrkInfo, IoError> {
    let mut src = Src::new(r, name);
    let mut head = [0u8; 1000];
    let got = src.fill(&mut head)?;
    let p = read_header(&head[..got], name)?;
    src.big = p.big;
    let (ns, np) = (p.header.n_scalars as usize, p.header.n_properties as usize);
    let m = p.affine;
    let (mut buf, mut points, mut scal, mut prop) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut count = 0usize;
    while p.n_count == 0 || count < p.n_count {
        let at = src.pos;
        let mut b4 = [0u8; 4];
        match src.fill(&mut b4)? {
            0 => break,
            4 => {}
            left => {
                let problem = format!("truncated: need 4 bytes for a point count, {left} left");
                return Err(IoError::offset(name, at, problem));
            }
        }
        let n = src.i32_at(&b4);
        if n < 0 {
            return Err(IoError::offset(name, at, format!("point count {n} is negative")));
        }
        let need = p.streamline_bytes(n as u64) - 4;
        let got = src.chunk(need, &mut buf)?;
        if (got as u64) < need {
            let problem = format!("truncated streamline {count}: {n} points need {need} bytes, {got} left");
            return Err(IoError::offset(name, at, problem));
        }
        points.clear();
        scal.clear();
        prop.clear();
        for (k, rec) in buf.chunks_exact(4 * (3 + ns)).take(n as usize).enumerate() {
            let v: [f64; 3] = std::array::from_fn(|i| src.f32_at(&rec[4 * i..]) as f64);
            scal.extend((0..ns).map(|i| src.f32_at(&rec[12 + 4 * i..]) as f64));
            let q: [f64; 3] = std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2] + m[r][3]);
            if q.iter().any(|x| !x.is_finite()) {
                let pat = at + 4 + (k * 4 * (3 + ns)) as u64;
                return Err(IoError::offset(name, pat, "point has NaN or infinite coordinates"));
            }
            points.push(q);
        }
        prop.extend(buf[buf.len() - 4 * np..].chunks_exact(4).map(|b| src.f32_at(b) as f64));
        let flow = each(Line { index: count, points: &points, scalars: &scal, properties: &prop });
        count += 1;
        if flow == Flow::Stop {
            return Ok(p);
        }
    }
    if p.n_count > 0 && count < p.n_count {
        let problem = format!("truncated: header says {} streamlines, file holds {count}", p.n_count);
        return Err(IoError::offset(name, src.pos, problem));
    }
    let at = src.pos;
    let rest = src.rest()?;
    if rest > 0 {
        let problem = format!("{rest} bytes after the last of n_count = {} streamlines", p.n_count);
        return Err(IoError::offset(name, at, problem));
    }
    Ok(p)
}

/// Parse a `.trk` file into streamlines in RAS+ mm (no radii), with its header.
/// ([`read_data`] keeps the scalars and properties too.)
pub fn read(data: &[u8], name: &str) -> Result<(TrkHeader, Vec<Polyline>), IoError> {
    read_data(data, name).map(|(h, t)| (h, t.lines))
}

/// Parse a `.trk` file into streamlines in RAS+ mm with their per-point scalars and
/// per-streamline properties, named as nibabel names them, and the header.
pub fn read_data(data: &[u8], name: &str) -> Result<(TrkHeader, Tractogram), IoError> {
    let (mut lines, mut scal, mut prop) = (Vec::new(), Vec::new(), Vec::new());
    let p = stream(data, name, &mut |l| {
        lines.push(Polyline { points: l.points.to_vec(), radii: Vec::new() });
        scal.extend_from_slice(l.scalars);
        prop.extend_from_slice(l.properties);
        Flow::Continue
    })?;
    let (ns, np) = (p.header.n_scalars as usize, p.header.n_properties as usize);
    let per_point = if ns == 0 { Vec::new() } else { fields(&p.scalars, &scal, ns) };
    let per_line = if np == 0 { Vec::new() } else { fields(&p.properties, &prop, np) };
    Ok((p.header, Tractogram { lines, per_point, per_line, groups: Vec::new(), affine: Some(p.affine) }))
}

/// The named column groups of `all` (`n` columns per item) as fields.
pub(crate) fn fields(groups: &[(String, usize, usize)], all: &[f64], n: usize) -> Vec<Field> {
    let items = all.len().checked_div(n).unwrap_or(0);
    let groups = groups.iter().map(|(gname, a, w)| Field {
        name: gname.clone(),
        width: *w,
        values: (0..items).flat_map(|i| all[i * n + a..i * n + a + w].iter().copied()).collect(),
    });
    groups.collect()
}

/// Write streamlines given in RAS+ mm as a `.trk` file with header `h` (inverse of [`read`]:
/// `voxmm = (vox_to_ras⁻¹ · ras + ½) · voxel_size`), scalars and properties written as zeros.
/// `h` must hold a valid header (positive voxel sizes, invertible matrix).
pub fn write(h: &TrkHeader, lines: &[Polyline], big: bool) -> Vec<u8> {
    let mut out = vec![0u8; 1000];
    let put_i16 = |v: i16| if big { v.to_be_bytes() } else { v.to_le_bytes() };
    let put_i32 = |v: i32| if big { v.to_be_bytes() } else { v.to_le_bytes() };
    let put_f32 = |v: f32| if big { v.to_be_bytes() } else { v.to_le_bytes() };
    out[0..6].copy_from_slice(b"TRACK\0");
    for k in 0..3 {
        out[6 + 2 * k..8 + 2 * k].copy_from_slice(&put_i16(h.dim[k]));
        out[12 + 4 * k..16 + 4 * k].copy_from_slice(&put_f32(h.voxel_size[k]));
    }
    out[36..38].copy_from_slice(&put_i16(h.n_scalars));
    out[238..240].copy_from_slice(&put_i16(h.n_properties));
    for r in 0..4 {
        for k in 0..4 {
            let o = 440 + 16 * r + 4 * k;
            out[o..o + 4].copy_from_slice(&put_f32(h.vox_to_ras[r][k]));
        }
    }
    out[948..951].copy_from_slice(&h.voxel_order);
    out[988..992].copy_from_slice(&put_i32(lines.len() as i32));
    out[992..996].copy_from_slice(&put_i32(2));
    out[996..1000].copy_from_slice(&put_i32(1000));
    // Inverse of the 3×3 part (adjugate / determinant) and the translation.
    let m = h.vox_to_ras.map(|r| r.map(|v| v as f64));
    let cof = |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let adj = [
        [cof(1, 2, 1, 2), -cof(0, 2, 1, 2), cof(0, 1, 1, 2)],
        [-cof(1, 2, 0, 2), cof(0, 2, 0, 2), -cof(0, 1, 0, 2)],
        [cof(1, 2, 0, 1), -cof(0, 2, 0, 1), cof(0, 1, 0, 1)],
    ];
    let det = m[0][0] * adj[0][0] + m[0][1] * adj[1][0] + m[0][2] * adj[2][0];
    for l in lines {
        out.extend_from_slice(&put_i32(l.points.len() as i32));
        for p in &l.points {
            let q = [p[0] - m[0][3], p[1] - m[1][3], p[2] - m[2][3]];
            for (k, a) in adj.iter().enumerate() {
                let v = (a[0] * q[0] + a[1] * q[1] + a[2] * q[2]) / det;
                out.extend_from_slice(&put_f32(((v + 0.5) * h.voxel_size[k] as f64) as f32));
            }
            for _ in 0..h.n_scalars {
                out.extend_from_slice(&put_f32(0.0));
            }
        }
        for _ in 0..h.n_properties {
            out.extend_from_slice(&put_f32(0.0));
        }
    }
    out
}
