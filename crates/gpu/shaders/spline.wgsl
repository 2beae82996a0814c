// The spline piece kernel in f32, appended to link.wgsl (whose vector helpers, `Iv`, `EPS` and
// `inf()` it uses) with ray_space.wgsl and roots.wgsl (`crate::kernel::SPLINE_WGSL` joins the
// three): a port of the CPU's default solver, `Solver::Polynomial` (`src/kernel/spline.rs`:
// `QuadTube::line_interval_with`, `polynomial_line`, `intersect_pieces`/`pieces_in`), with `g`
// from the vectors (`src/kernel/spline/direct.rs`) and the candidates and their polish
// (`src/kernel/spline/ray_space.rs`) here; the capsule filter, rejections and ray-space set-up
// in ray_space.wgsl; the root finders (`src/math/roots.rs`, `src/math/quadric.rs`) in roots.wgsl.
//
// The CPU's Polynomial solver first tries a certified root count (`RaySpace::certified`: Descartes'
// rule on Bernstein coefficients of `P`, Taylor bounds) and takes `P`'s derivative cascade for the
// rays it cannot certify. Both paths return the interval of the kernel's band (`E`,
// `crate::spline_error_band`; the kernel tests hold each path to it). This port is the cascade
// path (`polynomial_line` with `Path::Cascade`) for every ray: one code path, no Descartes table.
//
// Every expression keeps the Rust one's operands and evaluation order (no fused multiply-add,
// products left to right as Rust writes `a * b * c`), as link.wgsl does. Rust's closures
// (the function a root finder solves) become a function id (`FN_*`) that `ev` dispatches on; the
// query's ray-space data live in private variables (`rs_*`, `dg_*`). NaN starts of the Rust
// (`no_start`, a model without a root) are `-inf()` here: like NaN, never strictly inside a
// bracket. Lanes do not exist here: a Rust mask is a bool, `T::select(m, a, b)` is `select(b, a, m)`.
// The constants are checked against the Rust sources by `tests/gpu/constants.rs`.

// direct.rs Direct::new: `T::epsilon() * T::cst(16.0) * (sw + sr)` (the gap's rounding τ).
const TAU_ULPS: f32 = 16.0;

// The functions a root finder solves (the Rust closures), with their derivatives.
// Direct::g1 (f), g2 (f'), g3 (f''): g_extrema's Halley level.
const FN_G1: u32 = 0u;
// Direct::g_sq (f), g1, g2: the roots of g (g_roots_from, Newton).
const FN_GSQ: u32 = 1u;
// ray_space.rs polish: F₁ = 2σh'√g − g' (ITP only).
const FN_F1: u32 = 2u;
// poly_breakpoints: level k of P's cascade is FN_POLY + k (f = P⁽ᵏ⁾, f' = P⁽ᵏ⁺¹⁾).
const FN_POLY: u32 = 3u;

// Starts of the Halley solves (cascade_level_halley's `start`).
const START_NONE: u32 = 0u;
const START_G1: u32 = 1u;
const START_G: u32 = 2u;

// ---- RaySpace (ray_space.rs) and Direct (direct.rs) of the current query ----
var<private> rs_h: vec3f;
var<private> rs_qa: vec3f;
var<private> rs_qb: vec3f;
var<private> rs_qc: vec3f;
var<private> rs_dhat: vec3f;
var<private> rs_tc: f32;
var<private> rs_inv_dlen: f32;
var<private> rs_tv: f32;
// P in powers of t − tv and its derivatives (poly_breakpoints' `ders`).
var<private> ders: array<array<f32, 7>, 5>;
var<private> dg_wa: vec3f;
var<private> dg_wb: vec3f;
var<private> dg_wc: vec3f;
var<private> dg_ra: f32;
var<private> dg_rb: f32;
var<private> dg_rc: f32;
var<private> dg_w_end: vec3f;
var<private> dg_r_end: f32;
var<private> dg_tau: f32;
// polish: h' scaled by σ.
var<private> pol_h1: vec2f;

fn nan_start() -> f32 {
    return -inf();
}
fn finite(x: f32) -> bool {
    return abs(x) < inf();
}
fn max_abs(v: vec3f) -> f32 {
    return max(max(abs(v.x), abs(v.y)), abs(v.z));
}
// ---- direct.rs: Direct ----
// Direct::wr: (w, r) at t, the end values at t ≥ 1.
fn dg_wr(t: f32) -> vec4f {
    let w = (dg_wa * t + dg_wb) * t + dg_wc;
    let r = (dg_ra * t + dg_rb) * t + dg_rc;
    if t >= 1.0 {
        return vec4f(dg_w_end, dg_r_end);
    }
    return vec4f(w, r);
}
// Direct::gap_g: (r − |w|, (r − |w|)(r + |w|)).
fn gap_g(t: f32) -> vec2f {
    let wr = dg_wr(t);
    let lw = len3(wr.xyz);
    let gap = wr.w - lw;
    return vec2f(gap, gap * (wr.w + lw));
}
fn g_of(t: f32) -> f32 {
    return gap_g(t).y;
}
// Direct::g_sq: r² − |w|².
fn g_sq(t: f32) -> f32 {
    let wr = dg_wr(t);
    return wr.w * wr.w - dot3(wr.xyz, wr.xyz);
}
// Direct::jet: w' = wa·2t + wb, r' = 2·ra·t + rb.
fn jet_w1(t: f32) -> vec3f {
    return dg_wa * (2.0 * t) + dg_wb;
}
fn jet_r1(t: f32) -> f32 {
    return 2.0 * dg_ra * t + dg_rb;
}
// Direct::gap_g_g1
fn gap_g_g1(t: f32) -> vec3f {
    let wr = dg_wr(t);
    let w1 = jet_w1(t);
    let r1 = jet_r1(t);
    let lw = len3(wr.xyz);
    let gap = wr.w - lw;
    return vec3f(gap, gap * (wr.w + lw), 2.0 * (wr.w * r1 - dot3(wr.xyz, w1)));
}
// Direct::g1: 2(r r' − w·w').
fn g1_of(t: f32) -> f32 {
    let wr = dg_wr(t);
    return 2.0 * (wr.w * jet_r1(t) - dot3(wr.xyz, jet_w1(t)));
}
// Direct::g2: 2(r'² + r·2ra − |w'|² − w·2wa).
fn g2_of(t: f32) -> f32 {
    let wr = dg_wr(t);
    let w1 = jet_w1(t);
    let r1 = jet_r1(t);
    return 2.0 * (r1 * r1 + wr.w * (2.0 * dg_ra) - dot3(w1, w1) - dot3(wr.xyz, dg_wa * 2.0));
}
// Direct::g3_coeffs
fn g3_coeffs() -> vec2f {
    return vec2f(dg_ra * dg_rb - dot3(dg_wa, dg_wb), dg_ra * dg_ra - dot3(dg_wa, dg_wa));
}
// Direct::g3: 12(c0 + 2t·c1).
fn g3_of(t: f32) -> f32 {
    let c = g3_coeffs();
    return 12.0 * (c.x + 2.0 * t * c.y);
}

// ray_space.rs polish's f1: 2·h1σ(x)·√max(g, 0) − g'.
fn f1_of(x: f32) -> f32 {
    return 2.0 * horner2(pol_h1, x) * sqrt(max(g_of(x), 0.0)) - g1_of(x);
}

// The function `id`'s derivative of order `k` (0, 1, 2) at x (the Rust closures f, df, d2f).
fn ev(id: u32, k: u32, x: f32) -> f32 {
    switch id {
        case FN_G1: {
            if k == 0u {
                return g1_of(x);
            }
            if k == 1u {
                return g2_of(x);
            }
            return g3_of(x);
        }
        case FN_GSQ: {
            if k == 0u {
                return g_sq(x);
            }
            if k == 1u {
                return g1_of(x);
            }
            return g2_of(x);
        }
        case FN_F1: {
            return f1_of(x);
        }
        default: {
            // poly_breakpoints: f = horner_slice(&p[..=deg]), df = horner_slice(&dp[..deg]).
            let lvl = id - FN_POLY;
            return horner_der(lvl + k, 6u - lvl - k, x);
        }
    }
}

// direct.rs Direct::g1_root_start
fn g1_root_start(a: f32, b: f32, fa: f32, fb: f32) -> f32 {
    let from_a = abs(fa) <= abs(fb);
    let e = select(b, a, from_a);
    let f = select(fb, fa, from_a);
    let dir = select(-1.0, 1.0, from_a);
    let r = -2.0 * f / g3_of(e);
    let ok = e > 0.0 && e < 1.0 && r > 0.0;
    return select(nan_start(), e + dir * sqrt(max(r, 0.0)), ok);
}

// direct.rs Direct::g_root_start (g_jet's g', g'' at e: the formulas of g1_of, g2_of).
fn g_root_start(a: f32, b: f32, ga: f32, gb: f32) -> f32 {
    let from_a = abs(ga) <= abs(gb);
    let e = select(b, a, from_a);
    return model_start(e, select(-1.0, 1.0, from_a), select(gb, ga, from_a), g1_of(e), g2_of(e));
}

fn start_of(kind: u32, a: f32, b: f32, fa: f32, fb: f32) -> f32 {
    if kind == START_G1 {
        return g1_root_start(a, b, fa, fb);
    }
    if kind == START_G {
        return g_root_start(a, b, fa, fb);
    }
    return nan_start();
}

// ---- direct.rs: g_extrema (Bracket::Newton), g_roots_from ----
fn g_extrema() -> array<f32, 5> {
    let bc = g3_coeffs();
    let b = bc.x;
    let a = bc.y;
    let c = dg_rb * dg_rb + 2.0 * dg_ra * dg_rc - dot3(dg_wb, dg_wb) - 2.0 * dot3(dg_wa, dg_wc);
    let x = quadratic_roots_in(c, 6.0 * b, 6.0 * a, 0.0, 1.0);
    var bp = array<f32, 8>(0.0, x.x, x.y, 1.0, 1.0, 1.0, 1.0, 1.0);
    let ext = cascade(bp, 4u, FN_G1, true, START_G1);
    return array<f32, 5>(ext[0], ext[1], ext[2], ext[3], ext[4]);
}

// The roots of g from its extrema: g_roots_started (start = START_G) or g_roots (START_NONE).
fn g_roots(e: array<f32, 5>, start: u32) -> array<f32, 6> {
    let ext = array<f32, 8>(e[0], e[1], e[2], e[3], e[4], e[4], e[4], e[4]);
    let bp = cascade(ext, 5u, FN_GSQ, true, start);
    return array<f32, 6>(bp[0], bp[1], bp[2], bp[3], bp[4], bp[5]);
}

// ---- ray_space.rs: p_breakpoints (poly_breakpoints of P about tv, shifted back) ----
fn p_breakpoints() -> array<f32, 8> {
    let lo = -rs_tv;
    let hi = 1.0 - rs_tv;
    let x = quadratic_roots_in(ders[4][0], ders[4][1], ders[4][2], lo, hi);
    var bp = array<f32, 8>(lo, x.x, x.y, hi, hi, hi, hi, hi);
    var n = 4u;
    var k = 4u;
    while k > 0u {
        k--;
        bp = cascade(bp, n, FN_POLY + k, false, START_NONE);
        n++;
    }
    var res: array<f32, 8>;
    for (var i = 0u; i < 8u; i++) {
        let t = clampr(rs_tv + bp[i], 0.0, 1.0);
        res[i] = select(select(t, 1.0, bp[i] >= hi), 0.0, bp[i] <= lo);
    }
    return res;
}

// ---- ray_space.rs: val, polish, best_of_candidates, polished_candidates, interval ----
// Crossings: s_in, u_in, s_out, u_out.
struct Crossings {
    s_in: f32,
    u_in: f32,
    s_out: f32,
    u_out: f32,
}

// σh − √max(g, 0)
fn val(t: f32, sigma: f32) -> f32 {
    return sigma * horner3(rs_h, t) - sqrt(max(g_of(t), 0.0));
}

// (value, t) of the polished candidate.
fn polish(t: f32, v: f32, sigma: f32, left: f32, right: f32) -> vec2f {
    pol_h1 = vec2f(rs_h.y * sigma, 2.0 * rs_h.z * sigma);
    let ft = f1_of(t);
    let go_right = ft < 0.0;
    let a = select(left, t, go_right);
    let b = select(t, right, go_right);
    let fa = select(f1_of(left), ft, go_right);
    let fb = select(ft, f1_of(right), go_right);
    let valid = opposite(fa, fb);
    if !valid {
        return vec2f(v, t);
    }
    let x = itp(FN_F1, a, b, fa, fb, valid);
    let vx = val(x, sigma);
    let better = valid && vx < v && gap_g(x).x >= -dg_tau;
    return select(vec2f(v, t), vec2f(vx, x), better);
}

// The candidates: `cand[..nc]` (P's roots and g's roots or extrema), each clamped to [lo, hi].
struct Best {
    cr: Crossings,
    found: bool,
    in_lo: f32,
    in_hi: f32,
    out_lo: f32,
    out_hi: f32,
}

fn best_of_candidates(cand: array<f32, 16>, nc: u32, lo: f32, hi: f32, all_real: bool) -> Best {
    let h1 = vec2f(rs_h.y, 2.0 * rs_h.z);
    var bi = inf();
    var ti = lo;
    var bo = inf();
    var to = lo;
    var any_ok = false;
    var at_t: array<f32, 16>;
    var at_i: array<f32, 16>;
    var at_o: array<f32, 16>;
    for (var k = 0u; k < nc; k++) {
        let t = clampr(cand[k], lo, hi);
        let gg = gap_g_g1(t);
        let ok = all_real || gg.x >= -dg_tau;
        let hv = horner3(rs_h, t);
        let sq = sqrt(max(gg.y, 0.0));
        let vi = hv - sq;
        let vo = -hv - sq;
        let bi_ = ok && vi < bi;
        let bo_ = ok && vo < bo;
        bi = select(bi, vi, bi_);
        ti = select(ti, t, bi_);
        bo = select(bo, vo, bo_);
        to = select(to, t, bo_);
        any_ok = any_ok || ok;
        let hs = 2.0 * horner2(h1, t) * sq;
        at_t[k] = t;
        at_i[k] = hs - gg.z;
        at_o[k] = -hs - gg.z;
    }
    var fi = 0.0;
    var fo = 0.0;
    for (var k = 0u; k < nc; k++) {
        fi = select(fi, at_i[k], at_t[k] == ti);
        fo = select(fo, at_o[k], at_t[k] == to);
    }
    let ri = fi < 0.0;
    let ro = fo < 0.0;
    var nb = vec4f(lo, hi, lo, hi);
    for (var k = 0u; k < nc; k++) {
        let t = at_t[k];
        let right_i = ri && at_i[k] >= 0.0;
        let left_i = !ri && at_i[k] <= 0.0;
        let right_o = ro && at_o[k] >= 0.0;
        let left_o = !ro && at_o[k] <= 0.0;
        nb.x = select(nb.x, t, left_i && t < ti && t > nb.x);
        nb.y = select(nb.y, t, right_i && t > ti && t < nb.y);
        nb.z = select(nb.z, t, left_o && t < to && t > nb.z);
        nb.w = select(nb.w, t, right_o && t > to && t < nb.w);
    }
    var b: Best;
    b.cr = Crossings(bi, ti, -bo, to);
    b.found = any_ok;
    b.in_lo = nb.x;
    b.in_hi = nb.y;
    b.out_lo = nb.z;
    b.out_hi = nb.w;
    return b;
}

fn polished_candidates(cand: array<f32, 16>, nc: u32, lo: f32, hi: f32, all_real: bool) -> Best {
    var best = best_of_candidates(cand, nc, lo, hi, all_real);
    let i = polish(best.cr.u_in, best.cr.s_in, 1.0, best.in_lo, best.in_hi);
    let o = polish(best.cr.u_out, -best.cr.s_out, -1.0, best.out_lo, best.out_hi);
    best.cr = Crossings(i.x, i.y, -o.x, o.y);
    return best;
}

fn ray_q(t: f32) -> vec3f {
    return rs_qa * (t * t) + rs_qb * t + rs_qc;
}

fn normal_at(s: f32, u: f32, fallback: vec3f) -> vec3f {
    let n = normalize_or_zero(rs_dhat * s - ray_q(u));
    return select(fallback, n, len2(n) > 0.0);
}

// RaySpace::interval for a line with the whole range (−∞, ∞): `clip` and not are alike there
// but for `t_in ≤ t_out` (in_range's other terms hold). `found` includes RaySpace's `near`.
fn rs_interval(x: Crossings, found: bool) -> Iv {
    let t_in = rs_tc + x.s_in * rs_inv_dlen;
    let t_out = rs_tc + x.s_out * rs_inv_dlen;
    if !(found && t_in <= t_out) {
        return iv_miss();
    }
    var iv: Iv;
    iv.t_in = t_in;
    iv.t_out = t_out;
    iv.n_in = normal_at(x.s_in, x.u_in, -rs_dhat);
    iv.n_out = normal_at(x.s_out, x.u_out, rs_dhat);
    iv.u_in = x.u_in;
    iv.u_out = x.u_out;
    iv.hit = true;
    return iv;
}

// ---- spline.rs: QuadTube::line_interval_with(ray, Solver::Polynomial) ----
// The hull [first entry, last exit] of the line (o + τ·d, τ ∈ ℝ) with the sweep of control
// points b and radii r; `polynomial_line` on P's cascade (see the top of this file).
fn spline_line(b0: vec3f, b1: vec3f, b2: vec3f, r: vec3f, o: vec3f, d: vec3f) -> Iv {
    if capsule_misses(b0, b1, b2, r, o, d) {
        return iv_miss();
    }
    if !ray_space(b0, b1, b2, r, o, d) {
        return iv_miss();
    }
    // polynomial_line: g's breakpoints hold its maxima; none real: a miss.
    let extrema = g_extrema();
    var is_real = false;
    for (var i = 0u; i < 5u; i++) {
        is_real = is_real || gap_g(extrema[i]).x >= -dg_tau;
    }
    if !is_real {
        return iv_miss();
    }
    let roots = g_roots(extrema, START_G);
    let bp = p_breakpoints();
    // P's roots bp[1..7], then g's roots z[1..5] and extrema (polished_candidates' c, extra).
    var cand: array<f32, 16>;
    for (var i = 0u; i < 6u; i++) {
        cand[i] = bp[i + 1u];
    }
    for (var i = 0u; i < 4u; i++) {
        cand[6u + i] = roots[i + 1u];
    }
    for (var i = 0u; i < 5u; i++) {
        cand[10u + i] = extrema[i];
    }
    let best = polished_candidates(cand, 15u, 0.0, 1.0, false);
    return rs_interval(best.cr, best.found && is_real);
}

// ---- spline.rs: QuadTube::intersect_pieces(ray, Solver::Polynomial) (pieces_in, clip) ----
// One interval per real interval of g (at most 5 slots, misses in the others; no capsule
// filter, as the CPU's).
struct Pieces {
    iv: array<Iv, 5>,
}

fn spline_pieces(b0: vec3f, b1: vec3f, b2: vec3f, r: vec3f, o: vec3f, d: vec3f) -> Pieces {
    var ps: Pieces;
    for (var k = 0u; k < 5u; k++) {
        ps.iv[k] = iv_miss();
    }
    if !ray_space(b0, b1, b2, r, o, d) {
        return ps;
    }
    // Direct::g_breakpoints(Bracket::Newton)
    let extrema = g_extrema();
    let z = g_roots(extrema, START_NONE);
    var real_k: array<bool, 5>;
    for (var k = 0u; k < 5u; k++) {
        let mid = (z[k] + z[k + 1u]) * 0.5;
        real_k[k] = g_of(mid) > 0.0 && z[k + 1u] > z[k];
    }
    var cut = array<bool, 6>(true, true, true, true, true, true);
    for (var j = 1u; j < 5u; j++) {
        let rj = real_k[j - 1u] && real_k[j];
        cut[j] = !rj || g_of(z[j]) <= 0.0;
    }
    let bp = p_breakpoints();
    var cand: array<f32, 16>;
    for (var i = 0u; i < 6u; i++) {
        cand[i] = bp[i + 1u];
    }
    for (var i = 0u; i < 5u; i++) {
        cand[6u + i] = extrema[i];
    }
    for (var k = 0u; k < 5u; k++) {
        let first = real_k[k] && cut[k];
        if !first {
            continue;
        }
        let lo = z[k];
        var hi = z[k + 1u];
        var open = true;
        for (var j = k + 1u; j < 5u; j++) {
            open = open && !cut[j];
            hi = select(hi, z[j + 1u], open);
        }
        let best = polished_candidates(cand, 11u, lo, hi, true);
        ps.iv[k] = rs_interval(best.cr, first);
    }
    return ps;
}
