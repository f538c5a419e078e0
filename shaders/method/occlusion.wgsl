// Occlusion culling of a large scene's bricks of glyphs (src/render/gumhold/occlusion.rs),
// composed after common.wgsl. Per slice of the bricks in this frame's order, cs_bricks lists the
// bricks that may show something (inside the frustum and, after the first slice, not behind
// what the slices before drew) and counts them into the dispatch arguments of the slice's
// cs_frames (prepass.wgsl), which then runs BRICK invocations per listed brick and none for the
// rest. cs_hiz keeps, per HIZ_TILE × HIZ_TILE tile of the image, the farthest depth drawn so far
// (1 where the background shows), and per HIZ_TILE × HIZ_TILE block of those tiles the farthest
// of theirs (a second level, for bricks too large on screen for the first).

// HIZ_TILE and BRICK of src/render/gumhold/occlusion.rs and src/render/bricks.rs; the
// prepass's workgroup (WORKGROUP in src/render/gumhold/prepass.rs).
const HIZ_TILE: u32 = 8u;
const BRICK: u32 = 256u;
const FRAMES_WORKGROUP: u32 = 64u;
// A brick whose rectangle spans more tiles than this across is kept untested (few and near).
const HIZ_REACH: i32 = 16;
// BrickSlice.flags: test against the depth tiles (not for the first slice).
const BRICKS_OCCLUDED: u32 = 1u;

struct BrickSlice {
    // The slice's bricks: positions first .. first + count of brick_order.
    first: u32,
    count: u32,
    flags: u32,
    _pad: u32,
}

// wgpu's DispatchIndirectArgs, x counted up by cs_bricks.
struct Dispatch {
    x: atomic<u32>,
    y: u32,
    z: u32,
}

@group(1) @binding(0) var drawn_depth: texture_depth_2d;
@group(1) @binding(1) var<storage, read_write> hiz: array<f32>;
// Per brick: a ball holding its glyphs (centre relative to the scene origin, radius).
@group(1) @binding(2) var<storage, read> brick_balls: array<vec4<f32>>;
@group(1) @binding(3) var<storage, read> brick_order: array<u32>;
@group(1) @binding(4) var<storage, read> brick_slice: BrickSlice;
// The slice's bricks that may show something (cs_frames' visible_bricks).
@group(1) @binding(5) var<storage, read_write> visible_out: array<u32>;
@group(1) @binding(6) var<storage, read_write> dispatch: Dispatch;

// Tiles across and down of level 0 (HIZ_TILE pixels) and of level 1 (HIZ_TILE² pixels, stored
// after level 0 in `hiz`).
fn hiz_tiles(level: u32) -> vec2<i32> {
    var n = (vec2<i32>(camera.viewport.xy) + i32(HIZ_TILE) - 1) / i32(HIZ_TILE);
    if level == 1u {
        n = (n + i32(HIZ_TILE) - 1) / i32(HIZ_TILE);
    }
    return n;
}

@compute @workgroup_size(8, 8)
fn cs_hiz(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    let tiles = (size + HIZ_TILE - 1u) / HIZ_TILE;
    if any(gid.xy >= tiles) {
        return;
    }
    let lo = gid.xy * HIZ_TILE;
    let hi = min(lo + HIZ_TILE, size);
    var far = 0.0;
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            far = max(far, textureLoad(drawn_depth, vec2<u32>(x, y), 0));
        }
    }
    hiz[gid.y * tiles.x + gid.x] = far;
}

// After cs_hiz: each level-1 tile, the farthest of its level-0 tiles.
@compute @workgroup_size(8, 8)
fn cs_hiz_coarse(@builtin(global_invocation_id) gid: vec3<u32>) {
    let fine = vec2<u32>(hiz_tiles(0u));
    let tiles = vec2<u32>(hiz_tiles(1u));
    if any(gid.xy >= tiles) {
        return;
    }
    let lo = gid.xy * HIZ_TILE;
    let hi = min(lo + HIZ_TILE, fine);
    var far = 0.0;
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            far = max(far, hiz[y * fine.x + x]);
        }
    }
    hiz[fine.x * fine.y + gid.y * tiles.x + gid.x] = far;
}

// Whether nothing within the ball (centre c, radius r) can be seen: it lies wholly outside a
// plane of the frustum, or (`occluded`) behind what the slices before drew at every pixel
// centre it could cover: the ball's view-aligned bounding cube projected, the depth of its near
// face against each tile's farthest. Nothing visible goes: a tile's farthest depth bounds every
// depth drawn in it, and every hit of a glyph in the ball lies at or beyond the cube's near face.
fn ball_hidden(c: vec3<f32>, r: f32, occluded: bool) -> bool {
    for (var k = 0u; k < 6u; k++) {
        let p = camera.frustum[k];
        if dot(p.xyz, c) + p.w < -r {
            return true;
        }
    }
    if !occluded {
        return false;
    }
    let v = camera.view;
    let ax = camera.view_proj * vec4<f32>(v[0].x, v[1].x, v[2].x, 0.0) * r;
    let ay = camera.view_proj * vec4<f32>(v[0].y, v[1].y, v[2].y, 0.0) * r;
    let az = camera.view_proj * vec4<f32>(v[0].z, v[1].z, v[2].z, 0.0) * r;
    let centre = camera.view_proj * vec4<f32>(c, 1.0);
    var lo = vec2<f32>(3.0e38);
    var hi = vec2<f32>(-3.0e38);
    for (var k = 0u; k < 8u; k++) {
        let s = vec3<f32>(f32(k & 1u), f32((k >> 1u) & 1u), f32(k >> 2u)) * 2.0 - 1.0;
        let clip = centre + s.x * ax + s.y * ay + s.z * az;
        if !(clip.w > 1e-6 * abs(centre.w) && all(abs(clip.xy) < vec2<f32>(1.0e4 * clip.w))) {
            return false;
        }
        let ndc = clip.xy / clip.w;
        let px = vec2<f32>((ndc.x + 1.0) * 0.5 * camera.viewport.x, (1.0 - ndc.y) * 0.5 * camera.viewport.y);
        lo = min(lo, px);
        hi = max(hi, px);
    }
    // The view distance of the cube's near face (view z runs towards the eye).
    let d = -(v * vec4<f32>(c, 1.0)).z - r;
    if !(d > camera.depth.z) {
        return false;
    }
    let near = view_depth(-d);
    // The pixel centres the rectangle holds, a pixel wider each side for the f32 rounding.
    let size = vec2<i32>(camera.viewport.xy);
    let first = max(vec2<i32>(floor(lo - 1.5)), vec2<i32>(0));
    let last = min(vec2<i32>(ceil(hi + 0.5)), size - 1);
    if any(first > last) {
        // No pixel centre of the image: the frustum test's tolerance let it through.
        return true;
    }
    // The finer level whose tiles the rectangle spans at most HIZ_REACH of across.
    var t0 = first / i32(HIZ_TILE);
    var t1 = last / i32(HIZ_TILE);
    var base = 0;
    var across = hiz_tiles(0u).x;
    if any(t1 - t0 >= vec2<i32>(HIZ_REACH)) {
        t0 = t0 / i32(HIZ_TILE);
        t1 = t1 / i32(HIZ_TILE);
        let fine = hiz_tiles(0u);
        base = fine.x * fine.y;
        across = hiz_tiles(1u).x;
        if any(t1 - t0 >= vec2<i32>(HIZ_REACH)) {
            return false;
        }
    }
    var far = 0.0;
    for (var ty = t0.y; ty <= t1.y; ty++) {
        for (var tx = t0.x; tx <= t1.x; tx++) {
            far = max(far, hiz[base + ty * across + tx]);
        }
        // Most bricks that show have the background in their first tiles.
        if !(near > far + 2.4e-7) {
            return false;
        }
    }
    // Four units in the last place of a depth in [0.5, 1]: twice what rounds the glyphs' own
    // depths (the shaders' view_depth of their hits, at or beyond the face) and this one.
    return near > far + 2.4e-7;
}

@compute @workgroup_size(64)
fn cs_bricks(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x == 0u {
        dispatch.y = 1u;
        dispatch.z = 1u;
    }
    if gid.x >= brick_slice.count {
        return;
    }
    let b = brick_order[brick_slice.first + gid.x];
    let ball = brick_balls[b];
    if ball_hidden(ball.xyz, ball.w, (brick_slice.flags & BRICKS_OCCLUDED) != 0u) {
        return;
    }
    let groups = BRICK / FRAMES_WORKGROUP;
    visible_out[atomicAdd(&dispatch.x, groups) / groups] = b;
}
