//! The seeded stream of the case generators: `rand_xoshiro`'s [`SplitMix64`] (Steele, Lea &
//! Flood's splitmix64; the state is the seed itself) with the float helpers the generators use.
//!
//! The stream and the float mapping are bit for bit those of the hand-rolled `Rng` the report
//! used before (`tubecast_render::scene::generate::Rng`), so the committed report numbers stay
//! what they are; the tests below pin values computed with that code.

pub use rand_xoshiro::rand_core::{RngCore, SeedableRng};
pub use rand_xoshiro::SplitMix64;

/// The generator for `seed` (state = `seed`).
pub fn splitmix(seed: u64) -> SplitMix64 {
    SplitMix64::seed_from_u64(seed)
}

/// Float helpers on any `u64` stream.
pub trait FloatRng: RngCore {
    /// Next value in `[0, 1)`: the top 53 bits of the next `u64` times `2⁻⁵³`.
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[a, b)`: `a + (b − a)·uniform()`.
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
    /// A uniformly distributed unit vector (Archimedes: `z` uniform in `[−1, 1)`, then an angle).
    fn unit(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, 2.0 * std::f64::consts::PI);
        let s = (1.0 - z * z).max(0.0).sqrt();
        [s * phi.cos(), s * phi.sin(), z]
    }
    /// A fair coin: `uniform() < ½`.
    fn coin(&mut self) -> bool {
        self.uniform() < 0.5
    }
}

impl<R: RngCore + ?Sized> FloatRng for R {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of the report's former `Rng(seed)` (splitmix64 written out by hand), computed with
    /// that code: the `u64` stream and the `[0, 1)` mapping must not move.
    #[test]
    fn stream_equals_the_former_hand_rolled_splitmix64() {
        let mut r = splitmix(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut r = splitmix(1234567);
        assert_eq!(r.next_u64(), 0x599E_D017_FB08_FC85);
        let mut r = splitmix(1234567);
        assert_eq!(r.uniform().to_bits(), UNIFORM_1234567);
        assert_eq!(r.range(-4.0, 4.0).to_bits(), RANGE_1234567);
    }

    // First draw of seed 1234567 as `uniform()` (0.3500795420214081) and the second as
    // `range(−4, 4)` (−2.610847226632699), bit patterns of the former `Rng`'s results.
    const UNIFORM_1234567: u64 = 0x3FD6_67B4_05FE_C23E;
    const RANGE_1234567: u64 = 0xC004_E303_DEE9_EAFE;

    #[test]
    fn unit_vectors_are_unit() {
        let mut r = splitmix(7);
        for _ in 0..100 {
            let [x, y, z] = r.unit();
            assert!(((x * x + y * y + z * z).sqrt() - 1.0).abs() <= 4.0 * f64::EPSILON);
        }
    }
}
