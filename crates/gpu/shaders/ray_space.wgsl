// The spline kernel's set-up in f32, part of spline.wgsl (its conventions; appended with it to
// link.wgsl): the chord-capsule filter (`src/kernel/spline/capsule.rs`), the exact early
// rejections (`src/kernel/spline/ray_space/reject.rs`) and `RaySpace::new`
// (`src/kernel/spline/ray_space.rs`), which fills spline.wgsl's private `rs_*`, `dg_*` and
// `ders`. The constants are checked against the Rust sources by `tests/gpu/constants.rs`.

// ray_space.rs RaySpace::new: f32 tiny-tube threshold 2⁻³⁸ and its scaling 2⁹⁰ (`(-38, 90)`).
const TINY_EXP: i32 = -38;
const TINY_UP_EXP: i32 = 90;
// reject.rs hull_misses: `rho + T::cst(128.0) * eps` and `T::cst(16.0) * eps * (...)`.
const HULL_REACH: f32 = 128.0;
const HULL_ORIENT: f32 = 16.0;
// reject.rs g_hull_misses: `-(T::cst(256.0) * T::epsilon())`.
const G_HULL_LIM: f32 = 256.0;
// capsule.rs capsule_misses: `T::cst(16384.0) * eps + T::cst(64.0) * eps * n1(w)`.
const CAPSULE_ABS: f32 = 16384.0;
const CAPSULE_REL: f32 = 64.0;

// ---- ray_space/reject.rs ----
fn hull_misses(c0: vec3f, c1: vec3f, c2: vec3f, rho: f32, dhat: vec3f) -> bool {
    var w = array<vec3f, 3>(cross3(c0, dhat), cross3(c1, dhat), cross3(c2, dhat));
    let lim = rho + HULL_REACH * EPS;
    let lim2 = lim * lim;
    var far = true;
    var pos = true;
    var neg = true;
    for (var i = 0u; i < 3u; i++) {
        let a = w[i];
        let b = w[(i + 1u) % 3u];
        let e = b - a;
        let ee = len2(e);
        let s = clampr(-dot3(a, e) / select(1.0, ee, ee > 0.0), 0.0, 1.0);
        far = far && len2(a + e * s) > lim2;
        let o = dot3(cross3(a, b), dhat);
        let k = HULL_ORIENT * EPS * (len2(a) + len2(b));
        pos = pos && o >= -k;
        neg = neg && o <= k;
    }
    return far && !(pos || neg) && lim > 0.0;
}

// math/bezier.rs split_half (N = 5): the left (`left`) or right half's coefficients.
fn split_half5(b: array<f32, 5>, left: bool) -> array<f32, 5> {
    var l: array<f32, 5>;
    var r: array<f32, 5>;
    var w = b;
    l[0] = w[0];
    r[4] = w[4];
    for (var k = 1u; k < 5u; k++) {
        for (var i = 0u; i < 5u - k; i++) {
            w[i] = (w[i] + w[i + 1u]) * 0.5;
        }
        l[k] = w[0];
        r[4u - k] = w[4u - k];
    }
    if left {
        return l;
    }
    return r;
}

fn all_below(v: array<f32, 5>, lim: f32) -> bool {
    var m = true;
    for (var i = 0u; i < 5u; i++) {
        m = m && v[i] < lim;
    }
    return m;
}

fn g_hull_misses(c0: vec3f, c1: vec3f, c2: vec3f, r: vec3f, dhat: vec3f) -> bool {
    let w0 = cross3(c0, dhat);
    let w1 = cross3(c1, dhat);
    let w2 = cross3(c2, dhat);
    // rs: T::cst(1.0 / 6.0)
    let sixth = 1.0 / 6.0;
    let g = array<f32, 5>(
        r.x * r.x - dot3(w0, w0),
        r.x * r.y - dot3(w0, w1),
        (2.0 * r.x * r.z + 4.0 * r.y * r.y - 2.0 * dot3(w0, w2) - 4.0 * dot3(w1, w1)) * sixth,
        r.y * r.z - dot3(w1, w2),
        r.z * r.z - dot3(w2, w2),
    );
    let lim = -(G_HULL_LIM * EPS);
    let l = split_half5(g, true);
    let rr = split_half5(g, false);
    return all_below(split_half5(l, true), lim) && all_below(split_half5(l, false), lim)
        && all_below(split_half5(rr, true), lim) && all_below(split_half5(rr, false), lim);
}

// ---- capsule.rs: capsule_misses ----
fn n1(x: vec3f) -> f32 {
    return abs(x.x) + abs(x.y) + abs(x.z);
}

fn capsule_misses(b0: vec3f, b1: vec3f, b2: vec3f, rr: vec3f, o: vec3f, d: vec3f) -> bool {
    var rho = max(max(rr.x, rr.y), rr.z);
    var v = b2 - b0;
    var sag = b1 - (b0 + b2) * 0.5;
    let s = max(max(max_abs(v), max_abs(sag)), rho);
    let ok = s > 0.0 && finite(s);
    let inv = 1.0 / select(1.0, s, ok);
    v = v * inv;
    sag = sag * inv;
    rho = rho * inv;
    let w = (b0 - o) * inv;
    let d2 = len2(d);
    let id2 = 1.0 / select(1.0, d2, d2 > 0.0);
    let wp = w - d * (dot3(w, d) * id2);
    let vp = v - d * (dot3(v, d) * id2);
    let vp2 = len2(vp);
    let u = clampr(-dot3(wp, vp) / select(1.0, vp2, vp2 > 0.0), 0.0, 1.0);
    let dist2 = len2(wp + vp * u);
    let sigma = 0.5 * n1(sag);
    let reach = rho + sigma + CAPSULE_ABS * EPS + CAPSULE_REL * EPS * n1(w);
    return ok && d2 > 0.0 && dist2 > reach * reach;
}

// ---- ray_space.rs: RaySpace::new (false: no line can meet the sweep) ----
fn ray_space(b0: vec3f, b1: vec3f, b2: vec3f, rr: vec3f, o: vec3f, d: vec3f) -> bool {
    let m = (b0 + b1 * 2.0 + b2) * 0.25;
    let d2 = len2(d);
    let dlen = sqrt(d2);
    let inv_dlen = 1.0 / dlen;
    let dhat = d * inv_dlen;
    let tc = dot3(m - o, d) / d2;
    let l = (o - m) + d * tc;
    let rmax = max(max(abs(rr.x), abs(rr.y)), abs(rr.z));
    let w = max(max(max(max_abs(b0 - m), max_abs(b1 - m)), max_abs(b2 - m)), rmax);
    let tiny = w < ldexp(1.0, TINY_EXP);
    let up = select(1.0, ldexp(1.0, TINY_UP_EXP), tiny);
    let down = select(1.0, ldexp(1.0, -TINY_UP_EXP), tiny);
    let big_up = max(max(len3((b0 - m) * up), len3((b1 - m) * up)), len3((b2 - m) * up)) + rmax * up;
    var near = len2(l * up) <= big_up * big_up;
    let ok = big_up > 0.0 && finite(big_up);
    let big_s = select(1.0, big_up * down, ok);
    let inv = 1.0 / select(1.0, big_up, ok);
    let c0 = ((b0 - m - l) * up) * inv;
    let c1 = ((b1 - m - l) * up) * inv;
    let c2 = ((b2 - m - l) * up) * inv;
    let qa = c0 - c1 * 2.0 + c2;
    let qb = (c1 - c0) * 2.0;
    let qc = c0;
    let r0 = (rr.x * up) * inv;
    let r1 = (rr.y * up) * inv;
    let r2 = (rr.z * up) * inv;
    near = near && !hull_misses(c0, c1, c2, max(max(r0, r1), r2), dhat);
    if !near {
        return false;
    }
    near = near && !g_hull_misses(c0, c1, c2, vec3f(r0, r1, r2), dhat);
    if !near {
        return false;
    }
    let ra = r0 - r1 * 2.0 + r2;
    let rb = (r1 - r0) * 2.0;
    let rc = r0;
    // ray_h
    rs_h = vec3f(dot3(qc, dhat), dot3(qb, dhat), dot3(qa, dhat));
    // The same about the vertex tv of the centre line.
    let qq = dot3(qa, qa);
    let tv0 = -dot3(qb, qa) / (2.0 * select(1.0, qq, qq > 0.0));
    let tv = clampr(select(0.0, tv0, qq > 0.0 && finite(tv0)), 0.0, 1.0);
    let sv = 1.0 - tv;
    // math/bezier.rs bernstein2(tv)
    let wv0 = sv * sv;
    let wv1 = 2.0 * sv * tv;
    let wv2 = tv * tv;
    let qcv = c0 * wv0 + c1 * wv1 + c2 * wv2;
    let qbv = ((c1 - c0) * sv + (c2 - c1) * tv) * 2.0;
    let rcv = r0 * wv0 + r1 * wv1 + r2 * wv2;
    let rbv = ((r1 - r0) * sv + (r2 - r1) * tv) * 2.0;
    // ray_polys([qa, qbv, qcv], [ra, rbv, rcv], dhat)
    let hv = vec3f(dot3(qcv, dhat), dot3(qbv, dhat), dot3(qa, dhat));
    let wa = cross3(qa, dhat);
    let wb = cross3(qbv, dhat);
    let wc = cross3(qcv, dhat);
    let w2 = array<f32, 5>(
        dot3(wc, wc),
        2.0 * dot3(wc, wb),
        dot3(wb, wb) + 2.0 * dot3(wc, wa),
        2.0 * dot3(wb, wa),
        dot3(wa, wa),
    );
    let r2s = array<f32, 5>(rcv * rcv, 2.0 * rcv * rbv, rbv * rbv + 2.0 * rcv * ra, 2.0 * rbv * ra, ra * ra);
    var gv: array<f32, 5>;
    for (var i = 0u; i < 5u; i++) {
        gv[i] = r2s[i] - w2[i];
    }
    // p_of(hv, gv): P = 4h'²g − g'² (poly_mul in its loop order), into ders[0].
    let h1 = vec2f(hv.y, 2.0 * hv.z);
    let g1 = vec4f(gv[1], 2.0 * gv[2], 3.0 * gv[3], 4.0 * gv[4]);
    var h1s = array<f32, 3>(0.0, 0.0, 0.0);
    for (var i = 0u; i < 2u; i++) {
        for (var j = 0u; j < 2u; j++) {
            h1s[i + j] += h1[i] * h1[j];
        }
    }
    var pa: array<f32, 7>;
    var pb: array<f32, 7>;
    for (var i = 0u; i < 3u; i++) {
        for (var j = 0u; j < 5u; j++) {
            pa[i + j] += h1s[i] * gv[j];
        }
    }
    for (var i = 0u; i < 4u; i++) {
        for (var j = 0u; j < 4u; j++) {
            pb[i + j] += g1[i] * g1[j];
        }
    }
    // poly_breakpoints: ders[k][i] = ders[k − 1][i + 1]·(i + 1).
    for (var i = 0u; i < 7u; i++) {
        ders[0][i] = 4.0 * pa[i] - pb[i];
    }
    for (var k = 1u; k < 5u; k++) {
        for (var i = 0u; i < 7u; i++) {
            ders[k][i] = 0.0;
        }
        for (var i = 0u; i < 7u - k; i++) {
            ders[k][i] = ders[k - 1u][i + 1u] * f32(i + 1u);
        }
    }
    // Direct::new([qa, qb, qc], [ra, rb, rc], dhat, (c2, r2))
    dg_wa = cross3(qa, dhat);
    dg_wb = cross3(qb, dhat);
    dg_wc = cross3(qc, dhat);
    dg_ra = ra;
    dg_rb = rb;
    dg_rc = rc;
    let sw = len3(dg_wa) + len3(dg_wb) + len3(dg_wc);
    let sr = abs(ra) + abs(rb) + abs(rc);
    dg_tau = EPS * TAU_ULPS * (sw + sr);
    dg_w_end = cross3(c2, dhat);
    dg_r_end = r2;
    rs_qa = qa;
    rs_qb = qb;
    rs_qc = qc;
    rs_dhat = dhat;
    rs_tc = tc;
    rs_inv_dlen = inv_dlen * big_s;
    rs_tv = tv;
    return true;
}
