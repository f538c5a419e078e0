// Splat depth and id per pixel with 32-bit atomics: cs_frames keeps each pixel's nearest depth
// key, cs_splat_ids (a second pass, after every key is final) the glyph that made it.
// Composed after prepass.wgsl where the adapter lacks 64-bit atomics (splat64.wgsl).

@group(1) @binding(5) var<storage, read_write> depth_keys: array<atomic<u32>>;
@group(1) @binding(6) var<storage, read_write> splat_ids_out: array<atomic<u32>>;
// The splat tiles' draw's view of binding 6: the glyph id (instance + 1) per pixel, 0 for none.
@group(1) @binding(8) var<storage, read> splat_ids: array<u32>;
// And of binding 5: the depth key per pixel.
@group(1) @binding(11) var<storage, read> splat_depths: array<u32>;

// Keep a splat's hit at pixel i: its depth (first pass), or its id where that depth is the
// pixel's nearest (`second`; ties: the highest instance).
fn splat_put(i: u32, depth: f32, id: u32, second: bool) {
    let key = depth_key(depth);
    if second {
        if key == atomicLoad(&depth_keys[i]) {
            atomicMax(&splat_ids_out[i], id);
        }
        return;
    }
    // Most pixels are nearer already: look before the slower atomic.
    if key > atomicLoad(&depth_keys[i]) {
        atomicMax(&depth_keys[i], key);
    }
}

fn splat_id(i: u32) -> u32 {
    return splat_ids[i];
}

// The depth key of pixel i's hit (the splat tiles' draw).
fn splat_depth_key(i: u32) -> u32 {
    return splat_depths[i];
}

// After cs_frames: the same pixel loop on the same glyph (bit for bit the hits cs_frames had),
// now recording ids.
@compute @workgroup_size(64)
fn cs_splat_ids(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&splat_info.count) {
        return;
    }
    splat_glyph(splat_list[gid.x], true);
}

// Whether pixel i already keeps a hit strictly nearer than depth key `key`: a glyph that cannot
// come nearer than that cannot win the pixel (keys only grow), so its ray need not be cast.
fn splat_nearer(i: u32, key: u32) -> bool {
    return atomicLoad(&depth_keys[i]) > key;
}
