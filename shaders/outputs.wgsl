// The fragment entry points every method shares. A method's file defines `VsOut` (with
// `position` and flat `id`) and `ray_cast(in) -> Hit`.

fn corrected(in: VsOut) -> Hit {
    let hit = ray_cast(in);
    // frag_depth is clamped, not clipped: a hit in front of the near plane is not drawn.
    if !(hit.depth >= 0.0 && hit.depth <= 1.0) {
        discard;
    }
    return hit;
}

@fragment
fn fs_depth(in: VsOut) -> OutDepth {
    let hit = corrected(in);
    return OutDepth(hit.color, in.id, hit.depth);
}

@fragment
fn fs_depth_aux(in: VsOut) -> OutDepthAux {
    let hit = corrected(in);
    return OutDepthAux(hit.color, in.id, vec4<f32>(hit.n_view, hit.z_rel), hit.depth);
}

@fragment
fn fs_depth_normal(in: VsOut) -> OutDepthNormal {
    let hit = corrected(in);
    return OutDepthNormal(hit.color, in.id, oct_encode(hit.n_view), hit.depth);
}

@fragment
fn fs_flat(in: VsOut) -> OutFlat {
    let hit = ray_cast(in);
    return OutFlat(hit.color, in.id);
}

@fragment
fn fs_flat_aux(in: VsOut) -> OutFlatAux {
    let hit = ray_cast(in);
    // The depth buffer holds the proxy's depth, so report the proxy's view z.
    return OutFlatAux(hit.color, in.id, vec4<f32>(hit.n_view, hit.z_proxy_rel));
}

@fragment
fn fs_flat_normal(in: VsOut) -> OutFlatNormal {
    let hit = ray_cast(in);
    return OutFlatNormal(hit.color, in.id, oct_encode(hit.n_view));
}

// The shadow map's entry points: what ray_cast shades is dead code here, which the compiler
// drops, so a texel costs the intersection alone.
@fragment
fn fs_shadow(in: VsOut) -> OutShadow {
    let hit = corrected(in);
    return OutShadow(in.id, hit.depth);
}

@fragment
fn fs_shadow_flat(in: VsOut) -> OutShadowFlat {
    let hit = ray_cast(in);
    return OutShadowFlat(in.id);
}
