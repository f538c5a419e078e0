// Tessellated superquadrics for the mesh baseline (`mesh:N`, MESH_SUPERQUADRIC in mesh.wgsl) and
// the superquadric's eye-inside test for `mesh:N` and `box`. The shared unit mesh is a θ × φ
// grid on the unit sphere (superquadric_grid in src/render/mesh.rs); sqm_vertex maps a grid
// direction d = (cos θ sin φ, sin θ sin φ, cos φ) through the glyph's own exponents (α, β, c) to
// its surface, as Teem's limnObjectPolarSuperquadFancyAdd places its vertices (signed powers;
// docs/book/src/developer/superquadric-derivation.md §1, local z the symmetry axis):
//
//     x = cos^α θ sin^β φ,   y = sin^α θ R_c(|z|),   z = cos^β φ,
//     R_c(|z|) = K_c^(c/2),   K_c = 1 − |cos φ|^(2β/c)   (= sin^β φ when c = β).
//
// The normal is the gradient of the inside–outside function H (docs §4) at the vertex, which
// for c = β is Barr's parametric normal (cos^(2−α) θ sin^(2−β) φ, …, cos^(2−β) φ) up to a
// positive factor, and which unlike the parametric form also holds for c ≠ β. Its components
// are formed as natural logarithms and scaled by the largest: the factors themselves overflow
// (|cos φ|^(2−β) next to the equator of a pinched β > 2 glyph, 2β/c ≈ 1e20) or underflow
// (exponents of 1e-20) while the direction does not. A component whose coordinate is exactly 0
// (the poles, the equator, θ multiples of π/2) is 0: the mirror-symmetric limit, the bisector
// on a ridge. No log of 0, no division by 0, no exp of a positive number beyond the largest
// term: finite for every exponent from 1e-30 up. The f64 twin, formula for formula, is
// superquadric_vertex in src/render/mesh.rs.

struct SqmVertex {
    // On the surface, local unit coordinates.
    p: vec3<f32>,
    // Unit outward normal, local unit coordinates.
    n: vec3<f32>,
}

// ln(1 − u) for 0 ≤ u ≤ 1/2, without the cancellation of 1 − u for small u (WGSL has no log1p):
// six terms of the series below 1/16 (truncation < u⁶/7 relative).
fn sqm_ln1m(u: f32) -> f32 {
    if u < 0.0625 {
        return -u * (1.0 + u * (0.5 + u * (0.33333334 + u * (0.25 + u * (0.2 + u * 0.16666667)))));
    }
    return log(1.0 - u);
}

// ln(1 − e^(−w)) for w = e^lw, finite for every finite lw (WGSL has no expm1): the series of
// (1 − e^(−w)) / w below w = 1/16, 0 above w = e⁴ (e^(−w) below an ulp of 1).
fn sqm_ln_1m_exp_neg(lw: f32) -> f32 {
    if lw < -2.7725887 {
        let w = exp(lw);
        return lw + log(1.0 - w * (0.5 - w * (0.16666667 - w * (0.041666668 - w * 0.008333334))));
    }
    if lw > 4.0 {
        return 0.0;
    }
    return log(1.0 - exp(-exp(lw)));
}

// ln |cos φ| from cos φ and sin φ (both nonzero), accurate near the poles, where
// 1 − |cos φ| = sin² φ / (1 + |cos φ|) is small and known better than |cos φ| is.
fn sqm_ln_cos(cz: f32, sp: f32) -> f32 {
    let a = abs(cz);
    if a > 0.5 {
        return sqm_ln1m(sp * sp / (1.0 + a));
    }
    return log(a);
}

// The grid direction d mapped through the exponents e = (α, β, c) (header).
fn sqm_vertex(d: vec3<f32>, e: vec3<f32>) -> SqmVertex {
    var out: SqmVertex;
    let rho = length(d.xy);
    if rho == 0.0 {
        // A pole: the tip of the profile, normal along the axis.
        let s = select(-1.0, 1.0, d.z >= 0.0);
        out.p = vec3<f32>(0.0, 0.0, s);
        out.n = out.p;
        return out;
    }
    let l = length(d);
    let sp = min(rho / l, 1.0);
    let cz = clamp(d.z / l, -1.0, 1.0);
    let ct = clamp(d.x / rho, -1.0, 1.0);
    let st = clamp(d.y / rho, -1.0, 1.0);
    let alpha = e.x;
    let beta = e.y;
    let c = e.z;
    let has_x = ct != 0.0;
    let has_y = st != 0.0;
    let has_z = cz != 0.0;
    // Logarithms of the nonzero factors; 0 stands in for a zero factor, whose terms are dropped.
    let lct = log(select(1.0, abs(ct), has_x));
    let lst = log(select(1.0, abs(st), has_y));
    let lsp = log(sp);
    var lcz = 0.0;
    if has_z {
        lcz = sqm_ln_cos(cz, sp);
    }
    // ln K_c: 2 ln sin φ for c = β; else ln(1 − e^(−w)), w = (2β/c) (−ln |cos φ|); 0 on the
    // equator (K_c = 1).
    let q = 2.0 * beta / c;
    var lk = 2.0 * lsp;
    if c != beta {
        lk = 0.0;
        if has_z {
            lk = sqm_ln_1m_exp_neg(log(q) + log(max(-lcz, 1.17549435e-38)));
        }
    }
    // Every exponent of exp below is ≤ 0: no overflow.
    out.p = vec3<f32>(
        select(0.0, sign(ct) * exp(alpha * lct + beta * lsp), has_x),
        select(0.0, sign(st) * exp(alpha * lst + 0.5 * c * lk), has_y),
        select(0.0, sign(cz) * exp(beta * lcz), has_z),
    );
    // ln |∂H/∂x|, ln |∂H/∂y|, and the two terms of ∂H/∂|z| (docs §4 with H = 1, u = |cos θ|^α,
    // w = |sin θ|^α; the common factor dropped).
    let lx = (2.0 - alpha) * lct - beta * lsp;
    let ly = (2.0 - alpha) * lst - 0.5 * c * lk;
    let t1 = 2.0 * lct + (2.0 - beta) * lcz - 2.0 * lsp;
    let t2 = 2.0 * lst + (q - beta) * lcz - lk;
    var lz = t1;
    if !has_x {
        lz = t2;
    } else if has_y {
        let m = max(t1, t2);
        lz = m + log(1.0 + exp(min(t1, t2) - m));
    }
    // ct and st are never both 0, so the largest present term is finite.
    let none = -3.0e38;
    let top = max(select(none, lx, has_x), max(select(none, ly, has_y), select(none, lz, has_z)));
    let n = vec3<f32>(
        select(0.0, sign(ct) * exp(lx - top), has_x),
        select(0.0, sign(st) * exp(ly - top), has_y),
        select(0.0, sign(cz) * exp(lz - top), has_z),
    );
    out.n = normalize(n);
    return out;
}

// R_e(z) = (1 − z^(2/e))^(e/2), the profile's half-width at height 0 ≤ z ≤ 1.
fn sqm_profile(z: f32, e: f32) -> f32 {
    if z == 0.0 {
        return 1.0;
    }
    let t = exp2(log2(z) * (2.0 / e));
    if t >= 1.0 {
        return 0.0;
    }
    return exp2(log2(1.0 - t) * (0.5 * e));
}

// a / r for a, r ≥ 0: 0 on the axis, 2 ("outside") beyond the profile, where it may be 0.
fn sqm_scaled(a: f32, r: f32) -> f32 {
    if a == 0.0 {
        return 0.0;
    }
    if a >= r {
        return select(2.0, 1.0, a == r);
    }
    return a / r;
}

// N_e(a, b) = (a^(2/e) + b^(2/e))^(e/2) for a, b ≥ 0, scaled by the larger: max(a, b) as e → 0.
fn sqm_pnorm(a: f32, b: f32, e: f32) -> f32 {
    let hi = max(a, b);
    let lo = min(a, b);
    if lo == 0.0 {
        return hi;
    }
    let r = exp2(log2(lo / hi) * (2.0 / e));
    return hi * exp2(log2(1.0 + r) * (0.5 * e));
}

// The inside–outside function H(|x|, |y|, |z|) = N_α(|x| / R_β(z), |y| / R_c(z)) of docs §4 at
// local unit point p (crate::glyph::superquadric::gauge in f32): ≤ 1 exactly on the solid; 2
// stands for the values that are infinite or overflow (outside).
fn sqm_gauge(p: vec3<f32>, e: vec3<f32>) -> f32 {
    let a = abs(p);
    if a.z >= 1.0 {
        return select(2.0, 1.0, a.z == 1.0 && a.x == 0.0 && a.y == 0.0);
    }
    let u = sqm_scaled(a.x, sqm_profile(a.z, e.y));
    let w = sqm_scaled(a.y, sqm_profile(a.z, e.z));
    return sqm_pnorm(u, w, e.x);
}
