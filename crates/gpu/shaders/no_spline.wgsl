// The spline kernel's entry points for a scene without spline pieces (appended to link.wgsl in
// place of spline.wgsl, ray_space.wgsl and roots.wgsl): tree.wgsl calls them only for spline
// items, so they are never reached, and the module stays the links' own. Lavapipe inlines the
// whole spline kernel into every walk and brute-force loop that can reach it: with it, the
// links' tree walk ran far slower there, and its brute-force loop returned no hits at all (a
// compiler fault not understood yet, which `tests/gpu/tree.rs` catches).

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
