// Closest-hit and any-hit queries over the CPU's wide BVH, appended to link.wgsl and
// spline.wgsl: a port of
// `crates/render/src/accel/tree.rs` (Tree::entries, Tree::walk) and of the leaf work of
// `WideBvh::closest_hit` / `any_hit` (`crates/render/src/accel/wide.rs`) with `Prim::local_origin`
// and `Prim::to_world` (`crates/render/src/scene/prim.rs`) done in f32 from the ray's restart
// point (see `crate::scene` for the error this adds). `STACK_SIZE` is substituted at build.

struct Params {
    n_rays: u32,
    n_items: u32,
    // 8·pad in world units (the CPU's `margin`) and the tree frame's scale.
    margin: f32,
    scale: f32,
    // The items closest_brute tries: [item_lo, item_hi).
    item_lo: u32,
    item_hi: u32,
    _pad0: u32,
    _pad1: u32,
}

// tree.rs: Node (256 bytes): lo[axis][child] as 6 vec4, hi likewise, child, count.
struct Node {
    lo: array<vec4f, 6>,
    hi: array<vec4f, 6>,
    child: array<vec4u, 2>,
    count: array<vec4u, 2>,
}

// crate::scene::GpuPrim: a link (kind 0) or a sphere (kind 1, radius ra) relative to `org`,
// the primitive's origin relative to the tree centre; or a spline piece (kind & 3 == 2) with
// control points a, b₁, b and radii ra, r₁, rb, where b₁, r₁ are the `a`, `ra` of the record
// prim_at(kind >> 2) (past the items' records).
struct Prim {
    a: vec3f,
    ra: f32,
    b: vec3f,
    rb: f32,
    org: vec3f,
    kind: u32,
}

// crate::scene::GpuRay: the ray restarted before the scene box (Frame::clip).
struct Ray {
    // Restart point − centre (world units) and the range in distance from it.
    o: vec3f,
    s_min: f32,
    // The unit direction rounded to f32 (the CPU's `dn.cast::<f32>()`).
    d: vec3f,
    s_max: f32,
    // The same ray in the tree frame: origin, and the obvhs ray's t_max.
    to: vec3f,
    tmax: f32,
    // Direction with −0 turned to +0 (Frame::clip's `+ 0.0`).
    td: vec3f,
    valid: u32,
}

// crate::scene::GpuHit
struct HitOut {
    n: vec3f,
    s: f32,
    u: f32,
    item: u32,
    entering: u32,
    // 1 where the loop budget ran out (`loops_cut`): the answer may be wrong.
    cut: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// The tree's nodes and the primitives, each split on record boundaries across four bindings
// (`Gpu::SPLIT`), every one within the adapter's storage buffer binding limit: records 0 to
// n − 1 in the first, n to 2n − 1 in the second, … (n per kind: `GpuScene::upload`). Read only
// through `node_at` and `prim_at`, which `crate::scene` writes in place of the placeholder below for
// the scene's split: a scene in one binding reads it directly; otherwise they pick the binding
// by index / n (branches, no loop: lavapipe's loop budget, `loops_cut`).
@group(0) @binding(1) var<storage, read> nodes0: array<Node>;
@group(0) @binding(2) var<storage, read> nodes1: array<Node>;
@group(0) @binding(3) var<storage, read> nodes2: array<Node>;
@group(0) @binding(4) var<storage, read> nodes3: array<Node>;
@group(0) @binding(5) var<storage, read> prims0: array<Prim>;
@group(0) @binding(6) var<storage, read> prims1: array<Prim>;
@group(0) @binding(7) var<storage, read> prims2: array<Prim>;
@group(0) @binding(8) var<storage, read> prims3: array<Prim>;
@group(0) @binding(9) var<storage, read> rays: array<Ray>;
// Binding 10 in the queries' module; lines.wgsl puts its per-ray offsets there and this at 11.
@group(0) @binding(OUT_BINDING) var<storage, read_write> out: array<HitOut>;

ACCESSORS

const NONE: u32 = 0xffffffffu;
const STACK: u32 = STACK_SIZEu;

// Whether this invocation's loops may have been cut short. Mesa's llvmpipe (lavapipe) counts the
// passes of every loop of a shader in one counter per SIMD vector of invocations, set to
// LP_MAX_TGSI_LOOP_ITERATIONS = 65535 when the shader starts and never reset (gallivm's
// `lp_exec_endloop`); once it is spent, every loop ends after its first pass, silently: a walk
// visits no node, a root finder stops at its start. The spline kernel's solves take tens to
// hundreds of passes per piece, so a tree walk through many spline pieces, or a brute-force loop
// over them, can spend it (lanes that run together share it). Called last, a loop that must pass
// twice passes once only where the counter ran out. Its bound comes from the uniform (never
// above 2 in practice: n_rays < 2³¹), so that no compiler unrolls it. Other drivers have no such
// counter; there it always passes twice.
fn loops_cut() -> u32 {
    let stop = 2u + (params.n_rays >> 31u);
    var c = 0u;
    loop {
        c++;
        if c >= stop {
            break;
        }
    }
    return select(0u, 1u, c < 2u);
}

// Item `it`'s line interval in distance from the restart point (Prim::intersect_unit's local
// ray, then Prim::to_world's `tc + t`, unclipped).
fn item_iv(r: Ray, it: u32) -> Iv {
    let p = prim_at(it);
    // Prim::local_origin: tc = (org − o)·dn, o_local = o + dn·tc − org.
    let tc = dot3(p.org - r.o, r.d);
    let lo = r.o + r.d * tc - p.org;
    var iv: Iv;
    let kind = p.kind & 3u;
    if kind == SPHERE {
        iv = sphere_line(lo, r.d, vec3f(0.0), p.ra, 0.0);
    } else if kind == SPLINE {
        // Prim::intersect_unit: QuadTube::intersect_with(Solver::Polynomial), the hull.
        let x = prim_at(p.kind >> 2u);
        iv = spline_line(p.a, x.a, p.b, vec3f(p.ra, x.ra, p.rb), lo, r.d);
    } else {
        iv = stable_line(Cone(p.a, p.ra, p.b, p.rb), lo, r.d);
    }
    iv.t_in = tc + iv.t_in;
    iv.t_out = tc + iv.t_out;
    return iv;
}

const SPHERE: u32 = 1u;
const SPLINE: u32 = 2u;

fn is_spline(it: u32) -> bool {
    return (prim_at(it).kind & 3u) == SPLINE;
}

// Item `it`'s exact line pieces (Prim::pieces): a spline piece's one interval per real interval
// of g (QuadTube::intersect_pieces, slots that miss included), as distances from the restart
// point. Only for spline items.
fn item_pieces(r: Ray, it: u32) -> Pieces {
    let p = prim_at(it);
    let tc = dot3(p.org - r.o, r.d);
    let lo = r.o + r.d * tc - p.org;
    let x = prim_at(p.kind >> 2u);
    var ps = spline_pieces(p.a, x.a, p.b, vec3f(p.ra, x.ra, p.rb), lo, r.d);
    for (var k = 0u; k < 5u; k++) {
        ps.iv[k].t_in = tc + ps.iv[k].t_in;
        ps.iv[k].t_out = tc + ps.iv[k].t_out;
    }
    return ps;
}

// An item's line intervals for the interval walks: its one interval, or a spline's pieces.
fn item_ivs(r: Ray, it: u32) -> Pieces {
    if is_spline(it) {
        return item_pieces(r, it);
    }
    var ps: Pieces;
    ps.iv[0] = item_iv(r, it);
    for (var k = 1u; k < 5u; k++) {
        ps.iv[k] = iv_miss();
    }
    return ps;
}

fn crossing(it: u32, s: f32, n: vec3f, u: f32, entering: bool) -> HitOut {
    var h: HitOut;
    h.item = it;
    h.s = s;
    h.n = n;
    h.u = u;
    h.entering = select(0u, 1u, entering);
    h.cut = 0u;
    return h;
}

// The first crossing of item `it` in [s_min, s_max] (Interval::first_hit); `item == NONE`
// when there is none.
fn test_item(r: Ray, it: u32) -> HitOut {
    var h: HitOut;
    h.item = NONE;
    let iv = item_iv(r, it);
    if !iv.hit {
        return h;
    }
    if (iv.t_in >= r.s_min && iv.t_in <= r.s_max) || !is_spline(it) {
        h = first_crossing(it, iv, r);
    } else if iv.t_out >= r.s_min && iv.t_in <= r.s_max {
        // Prim::first_hit_exit_unit: a spline's hull entry outside the range (the ray starts
        // inside the hull, perhaps in a gap between its pieces): the first crossing of its pieces.
        let ps = item_pieces(r, it);
        for (var k = 0u; k < 5u; k++) {
            if ps.iv[k].hit {
                let c = first_crossing(it, ps.iv[k], r);
                if closer(c, h) {
                    h = c;
                }
            }
        }
    }
    return h;
}

// Interval::first_hit: the entry if in [s_min, s_max], else the exit if there.
fn first_crossing(it: u32, iv: Iv, r: Ray) -> HitOut {
    var h: HitOut;
    h.item = NONE;
    if iv.t_in >= r.s_min && iv.t_in <= r.s_max {
        h = crossing(it, iv.t_in, iv.n_in, iv.u_in, true);
    } else if iv.t_out >= r.s_min && iv.t_out <= r.s_max {
        h = crossing(it, iv.t_out, iv.n_out, iv.u_out, false);
    }
    return h;
}

// Of two exits, the later one (equal: the lower item).
fn later(a: HitOut, b: HitOut) -> bool {
    return a.item != NONE && (b.item == NONE || a.s > b.s || (a.s == b.s && a.item < b.item));
}

fn closer(a: HitOut, b: HitOut) -> bool {
    return a.item != NONE && (b.item == NONE || a.s < b.s || (a.s == b.s && a.item < b.item));
}

fn plane(v: array<vec4f, 6>, axis: u32, i: u32) -> f32 {
    return v[axis * 2u + i / 4u][i % 4u];
}

// Tree::walk with the leaf work of WideBvh::closest_hit (any_only = false) or any_hit (true).
// The walk's modes.
const CLOSEST: u32 = 0u;
const ANY: u32 = 1u;
// The line interval with the least entry among those whose exit is ≥ s_min (the seed of
// the first union component).
const SEED: u32 = 2u;
// The least entry and the greatest exit among the line intervals meeting [span.x, span.y].
const SPAN: u32 = 3u;
// Every line interval meeting [span.x, span.y]: counted (COUNT), or counted and written as
// entry/exit pairs to out[slots.x], out[slots.x + 1], … for the first slots.y of them (LIST).
const COUNT: u32 = 4u;
const LIST: u32 = 5u;

// What a walk found: the hit (CLOSEST, ANY) or an entry, and an exit (SEED, SPAN); the number
// of intervals (COUNT, LIST).
struct Found {
    first: HitOut,
    last: HitOut,
    n: u32,
}

fn walk(r: Ray, mode: u32, span: vec2f, slots: vec2u) -> Found {
    var f: Found;
    f.first.item = NONE;
    f.last.item = NONE;
    f.n = 0u;
    if r.valid == 0u {
        return f;
    }
    // TreeRay::new: 1/d clamped to ±2²³ where |d| ≤ 2⁻²³.
    var inv: vec3f;
    for (var a = 0u; a < 3u; a++) {
        let x = r.td[a];
        inv[a] = select(1.0 / x, select(1.0, -1.0, x < 0.0) / EPS, abs(x) <= EPS);
    }
    var tmax = r.tmax;
    // The modes over a span (SPAN, COUNT, LIST) visit the boxes it reaches, loosened by the
    // box margin.
    if mode >= SPAN {
        tmax = min(tmax, (span.y + params.margin) * params.scale);
    }
    var st_c: array<vec2u, STACK>;
    var st_t: array<f32, STACK>;
    var top = 0u;
    var node = 0u;
    loop {
        // Tree::entries
        let n = node_at(node);
        var ot: array<f32, 8>;
        var oi: array<u32, 8>;
        var k = 0u;
        for (var i = 0u; i < 8u; i++) {
            var near = 0.0;
            var far = tmax;
            for (var a = 0u; a < 3u; a++) {
                let neg = inv[a] < 0.0;
                let lo = select(plane(n.lo, a, i), plane(n.hi, a, i), neg);
                let hi = select(plane(n.hi, a, i), plane(n.lo, a, i), neg);
                let t0 = (lo - r.to[a]) * inv[a];
                let t1 = (hi - r.to[a]) * inv[a];
                near = select(near, t0, t0 > near);
                far = select(far, t1, t1 < far);
            }
            if near <= far {
                // Insertion sort, nearest first.
                var j = k;
                while j > 0u && ot[j - 1u] > near {
                    ot[j] = ot[j - 1u];
                    oi[j] = oi[j - 1u];
                    j--;
                }
                ot[j] = near;
                oi[j] = i;
                k++;
            }
        }
        // Push all but the nearest, farthest first.
        for (var j = k; j > 1u; j--) {
            let i = oi[j - 1u];
            st_c[top] = vec2u(n.child[i / 4u][i % 4u], n.count[i / 4u][i % 4u]);
            st_t[top] = ot[j - 1u];
            top++;
        }
        var have_next = k > 0u;
        var next_c = vec2u(0u);
        var next_t = 0.0;
        if have_next {
            let i = oi[0];
            next_c = vec2u(n.child[i / 4u][i % 4u], n.count[i / 4u][i % 4u]);
            next_t = ot[0];
        }
        var descend = false;
        loop {
            var c: vec2u;
            var te: f32;
            if have_next {
                c = next_c;
                te = next_t;
                have_next = false;
            } else if top > 0u {
                top--;
                c = st_c[top];
                te = st_t[top];
            } else {
                break;
            }
            if te > tmax {
                continue;
            }
            if c.y == 0u {
                node = c.x;
                descend = true;
                break;
            }
            for (var it = c.x; it < c.x + c.y; it++) {
                if mode >= SPAN {
                    let ps = item_ivs(r, it);
                    for (var q = 0u; q < 5u; q++) {
                    let iv = ps.iv[q];
                    if iv.hit && iv.t_in <= span.y && iv.t_out >= span.x {
                        let e = crossing(it, iv.t_in, iv.n_in, iv.u_in, true);
                        let x = crossing(it, iv.t_out, iv.n_out, iv.u_out, false);
                        if mode == SPAN {
                            if closer(e, f.first) {
                                f.first = e;
                            }
                            if later(x, f.last) {
                                f.last = x;
                            }
                        } else {
                            if mode == LIST && f.n < slots.y {
                                out[slots.x + 2u * f.n] = e;
                                out[slots.x + 2u * f.n + 1u] = x;
                            }
                            f.n++;
                        }
                    }
                    }
                    continue;
                }
                var h: HitOut;
                var x: HitOut;
                if mode == SEED {
                    // The piece with the least entry among those whose exit is ≥ s_min.
                    let ps = item_ivs(r, it);
                    h.item = NONE;
                    for (var q = 0u; q < 5u; q++) {
                        let iv = ps.iv[q];
                        if iv.hit && iv.t_out >= r.s_min {
                            let e = crossing(it, iv.t_in, iv.n_in, iv.u_in, true);
                            if closer(e, h) {
                                h = e;
                                x = crossing(it, iv.t_out, iv.n_out, iv.u_out, false);
                            }
                        }
                    }
                } else {
                    h = test_item(r, it);
                }
                if closer(h, f.first) {
                    f.first = h;
                    f.last = x;
                    if mode == ANY {
                        return f;
                    }
                    // Cull by the best so far, loosened by the box margin.
                    let tb = (h.s + params.margin) * params.scale;
                    if tb < tmax {
                        tmax = tb;
                    }
                }
            }
        }
        if !descend {
            break;
        }
    }
    return f;
}

fn ray_index(gid: vec3u, nwg: vec3u) -> u32 {
    return gid.x + gid.y * nwg.x * 64u;
}

@compute @workgroup_size(64)
fn closest_tree(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        var h = walk(rays[i], CLOSEST, vec2f(0.0), vec2u(0u)).first;
        h.cut = loops_cut();
        out[i] = h;
    }
}

@compute @workgroup_size(64)
fn any_tree(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        var h = walk(rays[i], ANY, vec2f(0.0), vec2u(0u)).first;
        h.cut = loops_cut();
        out[i] = h;
    }
}

// Every item of [item_lo, item_hi) against the ray, no tree: the reference the tree walk must
// equal (the host merges the item ranges' answers by `closer`).
@compute @workgroup_size(64)
fn closest_brute(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i >= params.n_rays {
        return;
    }
    let r = rays[i];
    var best: HitOut;
    best.item = NONE;
    if r.valid != 0u {
        for (var it = params.item_lo; it < params.item_hi; it++) {
            let h = test_item(r, it);
            if closer(h, best) {
                best = h;
            }
        }
    }
    best.cut = loops_cut();
    out[i] = best;
}

// The first component of the union of the line intervals that reaches [s_min, s_max]
// (`tubecast_render::accel::first_component`), in steps the host drives (`GpuScene::first_pieces`):
// seed_piece finds the seed interval, then span_piece, once per dispatch, the least entry and
// the greatest exit of every interval meeting the span [a, b] so far, until the span stops
// growing (each step adds every interval chained to it; at most one per item). One walk per
// dispatch: lavapipe's loop budget (`loops_cut`) is spent per dispatch, and a component
// chained through many spline pieces took more than it in one. Thread i writes ray i's entry to
// out[2i] and its exit to out[2i + 1].
@compute @workgroup_size(64)
fn seed_piece(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        piece_out(i, walk(rays[i], SEED, vec2f(0.0), vec2u(0u)));
    }
}

// One step of the span's growth: the host puts the span [a, b] in the ray's s_min, s_max.
@compute @workgroup_size(64)
fn span_piece(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        let r = rays[i];
        piece_out(i, walk(r, SPAN, vec2f(r.s_min, r.s_max), vec2u(0u)));
    }
}

fn piece_out(i: u32, found: Found) {
    var f = found;
    let cut = loops_cut();
    f.first.cut = cut;
    f.last.cut = cut;
    out[2u * i] = f.first;
    out[2u * i + 1u] = f.last;
}

// The number of line intervals meeting ray i's [s_min, s_max] (`intersect --query all`: the
// union's boundaries there are those of these intervals alone), in out[i].item; lines.wgsl's
// list_lines then writes them.
@compute @workgroup_size(64)
fn count_lines(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        let r = rays[i];
        var h: HitOut;
        h.item = walk(r, COUNT, vec2f(r.s_min, r.s_max), vec2u(0u)).n;
        h.cut = loops_cut();
        out[i] = h;
    }
}
