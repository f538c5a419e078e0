//! The triangle-mesh baselines other tools use: `mesh:N` draws one shared unit mesh per scene,
//! instanced once per glyph (an icosphere subdivided N times for ellipsoids, a prism with 6·2^N
//! sides and flat caps for cylinders, two hemispheres joined by a tube for capsules, a θ × φ
//! grid of 6·2^N × 3·2^N steps for superquadrics) and `box` the glyph's oriented box, flat
//! shaded. The vertex shader (shaders/mesh.wgsl) maps a unit-mesh point p to c + O diag(r) p
//! and its normal n to O diag(1/r) n (the inverse transpose); the fragment shader shades the
//! renormalised, interpolated normal with the shared `shade()`. Depth is the rasterised depth
//! of the mesh.
//!
//! Unit meshes live in the glyph's parameter space: the unit sphere for ellipsoids; for
//! cylinders the axis is x with |x| <= 1 and the cross-section the unit circle in (y, z); the box
//! is [−1, 1]³ (for a cylinder or a superquadric it encloses it). A capsule's proportions differ
//! per glyph, so its unit mesh is the capsule of segment half-length 1 and radius 1, each point
//! the end (x = ±1) plus the unit normal: the shader places it at c + O (h sign(p.x) x + R n)
//! with the glyph's `capsule_of` (h, R), and draws the box scaled to (h + R, R, R). A
//! superquadric's shape differs per glyph too, so its unit mesh is the parametric grid on the
//! unit sphere ([`superquadric_grid`]) and the shader maps each direction through the glyph's
//! exponents to its surface and normal (shaders/superquadric_mesh.wgsl, twin
//! [`superquadric_vertex`]) before scaling by the radii (local z the symmetry axis): Teem's
//! polar mesh, built per instance on the GPU with no per-glyph memory. Vertices lie on the
//! surface (inscribed meshes; where a pinched superquadric's profile is concave, β > 2, the
//! chords between them pass outside it). Every triangle winds counter-clockwise seen from
//! outside, so back faces can be culled.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::drawer::Drawer;
use crate::render::gpu_data::GPU_GLYPH_SIZE;
use crate::render::pipeline::{GlyphLayouts, PipelineInput, Variant, glyph_pipeline};
use crate::render::scene_buffers::ChunkBuffers;
use crate::render::shaders::ShaderSource;
use crate::request::{GlyphKind, Method, Proxy};

/// Mesh pipelines cull back faces: every unit mesh is closed and wound outward, and the glyph
/// transform c + O diag(r) p keeps orientation (O a rotation, r > 0). Culling halves the
/// triangles rasterised and matches the reference, which does not draw a glyph the eye is in.
pub const MESH_CULL_MODE: Option<wgpu::Face> = Some(wgpu::Face::Back);

/// One vertex of a unit mesh. Keep in sync with `vs_main`'s inputs in shaders/mesh.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    pub position: [f32; 3],
    /// Unit outward normal in the unit mesh's space.
    pub normal: [f32; 3],
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

/// An indexed triangle list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<MeshVertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Bytes of the shared vertex and index buffers.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.indices.as_slice())
    }

    fn push(&mut self, position: [f64; 3], normal: [f64; 3]) -> u32 {
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        self.vertices.push(MeshVertex {
            position: f(position),
            normal: f(normal),
        });
        (self.vertices.len() - 1) as u32
    }
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

/// The icosahedron (level 0, Gumhold's comparison) split `level` times into four triangles per
/// triangle, midpoints pushed onto the unit sphere: 10·4^N + 2 vertices, 20·4^N triangles.
/// Positions are the normals.
pub fn icosphere(level: u8) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut points: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .into_iter()
    .map(normalize)
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, points: &mut Vec<[f64; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (points[a as usize], points[b as usize]);
                points.push(normalize([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                (points.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = mid(a, b, &mut points);
            let bc = mid(b, c, &mut points);
            let ca = mid(c, a, &mut points);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let mut mesh = Mesh::default();
    for p in points {
        mesh.push(p, p);
    }
    mesh.indices = faces.into_iter().flatten().collect();
    mesh
}

/// Sides of the `mesh:N` prism.
pub fn prism_sides(level: u8) -> u32 {
    6 << level
}

/// The unit cylinder as a prism with 6·2^N sides (smooth normals around, the rings shared by the
/// side quads) and flat caps (their own vertices, a fan around the centre): 4S + 2 vertices and
/// 4S triangles for S sides.
pub fn prism(level: u8) -> Mesh {
    let s = prism_sides(level);
    let mut mesh = Mesh::default();
    let ring = |k: u32| {
        let a = std::f64::consts::TAU * f64::from(k % s) / f64::from(s);
        (a.cos(), a.sin())
    };
    // Sides: vertex 2k at x = −1, 2k + 1 at x = +1.
    for k in 0..s {
        let (c, si) = ring(k);
        mesh.push([-1.0, c, si], [0.0, c, si]);
        mesh.push([1.0, c, si], [0.0, c, si]);
    }
    for k in 0..s {
        let (a0, a1) = (2 * k, 2 * k + 1);
        let (b0, b1) = (2 * ((k + 1) % s), 2 * ((k + 1) % s) + 1);
        mesh.indices.extend([a0, b0, b1, a0, b1, a1]);
    }
    // Caps: the centre, then the ring.
    for x in [-1.0, 1.0] {
        let centre = mesh.push([x, 0.0, 0.0], [x, 0.0, 0.0]);
        for k in 0..s {
            let (c, si) = ring(k);
            mesh.push([x, c, si], [x, 0.0, 0.0]);
        }
        for k in 0..s {
            let (i, j) = (centre + 1 + k, centre + 1 + (k + 1) % s);
            if x > 0.0 {
                mesh.indices.extend([centre, i, j]);
            } else {
                mesh.indices.extend([centre, j, i]);
            }
        }
    }
    mesh
}

/// Latitude steps per hemisphere of the `mesh:N` capsule: as close to the longitude step (a
/// quarter of the sides) as whole steps allow.
pub fn capsule_rings(level: u8) -> u32 {
    prism_sides(level).div_ceil(4)
}

/// The unit capsule (segment x ∈ [−1, 1], radius 1) with 6·2^N sides around and M =
/// [`capsule_rings`] latitude steps per hemisphere, smooth normals throughout (the equators are
/// shared by the hemisphere and the tube): 2MS + 2 vertices and 4MS triangles for S sides.
pub fn capsule(level: u8) -> Mesh {
    let s = prism_sides(level);
    let m = capsule_rings(level);
    let mut mesh = Mesh::default();
    // Ring j of end `x` at polar angle θ = j π / (2M) from that end's pole.
    let ring_point = |x: f64, j: u32, k: u32| {
        let theta = std::f64::consts::FRAC_PI_2 * f64::from(j) / f64::from(m);
        let a = std::f64::consts::TAU * f64::from(k % s) / f64::from(s);
        let n = [
            x * theta.cos(),
            theta.sin() * a.cos(),
            theta.sin() * a.sin(),
        ];
        ([x + n[0], n[1], n[2]], n)
    };
    let pole_a = mesh.push([-2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]);
    // Rings from the −x pole to its equator, then from the +x equator to its pole: 2M rings.
    let mut rings: Vec<u32> = Vec::new();
    for (x, js) in [
        (-1.0, (1..=m).collect::<Vec<_>>()),
        (1.0, (1..=m).rev().collect()),
    ] {
        for j in js {
            rings.push(mesh.vertices.len() as u32);
            for k in 0..s {
                let (p, n) = ring_point(x, j, k);
                mesh.push(p, n);
            }
        }
    }
    let pole_b = mesh.push([2.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    // Looking down −x at the −x pole the ring angle a runs clockwise.
    let first = rings[0];
    for k in 0..s {
        mesh.indices
            .extend([pole_a, first + (k + 1) % s, first + k]);
    }
    for pair in rings.windows(2) {
        let (r0, r1) = (pair[0], pair[1]);
        for k in 0..s {
            let k1 = (k + 1) % s;
            mesh.indices
                .extend([r0 + k, r0 + k1, r1 + k1, r0 + k, r1 + k1, r1 + k]);
        }
    }
    let last = *rings.last().unwrap();
    for k in 0..s {
        mesh.indices.extend([pole_b, last + k, last + (k + 1) % s]);
    }
    mesh
}

/// Latitude steps from pole to pole of the `mesh:N` superquadric grid: half the steps around
/// ([`prism_sides`]), so that θ and φ advance by the same angle 2π/S. Teem's `tend glyph` uses
/// 2·`-gr` steps around and `-gr` from pole to pole, default `-gr 10` (20 × 10): between levels 1
/// (12 × 6) and 2 (24 × 12).
pub fn superquadric_rings(level: u8) -> u32 {
    prism_sides(level) / 2
}

/// `cos` and `sin` of `2π k / n`, exactly 0 and ±1 at quarter turns: grid directions in the mirror
/// planes of the superquadric then have exact zeros, where the shader's powers of 0 take their
/// limits.
fn turn(k: u32, n: u32) -> (f64, f64) {
    let k = k % n;
    if (4 * k).is_multiple_of(n) {
        return match 4 * k / n {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        };
    }
    let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
    (a.cos(), a.sin())
}

/// The shared parametric grid of tessellated superquadrics (`mesh:N`, as Teem's
/// `limnObjectPolarSuperquadFancyAdd` builds each glyph): θ × φ on the unit sphere with S =
/// [`prism_sides`] steps of θ around the local z axis and M = [`superquadric_rings`] steps of φ
/// from the pole z = 1 to z = −1, the poles single vertices. Each vertex stores its direction
/// d = (cos θ sin φ, sin θ sin φ, cos φ) as both position and normal (the unit sphere's); the
/// vertex shader maps d through the glyph's exponents to the superquadric
/// ([`superquadric_vertex`]). Exact zeros at the poles, on the equator (M even, level ≥ 1) and at
/// θ multiples of π/2 (S divisible by 4, level ≥ 1). S(M − 1) + 2 vertices, 2S(M − 1)
/// triangles (a fan at each pole, two per quad between rings).
pub fn superquadric_grid(level: u8) -> Mesh {
    let s = prism_sides(level);
    let m = superquadric_rings(level);
    let mut mesh = Mesh::default();
    let north = mesh.push([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
    // Ring j (1 ≤ j < M) starts at vertex 1 + (j − 1) S; φ = j π / M is the turn j / (2M).
    for j in 1..m {
        let (cp, sp) = turn(j, 2 * m);
        for k in 0..s {
            let (ct, st) = turn(k, s);
            let d = [ct * sp, st * sp, cp];
            mesh.push(d, d);
        }
    }
    let south = mesh.push([0.0, 0.0, -1.0], [0.0, 0.0, -1.0]);
    let ring = |j: u32, k: u32| 1 + (j - 1) * s + k % s;
    // θ runs counter-clockwise about +z, φ from +z down.
    for k in 0..s {
        mesh.indices.extend([north, ring(1, k), ring(1, k + 1)]);
    }
    for j in 1..m - 1 {
        for k in 0..s {
            let (a0, a1) = (ring(j, k), ring(j, k + 1));
            let (b0, b1) = (ring(j + 1, k), ring(j + 1, k + 1));
            mesh.indices.extend([a0, b0, b1, a0, b1, a1]);
        }
    }
    for k in 0..s {
        mesh.indices
            .extend([south, ring(m - 1, k + 1), ring(m - 1, k)]);
    }
    mesh
}

/// ln(1 − u) for 0 ≤ u ≤ 1/2 without the cancellation of 1 − u for small u (`sqm_ln1m`).
fn sq_ln1m(u: f64) -> f64 {
    if u < 0.0625 {
        -u * (1.0 + u * (0.5 + u * (1.0 / 3.0 + u * (0.25 + u * (0.2 + u / 6.0)))))
    } else {
        (1.0 - u).ln()
    }
}

/// ln(1 − e^(−w)) for w = e^lw (`sqm_ln_1m_exp_neg`), finite for every finite lw.
fn sq_ln_1m_exp_neg(lw: f64) -> f64 {
    if lw < -2.772_588_722_239_781 {
        let w = lw.exp();
        lw + (1.0 - w * (0.5 - w * (1.0 / 6.0 - w * (1.0 / 24.0 - w / 120.0)))).ln()
    } else if lw > 4.0 {
        0.0
    } else {
        (1.0 - (-lw.exp()).exp()).ln()
    }
}

/// ln |cos φ| from cos φ and sin φ (both nonzero), accurate near the poles (`sqm_ln_cos`).
fn sq_ln_cos(cz: f64, sp: f64) -> f64 {
    let a = cz.abs();
    if a > 0.5 {
        sq_ln1m(sp * sp / (1.0 + a))
    } else {
        a.ln()
    }
}

/// The f64 twin of `sqm_vertex` (shaders/superquadric_mesh.wgsl), formula for formula: the
/// grid direction `d` of [`superquadric_grid`] mapped through the exponents `e = (α, β, c)` to
/// the superquadric's surface, and the unit outward normal there, in local unit coordinates
/// (docs/book/src/developer/superquadric-derivation.md §1: local z the symmetry axis).
///
/// With (cos θ, sin θ) the direction of `d`'s (x, y) and (sin φ, cos φ) its distance from the
/// axis and its z (signed powers throughout):
///
/// ```text
/// x = cos^α θ sin^β φ,   y = sin^α θ R_c(|z|),   z = cos^β φ,
/// R_c(|z|) = K_c^(c/2),  K_c = 1 − |cos φ|^(2β/c)      (= sin^β φ for c = β),
/// ```
///
/// Kindlmann's surface with Teem's stretch of y by R_c / R_β for c ≠ β. The normal is the
/// gradient of the inside–outside function H (docs §4) at the vertex, where H = 1, u = |cos
/// θ|^α and w = |sin θ|^α (signed factors keep their coordinate's sign):
///
/// ```text
/// ∂H/∂x ∝ cos^(2−α) θ / sin^β φ,   ∂H/∂y ∝ sin^(2−α) θ / K_c^(c/2),
/// ∂H/∂z ∝ sgn(cos φ) (cos²θ |cos φ|^(2−β) / sin²φ + sin²θ |cos φ|^(2β/c − β) / K_c),
/// ```
///
/// which for c = β is sin^(−2) φ times Barr's parametric normal (cos^(2−α) θ sin^(2−β) φ,
/// sin^(2−α) θ sin^(2−β) φ, cos^(2−β) φ). Each component is formed as a natural logarithm and
/// all are scaled by the largest, so nothing overflows where the factors do (pinched β > 2
/// next to the equator, 2β/c ≈ 1e20) or underflows to a lost direction (exponents of 1e-20); a
/// component whose coordinate is exactly 0 is 0 (the mirror-symmetric limit, the bisector on
/// ridges), and the poles have normal ±z. No NaN for exponents from
/// 1e-30 up.
pub fn superquadric_vertex(d: [f64; 3], e: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let rho = d[0].hypot(d[1]);
    if rho == 0.0 {
        let s = if d[2] >= 0.0 { 1.0 } else { -1.0 };
        return ([0.0, 0.0, s], [0.0, 0.0, s]);
    }
    let l = (rho * rho + d[2] * d[2]).sqrt();
    let sp = (rho / l).min(1.0);
    let cz = (d[2] / l).clamp(-1.0, 1.0);
    let ct = (d[0] / rho).clamp(-1.0, 1.0);
    let st = (d[1] / rho).clamp(-1.0, 1.0);
    let [alpha, beta, c] = e;
    let (has_x, has_y, has_z) = (ct != 0.0, st != 0.0, cz != 0.0);
    let lct = if has_x { ct.abs().ln() } else { 0.0 };
    let lst = if has_y { st.abs().ln() } else { 0.0 };
    let lsp = sp.ln();
    let lcz = if has_z { sq_ln_cos(cz, sp) } else { 0.0 };
    let q = 2.0 * beta / c;
    let lk = if c == beta {
        2.0 * lsp
    } else if has_z {
        sq_ln_1m_exp_neg(q.ln() + (-lcz).max(f64::from(f32::MIN_POSITIVE)).ln())
    } else {
        0.0
    };
    let sgn = |v: f64| if v > 0.0 { 1.0 } else { -1.0 };
    let p = [
        if has_x {
            sgn(ct) * (alpha * lct + beta * lsp).exp()
        } else {
            0.0
        },
        if has_y {
            sgn(st) * (alpha * lst + 0.5 * c * lk).exp()
        } else {
            0.0
        },
        if has_z {
            sgn(cz) * (beta * lcz).exp()
        } else {
            0.0
        },
    ];
    let lx = (2.0 - alpha) * lct - beta * lsp;
    let ly = (2.0 - alpha) * lst - 0.5 * c * lk;
    let t1 = 2.0 * lct + (2.0 - beta) * lcz - 2.0 * lsp;
    let t2 = 2.0 * lst + (q - beta) * lcz - lk;
    let lz = if !has_x {
        t2
    } else if !has_y {
        t1
    } else {
        let m = t1.max(t2);
        m + (1.0 + (t1.min(t2) - m).exp()).ln()
    };
    let none = -3.0e38;
    let pick = |has: bool, v: f64| if has { v } else { none };
    let top = pick(has_x, lx).max(pick(has_y, ly)).max(pick(has_z, lz));
    let n = [
        if has_x {
            sgn(ct) * (lx - top).exp()
        } else {
            0.0
        },
        if has_y {
            sgn(st) * (ly - top).exp()
        } else {
            0.0
        },
        if has_z {
            sgn(cz) * (lz - top).exp()
        } else {
            0.0
        },
    ];
    (p, normalize(n))
}

/// The cube [−1, 1]³ with flat faces: 24 vertices (4 per face), 12 triangles.
pub fn cube() -> Mesh {
    let mut mesh = Mesh::default();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = [0.0; 3];
            n[axis] = sign;
            // (u, v, n) right-handed, so (±u, ±v) in this order winds counter-clockwise about n.
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = mesh.vertices.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = n;
                p[u] = a * sign;
                p[v] = b;
                mesh.push(p, n);
            }
            mesh.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    mesh
}

/// The unit mesh a method draws for a glyph shape, or `None` for ray-cast methods.
pub fn unit_mesh(method: Method, glyph: GlyphKind) -> Option<Mesh> {
    match (method, glyph) {
        (Method::Mesh(n), GlyphKind::Ellipsoid) => Some(icosphere(n)),
        (Method::Mesh(n), GlyphKind::Cylinder) => Some(prism(n)),
        (Method::Mesh(n), GlyphKind::Capsule) => Some(capsule(n)),
        (Method::Mesh(n), GlyphKind::Superquadric) => Some(superquadric_grid(n)),
        (Method::Box, _) => Some(cube()),
        _ => None,
    }
}

/// (vertices, triangles) per glyph: the unit mesh's for the mesh methods, the 4-vertex strip
/// (2 triangles) of the Gumhold and Sigg proxies, nothing for the CPU reference. Without building
/// the mesh.
pub fn mesh_stats(method: Method, glyph: GlyphKind) -> (usize, usize) {
    match (method, glyph) {
        (Method::Mesh(n), GlyphKind::Ellipsoid) => {
            let f = 1usize << (2 * u32::from(n));
            (10 * f + 2, 20 * f)
        }
        (Method::Mesh(n), GlyphKind::Cylinder) => {
            let s = prism_sides(n) as usize;
            (4 * s + 2, 4 * s)
        }
        (Method::Mesh(n), GlyphKind::Capsule) => {
            let (s, m) = (prism_sides(n) as usize, capsule_rings(n) as usize);
            (2 * m * s + 2, 4 * m * s)
        }
        (Method::Mesh(n), GlyphKind::Superquadric) => {
            let (s, m) = (prism_sides(n) as usize, superquadric_rings(n) as usize);
            (s * (m - 1) + 2, 2 * s * (m - 1))
        }
        (Method::Box, _) => (24, 12),
        (Method::Gumhold | Method::Sigg, _) => (4, 2),
        (Method::Reference, _) => (0, 0),
    }
}

/// GPU bytes per glyph: the instance record only, for every method. The mesh methods add one
/// shared unit mesh per scene ([`shared_mesh_bytes`]), not per glyph.
pub fn bytes_per_glyph(_method: Method) -> usize {
    GPU_GLYPH_SIZE
}

/// Bytes of the vertex and index buffers a mesh method shares across all glyphs of a scene.
pub fn shared_mesh_bytes(method: Method, glyph: GlyphKind) -> usize {
    let (v, t) = mesh_stats(method, glyph);
    match method {
        Method::Mesh(_) | Method::Box => v * std::mem::size_of::<MeshVertex>() + t * 3 * 4,
        _ => 0,
    }
}

/// Triangles per glyph of a tessellated method (`None` for impostors, whose cost does not grow
/// with a level).
pub fn triangles_per_glyph(method: Method, glyph: GlyphKind) -> Option<u64> {
    match method {
        Method::Mesh(_) | Method::Box => Some(mesh_stats(method, glyph).1 as u64),
        _ => None,
    }
}

/// A mesh method's pipelines (one per output variant) and its shared unit mesh.
pub struct MeshRenderer {
    pipelines: Vec<wgpu::RenderPipeline>,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

impl MeshRenderer {
    /// An error for a method that is not a mesh method.
    pub fn new(
        ctx: &GpuContext,
        layouts: &GlyphLayouts,
        method: Method,
        glyph: GlyphKind,
    ) -> Result<Self, RenderError> {
        let layout = &layouts.pipeline;
        let mesh = unit_mesh(method, glyph)
            .ok_or_else(|| RenderError::Unsupported(format!("{method} is not a mesh method")))?;
        let source = ShaderSource::Mesh;
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(source.name()),
                source: wgpu::ShaderSource::Wgsl(source.text().into()),
            });
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX_ATTRIBUTES,
        })];
        let cylinder = f64::from(u8::from(glyph == GlyphKind::Cylinder));
        // mesh.wgsl's MESH_CAPSULE and MESH_SUPERQUADRIC: 1 for the shape's own unit mesh, 2
        // for its box.
        let code = |kind: GlyphKind| match (glyph == kind, method) {
            (false, _) => 0.0,
            (true, Method::Box) => 2.0,
            (true, _) => 1.0,
        };
        let input = PipelineInput {
            buffers: &buffers,
            cull_mode: MESH_CULL_MODE,
            constants: &[
                ("MESH_CYLINDER", cylinder),
                ("MESH_CAPSULE", code(GlyphKind::Capsule)),
                ("MESH_SUPERQUADRIC", code(GlyphKind::Superquadric)),
            ],
            ..Default::default()
        };
        let label = format!("{method} {glyph}");
        let pipelines = Variant::ALL
            .map(|v| {
                glyph_pipeline(
                    &ctx.device,
                    layout,
                    &module,
                    &label,
                    wgpu::PrimitiveTopology::TriangleList,
                    v,
                    &input,
                )
            })
            .into_iter()
            .collect();
        let buffer = |contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&label),
                    contents,
                    usage,
                })
        };
        Ok(Self {
            pipelines,
            vertices: buffer(
                bytemuck::cast_slice(&mesh.vertices),
                wgpu::BufferUsages::VERTEX,
            ),
            indices: buffer(
                bytemuck::cast_slice(&mesh.indices),
                wgpu::BufferUsages::INDEX,
            ),
            index_count: mesh.indices.len() as u32,
        })
    }
}

impl Drawer for MeshRenderer {
    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        _proxy: Proxy,
        chunk: &ChunkBuffers,
    ) {
        // Variant::ALL is in index order.
        pass.set_pipeline(&self.pipelines[variant.index()]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, chunk.instances());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| f64::from(a[i]) - f64::from(b[i]))
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Closed (every edge, by vertex position, used once each way: faces with their own
    /// vertices still meet), outward counter-clockwise winding, unit normals on the outward side.
    fn check_closed_outward(name: &str, m: &Mesh) {
        let key = |i: u32| m.vertices[i as usize].position.map(f32::to_bits);
        let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
                *edges.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
            }
            let [a, b, c] = [0, 1, 2].map(|k| m.vertices[t[k] as usize]);
            let face = cross(sub(b.position, a.position), sub(c.position, a.position));
            let centroid = [0, 1, 2].map(|i| {
                (f64::from(a.position[i]) + f64::from(b.position[i]) + f64::from(c.position[i]))
                    / 3.0
            });
            assert!(dot(face, centroid) > 0.0, "{name}: inward triangle {t:?}");
            for v in [a, b, c] {
                let n = v.normal.map(f64::from);
                assert!((dot(n, n) - 1.0).abs() < 1e-6, "{name}: normal {v:?}");
                assert!(dot(n, face) > 0.0, "{name}: normal against face {v:?}");
            }
        }
        assert!(edges.values().all(|&e| e == 0), "{name}: not closed");
        assert!(m.indices.iter().all(|&i| (i as usize) < m.vertices.len()));
    }

    #[test]
    fn unit_meshes_are_closed_outward_and_match_their_stats() {
        for glyph in [
            GlyphKind::Ellipsoid,
            GlyphKind::Cylinder,
            GlyphKind::Capsule,
            GlyphKind::Superquadric,
        ] {
            let mut methods: Vec<Method> = (0..=Method::MAX_MESH_LEVEL).map(Method::Mesh).collect();
            methods.push(Method::Box);
            for method in methods {
                let m = unit_mesh(method, glyph).unwrap();
                let name = format!("{method} {glyph}");
                check_closed_outward(&name, &m);
                assert_eq!(
                    mesh_stats(method, glyph),
                    (m.vertices.len(), m.triangles()),
                    "{name}"
                );
                assert_eq!(shared_mesh_bytes(method, glyph), m.bytes(), "{name}");
            }
        }
        assert_eq!(mesh_stats(Method::Mesh(0), GlyphKind::Ellipsoid), (12, 20));
        assert_eq!(
            mesh_stats(Method::Mesh(6), GlyphKind::Ellipsoid),
            (40962, 81920)
        );
        assert_eq!(mesh_stats(Method::Mesh(0), GlyphKind::Cylinder), (26, 24));
        assert_eq!(mesh_stats(Method::Mesh(0), GlyphKind::Capsule), (26, 48));
        // 6 × 3 steps: 6 · 2 rings + 2 poles; 6 · 2 fan triangles + 6 · 2 in the one band.
        assert_eq!(
            mesh_stats(Method::Mesh(0), GlyphKind::Superquadric),
            (14, 24)
        );
        assert_eq!(
            mesh_stats(Method::Mesh(6), GlyphKind::Superquadric),
            (73346, 146688)
        );
        assert_eq!(mesh_stats(Method::Box, GlyphKind::Superquadric), (24, 12));
        assert!(unit_mesh(Method::Gumhold, GlyphKind::Ellipsoid).is_none());
    }

    #[test]
    fn vertices_lie_on_the_surface() {
        for v in icosphere(3).vertices {
            let p = v.position.map(f64::from);
            assert!((dot(p, p) - 1.0).abs() < 1e-6);
            assert_eq!(v.position, v.normal);
        }
        for v in prism(2).vertices {
            let [x, y, z] = v.position.map(f64::from);
            let on_side = (x.abs() - 1.0).abs() < 1e-6 && ((y * y + z * z) - 1.0).abs() < 1e-6;
            let on_cap = (x.abs() - 1.0).abs() < 1e-6 && y * y + z * z <= 1.0 + 1e-6;
            assert!(on_side || on_cap, "{v:?}");
        }
        for level in 0..=2 {
            for v in capsule(level).vertices {
                // The end plus the unit normal, on the outer side of its end.
                let p = v.position.map(f64::from);
                let n = v.normal.map(f64::from);
                let end = p[0].signum();
                assert!((dot(n, n) - 1.0).abs() < 1e-6, "{v:?}");
                assert!(
                    (p[0] - end - n[0]).abs() < 1e-6 && p[1] == n[1] && p[2] == n[2],
                    "{v:?}"
                );
                assert!(n[0] * end >= -1e-7, "{v:?}");
            }
        }
        for v in cube().vertices {
            assert!(v.position.iter().all(|x| x.abs() == 1.0));
        }
    }
    /// Exponents (α, β, c) across what the mappings give and beyond: the sphere, Kindlmann
    /// shapes down to γ = 10 (1e-20), Schultz–Kindlmann anchors and blends with c ≠ β (funk,
    /// zone 5), pinched thorns up to β_max = 5, a pinched cross-section (α = 5) and c on
    /// either side of β.
    const SQ_EXPONENTS: [[f64; 3]; 16] = [
        [1.0, 1.0, 1.0],
        [1.0, 0.216, 0.216],
        [0.3, 1.0, 1.0],
        [1e-20, 1e-20, 1e-20],
        [1.0, 1e-20, 1e-20],
        [1e-20, 1.0, 1.0],
        [1e-5, 2.0, 2.0],
        [2.0, 2.0, 2.0],
        [1.0, 3.0, 3.0],
        [1e-5, 3.0, 2.0],
        [0.55, 2.75, 2.3],
        [1.0, 5.0, 5.0],
        [0.5, 5.0, 2.0],
        [5.0, 1.0, 1.0],
        [1.0, 1.2, 3.0],
        [0.7, 1.6, 0.5],
    ];

    /// Smooth shapes (every exponent in (0, 2)), where H has a gradient everywhere off the
    /// poles.
    const SQ_SMOOTH: [[f64; 3]; 5] = [
        [1.0, 1.0, 1.0],
        [0.5, 0.8, 0.8],
        [1.5, 1.2, 1.2],
        [0.7, 1.6, 1.1],
        [1.2, 0.6, 0.9],
    ];

    /// The grid's directions as the GPU reads them (f32).
    fn grid_directions(level: u8) -> Vec<[f64; 3]> {
        superquadric_grid(level)
            .vertices
            .iter()
            .map(|v| v.position.map(f64::from))
            .collect()
    }

    fn gauge_at(e: [f64; 3], p: [f64; 3]) -> f64 {
        crate::glyph::superquadric::gauge(e, p.map(f64::abs))
    }

    #[test]
    fn superquadric_grid_has_exact_zeros_and_counts() {
        for level in 0..=3 {
            let m = superquadric_grid(level);
            let (s, r) = (
                prism_sides(level) as usize,
                superquadric_rings(level) as usize,
            );
            assert_eq!(m.vertices.len(), s * (r - 1) + 2);
            assert_eq!(m.triangles(), 2 * s * (r - 1));
            for v in &m.vertices {
                let p = v.position.map(f64::from);
                assert!((dot(p, p) - 1.0).abs() < 1e-6, "{v:?}");
                assert_eq!(v.position, v.normal);
            }
            let on =
                |f: &dyn Fn([f32; 3]) -> bool| m.vertices.iter().filter(|v| f(v.position)).count();
            assert_eq!(on(&|p| p[0] == 0.0 && p[1] == 0.0), 2, "poles");
            if level >= 1 {
                // The equator, and the two mirror planes (through the poles, counted once).
                assert_eq!(on(&|p| p[2] == 0.0), s, "equator");
                assert_eq!(on(&|p| p[0] == 0.0), 2 * (r - 1) + 2, "x = 0");
                assert_eq!(on(&|p| p[1] == 0.0), 2 * (r - 1) + 2, "y = 0");
            }
        }
        // Teem's default resolution (tend glyph -gr 10: 20 × 10) lies between levels 1 and 2.
        assert_eq!((prism_sides(1), superquadric_rings(1)), (12, 6));
        assert_eq!((prism_sides(2), superquadric_rings(2)), (24, 12));
    }

    /// Every grid vertex mapped through the twin lies on the superquadric: H = 1 to 1e-6, or
    /// where f64 rounds the vertex onto the cap plane |z| = 1 (β ≈ 1e-20: z = 1 − O(1e-20), where
    /// H jumps from ≤ 1 to ∞), the surface crosses the segment from 0.999999 to 1.000001 times
    /// the point. Normals are finite, unit and outward, and no coordinate is NaN, for every
    /// exponent set.
    #[test]
    fn superquadric_vertices_lie_on_the_surface() {
        for level in 0..=4 {
            let dirs = grid_directions(level);
            for e in SQ_EXPONENTS {
                let mut on_cap_plane = 0;
                for &d in &dirs {
                    let (p, n) = superquadric_vertex(d, e);
                    let what = format!("mesh:{level} {e:?} at {d:?}: {p:?}, {n:?}");
                    assert!(p.iter().chain(&n).all(|x| x.is_finite()), "{what}");
                    assert!((dot(n, n) - 1.0).abs() < 1e-12, "{what}");
                    assert!(dot(n, p) > 0.0, "{what}: normal not outward");
                    for (i, x) in p.iter().enumerate() {
                        // Coordinates keep the direction's sign and zeros.
                        assert!(x.abs() <= 1.0, "{what}");
                        assert_eq!(*x == 0.0, d[i] == 0.0, "{what}: zero");
                        assert!(*x == 0.0 || x.signum() == d[i].signum(), "{what}: sign");
                    }
                    let inner = gauge_at(e, p.map(|x| x * (1.0 - 1e-6)));
                    let outer = gauge_at(e, p.map(|x| x * (1.0 + 1e-6)));
                    assert!(inner <= 1.0 && outer >= 1.0, "{what}: {inner} .. {outer}");
                    let h = gauge_at(e, p);
                    if p[2].abs() < 1.0 || (p[0] == 0.0 && p[1] == 0.0) {
                        assert!((h - 1.0).abs() <= 1e-6, "{what}: H = {h}");
                    } else {
                        on_cap_plane += 1;
                    }
                }
                // Only exponents that round z to ±1 in f64 (β ≈ 1e-20) put vertices there.
                assert!(
                    on_cap_plane == 0 || e[1] < 1e-15,
                    "mesh:{level} {e:?}: {on_cap_plane}"
                );
            }
        }
    }

    /// Where the surface is smooth, the twin's normal is the direction of H's numerical
    /// gradient (central differences). Off the poles' neighbourhood, where H's derivatives
    /// grow without bound (|z| ≤ 0.95).
    #[test]
    fn superquadric_normals_are_the_gradient() {
        let h = 1e-6;
        let mut checked = 0;
        for e in SQ_SMOOTH {
            for d in grid_directions(4) {
                let (p, n) = superquadric_vertex(d, e);
                if p[2].abs() > 0.95 {
                    continue;
                }
                let grad = [0, 1, 2].map(|i| {
                    let (mut a, mut b) = (p, p);
                    a[i] += h;
                    b[i] -= h;
                    (gauge_at(e, a) - gauge_at(e, b)) / (2.0 * h)
                });
                let g = normalize(grad);
                let err = [0, 1, 2].map(|i| g[i] - n[i]);
                assert!(
                    dot(err, err).sqrt() < 1e-6,
                    "{e:?} at {d:?}: normal {n:?}, gradient {g:?}"
                );
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    /// The mapped grid stays consistently wound: no triangle of the mapped mesh turns its back
    /// to its own vertex normals (degenerate ones excepted: β ≈ 0 collapses the rings between
    /// pole and equator onto the caps' rims).
    #[test]
    fn mapped_superquadric_triangles_face_outward() {
        for level in 1..=4 {
            let grid = superquadric_grid(level);
            for e in SQ_EXPONENTS {
                let mapped: Vec<_> = grid
                    .vertices
                    .iter()
                    .map(|v| superquadric_vertex(v.position.map(f64::from), e))
                    .collect();
                for t in grid.indices.chunks_exact(3) {
                    let [a, b, c] = [0, 1, 2].map(|k| mapped[t[k] as usize]);
                    let ab = [0, 1, 2].map(|i| b.0[i] - a.0[i]);
                    let ac = [0, 1, 2].map(|i| c.0[i] - a.0[i]);
                    let face = cross(ab, ac);
                    // Degenerate: thinner than 1e-6 (the grid's f32 directions make slivers of
                    // ~1e-8 between vertices that β ≈ 0 maps onto the same rim point).
                    let bc = [0, 1, 2].map(|i| c.0[i] - b.0[i]);
                    let longest = [ab, ac, bc]
                        .map(|v| dot(v, v))
                        .into_iter()
                        .fold(0.0, f64::max);
                    if dot(face, face) <= 1e-12 * longest {
                        continue;
                    }
                    let ns = [0, 1, 2].map(|i| a.1[i] + b.1[i] + c.1[i]);
                    assert!(
                        dot(face, ns) > 0.0,
                        "mesh:{level} {e:?}: triangle {t:?} inward"
                    );
                }
            }
        }
    }

    /// No NaN or infinity for any direction (on or off the grid, in f32 as stored) and any
    /// exponent between 1e-30 and 5, the extremes mixed.
    #[test]
    fn superquadric_vertex_never_nan() {
        let extremes = [1e-30, 1e-20, 1e-5, 0.5, 1.0, 2.0, 3.0, 5.0];
        let mut dirs = grid_directions(6);
        let mut x = 0.5f64;
        for _ in 0..2000 {
            // Pseudo-random directions, some next to the poles and the mirror planes.
            let mut next = || {
                x = (x * 3.987 + 0.1234).fract();
                2.0 * x - 1.0
            };
            let v = [next(), next() * 1e-3f64.powf(next().abs() * 3.0), next()];
            dirs.push(normalize(v).map(|c| f64::from(c as f32)));
        }
        for &a in &extremes {
            for &b in &extremes {
                for &c in &extremes {
                    for d in dirs.iter().step_by(7) {
                        let (p, n) = superquadric_vertex(*d, [a, b, c]);
                        assert!(
                            p.iter().chain(&n).all(|v| v.is_finite()),
                            "{:?} at {d:?}: {p:?} {n:?}",
                            [a, b, c]
                        );
                        assert!((dot(n, n) - 1.0).abs() < 1e-12 && dot(n, p) > 0.0);
                    }
                }
            }
        }
    }
}
