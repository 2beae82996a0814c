//! A tiny `f64` vector: the oracle's own, so that it shares no code with the kernels it judges.
//!
//! Every operation rounds exactly as the obvious component formula (`x·x + y·y + z·z`, left to
//! right): the report's committed numbers were computed with that arithmetic.

use core::ops::{Add, Mul, Neg, Sub};

/// A point or direction in `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

impl Vec3 {
    /// `(x, y, z)`.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }
    /// Dot product `x·x' + y·y' + z·z'` (left to right).
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Squared length.
    pub fn length2(self) -> f64 {
        self.dot(self)
    }
    /// Length.
    pub fn length(self) -> f64 {
        self.length2().sqrt()
    }
    /// Largest absolute component.
    pub fn max_abs(self) -> f64 {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    /// `self / |self|`, scaled by the largest component first (so that squares neither under-
    /// nor overflow); the zero vector (and a non-finite one) maps to zero.
    pub fn normalize_or_zero(self) -> Self {
        let m = self.max_abs();
        let pos = m > 0.0 && m.is_finite();
        let v = self * (1.0 / if pos { m } else { 1.0 });
        let l = v.length();
        v * if pos { 1.0 / l } else { 0.0 }
    }
    /// Each component rounded to `f32` and back.
    pub fn round_f32(self) -> Self {
        Self::new(self.x as f32 as f64, self.y as f32 as f64, self.z as f32 as f64)
    }
    /// `[x, y, z]`.
    pub fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

impl From<[f64; 3]> for Vec3 {
    fn from(a: [f64; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
}

impl Add for Vec3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for Vec3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for Vec3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for Vec3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// A line `o + t·d` (`d ≠ 0`, any length); rays of the cases use the range `[0, ∞)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// Origin.
    pub o: Vec3,
    /// Direction.
    pub d: Vec3,
}

impl Line {
    /// The point `o + t·d`.
    pub fn at(&self, t: f64) -> Vec3 {
        self.o + self.d * t
    }
}

/// The line's distance from `c`: `|f + d·t_c|` with `f = o − c`, `t_c = −f·d/|d|²` (the foot
/// of the perpendicular, re-centred on `c` so that no large `|o|` cancels).
pub fn line_dist(line: &Line, c: Vec3) -> f64 {
    let f = line.o - c;
    let tc = -f.dot(line.d) / line.d.length2();
    (f + line.d * tc).length()
}

/// Line–sphere `(t_in, t_out)`, if the line meets the sphere `B(c, r)` (`r > 0`).
///
/// Re-centred on the foot of the perpendicular `t_c` (see [`line_dist`]): the half chord is
/// `h = √((r² − |q|²)/|d|²)` with `q = f + d·t_c`, which avoids the cancellation in the textbook
/// discriminant `b² − a·c` when the sphere is small against `|o − c|`. A sphere of radius zero
/// (a cone's tip) is no sphere: `None`.
pub fn sphere_crossing(line: &Line, c: Vec3, r: f64) -> Option<(f64, f64)> {
    let d2 = line.d.length2();
    let f = line.o - c;
    let tc = -f.dot(line.d) / d2;
    let q = f + line.d * tc;
    let h2 = (r * r - q.length2()) / d2;
    if h2 < 0.0 || r <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some((tc - h, tc + h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_crossing_of_a_unit_sphere_is_the_closed_form() {
        // o = (−3, 0.6, 0), d = (2, 0, 0): the line y = 0.6 meets x² + y² = 1 at x = ±0.8,
        // i.e. t = (−3 ± 0.8 … ) / 2 → t_in = 1.1, t_out = 1.9.
        let line = Line { o: Vec3::new(-3.0, 0.6, 0.0), d: Vec3::new(2.0, 0.0, 0.0) };
        let (a, b) = sphere_crossing(&line, Vec3::default(), 1.0).expect("meets");
        assert!((a - 1.1).abs() < 4.0 * f64::EPSILON && (b - 1.9).abs() < 4.0 * f64::EPSILON, "{a} {b}");
        assert!((line_dist(&line, Vec3::default()) - 0.6).abs() < 2.0 * f64::EPSILON);
        let miss = Line { o: Vec3::new(-3.0, 1.0 + 1e-12, 0.0), ..line };
        assert_eq!(sphere_crossing(&miss, Vec3::default(), 1.0), None);
        assert_eq!(sphere_crossing(&line, Vec3::new(0.0, 0.6, 0.0), 0.0), None, "zero radius");
    }

    #[test]
    fn normalize_or_zero_is_unit_and_survives_tiny_and_zero_vectors() {
        let v = Vec3::new(3e-200, 4e-200, 0.0).normalize_or_zero();
        assert!((v.x - 0.6).abs() < 2.0 * f64::EPSILON && (v.y - 0.8).abs() < 2.0 * f64::EPSILON, "{v:?}");
        assert_eq!(Vec3::default().normalize_or_zero(), Vec3::default());
    }
}
