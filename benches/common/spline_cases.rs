// The spline bench's rays, shared by `benches/spline.rs` and the lab's `newton_certificate`
// bench (`include!`d by both, so both time the same 64 rays): `N` (segment, link, ray) triples.
// Needs `QuadTube`, `RoundCone`, `Ray`, `V3`, `Primitive`, `rand::{Rng, SeedableRng}` and `N`.

/// Which rays a group runs.
#[derive(Clone, Copy, PartialEq)]
#[allow(dead_code)] // the lab's bench runs only `Hits`
enum Mix {
    /// The first 64 generated (22 hits, by the f64 default solver).
    All,
    /// The first 64 that hit the spline (f64, default solver).
    Hits,
    /// The first 64 that miss it.
    Misses,
}

fn cases(mix: Mix) -> Vec<(QuadTube<f64>, RoundCone<f64>, Ray<f64>)> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let mut v = || V3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
    let mut out = Vec::new();
    while out.len() < N {
        let (a, m, b) = (v(), v(), v());
        let (tgt, dir) = (v() * 0.8, v());
        if dir.length() < 0.2 {
            continue;
        }
        let t = QuadTube::new([a, m, b], [0.3, 0.4, 0.2]).unwrap();
        let l = RoundCone::new(a, 0.3, b, 0.2).unwrap();
        let o = tgt - dir * (5.0 / dir.length());
        let ray = Ray::new(o, dir);
        let hit = t.intersect(&ray).hit;
        if mix == Mix::All || (mix == Mix::Hits) == hit {
            out.push((t, l, ray));
        }
    }
    out
}
