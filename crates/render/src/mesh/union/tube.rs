//! The exact round cones the certificate measures against (their signed distance is the
//! kernel's closed form, `Primitive::sdf`): its gradient, their support function, and a hash of
//! cells that finds the tubes near a box.

use std::collections::HashMap;
use tubecast::{Primitive, RoundCone, V3};

pub(super) type P = V3<f64>;

/// The unit vector along `v`, or the x axis for a zero vector (a direction is needed only
/// as a choice of tangent plane: any unit vector keeps the bounds valid).
pub(super) fn unit(v: P) -> P {
    let n = v.length();
    if n > 0.0 && n.is_finite() {
        v * (1.0 / n)
    } else {
        V3::new(1.0, 0.0, 0.0)
    }
}

/// The gradient of the round cone's signed distance at `x`: the unit vector from the nearest
/// generating ball's centre (the side of the cone: its outward normal there). Where the
/// distance is differentiable (everywhere but the medial axis inside) this is the gradient,
/// and the signed distance of a convex set is convex, so `f(p) ≥ f(x) + g·(p − x)`.
pub(super) fn gradient(l: &RoundCone<f64>, x: P) -> P {
    let v = l.b - l.a;
    let len = v.length();
    let dr = l.ra - l.rb;
    if dr.abs() >= len {
        return unit(x - if l.ra >= l.rb { l.a } else { l.b });
    }
    let axis = v * (1.0 / len);
    let s = dr / len;
    let c = ((1.0 - s) * (1.0 + s)).sqrt();
    let y = x - l.a;
    let z = y.dot(axis);
    let radial = y - axis * z;
    let rho = radial.length();
    let k = c * z - s * rho;
    if k < 0.0 {
        unit(y)
    } else if k > c * len {
        unit(x - l.b)
    } else {
        side_normal(axis, s, c, radial, rho)
    }
}

/// The side's outward normal at the radial offset `radial` (length `rho`) from the axis: the
/// axis tilted by the cone's half-angle (sine `s`, cosine `c`).
fn side_normal(axis: P, s: f64, c: f64, radial: P, rho: f64) -> P {
    let rdir = if rho > 0.0 { radial * (1.0 / rho) } else { unit(axis.cross(V3::new(0.3, 0.5, 0.8))) };
    axis * s + rdir * c
}

/// The normal of the round cone's side at `x`'s angle about its axis, wherever `x` lies along
/// it (the gradient where `x` faces the side; beyond an end, the side's normal rather than the
/// end ball's). Near a joint of two links the end ball's normal tilts along the axis, and its
/// tangent plane then rises above a long piece lying on the side; the side's does not. Falls
/// back to the gradient where the cone has no side (one ball holds the other).
pub(super) fn side(l: &RoundCone<f64>, x: P) -> P {
    let v = l.b - l.a;
    let len = v.length();
    let dr = l.ra - l.rb;
    if dr.abs() >= len {
        return gradient(l, x);
    }
    let axis = v * (1.0 / len);
    let s = dr / len;
    let c = ((1.0 - s) * (1.0 + s)).sqrt();
    let y = x - l.a;
    let radial = y - axis * y.dot(axis);
    side_normal(axis, s, c, radial, radial.length())
}

/// The support function `h(n) = max {n·y : y in the cone}` for a unit `n`: the cone is the
/// convex hull of its two end balls, so `h(n) = max(n·a + r_a, n·b + r_b)`, and the half-space
/// `n·y ≥ h(n)` meets no interior point of the cone.
pub(super) fn support(t: &RoundCone<f64>, n: P) -> f64 {
    (n.dot(t.a) + t.ra).max(n.dot(t.b) + t.rb)
}

/// The tubes by cells of side `cell`: a tube is listed in every cell its bounding box meets.
pub(super) struct Index {
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl Index {
    pub(super) fn new(tubes: &[RoundCone<f64>], cell: f64) -> Self {
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (k, t) in tubes.iter().enumerate() {
            let b = t.aabb();
            let (lo, hi) = (Self::key(cell, b.min), Self::key(cell, b.max));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        cells.entry([x, y, z]).or_default().push(k as u32);
                    }
                }
            }
        }
        Self { cell, cells }
    }

    fn key(cell: f64, p: P) -> [i64; 3] {
        [(p.x / cell).floor() as i64, (p.y / cell).floor() as i64, (p.z / cell).floor() as i64]
    }

    /// Every tube whose bounding box meets the box `[lo − margin, hi + margin]` (others are
    /// farther than `margin` from every point of `[lo, hi]`), into `out` (sorted, unique).
    pub(super) fn near(&self, lo: P, hi: P, margin: f64, out: &mut Vec<u32>) {
        out.clear();
        let m = V3::new(margin, margin, margin);
        let (a, b) = (Self::key(self.cell, lo - m), Self::key(self.cell, hi + m));
        let count = (b[0] - a[0] + 1) as f64 * (b[1] - a[1] + 1) as f64 * (b[2] - a[2] + 1) as f64;
        if count > self.cells.len() as f64 {
            for v in self.cells.values() {
                out.extend_from_slice(v);
            }
        } else {
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        if let Some(v) = self.cells.get(&[x, y, z]) {
                            out.extend_from_slice(v);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}
