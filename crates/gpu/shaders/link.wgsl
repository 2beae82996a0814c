// The stable round-cone link kernel and the sphere kernel in f32: a port of
// `src/kernel/link/stable.rs` (RoundCone::stable_line), of the helpers it calls in
// `src/math/quadric.rs` (slab, quadric_in_slab_disc, citardauq_q, sphere_chord) and
// `src/math/frame.rs` (orthonormal_basis), and of `src/kernel/sphere.rs` (sphere_line).
//
// Every expression keeps the Rust one's operands and evaluation order (left to right, products
// before sums, no fused multiply-add, dot and cross products written out as `src/vec.rs` writes
// them), so that an IEEE-conforming adapter computes the same bits as the CPU's scalar f32
// kernel. Each block names the Rust item it ports; the comment `// rs:` quotes the Rust line
// where the WGSL spelling differs from it. `T::select(m, a, b)` is `select(b, a, m)` here.
// The constants below are checked against the Rust sources by `tests/gpu/constants.rs`.

// f32::EPSILON (`T::epsilon()` for f32).
const EPS: f32 = 1.1920929e-7;
// StableFrame::new: `c2.ge(T::epsilon() * T::cst(64.0))` (stump dropped below it).
const CONE_DROP: f32 = 64.0;
// StableFrame::new: `q2.gt(T::cst(1e-12))` (ray skew to the axis).
const SKEW: f32 = 1e-12;
// StumpSide::polish: `T::epsilon().sqrt() * T::cst(8.0) * scale` (Newton step limit).
const STEP_LIM: f32 = 8.0;
// StumpSide::polish: `T::epsilon() * T::cst(64.0) * scale.min(self.sd)` (on-side tolerance).
const TIGHT: f32 = 64.0;
// StumpSide::settle: `for _ in 0..3` (Newton rounds).
const SETTLE_ROUNDS: i32 = 3;
// quadric_in_slab_disc: `(b * b).gt(T::cst(16.0) * (a * c).abs())` (roots far apart).
const FAR_APART: f32 = 16.0;

// +∞ (WGSL has no infinity literal, and a constant expression may not overflow).
const INF_BITS: u32 = 0x7f800000u;
fn inf() -> f32 {
    return bitcast<f32>(INF_BITS);
}

// ---- src/vec.rs ----
fn dot3(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
fn cross3(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
fn len2(a: vec3f) -> f32 {
    return dot3(a, a);
}
fn len3(a: vec3f) -> f32 {
    return sqrt(len2(a));
}
// V3::normalize_or_zero
fn normalize_or_zero(v: vec3f) -> vec3f {
    let m = max(max(abs(v.x), abs(v.y)), abs(v.z)); // rs: self.max_abs()
    let pos = m > 0.0 && m < inf(); // rs: m.gt(T::zero()) & m.is_finite()
    let w = v * (1.0 / select(1.0, m, pos));
    let l = len3(w);
    return w * select(0.0, 1.0 / l, pos);
}
// Real::copysign_of: `s = ±0` counts as positive.
fn copysign_of(x: f32, s: f32) -> f32 {
    let a = abs(x);
    return select(a, -a, s < 0.0);
}
// Real::clamp: `self.max(lo).min(hi)`.
fn clampr(x: f32, lo: f32, hi: f32) -> f32 {
    return min(max(x, lo), hi);
}

// ---- src/math/frame.rs: orthonormal_basis(n).0 ----
fn basis_x(n: vec3f) -> vec3f {
    let sign = copysign_of(1.0, n.z);
    let a = -1.0 / (sign + n.z);
    return vec3f(1.0 + sign * n.x * n.x * a, sign * (n.x * n.y * a), -sign * n.x);
}

// ---- src/math/quadric.rs ----
fn citardauq_q(b: f32, sq: f32) -> f32 {
    return -(b + copysign_of(sq, b));
}

// SlabInterval
struct SlabIv {
    t0: f32,
    t1: f32,
    root0: bool,
    root1: bool,
    ok: bool,
}

fn quadric_in_slab_disc(a: f32, b: f32, c: f32, disc: f32, lo: f32, hi: f32) -> SlabIv {
    let real = disc >= 0.0;
    let sq = sqrt(max(disc, 0.0));
    let q = citardauq_q(b, sq);
    let q_nz = q != 0.0;
    let a_nz = a != 0.0;
    var r1 = q / select(1.0, a, a_nz);
    var r2 = c / select(1.0, q, q_nz);
    let far_apart = (b * b) > FAR_APART * abs(a * c);
    let mid = -b / select(1.0, a, a_nz);
    let half = sq / abs(select(1.0, a, a_nz));
    r1 = select(mid - half, r1, far_apart);
    r2 = select(mid + half, r2, far_apart);
    let rl = min(r1, r2);
    let rh = max(r1, r2);

    let pos = a > 0.0;
    let p0 = max(lo, rl); // rs: lo.max(rl)
    let p1 = min(hi, rh); // rs: hi.min(rh)
    let pq0 = rl >= lo;
    let pq1 = rh <= hi;
    let pos_ok = real && q_nz && p0 <= p1;

    let neg = a < 0.0;
    let ra = real && q_nz;
    let a0 = lo;
    let a1 = select(hi, min(hi, rl), ra);
    let b0 = select(lo, max(lo, rh), ra);
    let b1 = hi;
    let ok_a = a0 <= a1;
    let ok_b = b0 <= b1;
    let take_a = ok_a && (!ok_b || (a1 - a0) >= (b1 - b0));
    let n0 = select(b0, a0, take_a);
    let n1 = select(b1, a1, take_a);
    let nq0 = !take_a && ra && rh >= lo;
    let nq1 = take_a && ra && rl <= hi;
    let neg_ok = ok_a || ok_b;

    let lin = !a_nz;
    let b_pos = b > 0.0;
    let b_neg = b < 0.0;
    let root = -c / select(1.0, b + b, b_pos || b_neg);
    let l0 = select(lo, max(lo, root), b_neg);
    let l1 = select(hi, min(hi, root), b_pos);
    let lin_ok = l0 <= l1 && ((b_pos || b_neg) || c <= 0.0);
    let lq0 = b_neg && root >= lo;
    let lq1 = b_pos && root <= hi;

    var out: SlabIv;
    out.t0 = select(select(p0, n0, neg), l0, lin);
    out.t1 = select(select(p1, n1, neg), l1, lin);
    out.root0 = (lin && lq0) || (neg && nq0) || (pos && pq0);
    out.root1 = (lin && lq1) || (neg && nq1) || (pos && pq1);
    out.ok = (lin && lin_ok) || (neg && neg_ok) || (pos && pos_ok);
    return out;
}

// slab: `{t : lo ≤ z0 + t·zd ≤ hi}` as (t0, t1).
fn slab(z0: f32, zd: f32, lo: f32, hi: f32) -> vec2f {
    let par = zd == 0.0;
    let inv = 1.0 / select(zd, 1.0, par);
    let ta = (lo - z0) * inv;
    let tb = (hi - z0) * inv;
    let inside = z0 >= lo && z0 <= hi;
    let t0 = select(min(ta, tb), select(inf(), -inf(), inside), par);
    let t1 = select(max(ta, tb), select(-inf(), inf(), inside), par);
    return vec2f(t0, t1);
}

// Chord
struct Chord {
    tc: f32,
    h: f32,
    l: vec3f,
    ok: bool,
}

fn sphere_chord(o: vec3f, dn: vec3f, c: vec3f, r: f32) -> Chord {
    let f = o - c;
    let tc = -dot3(f, dn);
    let l = f + dn * tc;
    let disc = r * r - len2(l);
    var out: Chord;
    out.ok = disc >= 0.0 && r > 0.0;
    out.h = sqrt(max(disc, 0.0));
    out.tc = tc;
    out.l = l;
    return out;
}

// ---- src/ray.rs: Interval<f32> (a miss: t_in = +∞, t_out = −∞, zero normals and u) ----
struct Iv {
    n_in: vec3f,
    t_in: f32,
    n_out: vec3f,
    t_out: f32,
    u_in: f32,
    u_out: f32,
    hit: bool,
}

fn iv_miss() -> Iv {
    var m: Iv;
    m.t_in = inf();
    m.t_out = -inf();
    m.hit = false;
    return m;
}

// ---- src/kernel/sphere.rs: sphere_line(ray, c, r, u) ----
fn sphere_line(o: vec3f, d: vec3f, c: vec3f, r: f32, u: f32) -> Iv {
    let dl = len3(d);
    let dn = d * (1.0 / dl);
    let ch = sphere_chord(o, dn, c, r);
    let inv_dl = 1.0 / dl;
    if !ch.ok {
        return iv_miss();
    }
    var out: Iv;
    out.t_in = (ch.tc - ch.h) * inv_dl;
    out.t_out = (ch.tc + ch.h) * inv_dl;
    out.n_in = normalize_or_zero(ch.l - dn * ch.h);
    out.n_out = normalize_or_zero(ch.l + dn * ch.h);
    out.u_in = u;
    out.u_out = u;
    out.hit = true;
    return out;
}

// ---- src/kernel/link/stable.rs ----

// RoundCone<f32>
struct Cone {
    a: vec3f,
    ra: f32,
    b: vec3f,
    rb: f32,
}

// StableFrame
struct Frame {
    len_s: f32,
    hl: f32,
    axis: vec3f,
    s: f32,
    c2: f32,
    has_cone: bool,
    dl: f32,
    dn: vec3f,
    zd: f32,
    q: vec3f,
    q2: f32,
    z0: f32,
    tc: f32,
    o: vec3f,
    ca: vec3f,
    cb: vec3f,
    sd: f32,
}

// StableFrame::new
fn frame_new(l: Cone, ray_o: vec3f, ray_d: vec3f) -> Frame {
    var f: Frame;
    let v = l.b - l.a;
    let len = len3(v);
    let dr = l.ra - l.rb;
    f.len_s = select(1.0, len, len > 0.0);
    let s = clampr(dr / f.len_s, -1.0, 1.0); // rs: (dr / len_s).clamp(-one, one)
    let c2 = (1.0 - s) * (1.0 + s);
    f.has_cone = abs(dr) < len && c2 >= EPS * CONE_DROP;
    f.axis = v * (1.0 / f.len_s);
    f.s = select(0.0, s, f.has_cone);
    f.c2 = select(1.0, c2, f.has_cone);
    f.hl = f.len_s * 0.5;

    f.dl = len3(ray_d);
    f.dn = ray_d * (1.0 / f.dl);
    f.zd = dot3(f.dn, f.axis);
    f.q = cross3(f.dn, f.axis);
    f.q2 = len2(f.q);
    let oa = ray_o - l.a;
    let mid = v * 0.5;
    let w = mid - oa;
    let skew = f.q2 > SKEW;
    var t_ax = (dot3(w, f.dn) - dot3(w, f.axis) * f.zd) / select(1.0, f.q2, skew);
    t_ax = select(dot3(w, f.dn), t_ax, skew);
    f.z0 = clampr(dot3(oa + f.dn * t_ax - mid, f.axis), -f.hl, f.hl);
    let c0 = mid + f.axis * f.z0;
    f.tc = dot3(c0 - oa, f.dn);
    f.o = oa + f.dn * f.tc - c0;
    f.ca = f.axis * (-f.hl - f.z0);
    f.cb = f.axis * (f.hl - f.z0);
    f.sd = max(max(len, l.ra), l.rb) + len3(w); // rs: len.max(l.ra).max(l.rb) + w.length()
    return f;
}

// StumpSide
struct Side {
    p: vec3f,
    q: vec3f,
    e: f32,
    cc: f32,
    szd: f32,
    hl: f32,
    r_big: f32,
    sd: f32,
    lo: f32,
    hi: f32,
    ok: bool,
}

// StumpSide::settle's `g_at`
fn side_g(sd: Side, k: f32) -> f32 {
    return sd.cc * len3(sd.p + sd.q * k) - (sd.e - sd.szd * k);
}

// StumpSide::settle: returns (k, g).
fn side_settle(sd: Side, k_in: f32, todo: bool, tight: f32) -> vec2f {
    var k = k_in;
    var g = side_g(sd, k);
    for (var i = 0; i < SETTLE_ROUNDS; i++) {
        if !(todo && abs(g) > tight) {
            break;
        }
        let pq = sd.p + sd.q * k;
        let rho = len3(pq);
        let dg = sd.cc * dot3(pq, sd.q) / select(1.0, rho, rho > 0.0) + sd.szd;
        if !(abs(dg) > sqrt(EPS)) {
            break;
        }
        k = clampr(k - g / dg, sd.lo, sd.hi);
        g = side_g(sd, k);
    }
    return vec2f(k, g);
}

// StumpSide::polish: (k, real, on the side).
struct Polished {
    k: f32,
    real: bool,
    side: bool,
}

fn side_polish(sd: Side, k: f32, root: bool) -> Polished {
    let pq = sd.p + sd.q * k;
    let rho = len3(pq);
    let g = sd.cc * rho - (sd.e - sd.szd * k);
    let dg = sd.cc * dot3(pq, sd.q) / select(1.0, rho, rho > 0.0) + sd.szd;
    let step = g / select(1.0, dg, abs(dg) > 0.0);
    let scale = abs(k) + sd.hl + sd.r_big + rho;
    let lim = sqrt(EPS) * STEP_LIM * scale;
    let cap_out = sd.ok && !root && g > 0.0;
    let good = (root || cap_out) && abs(dg) > sqrt(EPS) && abs(step) <= lim;
    let kp = select(k, clampr(k - step, sd.lo, sd.hi), good);
    let tight = EPS * TIGHT * min(scale, sd.sd); // rs: T::epsilon() * T::cst(64.0) * scale.min(self.sd)
    let st = side_settle(sd, kp, root || cap_out, tight);
    var out: Polished;
    out.k = st.x;
    // rs: !(root | cap_out) | ((root & g.abs().le(lim) | cap_out) & gp.abs().le(tight))
    out.real = !(root || cap_out) || (((root && abs(g) <= lim) || cap_out) && abs(st.y) <= tight);
    out.side = root || (good && cap_out);
    return out;
}

// StumpCrossings
struct Stump {
    k0: f32,
    k1: f32,
    side0: bool,
    side1: bool,
    ok: bool,
}

// StableFrame::stump_crossings
fn stump_crossings(f: Frame, l: Cone) -> Stump {
    let rm = (l.ra + l.rb) * 0.5 - f.s * f.z0;
    let zo = dot3(f.o, f.axis);
    let p = cross3(f.o, f.axis);
    let e = rm - f.s * zo;
    let qa = f.c2 * f.q2 - f.s * f.s * f.zd * f.zd;
    let qb = f.c2 * dot3(p, f.q) + f.s * f.zd * e;
    let qc = f.c2 * len2(p) - e * e;
    let sl = slab(zo, f.zd, l.ra * f.s - f.hl - f.z0, f.hl + l.rb * f.s - f.z0);
    let eq = f.q * e + p * (f.s * f.zd);
    let disc = f.c2 * (len2(eq) - f.c2 * len2(cross3(p, f.q)));
    let hits = quadric_in_slab_disc(qa, qb, qc, disc, sl.x, sl.y);
    var sd: Side;
    sd.p = p;
    sd.q = f.q;
    sd.e = e;
    sd.cc = sqrt(f.c2);
    sd.szd = f.s * f.zd;
    sd.hl = f.hl;
    sd.r_big = max(l.ra, l.rb);
    sd.sd = f.sd;
    sd.lo = sl.x;
    sd.hi = sl.y;
    sd.ok = hits.ok;
    let e0 = side_polish(sd, hits.t0, hits.root0 && hits.ok);
    let e1 = side_polish(sd, hits.t1, hits.root1 && hits.ok);
    var out: Stump;
    out.k0 = e0.k;
    out.k1 = e1.k;
    out.side0 = e0.side;
    out.side1 = e1.side;
    out.ok = hits.ok && e0.real && e1.real && f.has_cone && e0.k <= e1.k;
    return out;
}

// StableFrame::finish: normal (xyz) and curve parameter (w).
fn frame_finish(f: Frame, l: Cone, k: f32, on_a: bool, on_b: bool, cone: bool, side: bool) -> vec4f {
    let cc = sqrt(f.c2);
    let perp = basis_x(f.axis);
    let inv = 1.0 / (f.len_s * f.c2);
    let y = f.o + f.dn * k;
    let z = dot3(y, f.axis);
    var radial = normalize_or_zero(y - f.axis * z);
    radial = select(perp, radial, len2(radial) > 0.0);
    let side_n = radial * cc + f.axis * f.s;
    let cap_b = cone && !side && (z + f.z0) > (l.ra + l.rb) * f.s * 0.5;
    let use_b = on_b || cap_b;
    let use_a = on_a || (cone && !side && !cap_b);
    let to_end = y - select(f.ca, f.cb, use_b);
    let sph = use_a || use_b;
    let n = normalize_or_zero(select(side_n, to_end, sph && len2(to_end) > 0.0));
    let u_side = clampr((z + f.z0 + f.hl - l.ra * f.s) * inv, 0.0, 1.0);
    let u = select(select(u_side, 0.0, use_a), 1.0, use_b);
    return vec4f(n, u);
}

// PieceHull
struct Hull {
    t_in: f32,
    t_out: f32,
    in_a: bool,
    in_b: bool,
    cone_in: bool,
    side_in: bool,
    out_a: bool,
    out_b: bool,
    cone_out: bool,
    side_out: bool,
}

// RoundCone::stable_line(ray, spheres = true): the line interval of the local ray
// `ray_o + t·ray_d` (any direction length; t in the ray's own parameter).
fn stable_line(l: Cone, ray_o: vec3f, ray_d: vec3f) -> Iv {
    let f = frame_new(l, ray_o, ray_d);
    var h: Hull;
    h.t_in = inf();
    h.t_out = -inf();
    // PieceHull::add_spheres (widen by a, then by b)
    let a = sphere_chord(f.o, f.dn, f.ca, l.ra);
    let b = sphere_chord(f.o, f.dn, f.cb, l.rb);
    let ai = a.ok && (a.tc - a.h) < h.t_in;
    let ao = a.ok && (a.tc + a.h) > h.t_out;
    h.t_in = select(h.t_in, a.tc - a.h, ai);
    h.t_out = select(h.t_out, a.tc + a.h, ao);
    let bi = b.ok && (b.tc - b.h) < h.t_in;
    let bo = b.ok && (b.tc + b.h) > h.t_out;
    h.t_in = select(h.t_in, b.tc - b.h, bi);
    h.t_out = select(h.t_out, b.tc + b.h, bo);
    h.in_a = ai && !bi;
    h.out_a = ao && !bo;
    h.in_b = bi;
    h.out_b = bo;
    if f.has_cone {
        // PieceHull::add_stump
        let c = stump_crossings(f, l);
        let ci = c.ok && c.k0 < h.t_in;
        let co = c.ok && c.k1 > h.t_out;
        h.t_in = select(h.t_in, c.k0, ci);
        h.t_out = select(h.t_out, c.k1, co);
        h.in_a = h.in_a && !ci;
        h.in_b = h.in_b && !ci;
        h.out_a = h.out_a && !co;
        h.out_b = h.out_b && !co;
        h.cone_in = ci;
        h.cone_out = co;
        h.side_in = ci && c.side0;
        h.side_out = co && c.side1;
    }
    let hit = h.in_a || h.in_b || h.cone_in;
    if !hit {
        return iv_miss(); // rs: .masked(hit)
    }
    let fi = frame_finish(f, l, h.t_in, h.in_a, h.in_b, h.cone_in, h.side_in);
    let fo = frame_finish(f, l, h.t_out, h.out_a, h.out_b, h.cone_out, h.side_out);
    let inv_dl = 1.0 / f.dl;
    var out: Iv;
    out.t_in = (h.t_in + f.tc) * inv_dl;
    out.t_out = (h.t_out + f.tc) * inv_dl;
    out.n_in = fi.xyz;
    out.u_in = fi.w;
    out.n_out = fo.xyz;
    out.u_out = fo.w;
    out.hit = true;
    return out;
}
