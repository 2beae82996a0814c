//! The seeded generators are pinned: the README render and the committed reports depend on the
//! exact scenes. The splitmix64 outputs below come from an independent implementation of the
//! published algorithm (Steele, Lea & Flood 2014; a few lines of Python over 64-bit integers);
//! the scene values were recorded from the generators before they moved onto `rand_xoshiro`.

use tubecast_render::scene::generate::{self, Rng};

/// `uniform` is the top 53 bits of the splitmix64 output times 2⁻⁵³.
fn from_output(z: u64) -> f64 {
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn rng_is_splitmix64() {
    for (seed, want) in [
        (0u64, [0xe220_a839_7b1d_cdaf_u64, 0x6e78_9e6a_a1b9_65f4, 0x06c4_5d18_8009_454f]),
        (42, [0xbdd7_3226_2feb_6e95, 0x28ef_e333_b266_f103, 0x4752_6757_130f_9f52]),
    ] {
        let mut rng = Rng::new(seed);
        for (k, z) in want.into_iter().enumerate() {
            assert_eq!(rng.uniform().to_bits(), from_output(z).to_bits(), "seed {seed}, draw {k}");
        }
    }
}

#[test]
fn generated_scenes_are_pinned() {
    let b = generate::bundle(3, 4, 9);
    assert_eq!(b[2].points[3].map(f64::to_bits), [4627730092099895296, 4622008702180229797, 4614148048453028869]);
    let f = generate::furball(2, 5, 4);
    assert_eq!(f[1].points[5].map(f64::to_bits), [13839782084354929154, 13845087006343213834, 4608848079527514917]);
    let n = generate::base_neuron(1);
    assert_eq!(n.len(), 901);
    let last = n[n.len() - 1];
    assert_eq!(last.pos.map(f64::to_bits), [4632705027995098916, 13836653187088472132, 4612707816267477864]);
    assert_eq!(last.radius.to_bits(), 4603336450760873542);
    // The README's scene: `tubecast generate neurons --n 2` (seed 1).
    let a = generate::neurons(2, &[n], 1);
    assert_eq!(a.len(), 7208);
    assert_eq!(a[a.len() - 1].pos.map(f64::to_bits), [4637234525881966970, 4631202903180096393, 13853334573488401730]);
    assert_eq!(Rng::new(5).unit().map(f64::to_bits), [4579292277117615881, 13830319522951098448, 13820699279319922240]);
}
