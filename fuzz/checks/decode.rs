// Input bytes → numbers, shared by the kernel fuzz checks (each `include!`s this file).

/// The 8 bytes at byte offset `at` (bytes past the end read as 0).
#[allow(dead_code)]
fn bytes8(data: &[u8], at: usize) -> [u8; 8] {
    let mut b = [0u8; 8];
    for (k, x) in b.iter_mut().enumerate() {
        *x = *data.get(at + k).unwrap_or(&0);
    }
    b
}

/// The little-endian `f64` at byte offset `at` (any bit pattern: NaN, ∞, subnormal, huge).
#[allow(dead_code)]
fn f64_at(data: &[u8], at: usize) -> f64 {
    f64::from_le_bytes(bytes8(data, at))
}
