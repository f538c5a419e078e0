// The compute prepass and splats shared by the glyphs that have them (Gumhold ellipsoids and
// superquadrics; src/render/gumhold/prepass.rs). The glyph's file, composed before this one,
// declares binding 1 (what cs_frames keeps of the drawn glyphs) and defines cs_frames,
// splat_glyph (its pixel loop, again for the second 32-bit pass) and splat_hit (one pixel's hit
// for the splat tiles' draw); splat32.wgsl or
// splat64.wgsl, composed after, gives splat_put and splat_id.

struct Slice {
    // Index of the slice's first glyph in the chunk.
    first: u32,
    count: u32,
    // --splat: glyphs whose proxy spans at most this many pixels across are splats (0: none).
    splat_max: u32,
    // SLICE_BRICKS: the glyphs are those of the bricks occlusion culling listed
    // (visible_bricks), BRICK invocations a brick, dispatched indirectly; first and count are
    // then unused (count bounds the splats' second pass).
    flags: u32,
}

const SLICE_BRICKS: u32 = 1u;
// Glyphs per brick (BRICK in src/render/bricks.rs) and the unused places of a brick.
const BRICK: u32 = 256u;
const NO_GLYPH: u32 = 0xffffffffu;
// The chunk's glyphs brick by brick, and the bricks of this slice that may show something
// (shaders/method/occlusion.wgsl).
@group(1) @binding(12) var<storage, read> brick_glyphs: array<u32>;
@group(1) @binding(13) var<storage, read> visible_bricks: array<u32>;

// wgpu's DrawIndirectArgs.
struct DrawArgs {
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
}

@group(1) @binding(0) var<storage, read> slice: Slice;
@group(1) @binding(2) var<storage, read_write> draw_args: DrawArgs;
// The instances (instance_index) of the splats.
@group(1) @binding(3) var<storage, read_write> splat_list: array<u32>;
// What the splats left for the draw after them: their count and the draw-indirect arguments of
// the splat tiles' quads (instance_count: the tiles listed).
struct SplatInfo {
    count: atomic<u32>,
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
}

@group(1) @binding(4) var<storage, read_write> splat_info: SplatInfo;
// Bindings 5, 6 and 8 (the per-pixel splat buffers) come from splat32.wgsl or splat64.wgsl.

// The splats are shaded by a quad per SPLAT_TILE × SPLAT_TILE block of pixels that some splat
// touches (not one rectangle round them all: a few splats scattered over the image would shade
// every pixel between them). tile_marks: per tile, whether it is listed yet; tile_list: the
// tiles listed, in the order the splats reached them.
const SPLAT_TILE: u32 = 16u;
@group(1) @binding(7) var<storage, read_write> tile_marks: array<atomic<u32>>;
@group(1) @binding(10) var<storage, read_write> tile_list: array<u32>;
// The draw's view of tile_list.
@group(1) @binding(9) var<storage, read> splat_tiles: array<u32>;

// Tiles per row of the image.
fn tiles_across() -> u32 {
    return (u32(camera.viewport.x) + SPLAT_TILE - 1u) / SPLAT_TILE;
}

// The glyph of this invocation of cs_frames (none past the slice's end); the first invocation
// also sets the draws' vertex counts.
fn prepass_glyph(gid: u32) -> u32 {
    if gid == 0u {
        draw_args.vertex_count = PROXY_VERTICES;
        splat_info.vertex_count = 4u;
    }
    if (slice.flags & SLICE_BRICKS) != 0u {
        // The dispatch holds exactly BRICK invocations per listed brick.
        let local = brick_glyphs[visible_bricks[gid / BRICK] * BRICK + gid % BRICK];
        if local == NO_GLYPH {
            return 0xffffffffu;
        }
        return chunk.base + local;
    }
    if gid >= slice.count {
        return 0xffffffffu;
    }
    return chunk.base + slice.first + gid;
}

// Whether pixels `px` (first and last, inclusive) are few enough for a splat (slice.splat_max > 0).
fn splat_sized(px: vec4<i32>) -> bool {
    let size = px.zw - px.xy + 1;
    return size.x <= i32(slice.splat_max) && size.y <= i32(slice.splat_max);
}

// Record instance ii as a splat that kept some pixel of px (within the image), listing the
// tiles px touches that are not listed yet (at most 3 × 3 for splats up to 32 pixels).
fn splat_noted(ii: u32, px: vec4<i32>) {
    // 4 bytes, not a frame: the next passes recompute what they need.
    splat_list[atomicAdd(&splat_info.count, 1u)] = ii;
    let lo = vec2<u32>(px.xy) / SPLAT_TILE;
    let hi = vec2<u32>(px.zw) / SPLAT_TILE;
    let across = tiles_across();
    for (var ty = lo.y; ty <= hi.y; ty++) {
        for (var tx = lo.x; tx <= hi.x; tx++) {
            let t = ty * across + tx;
            // Most tiles are listed already: look before the slower atomic.
            if atomicLoad(&tile_marks[t]) == 0u && atomicOr(&tile_marks[t], 1u) == 0u {
                tile_list[atomicAdd(&splat_info.instance_count, 1u)] = t;
            }
        }
    }
}

// A strip of two triangles covering tile splat_tiles[k].
@vertex
fn vs_splat_tile(@builtin(vertex_index) vi: u32, @builtin(instance_index) k: u32) -> @builtin(position) vec4<f32> {
    let t = splat_tiles[k];
    let across = tiles_across();
    let corner = vec2<f32>(f32(vi & 1u), f32(vi >> 1u));
    let lo = vec2<f32>(f32(t % across), f32(t / across)) * f32(SPLAT_TILE);
    let px = min(lo + corner * f32(SPLAT_TILE), camera.viewport.xy);
    return vec4<f32>(px.x * 2.0 * camera.viewport.z - 1.0, 1.0 - px.y * 2.0 * camera.viewport.w, 0.0, 1.0);
}

// The splat hit at a pixel, or discard.
fn splat_at(position: vec4<f32>) -> Hit {
    let i = pixel_index(i32(position.x), i32(position.y));
    let id = splat_id(i);
    if id == 0u {
        discard;
    }
    var hit = splat_hit(id - 1u, position.xy, splat_depth_key(i));
    if hit.miss {
        // The compute passes found a hit here; a differently rounded miss at the very edge is
        // one.
        discard;
    }
    hit.id = id;
    return hit;
}

@fragment
fn fs_splat(@builtin(position) position: vec4<f32>) -> OutDepth {
    let hit = splat_at(position);
    return OutDepth(hit.color, hit.id, hit.depth);
}

@fragment
fn fs_splat_aux(@builtin(position) position: vec4<f32>) -> OutDepthAux {
    let hit = splat_at(position);
    return OutDepthAux(hit.color, hit.id, vec4<f32>(hit.n_view, hit.z_rel), hit.depth);
}

@fragment
fn fs_splat_normal(@builtin(position) position: vec4<f32>) -> OutDepthNormal {
    let hit = splat_at(position);
    return OutDepthNormal(hit.color, hit.id, oct_encode(hit.n_view), hit.depth);
}

// The shadow map's splats: the compute passes' id and the depth of their hit
// (splat_shadow_depth, the kind's), with no colour or normal, which the map does not keep.
@fragment
fn fs_splat_shadow(@builtin(position) position: vec4<f32>) -> OutShadow {
    let i = pixel_index(i32(position.x), i32(position.y));
    let id = splat_id(i);
    if id == 0u {
        discard;
    }
    return OutShadow(id, splat_shadow_depth(id - 1u, position.xy, splat_depth_key(i)));
}

// The pixels (first and last, inclusive) whose centres lie within the points' screen rectangle
// (clip positions), or none (x > z) when a point is behind the eye, in front of the near plane
// or projected near infinity or NaN: too big to splat.
fn splat_pixel_rect(clips: array<vec4<f32>, 4>) -> vec4<i32> {
    var lo = vec2<f32>(3.0e38);
    var hi = vec2<f32>(-3.0e38);
    for (var k = 0u; k < 4u; k++) {
        let clip = clips[k];
        if !(clip.w > 0.0 && clip.z >= 0.0 && all(abs(clip.xy) < vec2<f32>(1.0e4 * clip.w))) {
            return vec4<i32>(0, 0, 1 << 30u, 1 << 30u);
        }
        let px = clip_pixel(clip);
        lo = min(lo, px);
        hi = max(hi, px);
    }
    // Pixel i's centre is at i + 0.5.
    let first = max(vec2<i32>(ceil(lo - 0.5)), vec2<i32>(0));
    let last = min(vec2<i32>(floor(hi - 0.5)), vec2<i32>(camera.viewport.xy) - 1);
    return vec4<i32>(first, last);
}

// A clip position's framebuffer coordinates in pixels (pixel i's centre at i + 0.5).
fn clip_pixel(clip: vec4<f32>) -> vec2<f32> {
    let ndc = clip.xy / clip.w;
    return vec2<f32>((ndc.x + 1.0) * 0.5 * camera.viewport.x, (1.0 - ndc.y) * 0.5 * camera.viewport.y);
}

// THIN_EXACT: a proxy quad's corners (clip positions in strip order (-,-), (+,-), (-,+), (+,+),
// every one in front of the eye: splat_pixel_rect said so) in pixels, in order around it, for
// polygon_row. A thin glyph's splat rows come from its quad, not from a quadratic of the
// pixel's parameter-space ray: formed in f32, that ray is magnified k times across the glyph's
// section, and the quadratic's roots dropped pixels the ray hits (whole needles at k = 1e3,
// discs at 1e5; the ray cast decides each pixel).
fn quad_polygon(clips: array<vec4<f32>, 4>) -> array<vec2<f32>, 4> {
    return array<vec2<f32>, 4>(clip_pixel(clips[0]), clip_pixel(clips[1]), clip_pixel(clips[3]), clip_pixel(clips[2]));
}

// How far (pixels) a splat's row span reaches beyond the roots of its quadratic: their f32
// rounding is a small part of a pixel (the ray casting decides each pixel). A pixel and more each
// side, as before, cost the superquadrics' whole-field frame 17 %.
const SPAN_MARGIN: f32 = 0.125;

// The pixels of row y within [x0, x1] whose centres lie in the convex polygon p (pixels, in
// order around it), widened by SPAN_MARGIN; none where the row's centre line misses it.
fn polygon_row(p: array<vec2<f32>, 4>, y: i32, x0: i32, x1: i32) -> vec2<i32> {
    let yc = f32(y) + 0.5;
    var lo = 3.0e38;
    var hi = -3.0e38;
    for (var k = 0u; k < 4u; k++) {
        let a = p[k];
        let b = p[(k + 1u) & 3u];
        if min(a.y, b.y) <= yc && yc <= max(a.y, b.y) {
            var x = a.x;
            var x2 = b.x;
            if a.y != b.y {
                x = a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x);
                x2 = x;
            }
            lo = min(lo, min(x, x2));
            hi = max(hi, max(x, x2));
        }
    }
    if lo > hi {
        return vec2<i32>(x0 + 1, x0);
    }
    // Pixel i's centre is at i + 0.5.
    return vec2<i32>(max(i32(ceil(lo - 0.5 - SPAN_MARGIN)), x0), min(i32(floor(hi - 0.5 + SPAN_MARGIN)), x1));
}

// The pixels of a row within [x0, x1] whose centres x0 + x satisfy q.x x² + q.y x + q.z <= 0,
// widened by SPAN_MARGIN: every pixel where the quadratic is not convex, none where it has no
// root.
fn splat_span(q: vec3<f32>, x0: i32, x1: i32) -> vec2<i32> {
    if !(q.x > 0.0) {
        return vec2<i32>(x0, x1);
    }
    let disc = q.y * q.y - 4.0 * q.x * q.z;
    if disc < 0.0 {
        return vec2<i32>(x0 + 1, x0);
    }
    let root = sqrt(disc);
    let lo = (-q.y - root) / (2.0 * q.x);
    let hi = (-q.y + root) / (2.0 * q.x);
    return vec2<i32>(max(x0 + i32(ceil(lo - SPAN_MARGIN)), x0), min(x0 + i32(floor(hi + SPAN_MARGIN)), x1));
}

// Ordered like depths, larger for nearer (0: nothing); depths in [0, 1] order as their bits.
fn depth_key(depth: f32) -> u32 {
    return 0xffffffffu - bitcast<u32>(depth);
}

// The depth whose key is `key`.
fn key_depth(key: u32) -> f32 {
    return bitcast<f32>(0xffffffffu - key);
}

fn pixel_index(x: i32, y: i32) -> u32 {
    return u32(y) * u32(camera.viewport.x) + u32(x);
}
