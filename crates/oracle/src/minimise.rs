//! One-dimensional minimisers: golden-section search on values, and bisection on the sign of a
//! derivative.

/// Golden-section minimisation of a unimodal function on `[lo, hi]`: `(argmin, min)`.
///
/// The bracket shrinks by `g = (√5 − 1)/2` per step until it is below `1e-17·(1 + |x|)` (about
/// one ulp: the loop then stops making progress) or after 200 steps (`g²⁰⁰ ≈ 1e-42` of the
/// initial width); the result is the best of the final midpoint, both interior points and both
/// end points, so a monotone function returns its end point exactly.
///
/// On a smooth minimum the *value* is then exact to rounding, but the *argmin* only to `~√ε`
/// (the function is flat to second order there); use [`convex_argmin`] where the argmin itself
/// matters and a derivative is available.
pub fn golden_min(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo, hi);
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= 1e-17 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let mut best = ((a + b) / 2.0, f((a + b) / 2.0));
    for x in [lo, hi, c, d] {
        let v = f(x);
        if v < best.1 {
            best = (x, v);
        }
    }
    best
}

/// Minimiser of a convex differentiable function on `[0, 1]` by bisection on the sign of its
/// derivative `df` (monotone): resolves the argmin to ~1 ulp, where golden-section search on
/// values only resolves it to ~√ε (the function is flat to second order there).
///
/// The loop halves `[a, b]` until the midpoint equals an end (at most ~1075 halvings reach the
/// smallest subnormal spacing; 1100 is a safe cap).
pub fn convex_argmin(df: impl Fn(f64) -> f64) -> f64 {
    if df(0.0) >= 0.0 {
        return 0.0;
    }
    if df(1.0) <= 0.0 {
        return 1.0;
    }
    let (mut a, mut b) = (0.0f64, 1.0f64);
    for _ in 0..1100 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if df(m) < 0.0 {
            a = m
        } else {
            b = m
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_min_finds_a_parabola_vertex() {
        // f(x) = (x − 0.3)² + 2: min 2 at 0.3. The value is exact to rounding; the argmin is
        // resolved to ~√ε ≈ 1.5e-8 (second-order flatness), so allow 1e-7.
        let (x, v) = golden_min(|x| (x - 0.3) * (x - 0.3) + 2.0, -1.0, 4.0);
        assert!((x - 0.3).abs() < 1e-7, "argmin {x}");
        assert!((v - 2.0).abs() <= 2.0 * f64::EPSILON, "min {v}");
    }

    #[test]
    fn golden_min_returns_the_end_of_a_monotone_function() {
        assert_eq!(golden_min(|x| x, 0.25, 0.75), (0.25, 0.25));
        assert_eq!(golden_min(|x| -x, 0.25, 0.75), (0.75, -0.75));
    }

    #[test]
    fn convex_argmin_resolves_the_argmin_to_an_ulp() {
        // f(x) = (x − 1/3)², f' = 2(x − 1/3): the argmin is 1/3 to one or two ulps.
        let x = convex_argmin(|x| 2.0 * (x - 1.0 / 3.0));
        assert!((x - 1.0 / 3.0).abs() <= 2.0 * f64::EPSILON, "{x}");
        assert_eq!(convex_argmin(|x| x + 1.0), 0.0, "increasing: left end");
        assert_eq!(convex_argmin(|x| x - 2.0), 1.0, "decreasing: right end");
    }
}
