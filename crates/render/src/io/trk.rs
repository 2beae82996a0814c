//! TrackVis `.trk` streamlines: a 1000-byte header, then per streamline an `int32` point count,
//! `count × (3 + n_scalars)` `float32`s and `n_properties` `float32`s. Either byte order (the
//! header's `hdr_size` field, 1000, tells which).
//!
//! Points are stored in "voxmm" space (voxel index × voxel size, origin at the corner of the
//! first voxel). They are returned in RAS+ millimetres exactly as nibabel does:
//! `ras = vox_to_ras · (voxmm / voxel_size − ½)` — the `−½` moves the origin from the voxel's
//! corner to its centre. A header whose `vox_to_ras[3][3]` is 0 (old writers leave the matrix
//! unset) is read with the identity matrix, as nibabel does. When `voxel_order` is set and
//! disagrees with the orientation of `vox_to_ras`, nibabel reorients the axes; this reader
//! reports an error instead of guessing.

use super::{Cursor, IoError, Polyline};
use std::cmp::Ordering;

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

/// Axis codes (`R/L`, `A/P`, `S/I`) of the voxel axes of an affine: for each column the
/// world axis with the largest weight and its sign.
fn axcodes(m: &[[f32; 4]; 4]) -> [u8; 3] {
    let mut out = [0u8; 3];
    for (j, o) in out.iter_mut().enumerate() {
        let (mut best, mut bi) = (-1.0f32, 0);
        for (i, row) in m.iter().enumerate().take(3) {
            if row[j].abs() > best {
                best = row[j].abs();
                bi = i;
            }
        }
        let pos = m[bi][j] >= 0.0;
        *o = match (bi, pos) {
            (0, true) => b'R',
            (0, false) => b'L',
            (1, true) => b'A',
            (1, false) => b'P',
            (_, true) => b'S',
            (_, false) => b'I',
        };
    }
    out
}

/// The validated header of a TrackVis file, its byte order (`true`: big endian) and
/// `n_count` (0: unknown).
fn read_header(data: &[u8], name: &str) -> Result<(TrkHeader, bool, i32), IoError> {
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
    c.pos = 6;
    let mut h = TrkHeader::default();
    for d in h.dim.iter_mut() {
        *d = c.i16("dim")?;
    }
    for k in 0..3 {
        let at = c.pos as u64;
        let v = c.f32("voxel_size")?;
        if !(v.is_finite() && v > 0.0) {
            return Err(IoError::offset(name, at, format!("voxel size {v} is not a positive number")));
        }
        h.voxel_size[k] = v;
    }
    c.pos = 36;
    h.n_scalars = c.i16("n_scalars")?;
    if !(0..=10).contains(&h.n_scalars) {
        return Err(IoError::offset(name, 36, format!("n_scalars {} is not in 0..=10", h.n_scalars)));
    }
    c.pos = 238;
    h.n_properties = c.i16("n_properties")?;
    if !(0..=10).contains(&h.n_properties) {
        return Err(IoError::offset(name, 238, format!("n_properties {} is not in 0..=10", h.n_properties)));
    }
    c.pos = 440;
    for r in 0..4 {
        for k in 0..4 {
            h.vox_to_ras[r][k] = c.f32("vox_to_ras")?;
        }
    }
    let unset = h.vox_to_ras[3][3] == 0.0;
    if unset {
        h.vox_to_ras = TrkHeader::default().vox_to_ras;
    }
    if h.vox_to_ras.iter().flatten().any(|v| !v.is_finite()) {
        return Err(IoError::offset(name, 440, "vox_to_ras has NaN or infinite entries"));
    }
    let m = h.vox_to_ras.map(|r| r.map(|v| v as f64));
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if det.abs().partial_cmp(&0.0) != Some(Ordering::Greater) || !det.is_finite() {
        return Err(IoError::offset(name, 440, "vox_to_ras is singular"));
    }
    h.voxel_order.copy_from_slice(&data[948..951]);
    let order = h.voxel_order.map(|b| b.to_ascii_uppercase());
    if !unset && order != [0, 0, 0] && order != axcodes(&h.vox_to_ras) {
        return Err(IoError::offset(
            name,
            948,
            format!(
                "voxel_order {:?} disagrees with the orientation of vox_to_ras ({:?}); reorienting is unsupported",
                String::from_utf8_lossy(&order),
                String::from_utf8_lossy(&axcodes(&h.vox_to_ras))
            ),
        ));
    }
    c.pos = 988;
    let n_count = c.i32("n_count")?;
    if n_count < 0 {
        return Err(IoError::offset(name, 988, format!("n_count {n_count} is negative")));
    }
    Ok((h, big, n_count))
}

/// Parse a `.trk` file into streamlines in RAS+ mm (no radii), with its header.
///
/// Errors: short header, bad magic, `hdr_size` ≠ 1000 in both byte orders, non-positive or
/// non-finite voxel size, negative or too many scalars/properties, a singular or non-finite
/// `vox_to_ras`, a `voxel_order` that disagrees with it, a negative point count, a truncated
/// streamline, non-finite coordinates, fewer streamlines than `n_count`, or trailing bytes.
pub fn read(data: &[u8], name: &str) -> Result<(TrkHeader, Vec<Polyline>), IoError> {
    let (h, big, n_count) = read_header(data, name)?;
    let m = h.vox_to_ras.map(|r| r.map(|v| v as f64));
    let mut c = Cursor::new(data, name, big);
    c.pos = 1000;
    let per_point = 3 + h.n_scalars as usize;
    let vs = h.voxel_size.map(|v| v as f64);
    let mut out = Vec::new();
    while c.remaining() > 0 && (n_count == 0 || out.len() < n_count as usize) {
        let at = c.pos as u64;
        let n = c.i32("a point count")?;
        if n < 0 {
            return Err(IoError::offset(name, at, format!("point count {n} is negative")));
        }
        let need = (n as u64) * per_point as u64 * 4 + h.n_properties as u64 * 4;
        if need > c.remaining() as u64 {
            return Err(IoError::offset(
                name,
                at,
                format!("truncated streamline {}: {n} points need {need} bytes, {} left", out.len(), c.remaining()),
            ));
        }
        let mut pl = Polyline { points: Vec::with_capacity(n as usize), radii: Vec::new() };
        for _ in 0..n {
            let pat = c.pos as u64;
            let mut v = [0.0f64; 3];
            for (k, x) in v.iter_mut().enumerate() {
                let f = c.f32("a point")? as f64;
                // Voxel-centre index coordinates.
                *x = f / vs[k] - 0.5;
            }
            for _ in 0..h.n_scalars {
                c.f32("a scalar")?;
            }
            let p: [f64; 3] = std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2] + m[r][3]);
            if p.iter().any(|x| !x.is_finite()) {
                return Err(IoError::offset(name, pat, "point has NaN or infinite coordinates"));
            }
            pl.points.push(p);
        }
        for _ in 0..h.n_properties {
            c.f32("a property")?;
        }
        out.push(pl);
    }
    if n_count > 0 && out.len() < n_count as usize {
        return Err(IoError::offset(
            name,
            c.pos as u64,
            format!("truncated: header says {n_count} streamlines, file holds {}", out.len()),
        ));
    }
    if c.remaining() > 0 {
        return Err(IoError::offset(
            name,
            c.pos as u64,
            format!("{} bytes after the last of n_count = {n_count} streamlines", c.remaining()),
        ));
    }
    Ok((h, out))
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
