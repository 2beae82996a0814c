//! What a spline costs, scalar and in lanes: the spline kernel (`QuadTube::intersect`, the default
//! `Polynomial` solver) against the stable link (`RoundCone::intersect`) on the spline bench's
//! rays (`benches/common/spline_cases.rs`), per call as `cargo bench --bench spline` calls them,
//! by repeated median of paired ratios (not criterion), and the **floor** that any per-call lane
//! kernel with the measured scalar hit path must stay above.
//!
//! # The floor
//!
//! A lane call answers `W` (segment, ray) pairs (`W = 8` for `WideF32x8`). The `k_p` pairs of
//! pack `p` that hit need the hit path: the work a hit costs beyond what a rejected miss costs,
//! `c_hit − c_miss` in scalar. It runs lane by lane at that scalar cost, or in one lane pass over
//! the pack, whose cost is at least `W·(c_hit − c_miss)/G_s` where `G_s` is what the hit path
//! gains from lanes per pair. Counting the rejections and the misses as free, pack `p` costs at
//! least `(c_hit − c_miss)·min(k_p, W/G_s)`, and the link's lanes cost `W·c_link/G_l` per pack
//! (`G_l` the link's own gain from lanes), so over the `N/W` packs
//!
//! ```text
//! spline lanes ÷ link lanes  ≥  (G_l·H / N) · Σ_p min(k_p, W/G_s),   H = (c_hit − c_miss) / c_link
//! ```
//!
//! with `c_hit`, `c_miss`, `c_link` the scalar costs per pair on the bench's hits, misses and
//! the link. Where every pack holds at least `W/G_s` hits the bound is `H·G_l/G_s`: `H` itself
//! at `G_s = G_l`. Only the measured `H`, `G_l` and the pack composition enter;
//! [`floor`] evaluates it and [`gain_needed`] solves it for the `G_s` a ratio of 4 needs.

use super::{ensure_dir, machine, write_text, ReportError, ReportFiles, ReportOptions};
use rand::{Rng, SeedableRng};
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;
use tubecast::{Primitive, QuadTube, Ray, Real, RoundCone, Scalar, WideF32x8, WideF64x4, V3};

/// Pairs per case set, as in `benches/spline.rs`.
const N: usize = 64;

// `cases(mix)`: the spline bench's (segment, link, ray) triples.
include!("../../../../benches/common/spline_cases.rs");

/// `(G_l·H/N)·Σ_p min(k_p, w/g_s)`: the least ratio (spline lanes ÷ link lanes) of a per-call
/// lane kernel whose hit path (a hit's cost beyond a miss's) costs `h` links in scalar and gains
/// `g_s` from lanes, where the link gains `g_l` and pack `p` holds `k[p]` hits of its `w` pairs
/// (module docs); `n` pairs in all.
pub fn floor(k: &[usize], w: usize, n: usize, h: f64, g_l: f64, g_s: f64) -> f64 {
    let cap = w as f64 / g_s;
    g_l * h / n as f64 * k.iter().map(|&k| (k as f64).min(cap)).sum::<f64>()
}

/// The least lane gain `G_s` of the hit path for which [`floor`] is at most `target`, or `None`
/// where no gain up to `w` (every lane useful) reaches it.
pub fn gain_needed(k: &[usize], w: usize, n: usize, h: f64, g_l: f64, target: f64) -> Option<f64> {
    if floor(k, w, n, h, g_l, w as f64) > target {
        return None;
    }
    // `floor` falls as `g_s` rises: bisect on [1/1024, w] (60 halvings: far below the
    // timings' own spread).
    let (mut lo, mut hi) = (1.0 / 1024.0, w as f64);
    if floor(k, w, n, h, g_l, lo) <= target {
        return Some(lo);
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if floor(k, w, n, h, g_l, mid) <= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// One precision's packs of the case set.
type Packs<T> = Vec<(QuadTube<T>, RoundCone<T>, Ray<T>)>;
/// A case set as `cases` makes it: `f64` (segment, link, ray) triples.
type Cases = Packs<f64>;

fn packs<T: Real>(cs: &Cases) -> Packs<T>
where
    T::Elem: Scalar,
{
    let w = T::LANES;
    (0..cs.len() / w)
        .map(|k| {
            let t = QuadTube::<T>::from_lanes(|i| cs[k * w + i].0.cast());
            let l = RoundCone::<T>::from_lanes(|i| cs[k * w + i].1.cast());
            let r = Ray::<T>::from_fn(|i| Ray::new(cs[k * w + i].2.o.cast(), cs[k * w + i].2.d.cast()));
            (t, l, r)
        })
        .collect()
}

/// Every pack's link (`spline = false`) or spline call, `reps` times, as the bench's loop.
fn sweep<T: Real>(p: &Packs<T>, spline: bool, reps: usize) -> T {
    let mut acc = T::zero();
    for _ in 0..reps {
        for (t, l, r) in p {
            let iv = if spline { black_box(t).intersect(black_box(r)) } else { black_box(l).intersect(black_box(r)) };
            acc += iv.entry.t.min(T::cst(1e9));
        }
    }
    acc
}

/// One timed row: nanoseconds per pair of the link and the spline, and their ratio, each as
/// `[q1, median, q3]` over `reps` repetitions; a repetition times the link and then the spline
/// on the same packs, each for at least `min_s` seconds, and its ratio is
/// taken within it (so load that comes and goes moves both sides). Wall time on the calling
/// thread, as criterion measures.
struct Row {
    link: [f64; 3],
    spline: [f64; 3],
    ratio: [f64; 3],
}

fn quartiles(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    [v[n / 4], v[n / 2], v[(3 * n) / 4]]
}

fn timed<T: Real>(p: &Packs<T>, reps: usize, min_s: f64) -> Row {
    let pairs = (p.len() * T::LANES) as f64;
    let run = |spline: bool, k: usize| {
        let t0 = Instant::now();
        black_box(sweep(p, spline, k));
        t0.elapsed().as_secs_f64()
    };
    // Calibration: calls per repetition so that one side takes ≥ min_s (from a run of ≥ 5 ms).
    let per = |spline: bool| {
        let mut k = 1;
        let mut s = run(spline, k);
        while s < 5e-3 && k < 1 << 24 {
            k *= 4;
            s = run(spline, k);
        }
        (min_s / (s / k as f64)).ceil().clamp(1.0, 1e8) as usize
    };
    let (kl, ks) = (per(false), per(true));
    let (mut l, mut s, mut q) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..reps {
        let (tl, ts) = (run(false, kl) / (kl as f64 * pairs) * 1e9, run(true, ks) / (ks as f64 * pairs) * 1e9);
        l.push(tl);
        s.push(ts);
        q.push(ts / tl);
    }
    Row { link: quartiles(l), spline: quartiles(s), ratio: quartiles(q) }
}

/// The timed rows of one precision for the three case sets.
fn rows<T: Real>(sets: &[Cases; 3], reps: usize, min_s: f64) -> [Row; 3]
where
    T::Elem: Scalar,
{
    std::array::from_fn(|i| timed(&packs::<T>(&sets[i]), reps, min_s))
}

/// Writes `spline_lanes.md` into `out`. `opts.time_ms == 0` (the quick setting) times 3
/// repetitions of 2 ms per side, for tests; otherwise 15 of 30 ms.
pub fn run_spline_lanes(out: &Path, opts: &ReportOptions) -> Result<ReportFiles, ReportError> {
    opts.validate()?;
    ensure_dir(out)?;
    let (reps, min_s) = if opts.time_ms == 0 { (3, 2e-3) } else { (15, 30e-3) };
    let sets = [cases(Mix::All), cases(Mix::Hits), cases(Mix::Misses)];
    // The bench's hits: the f64 kernel's, per pack of 8 of the mixed set.
    let w = WideF32x8::LANES;
    let k: Vec<usize> = sets[0].chunks(w).map(|c| c.iter().filter(|(t, _, r)| t.intersect(r).hit).count()).collect();
    let timed: [(&str, [Row; 3]); 4] = [
        ("f32", rows::<f32>(&sets, reps, min_s)),
        ("f32x8", rows::<WideF32x8>(&sets, reps, min_s)),
        ("f64", rows::<f64>(&sets, reps, min_s)),
        ("f64x4", rows::<WideF64x4>(&sets, reps, min_s)),
    ];
    let mut md = format!(
        "# Spline kernel cost per call, scalar and lanes, and the floor of a per-call lane kernel\n\n\
         Generated by `cargo run --release -p tubecast-lab -- spline-lanes` (plain release build, no RUSTFLAGS).\n\
         Machine: {}.\n\n\
         Rays: the spline bench's (`benches/common/spline_cases.rs`, as `cargo bench --bench spline` times them): \
         `mixed` the first {N} generated, `hits` / `misses` the first {N} that hit / miss (f64 kernel). \
         Spline: `QuadTube::intersect` (default solver `Polynomial`); link: `RoundCone::intersect` on the \
         segment's chord, same rays. Measure: ns per (segment, ray) pair in wall time on one thread; \
         each of {reps} repetitions times the link and then the spline (each ≥ {} ms), and the ratio is taken \
         within the repetition; median and quartiles (q1 – q3) over the repetitions.\n\n\
         | precision | rays | link ns per pair | spline ns per pair | spline ÷ link: median | q1 – q3 |\n\
         |---|---|---|---|---|---|\n",
        machine(),
        min_s * 1e3
    );
    for (name, rs) in &timed {
        for (set, r) in ["mixed", "hits", "misses"].iter().zip(rs) {
            let _ = writeln!(
                md,
                "| {name} | {set} | {:.1} | {:.1} | {:.2} | {:.2} – {:.2} |",
                r.link[1], r.spline[1], r.ratio[1], r.ratio[0], r.ratio[2]
            );
        }
    }
    let [f32r, f32x8r, _, _] = &timed;
    let (hit, miss) = (&f32r.1[1], &f32r.1[2]);
    let h = hit.ratio[1] - miss.ratio[1];
    // The link runs in every row: its gain pooled over the three sets (one set's pair of
    // medians moved by ±20% between runs).
    let g_l = (0..3).map(|i| f32r.1[i].link[1]).sum::<f64>() / (0..3).map(|i| f32x8r.1[i].link[1]).sum::<f64>();
    let g_hit = (hit.spline[1] - miss.spline[1]) / (f32x8r.1[1].spline[1] - f32x8r.1[2].spline[1]);
    let _ = write!(
        md,
        "\n## The floor of a per-call lane kernel (f32x8, mixed rays)\n\n\
         A lane call answers its {w} pairs; the k_p hits of pack p cost at least H·min(k_p, {w}/G_s) links (lane by \
         lane at the scalar cost, or one lane pass at ≥ {w}·H/G_s), rejections and misses counted as free, so \
         f32x8 mixed spline ÷ link ≥ (G_l·H/{N})·Σ_p min(k_p, {w}/G_s) (derivation: \
         `crates/lab/src/report/spline_lanes.rs`). The inputs, from the rows above:\n\n\
         | input | value | from |\n|---|---|---|\n\
         | k_p | {} | hits per pack of {w} in the mixed set ({} of {N}), f64 kernel |\n\
         | H | {h:.2} | the hit path (a hit's cost beyond a miss's) in links: f32 spline ÷ link, hits − misses ({:.2} − {:.2}) |\n\
         | G_l | {g_l:.2} | the link's gain from lanes: link f32 ÷ link f32x8 per pair, summed over the three sets |\n\
         | G_s today | {g_hit:.2} | the hit path's gain from lanes: (spline hits − misses) f32 ÷ f32x8 per pair |\n\n\
         | hit path's lane gain G_s | floor of spline ÷ link, f32x8 mixed |\n|---|---|\n",
        k.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(" "),
        k.iter().sum::<usize>(),
        hit.ratio[1],
        miss.ratio[1]
    );
    for (label, g) in [
        (format!("{g_hit:.2} (today's)"), g_hit),
        (format!("{g_l:.2} (the link's)"), g_l),
        ("4 (SSE width, no AVX2)".to_string(), 4.0),
        (format!("{w} (every lane useful)"), w as f64),
    ] {
        let _ = writeln!(md, "| {label} | {:.2} |", floor(&k, w, N, h, g_l, g));
    }
    let need = gain_needed(&k, w, N, h, g_l, 4.0);
    let _ = write!(
        md,
        "\nFor ≤ 4× with today's hit path (H = {h:.2}): {}. Where the hit path gains what the link gains \
         (G_s = G_l), ≤ 4× needs H ≤ {:.2} links per hit in scalar.\n",
        need.map_or(format!("no gain from lanes is enough, not even {w} per pair (every lane useful)"), |g| {
            format!("the hit path would have to gain G_s ≥ {g:.2} from lanes per pair")
        }),
        4.0 * h / floor(&k, w, N, h, g_l, g_l)
    );
    let mdp = out.join("spline_lanes.md");
    write_text(&mdp, &md)?;
    Ok(ReportFiles { markdown: mdp, charts: Vec::new() })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed: packs [3, 1, 0, 2], w = 4, n = 16, H = 8, G_l = 2. At G_s = 2 the cap is
    /// 4/2 = 2: Σ min = 2 + 1 + 0 + 2 = 5, floor = 2·8/16·5 = 5. At G_s = 4 the cap is 1: Σ = 3,
    /// floor = 3. At G_s = 1 the cap is 4: Σ = 6, floor = 6.
    #[test]
    fn floor_by_hand() {
        let k = [3, 1, 0, 2];
        assert_eq!(floor(&k, 4, 16, 8.0, 2.0, 2.0), 5.0);
        assert_eq!(floor(&k, 4, 16, 8.0, 2.0, 4.0), 3.0);
        assert_eq!(floor(&k, 4, 16, 8.0, 2.0, 1.0), 6.0);
    }

    /// Target 4 on the case above: Σ min(k, 4/G_s) must be ≤ 4, i.e. cap c with
    /// min(3,c) + min(1,c) + min(2,c) ≤ 4: c = 1.5 gives 1.5 + 1 + 1.5 = 4, so G_s = 4/1.5 = 8/3.
    /// Target 2 needs Σ ≤ 2, below the 3 of every lane useful (G_s = 4): none.
    #[test]
    fn gain_needed_by_hand() {
        let k = [3, 1, 0, 2];
        let g = gain_needed(&k, 4, 16, 8.0, 2.0, 4.0).unwrap();
        assert!((g - 8.0 / 3.0).abs() < 1e-9, "{g}");
        assert_eq!(gain_needed(&k, 4, 16, 8.0, 2.0, 2.0), None);
    }
}
