// Deferred shading with outlines and shadows (Sigg et al. 2006, §4), one full-screen pass over the
// geometry buffer the glyph methods wrote: base colour (a copy of the colour target, written
// unlit), glyph id, aux (view normal) and depth. The f64 twins: src/effects/shade.rs (shading),
// src/effects/outline.rs (the edge filter), the reference's shadow rays.
// Keep `Effects` in sync with EffectsUniform in src/render/effects.rs.
//
// Composed after common.wgsl and the scene's shape files (src/render/effects.rs,
// composite_source), whose group 0 (camera, glyphs) the pass binds as a glyph method does: in a
// penumbra the pass casts the exact shadow ray against the glyphs the shadow map names there.

struct Effects {
    // View space from the eye's clip space.
    inv_proj: mat4x4<f32>,
    // The shadow map's clip space from the eye's view space.
    view_to_light: mat4x4<f32>,
    // xyz: unit direction towards the key light (view space); w: its share of the diffuse
    // light (src/effects/shade.rs KEY_SHARE).
    key: vec4<f32>,
    // x: ambient, y: diffuse, z: specular, w: shininess.
    lighting: vec4<f32>,
    // rgb: outline colour; a: strength.
    outline: vec4<f32>,
    // x: NORMAL_EDGE, y: DEPTH_EDGE (src/effects/outline.rs), z: unused, w: the depth bias of
    // shadow lookups (shadow map depth units).
    edges: vec4<f32>,
    // x, y: image size in pixels.
    viewport: vec4<f32>,
    // x: outline reach in samples, y: shadow map side, z: PCF radius, w: flags (FLAG_*).
    params: vec4<u32>,
    // World (relative to the scene origin) from the eye's view space.
    view_to_world: mat4x4<f32>,
    // xyz: unit direction towards the key light (world); w unused.
    key_world: vec4<f32>,
    // Ambient occlusion (src/effects/ao.rs): x strength, y reach R (world), z R in the
    // volume's unit (mean largest radii), w the volume's last mip level.
    ao: vec4<f32>,
    // xyz: the volume's low corner (world, relative to the scene origin); w: its smallest cell.
    volume_lo: vec4<f32>,
    // xyz: 1 / the volume's size (world to texture coordinates); w unused.
    volume_scale: vec4<f32>,
}

const FLAG_ORTHO: u32 = 1u;
const FLAG_ADAPTIVE: u32 = 2u;
const FLAG_OUTLINES: u32 = 4u;
const FLAG_SHADOWS: u32 = 8u;
// The glyph group is bound with every glyph of the scene: penumbrae are re-tested exactly.
const FLAG_EXACT: u32 = 16u;
const FLAG_AO: u32 = 32u;

@group(1) @binding(0) var<uniform> fx: Effects;
@group(1) @binding(1) var albedo: texture_2d<f32>;
@group(1) @binding(2) var ids: texture_2d<u32>;
@group(1) @binding(3) var aux: texture_2d<f32>;
@group(1) @binding(4) var depth: texture_depth_2d;
@group(1) @binding(5) var shadow_map: texture_depth_2d;
// The glyph (instance + 1) nearest the light in each texel.
@group(1) @binding(6) var shadow_ids: texture_2d<u32>;
// σ·(mean largest radius) of the glyphs, cell-centred over the scene's box, with its mips.
@group(1) @binding(7) var volume: texture_3d<f32>;
@group(1) @binding(8) var volume_sampler: sampler;

@vertex
fn vs_full(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the viewport, on the far plane: the pass's depth test (greater,
    // against the glyphs' depth, src/render/effects.rs) keeps the pixels something covers.
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    return vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 1.0, 1.0);
}

// The effects a pipeline is built for (src/render/effects.rs): what a frame does not ask for is
// compiled out, so deferred shading alone does not carry the shadow and occlusion code.
override OUTLINES: bool = true;
override SHADOWS: bool = true;
override AO: bool = true;
// The aux target holds the view normal alone, octahedral (oct_encode in common.wgsl), where
// nothing reads it back (AuxTarget::Normal in src/request/mod.rs), else with the view z.
override OCTAHEDRAL_NORMALS: bool = false;

fn view_normal(px: vec2<i32>) -> vec3<f32> {
    let a = textureLoad(aux, px, 0);
    if OCTAHEDRAL_NORMALS {
        return oct_decode(a.xy);
    }
    return a.xyz;
}

fn has(flag: u32) -> bool {
    let built = (flag != FLAG_OUTLINES || OUTLINES) && (flag != FLAG_SHADOWS || SHADOWS)
        && (flag != FLAG_AO || AO);
    return built && (fx.params.w & flag) != 0u;
}

// The view-space point a pixel's depth puts on its ray.
fn view_position(px: vec2<i32>) -> vec3<f32> {
    let d = textureLoad(depth, px, 0);
    let ndc = vec2<f32>(
        (f32(px.x) + 0.5) * 2.0 / fx.viewport.x - 1.0,
        1.0 - (f32(px.y) + 0.5) * 2.0 / fx.viewport.y,
    );
    let v = fx.inv_proj * vec4<f32>(ndc, d, 1.0);
    return v.xyz / v.w;
}

fn clamp_px(p: vec2<i32>) -> vec2<i32> {
    return clamp(p, vec2<i32>(0), vec2<i32>(fx.viewport.xy) - 1);
}

// The view distance a pixel's depth puts on its ray: a projection's view z and w depend on its
// depth alone (the x and y terms of inv_proj's rows 2 and 3 are zero, off-centre tiles
// included), so two rows of the matrix, not a whole product.
fn view_distance(px: vec2<i32>) -> f32 {
    let d = textureLoad(depth, px, 0);
    let z = fx.inv_proj[2].z * d + fx.inv_proj[3].z;
    let w = fx.inv_proj[2].w * d + fx.inv_proj[3].w;
    return -z / w;
}

// The outline filter of src/effects/outline.rs: another glyph (or none) among the 3×3 samples
// `reach` apart, else the Sobel gradient of the normal or of the relative view distance. The ids
// are read first (most outline pixels end there), and the centre's weights are zero, so its
// normal and depth are not read.
fn is_outline(px: vec2<i32>, id: u32, distance: f32) -> bool {
    let k = i32(max(fx.params.x, 1u));
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            if (i != 0 || j != 0) && textureLoad(ids, clamp_px(px + vec2<i32>(i, j) * k), 0).r != id {
                return true;
            }
        }
    }
    var gx_n = vec3<f32>(0.0);
    var gy_n = vec3<f32>(0.0);
    var gx_d = 0.0;
    var gy_d = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            if i == 0 && j == 0 {
                continue;
            }
            let q = clamp_px(px + vec2<i32>(i, j) * k);
            // Sobel: the x weight is i times 2 on the centre row, 1 off it.
            let wx = f32(i) * f32(2 - abs(j));
            let wy = f32(j) * f32(2 - abs(i));
            let n = view_normal(q);
            let s = view_distance(q);
            gx_n += n * wx;
            gy_n += n * wy;
            gx_d += s * wx;
            gy_d += s * wy;
        }
    }
    let g_n = sqrt(dot(gx_n, gx_n) + dot(gy_n, gy_n));
    let g_d = sqrt(gx_d * gx_d + gy_d * gy_d) / max(abs(distance), 1e-30);
    return g_n > fx.edges.x || g_d > fx.edges.y;
}

// The glyph (instance + 1) whose texel shadows a point at light depth z, or 0: the map sees the
// point there, or sees the point's own glyph (a convex glyph shadows itself only where it faces
// away from the light, which the caller decides exactly, so its own texels never shadow it: no
// acne at any slope).
fn tap(texel: vec2<i32>, offset: vec2<i32>, z: f32, own: u32) -> u32 {
    let size = i32(fx.params.y);
    let q = clamp(texel + offset, vec2<i32>(0), vec2<i32>(size - 1));
    let caster = textureLoad(shadow_ids, q, 0).r;
    if z <= textureLoad(shadow_map, q, 0) || caster == own {
        return 0u;
    }
    return caster;
}

fn lit_tap(texel: vec2<i32>, offset: vec2<i32>, z: f32, own: u32) -> f32 {
    return select(0.0, 1.0, tap(texel, offset, z, own) == 0u);
}

// Set where the shape code (composed before this file) would discard: a missed shadow ray.
var<private> shadow_missed: bool;

// Whether glyph `instance` lies on the ray from `p` (world, relative to the scene origin)
// towards the light `l`: the shape's own entry (shape_entry, as Gumhold's solids cast it) in its
// parameter space.
fn blocks_light(instance: u32, p: vec3<f32>, l: vec3<f32>) -> bool {
    shadow_missed = false;
    let g = load_glyph(instance);
    let o = quat_to_mat3(g.rotation);
    let solid = shape_of(g, instance);
    let ot = transpose(o);
    let e = shape_entry((ot * (p - g.centre)) / solid.scale, (ot * l) / solid.scale, solid.shape, 0.0);
    return !shadow_missed && e.x > 0.0;
}

// How lit the key light leaves a point: percentage-closer filtering over (2r+1)² texels placed
// at the point's exact position in the map (the kernel's edge texels weighted by their
// overlap, bilinearly), or, with the adaptive test, over the kernel's corners and centre where
// those agree. In a penumbra the map knows the shadow's edge only to a texel; the exact shadow
// ray against the casters the kernel saw decides which side of one half the point falls, and
// the filter keeps its softness on that side.
fn lit_fraction(p_view: vec3<f32>, nk: f32, own: u32) -> f32 {
    let q = fx.view_to_light * vec4<f32>(p_view, 1.0);
    let c = q.xyz / q.w;
    let uv = vec2<f32>(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) || c.z > 1.0 {
        return 1.0;
    }
    let f = uv * f32(fx.params.y) - 0.5;
    let texel = vec2<i32>(floor(f));
    let t = f - floor(f);
    let r = i32(fx.params.z);
    // The kernel reaches r + 1 texels: a surface at angle θ to the light rises tan θ per texel
    // across it, which must not shadow the point itself.
    let tan_theta = min(sqrt(max(1.0 - nk * nk, 0.0)) / max(nk, 1e-6), 8.0);
    let z = c.z - fx.edges.w * (1.0 + f32(r + 1) * tan_theta);
    if has(FLAG_ADAPTIVE) {
        let probe = lit_tap(texel, vec2<i32>(-r, -r), z, own) + lit_tap(texel, vec2<i32>(r + 1, -r), z, own)
            + lit_tap(texel, vec2<i32>(-r, r + 1), z, own) + lit_tap(texel, vec2<i32>(r + 1, r + 1), z, own)
            + lit_tap(texel, vec2<i32>(0, 0), z, own);
        // Wholly lit by the probe: done. Wholly shadowed: done if the centre's caster does
        // shadow the point exactly; else the point may lie in a gap narrower than a texel,
        // which the whole kernel and its casters decide below.
        if probe == 5.0 || (probe == 0.0 && !has(FLAG_EXACT)) {
            return probe / 5.0;
        }
        if probe == 0.0 {
            let p = (fx.view_to_world * vec4<f32>(p_view, 1.0)).xyz;
            if blocks_light(tap(texel, vec2<i32>(0, 0), z, own) - 1u, p, fx.key_world.xyz) {
                return 0.0;
            }
        }
    }
    var sum = 0.0;
    var weight = 0.0;
    // The casters the kernel saw, a few distinct ones (neighbouring texels mostly repeat one).
    var casters = array<u32, 8>(0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    var found = 0u;
    for (var j = -r; j <= r + 1; j++) {
        let wy = select(select(1.0, t.y, j == r + 1), 1.0 - t.y, j == -r);
        for (var i = -r; i <= r + 1; i++) {
            let wx = select(select(1.0, t.x, i == r + 1), 1.0 - t.x, i == -r);
            let caster = tap(texel, vec2<i32>(i, j), z, own);
            if caster == 0u {
                sum += wx * wy;
            } else if found < 8u {
                var seen = false;
                for (var k = 0u; k < found; k++) {
                    seen = seen || casters[k] == caster;
                }
                if !seen {
                    casters[found] = caster;
                    found++;
                }
            }
            weight += wx * wy;
        }
    }
    let soft = sum / weight;
    if !has(FLAG_EXACT) || found == 0u {
        return soft;
    }
    let p = (fx.view_to_world * vec4<f32>(p_view, 1.0)).xyz;
    // Kept a little off one half, which the 8-bit effects target would round either way.
    for (var k = 0u; k < found; k++) {
        if blocks_light(casters[k] - 1u, p, fx.key_world.xyz) {
            return min(soft, 0.45);
        }
    }
    return max(soft, 0.55);
}

// The cones of src/effects/ao.rs (hemisphere(AO_CONES), about +z): a Fibonacci spiral on the
// disc lifted to the hemisphere, cosine-weighted.
const AO_CONES: u32 = 4u;
const AO_STEPS: u32 = 3u;
// The mip level's cell over the distance marched: below the cones' own width (four cones share
// the hemisphere's 2π sr, about 0.87), so that a level's blur, which reaches about one of its
// cells, does not reach back to the surface the cone leaves (a large glyph would otherwise
// occlude itself).
const AO_CONE_SLOPE: f32 = 0.3;

// The open fraction of the sky at p (world, relative to the scene origin) about the unit normal
// n: each cone sees exp(−∫σ) along its axis, σ read from the mip level as wide as the cone.
fn open_fraction(p: vec3<f32>, n: vec3<f32>) -> f32 {
    // Frisvad's frame with Duff et al.'s sign (src/effects/ao.rs frame).
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let tx = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let ty = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    let reach = fx.ao.y;
    let dt = 1.0 / f32(AO_STEPS);
    var open = 0.0;
    for (var k = 0u; k < AO_CONES; k++) {
        let r = sqrt((f32(k) + 0.5) / f32(AO_CONES));
        let phi = 2.3999632 * f32(k);
        let d = tx * (r * cos(phi)) + ty * (r * sin(phi)) + n * sqrt(max(1.0 - r * r, 0.0));
        var tau = 0.0;
        for (var i = 0u; i < AO_STEPS; i++) {
            let t = (f32(i) + 0.5) * dt * reach;
            let uvw = (p + d * t - fx.volume_lo.xyz) * fx.volume_scale.xyz;
            if all(uvw >= vec3<f32>(0.0)) && all(uvw <= vec3<f32>(1.0)) {
                let level = clamp(log2(max(AO_CONE_SLOPE * t / fx.volume_lo.w, 1.0)), 0.0, fx.ao.w);
                tau += textureSampleLevel(volume, volume_sampler, uvw, level).r * fx.ao.z * dt;
            }
        }
        open += exp(-tau);
    }
    return open / f32(AO_CONES);
}

struct Out {
    @location(0) color: vec4<f32>,
    // r: lit fraction, g: outline state (read back for the accuracy check).
    @location(1) effects: vec4<f32>,
}

@fragment
fn fs_composite(@builtin(position) pos: vec4<f32>) -> Out {
    let px = vec2<i32>(floor(pos.xy));
    let id = textureLoad(ids, px, 0).r;
    if id == 0u {
        discard;
    }
    let base = textureLoad(albedo, px, 0);
    let n = normalize(view_normal(px));
    let p = view_position(px);
    var l = vec3<f32>(0.0, 0.0, 1.0);
    if !has(FLAG_ORTHO) {
        l = normalize(-p);
    }
    let nl = max(dot(n, l), 0.0);
    var lit = 1.0;
    // Ambient occlusion scales the ambient and headlight terms, not the key light's.
    var open = 1.0;
    var occlusion = 1.0;
    if has(FLAG_AO) {
        let p_world = (fx.view_to_world * vec4<f32>(p, 1.0)).xyz;
        let n_world = normalize((fx.view_to_world * vec4<f32>(n, 0.0)).xyz);
        open = open_fraction(p_world, n_world);
        occlusion = 1.0 - fx.ao.x * (1.0 - open);
    }
    var diffuse = nl * occlusion;
    if has(FLAG_SHADOWS) {
        let nk = max(dot(n, fx.key.xyz), 0.0);
        // A surface facing away from the light is in its own (attached) shadow.
        lit = select(0.0, lit_fraction(p, nk, id), nk > 0.0);
        diffuse = (1.0 - fx.key.w) * nl * occlusion + fx.key.w * lit * nk;
    }
    let spec = pow(nl, fx.lighting.w);
    var c = clamp(base.rgb * (fx.lighting.x * occlusion + fx.lighting.y * diffuse) + vec3<f32>(fx.lighting.z * spec), vec3<f32>(0.0), vec3<f32>(1.0));
    var edge = false;
    if has(FLAG_OUTLINES) {
        edge = is_outline(px, id, -p.z);
        if edge {
            c = mix(c, fx.outline.rgb, fx.outline.a);
        }
    }
    return Out(vec4<f32>(c, base.a), vec4<f32>(lit, select(0.0, 1.0, edge), open, 1.0));
}
