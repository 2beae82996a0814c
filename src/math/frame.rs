//! Orthonormal frames.

use crate::real::Real;
use crate::vec::V3;

/// Two unit vectors that complete the unit vector `n` to an orthonormal frame, branch-free
/// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
#[inline(always)]
pub fn orthonormal_basis<T: Real>(n: V3<T>) -> (V3<T>, V3<T>) {
    let one = T::one();
    let sign = one.copysign_of(n.z);
    let a = -one / (sign + n.z);
    let b = n.x * n.y * a;
    let bx = V3::new(one + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let by = V3::new(b, sign + n.y * n.y * a, -n.y);
    (bx, by)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        // Rounding: each component is a few operations on unit-sized numbers, so the dot
        // products are within a few ε of 0 or 1; 16ε leaves room for the (1 + n.z) → small case.
        for n in [
            V3::new(0.0f64, 0.0, 1.0),
            V3::new(0.0, 0.0, -1.0),
            V3::new(0.6, 0.0, 0.8),
            V3::new(0.48, -0.6, -0.64),
            V3::new(1.0, 0.0, 0.0),
        ] {
            let (x, y) = orthonormal_basis(n);
            let tol = 16.0 * f64::EPSILON;
            for (a, b, want) in [(x, x, 1.0), (y, y, 1.0), (x, y, 0.0), (x, n, 0.0), (y, n, 0.0)] {
                assert!((a.dot(b) - want).abs() <= tol, "n = {n:?}");
            }
        }
    }
}
