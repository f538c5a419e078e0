// Splat depth and id per pixel with one 64-bit atomic max: the depth key in the high word, the
// glyph id (instance + 1) in the low word, so the nearest hit wins with its id (ties: the
// highest instance). Needs SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX; composed after
// prepass.wgsl in place of splat32.wgsl.

@group(1) @binding(5) var<storage, read_write> splat_keys: array<atomic<u64>>;
// The splat tiles' draw's view of binding 5: (id, depth key) per pixel.
@group(1) @binding(8) var<storage, read> splat_words: array<vec2<u32>>;

// Keep a splat's hit at pixel i (one pass: `second` is never set).
fn splat_put(i: u32, depth: f32, id: u32, second: bool) {
    atomicMax(&splat_keys[i], (u64(depth_key(depth)) << 32u) | u64(id));
}

fn splat_id(i: u32) -> u32 {
    return splat_words[i].x;
}

// The depth key of pixel i's hit (the splat tiles' draw).
fn splat_depth_key(i: u32) -> u32 {
    return splat_words[i].y;
}

// Whether pixel i already keeps a hit strictly nearer than depth key `key`: a glyph that cannot
// come nearer than that cannot win the pixel (keys only grow), so its ray need not be cast.
fn splat_nearer(i: u32, key: u32) -> bool {
    return u32(atomicLoad(&splat_keys[i]) >> 32u) > key;
}
