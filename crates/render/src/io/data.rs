//! Streamlines with the data the formats carry beside the points: per-point scalars
//! (TrackVis scalars, MRtrix `.tsf`, TRX `dpv`) and per-streamline properties (TrackVis
//! properties, TRX `dps`).

use super::{IoError, Polyline};

/// A named column group: `width` values per item (per point or per streamline), row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The name the file gives it (`"fa"`, `"colors"`, ...).
    pub name: String,
    /// Values per item (1 for a scalar, 3 for a colour, ...).
    pub width: usize,
    /// `items × width` values, item after item.
    pub values: Vec<f64>,
}

impl Field {
    /// Column `col` of item `i`.
    pub fn get(&self, i: usize, col: usize) -> f64 {
        self.values[i * self.width + col]
    }
    /// Number of items (values / width; 0 for a zero-width field).
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.width).unwrap_or(0)
    }
    /// True when the field holds no items.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Streamlines with their per-point and per-streamline data.
///
/// ```
/// use tubecast_render::io::{data::{Field, Tractogram}, Polyline};
/// let t = Tractogram {
///     lines: vec![Polyline { points: vec![[0.0; 3], [1.0, 0.0, 0.0]], radii: vec![] }],
///     per_point: vec![Field { name: "fa".into(), width: 1, values: vec![0.2, 0.4] }],
///     per_line: vec![],
///     groups: vec![],
///     affine: None,
/// };
/// assert_eq!(t.point_field("fa").unwrap().get(1, 0), 0.4);
/// assert_eq!(t.point_count(), 2);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tractogram {
    /// The streamlines, in the file's world space (RAS+ mm for TrackVis, MRtrix and TRX).
    pub lines: Vec<Polyline>,
    /// Per-point fields, each with one item per point of all streamlines in order.
    pub per_point: Vec<Field>,
    /// Per-streamline fields, each with one item per streamline.
    pub per_line: Vec<Field>,
    /// Named groups of streamlines (TRX `groups/`): streamline indices.
    pub groups: Vec<(String, Vec<u64>)>,
    /// The affine the reader applied to the stored coordinates (stored → world, row-major),
    /// where the format has one (TrackVis: voxmm → RAS+ mm).
    pub affine: Option<[[f64; 4]; 4]>,
}

impl Tractogram {
    /// Total number of points.
    pub fn point_count(&self) -> usize {
        self.lines.iter().map(|l| l.points.len()).sum()
    }
    /// The per-point field called `name`.
    pub fn point_field(&self, name: &str) -> Option<&Field> {
        self.per_point.iter().find(|f| f.name == name)
    }
    /// The per-streamline field called `name`.
    pub fn line_field(&self, name: &str) -> Option<&Field> {
        self.per_line.iter().find(|f| f.name == name)
    }
    /// Check that every field has one item per point / streamline; `file` names the file in
    /// the error. Values may be NaN (the formats allow it; colouring shows them as missing).
    pub fn validate(&self, file: &str) -> Result<(), IoError> {
        let (np, nl) = (self.point_count(), self.lines.len());
        for (fields, n, what) in [(&self.per_point, np, "point"), (&self.per_line, nl, "streamline")] {
            for f in fields {
                if f.values.len() != n * f.width {
                    let got = f.values.len();
                    let problem = format!("{what} field {:?} has {got} values, expected {n} × {}", f.name, f.width);
                    return Err(IoError::file(file, problem));
                }
            }
        }
        Ok(())
    }
}
