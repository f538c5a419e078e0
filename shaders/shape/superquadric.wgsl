// Superquadric glyphs, the shape interface of common.wgsl: parameter space is the local frame
// (third column the symmetry axis) scaled by the radii, where the solid lies in the unit box;
// Gumhold's quad is that of the smallest ball about the centre holding the solid (sq_bound: 1
// for an ellipsoid, √2 for a cylinder, at most √3, the box's corner). The first crossing is
// found by superquadric_finder.wgsl (docs/book/src/developer/superquadric-derivation.md §6); mesh:N maps a shared grid through
// the exponents (superquadric_mesh.wgsl); Gumhold's splats are superquadric_splat.wgsl.
// Twin: src/twin/superquadric.rs.

// The unit box's corner: no superquadric reaches beyond it.
fn shape_radius(radii: vec3<f32>) -> f32 {
    return length(radii);
}

// The shape: the exponents (α, β, c) and the bounding ball's radius.
fn shape_of(g: Glyph, ii: u32) -> Solid {
    let e = load_exponents(ii);
    let bound = sq_bound(e);
    return Solid(g.radii, vec3<f32>(bound), vec4<f32>(e, bound));
}

fn shape_contains(p: vec3<f32>, shape: vec4<f32>) -> bool {
    return sq_contains(p, shape.xyz);
}

fn shape_entry(o: vec3<f32>, v: vec3<f32>, shape: vec4<f32>, t_min: f32) -> vec4<f32> {
    let h = sq_first(o, v, shape.xyz, t_min, shape.w);
    if !h.hit {
        discard;
    }
    return vec4<f32>(h.s, h.n);
}

// The solid lies in its local unit box (half-sizes the radii) and in the ellipsoid of semi-axes
// s·radii (s = sq_bound), so the screen box is the intersection of the hull of the box's eight
// projected corners and the ellipsoid's eq. 5 box (both exact in front of the camera plane; the
// first is tighter for boxy glyphs, the second for round ones), and a frustum plane is missed
// when it misses all eight corners.
fn shape_box(g: Glyph, o: mat3x3<f32>, solid: Solid) -> SiggBox {
    let mc = camera.view_proj * vec4<f32>(g.centre, 1.0);
    let mu = camera.view_proj * vec4<f32>(o[0] * g.radii.x, 0.0);
    let mv = camera.view_proj * vec4<f32>(o[1] * g.radii.y, 0.0);
    let mw = camera.view_proj * vec4<f32>(o[2] * g.radii.z, 0.0);
    var b: SiggBox;
    b.reach_a = vec3<f32>(
        box_reach(mc.w + mc.x, mu.w + mu.x, mv.w + mv.x, mw.w + mw.x),
        box_reach(mc.w - mc.x, mu.w - mu.x, mv.w - mv.x, mw.w - mw.x),
        box_reach(mc.w + mc.y, mu.w + mu.y, mv.w + mv.y, mw.w + mw.y),
    );
    b.reach_b = vec3<f32>(
        box_reach(mc.w - mc.y, mu.w - mu.y, mv.w - mv.y, mw.w - mw.y),
        box_reach(mc.z, mu.z, mv.z, mw.z),
        box_reach(mc.w - mc.z, mu.w - mu.z, mv.w - mv.z, mw.w - mw.z),
    );
    if outside_frustum(b) {
        b.kind = PROXY_CULL;
        return b;
    }
    var lo = vec2<f32>(3.0e38);
    var hi = vec2<f32>(-3.0e38);
    var in_front = 0u;
    for (var k = 0u; k < 8u; k++) {
        let s = vec3<f32>(
            select(-1.0, 1.0, (k & 1u) != 0u),
            select(-1.0, 1.0, (k & 2u) != 0u),
            select(-1.0, 1.0, (k & 4u) != 0u),
        );
        let p = mc + s.x * mu + s.y * mv + s.z * mw;
        if p.w > 0.0 {
            in_front += 1u;
            lo = min(lo, p.xy / p.w);
            hi = max(hi, p.xy / p.w);
        }
    }
    if in_front == 0u {
        b.kind = PROXY_CULL;
        return b;
    }
    if in_front == 8u {
        let bound = solid.shape.w;
        let q = quadric_box(o[0] * (bound * g.radii.x), o[1] * (bound * g.radii.y), o[2] * (bound * g.radii.z), g.centre);
        b.kind = PROXY_BOX;
        b.lo = lo;
        b.hi = hi;
        if q.kind == PROXY_BOX {
            b.lo = max(lo, q.lo);
            b.hi = min(hi, q.hi);
        }
        b.z = clamp(mc.z / mc.w, 0.0, 1.0);
    } else {
        // The box crosses the camera plane.
        b.kind = PROXY_VIEWPORT;
    }
    return b;
}

// max over s ∈ [−1, 1]³ of c + s·(u, v, w).
fn box_reach(c: f32, u: f32, v: f32, w: f32) -> f32 {
    return c + abs(u) + abs(v) + abs(w);
}

// The first crossing in front of the ray's start (eye, or the orthographic camera plane).
fn shape_cast(r: ptr<function, ParamRay>, shape: vec4<f32>) -> vec4<f32> {
    let h = sq_first((*r).o_t, (*r).v_t, shape.xyz, -(*r).t0, shape.w);
    if !h.hit {
        discard;
    }
    return vec4<f32>(h.s, h.n);
}

// The grid direction mapped to the glyph's surface through its exponents (floored where 2/e must
// stay finite: pack_exponents stores ≥ 1e-30), then scaled by the radii.
fn shape_mesh_point(p: vec3<f32>, n: vec3<f32>, g: Glyph, solid: Solid) -> MeshPoint {
    let s = sqm_vertex(p, max(solid.shape.xyz, vec3<f32>(1e-30)));
    return MeshPoint(s.p * g.radii, s.n / g.radii);
}

// The box [−1, 1]³ scaled by the radii holds every superquadric.
fn shape_box_half(g: Glyph, solid: Solid) -> vec3<f32> {
    return g.radii;
}

// One colour per glyph (only ODF glyphs colour their pixels by direction).
fn shape_tint(dir: vec3<f32>, local: vec3<f32>, shape: vec4<f32>, base: vec3<f32>) -> vec3<f32> {
    return base;
}
