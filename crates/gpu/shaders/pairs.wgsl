// One kernel call per thread: link, sphere or spline i against local ray i. Appended to link.wgsl
// and spline.wgsl.

struct Params {
    n: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// A primitive in its local frame and a local ray (crate::kernel::PairIn).
struct PairIn {
    a: vec3f,
    ra: f32,
    b: vec3f,
    rb: f32,
    o: vec3f,
    // 0: the link (a, ra)–(b, rb); 1: the sphere (0, ra); 2: the spline with control points
    // a, c, b and radii ra, rc, rb (its hull); 3: that spline's exact piece number `slot`.
    kind: u32,
    d: vec3f,
    slot: u32,
    c: vec3f,
    rc: f32,
}

// crate::kernel::IvOut
struct IvOut {
    n_in: vec3f,
    t_in: f32,
    n_out: vec3f,
    t_out: f32,
    u_in: f32,
    u_out: f32,
    hit: u32,
    // 1 where lavapipe's loop budget ran out (tree.wgsl's `loops_cut`, whose reasoning holds
    // here: the spline kernel's solves are loops): the answer may be wrong.
    cut: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> pairs: array<PairIn>;
@group(0) @binding(2) var<storage, read_write> out: array<IvOut>;

@compute @workgroup_size(64)
fn pairs_main(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = gid.x + gid.y * nwg.x * 64u;
    if i >= params.n {
        return;
    }
    let p = pairs[i];
    var iv: Iv;
    if p.kind == 1u {
        iv = sphere_line(p.o, p.d, vec3f(0.0), p.ra, 0.0);
    } else if p.kind == 2u {
        iv = spline_line(p.a, p.c, p.b, vec3f(p.ra, p.rc, p.rb), p.o, p.d);
    } else if p.kind == 3u {
        let ps = spline_pieces(p.a, p.c, p.b, vec3f(p.ra, p.rc, p.rb), p.o, p.d);
        iv = ps.iv[min(p.slot, 4u)];
    } else {
        iv = stable_line(Cone(p.a, p.ra, p.b, p.rb), p.o, p.d);
    }
    var r: IvOut;
    r.n_in = iv.n_in;
    r.t_in = iv.t_in;
    r.n_out = iv.n_out;
    r.t_out = iv.t_out;
    r.u_in = iv.u_in;
    r.u_out = iv.u_out;
    r.hit = select(0u, 1u, iv.hit);
    // tree.wgsl's loops_cut (this module has no tree.wgsl).
    let stop = 2u + (params.n >> 31u);
    var c = 0u;
    loop {
        c++;
        if c >= stop {
            break;
        }
    }
    r.cut = select(0u, 1u, c < 2u);
    out[i] = r;
}
