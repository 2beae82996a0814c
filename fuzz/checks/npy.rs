// Invariants of the .npy reader: no panic; on success data.len() == rows × cols, and the
// array round-trips through the writer bit for bit.
pub fn check(data: &[u8]) {
    if let Ok(a) = tubecast_render::io::npy::read(data, "fuzz.npy", None) {
        assert_eq!(a.data.len(), a.rows * a.cols);
        let b = tubecast_render::io::npy::read(&tubecast_render::io::npy::write(&a), "rt.npy", None).expect("round trip");
        assert_eq!((a.rows, a.cols), (b.rows, b.cols));
        assert!(a.data.iter().zip(&b.data).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}
