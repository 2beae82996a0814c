// The line intervals that count_lines (tree.wgsl) counted, appended to tree.wgsl with `out` at
// binding 11: ray i's go to out[2·offsets[i]] onwards as entry/exit pairs, in walk order, at
// most offsets[i + 1] − offsets[i] of them (the count); the first entry's `cut` says whether
// the walk's loops were cut short (`loops_cut`; a ray with no slots has nothing to lose).

@group(0) @binding(10) var<storage, read> offsets: array<u32>;

@compute @workgroup_size(64)
fn list_lines(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) nwg: vec3u) {
    let i = ray_index(gid, nwg);
    if i < params.n_rays {
        let r = rays[i];
        let slots = vec2u(2u * offsets[i], offsets[i + 1u] - offsets[i]);
        _ = walk(r, LIST, vec2f(r.s_min, r.s_max), slots);
        let cut = loops_cut();
        if slots.y > 0u {
            out[slots.x].cut = cut;
        }
    }
}
