// Splat depth and id per pixel with 32-bit atomics: cs_frames keeps each pixel's nearest depth
// key, cs_splat_ids (a second pass, after every key is final) the glyph that made it.
// Composed after gumhold_ellipsoid.wgsl where the adapter lacks 64-bit atomics (splat64.wgsl).

@group(1) @binding(5) var<storage, read_write> depth_keys: array<atomic<u32>>;
@group(1) @binding(6) var<storage, read_write> splat_ids_out: array<atomic<u32>>;
// The full-screen draw's view of binding 6: the glyph id (instance + 1) per pixel, 0 for none.
@group(1) @binding(8) var<storage, read> splat_ids: array<u32>;

fn splat_keep(i: u32, depth: f32, id: u32) {
    let key = depth_key(depth);
    // Most pixels are nearer already: look before the slower atomic.
    if key > atomicLoad(&depth_keys[i]) {
        atomicMax(&depth_keys[i], key);
    }
}

fn splat_id(i: u32) -> u32 {
    return splat_ids[i];
}

// After cs_frames: each pixel's splat is the one whose hit made its depth key (ties: the
// highest instance).
@compute @workgroup_size(64)
fn cs_splat_ids(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&splat_info.count) {
        return;
    }
    // The same function on the same glyph: bit for bit the frame cs_frames had.
    let f = glyph_frame(splat_list[gid.x]).frame;
    let px = splat_pixels(f);
    let setup = splat_setup(f);
    for (var y = px.y; y <= px.w; y++) {
        let span = splat_row(setup, y, px.x, px.z);
        for (var x = span.x; x <= span.y; x++) {
            let depth = splat_depth(setup, splat_q(setup, vec2<f32>(f32(x) + 0.5, f32(y) + 0.5)));
            let i = pixel_index(x, y);
            if depth >= 0.0 && depth_key(depth) == atomicLoad(&depth_keys[i]) {
                atomicMax(&splat_ids_out[i], f.id);
            }
        }
    }
}
