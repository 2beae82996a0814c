//! Axis orientations of voxel grids, as nibabel computes them (`nibabel.orientations`):
//! the orientation of an affine (`io_orientation`), of axis codes such as `"LPS"`
//! (`axcodes2ornt`), and the affine that moves voxel indices from one orientation to another
//! (`ornt_transform` then `inv_ornt_aff`). Used by the TrackVis reader to reorient files whose
//! `voxel_order` differs from their `vox_to_ras`.

/// Per voxel axis: the world axis it runs along (0 = R/L, 1 = A/P, 2 = S/I) and the sign
/// (`1`: towards R, A or S).
pub(crate) type Ornt = [(usize, f64); 3];

/// A row-major 4×4 affine.
pub(crate) type Affine = [[f64; 4]; 4];

/// `a · b`.
pub(crate) fn mul(a: &Affine, b: &Affine) -> Affine {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// The identity.
pub(crate) fn eye() -> Affine {
    std::array::from_fn(|r| std::array::from_fn(|c| if r == c { 1.0 } else { 0.0 }))
}

fn det3(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// `(m⁻¹)ᵀ` of a non-singular 3×3 matrix.
fn inv_t(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let d = det3(m);
    let c = |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    // Cofactor matrix / det = (m⁻¹)ᵀ.
    [
        [c(1, 2, 1, 2) / d, -c(1, 2, 0, 2) / d, c(1, 2, 0, 1) / d],
        [-c(0, 2, 1, 2) / d, c(0, 2, 0, 2) / d, -c(0, 2, 0, 1) / d],
        [c(0, 1, 1, 2) / d, -c(0, 1, 0, 2) / d, c(0, 1, 0, 1) / d],
    ]
}

/// The orientation of the voxel axes of `aff` (nibabel's `io_orientation`): the columns of
/// the 3×3 part are normalised, replaced by the nearest orthogonal matrix (polar factor, here
/// by Newton's iteration `R ← (R + R⁻ᵀ)/2` instead of an SVD: same limit for a non-singular
/// matrix), then each voxel axis in order takes the world axis of its largest entry, that
/// world axis leaving the contest. `None` for a singular or non-finite matrix.
pub(crate) fn io_orientation(aff: &Affine) -> Option<Ornt> {
    let mut r = [[0.0f64; 3]; 3];
    for c in 0..3 {
        let z = (0..3).map(|k| aff[k][c] * aff[k][c]).sum::<f64>().sqrt();
        let z = if z == 0.0 { 1.0 } else { z };
        for k in 0..3 {
            r[k][c] = aff[k][c] / z;
        }
    }
    let d = det3(&r);
    if !(d.is_finite() && d.abs() > 1e-12) {
        return None;
    }
    for _ in 0..100 {
        let it = inv_t(&r);
        let next: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (r[i][j] + it[i][j])));
        let change = (0..9).map(|k| (next[k / 3][k % 3] - r[k / 3][k % 3]).abs()).fold(0.0, f64::max);
        r = next;
        if change < 1e-15 {
            break;
        }
    }
    let mut out = [(0usize, 1.0f64); 3];
    for (c, o) in out.iter_mut().enumerate() {
        let (mut best, mut bi) = (-1.0f64, 0);
        for (k, row) in r.iter().enumerate() {
            if row[c].abs() > best {
                best = row[c].abs();
                bi = k;
            }
        }
        if best <= 0.0 {
            return None;
        }
        *o = (bi, if r[bi][c] < 0.0 { -1.0 } else { 1.0 });
        r[bi] = [0.0; 3];
    }
    Some(out)
}

/// The orientation named by three axis codes (`R`/`L`, `A`/`P`, `S`/`I`, any case), each world
/// axis once; `None` otherwise (nibabel's `axcodes2ornt` raises there).
pub(crate) fn parse_axcodes(code: &[u8]) -> Option<Ornt> {
    if code.len() != 3 {
        return None;
    }
    let mut out = [(0usize, 1.0f64); 3];
    let mut seen = [false; 3];
    for (o, &b) in out.iter_mut().zip(code) {
        *o = match b.to_ascii_uppercase() {
            b'R' => (0, 1.0),
            b'L' => (0, -1.0),
            b'A' => (1, 1.0),
            b'P' => (1, -1.0),
            b'S' => (2, 1.0),
            b'I' => (2, -1.0),
            _ => return None,
        };
        if std::mem::replace(&mut seen[o.0], true) {
            return None;
        }
    }
    Some(out)
}

/// nibabel's `inv_ornt_aff(ornt_transform(from, to), dims)`: the affine taking voxel indices
/// of a grid of `dims` voxels oriented as `to` to the same voxel's indices oriented as `from`
/// (`x ↦ dims − 1 − x` on a flipped axis, then the axes permuted).
pub(crate) fn reorient(from: &Ornt, to: &Ornt, dims: [f64; 3]) -> Affine {
    // ornt_transform: start axis i runs along end axis j with relative flip f.
    let mut t = [(0usize, 1.0f64); 3];
    for (i, &(w, s)) in from.iter().enumerate() {
        let j = to.iter().position(|&(w2, _)| w2 == w).expect("both orientations name each world axis once");
        t[i] = (j, if s == to[j].1 { 1.0 } else { -1.0 });
    }
    // undo_reorder: row i picks input axis t[i].0; undo_flip: y_i = f_i·x_i + (dims_i − 1)(1 − f_i)/2.
    let mut m = [[0.0f64; 4]; 4];
    for (i, &(j, f)) in t.iter().enumerate() {
        m[i][j] = f;
        let c = -(dims[i] - 1.0) / 2.0;
        m[i][3] = f * c - c;
    }
    m[3][3] = 1.0;
    m
}
