// The spline kernel's entry points for a scene without spline pieces (appended to link.wgsl in
// place of spline.wgsl, ray_space.wgsl and roots.wgsl): tree.wgsl calls them only for spline
// items, so they are never reached, and the module stays the links' own. Lavapipe inlines the
// whole spline kernel into every walk and brute-force loop that can reach it and runs it, masked,
// wherever its lanes disagree on the branch: with it, the links' tree walk ran far slower there,
// and each of its loops spent a pass of the driver's loop budget per link (tree.wgsl's
// `loops_cut`).

// spline.wgsl's Pieces.
struct Pieces {
    iv: array<Iv, 5>,
}

fn spline_line(b0: vec3f, b1: vec3f, b2: vec3f, r: vec3f, o: vec3f, d: vec3f) -> Iv {
    return iv_miss();
}

fn spline_pieces(b0: vec3f, b1: vec3f, b2: vec3f, r: vec3f, o: vec3f, d: vec3f) -> Pieces {
    var ps: Pieces;
    for (var k = 0u; k < 5u; k++) {
        ps.iv[k] = iv_miss();
    }
    return ps;
}
