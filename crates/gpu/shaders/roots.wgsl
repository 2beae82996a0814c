// The root finders of the derivative cascade in f32, appended to link.wgsl (helpers, `EPS`)
// with spline.wgsl (which defines `ev`, the function a solve is of, and `start_of`, its start):
// a port of `src/math/roots.rs` (`horner`, `opposite`, `default_tol`, `regula_falsi`,
// `model_start`, the safeguarded Newton/Halley solve `halley_or_newton`, `itp`, `level_with`
// behind `cascade_level` and `cascade_level_halley`) and of `src/math/quadric.rs`
// (`quadratic_roots_in`). The conventions are spline.wgsl's; the constants are checked against
// the Rust sources by `tests/gpu/constants.rs`.

// src/math/roots.rs: MAX_ITER (ITP and Newton iteration cap).
const MAX_ITER: u32 = 64u;
// src/math/roots.rs: default_tol, `T::epsilon() * T::cst(4.0)`.
const TOL_ULPS: f32 = 4.0;
// math/roots.rs itp: `T::cst(0.2) / ...` (κ₁·w₀).
const ITP_K1: f32 = 0.2;


fn opposite(fa: f32, fb: f32) -> bool {
    return (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0);
}
fn tol() -> f32 {
    return EPS * TOL_ULPS;
}


// ---- math/roots.rs: horner ----
fn horner3(c: vec3f, x: f32) -> f32 {
    return (c.z * x + c.y) * x + c.x;
}
fn horner2(c: vec2f, x: f32) -> f32 {
    return c.y * x + c.x;
}
// horner_slice over ders[k][0..=deg]: the same operations in the same order, written out over
// the seven slots without a loop (a loop here would be the kernel's busiest: several passes per
// solver step, from lavapipe's loop budget, tree.wgsl's `loops_cut`). Slots above `deg` are
// passed over: `acc` restarts as ders[k][deg] at slot `deg`, as the loop starts.
fn horner_der(k: u32, deg: u32, x: f32) -> f32 {
    let c = ders[k];
    var acc = c[6];
    acc = select(acc * x + c[5], c[5], deg == 5u);
    acc = select(acc * x + c[4], c[4], deg == 4u);
    acc = select(acc * x + c[3], c[3], deg == 3u);
    acc = select(acc * x + c[2], c[2], deg == 2u);
    acc = select(acc * x + c[1], c[1], deg == 1u);
    acc = select(acc * x + c[0], c[0], deg == 0u);
    return acc;
}


// ---- math/quadric.rs: quadratic_roots_in(c, lo, hi) ----
fn quadratic_roots_in(c0: f32, c1: f32, c2: f32, lo: f32, hi: f32) -> vec2f {
    let a = c2;
    let b = c1;
    let cc = c0;
    let disc = b * b - 4.0 * a * cc;
    let has2 = disc >= 0.0 && abs(a) > 0.0;
    let q = citardauq_q(b, sqrt(max(disc, 0.0))) * 0.5;
    let qs = select(q, 1.0, q == 0.0);
    let a_s = select(1.0, a, has2);
    var x1 = select(hi, q / a_s, has2);
    let x2 = select(select(hi, x1, has2), cc / qs, has2 && abs(q) > 0.0);
    let lin = a == 0.0 && abs(b) > 0.0;
    let bl = select(1.0, b, lin);
    x1 = select(x1, -cc / bl, lin);
    let y1 = clampr(x1, lo, hi);
    let y2 = clampr(x2, lo, hi);
    return vec2f(min(y1, y2), max(y1, y2));
}

// ---- math/roots.rs: regula_falsi, model_start ----
fn regula_falsi(a: f32, b: f32, fa: f32, fb: f32) -> f32 {
    let den = fb - fa;
    return a - fa * (b - a) / select(den, 1.0, den == 0.0);
}

fn model_start(e: f32, dir: f32, f: f32, f1: f32, f2: f32) -> f32 {
    let disc = f1 * f1 - 2.0 * f * f2;
    let sq = sqrt(max(disc, 0.0));
    let q = -0.5 * (f1 + select(-sq, sq, f1 >= 0.0));
    let d1 = q / (0.5 * f2);
    let d2 = f / q;
    let ok1 = (d1 * dir) > 0.0;
    let ok2 = (d2 * dir) > 0.0;
    let d = select(select(nan_start(), d2, ok2), d1, ok1 && (!ok2 || abs(d1) <= abs(d2)));
    return select(nan_start(), e + d, disc >= 0.0);
}


// ---- math/roots.rs: halley_or_newton (Newton::new_at, Newton::step) ----
fn newton(id: u32, use_d2: bool, a0: f32, b0: f32, fa: f32, fb: f32, x0: f32, valid: bool) -> f32 {
    let tl = tol();
    let s = select(1.0, -1.0, fa > 0.0);
    var a = a0;
    var b = b0;
    var ya = fa * s;
    var yb = fb * s;
    var x = select((a + b) * 0.5, clampr(regula_falsi(a, b, ya, yb), a, b), valid);
    var done = !valid || (b - a) <= tl;
    if valid && x0 > a && x0 < b {
        x = x0;
    }
    var it = 0u;
    while !done && it < MAX_ITER {
        it++;
        var d2fx = 0.0;
        if use_d2 {
            d2fx = ev(id, 2u, x);
        }
        let y = ev(id, 0u, x) * s;
        let dy = ev(id, 1u, x) * s;
        if y < 0.0 {
            a = x;
            ya = y;
        }
        if y > 0.0 {
            b = x;
            yb = y;
        }
        let xn = x - y / dy;
        let inside = xn > a && xn < b;
        let xm = (a + b) * 0.5;
        let reach = abs(dy * tl) * 2.0;
        let at_a = !inside && xn <= a && xn >= a - tl && abs(ya) <= reach;
        let at_b = !inside && xn >= b && xn <= b + tl && abs(yb) <= reach;
        var xnew = select(select(select(xm, b, at_b), a, at_a), xn, inside);
        if use_d2 {
            let d2y = d2fx * s;
            let dy2 = dy * dy;
            let yd2 = y * d2y;
            let xh = x - 2.0 * y * dy / (2.0 * dy2 - yd2);
            let take = abs(yd2) <= dy2 && xh > a && xh < b;
            xnew = select(xnew, xh, take);
        }
        let stp = abs(xnew - x);
        let conv = y == 0.0 || stp <= tl || (b - a) <= tl || at_a || at_b;
        if y != 0.0 {
            x = xnew;
        }
        done = done || conv;
    }
    return x;
}

// ---- math/roots.rs: itp (Itp::new, point, update, result) ----
fn itp(id: u32, a0: f32, b0: f32, fa: f32, fb: f32, valid: bool) -> f32 {
    let tl = tol();
    let s = select(1.0, -1.0, fa > 0.0);
    var a = a0;
    var b = b0;
    let w0 = b - a;
    let k1 = ITP_K1 / select(1.0, w0, w0 > 0.0);
    var xprev = (a + b) * 0.5;
    var ya = fa * s;
    var yb = fb * s;
    var rmax = w0;
    var done = !valid || w0 <= tl * 2.0;
    var stepped = false;
    var xlast = xprev;
    var it = 0u;
    while !done && it < MAX_ITER {
        it++;
        // Itp::point
        let w = b - a;
        let xh = (a + b) * 0.5;
        let r = rmax - w * 0.5;
        let delta = k1 * w * w;
        let den = yb - ya;
        let xf = (yb * a - ya * b) / select(1.0, den, den > 0.0);
        let sigma = select(-1.0, 1.0, xh >= xf);
        let xt = select(xh, xf + sigma * delta, delta <= abs(xh - xf));
        let x = clampr(select(xh - sigma * r, xt, abs(xt - xh) <= r), a, b);
        // Itp::update
        let y = ev(id, 0u, x) * s;
        let lo = y < 0.0;
        let hi = y > 0.0;
        let ex = y == 0.0;
        if lo || ex {
            a = x;
        }
        if lo {
            ya = y;
        }
        if hi || ex {
            b = x;
        }
        if hi {
            yb = y;
        }
        rmax = rmax * 0.5;
        let st = abs(x - xprev) <= tl && it > 1u;
        stepped = stepped || st || ex;
        xlast = x;
        xprev = x;
        done = done || (b - a) <= tl * 2.0 || ex || st;
    }
    return select((a + b) * 0.5, xlast, stepped);
}

// ---- math/roots.rs: level_with (cascade_level, cascade_level_halley) ----
// Pieces are solved one at a time (the CPU's scalar pairs give the same roots: `pair_of`).
fn cascade(bp: array<f32, 8>, n: u32, id: u32, use_d2: bool, start: u32) -> array<f32, 8> {
    var fv: array<f32, 8>;
    for (var i = 0u; i < n; i++) {
        fv[i] = ev(id, 0u, bp[i]);
    }
    var res: array<f32, 8>;
    res[0] = bp[0];
    res[n] = bp[n - 1u];
    let nudge = sqrt(EPS);
    for (var i = 0u; i < n - 1u; i++) {
        var a = bp[i];
        var b = bp[i + 1u];
        var fa = fv[i];
        var fb = fv[i + 1u];
        var za = fa == 0.0;
        var zb = fb == 0.0;
        if za || zb {
            let w = (b - a) * nudge;
            let a2 = a + w;
            let b2 = b - w;
            let ok = w > 0.0;
            za = za && ok;
            zb = zb && ok;
            if za {
                a = a2;
                fa = ev(id, 0u, a2);
            }
            if zb {
                b = b2;
                fb = ev(id, 0u, b2);
            }
        }
        let valid = opposite(fa, fb);
        res[i + 1u] = select(bp[i + 1u], bp[i], fv[i] == 0.0);
        if valid {
            res[i + 1u] = newton(id, use_d2, a, b, fa, fb, start_of(start, a, b, fa, fb), valid);
        }
    }
    return res;
}
