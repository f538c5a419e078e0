//! The triangle-mesh baselines other tools use: `mesh:N` draws one shared unit mesh per scene,
//! instanced once per glyph (an icosphere subdivided N times for ellipsoids, a prism with 6·2^N
//! sides and flat caps for cylinders, two hemispheres joined by a tube for capsules) and `box`
//! the glyph's oriented box, flat shaded. The vertex shader (shaders/mesh.wgsl) maps a unit-mesh
//! point p to c + O diag(r) p and its normal n to O diag(1/r) n (the inverse transpose); the
//! fragment shader shades the renormalised, interpolated normal with the shared `shade()`. Depth
//! is the rasterised depth of the mesh.
//!
//! Unit meshes live in the glyph's parameter space: the unit sphere for ellipsoids; for
//! cylinders the axis is x with |x| <= 1 and the cross-section the unit circle in (y, z); the box
//! is [−1, 1]³ (for a cylinder it encloses it). A capsule's proportions differ per glyph, so its
//! unit mesh is the capsule of segment half-length 1 and radius 1, each point the end (x = ±1)
//! plus the unit normal: the shader places it at c + O (h sign(p.x) x + R n) with the glyph's
//! `capsule_of` (h, R), and draws the box scaled to (h + R, R, R). Vertices lie on the surface
//! (inscribed meshes). Every triangle winds counter-clockwise seen from outside, so back faces
//! can be culled.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::drawer::Drawer;
use crate::render::gpu_data::GPU_GLYPH_SIZE;
use crate::render::pipeline::{GlyphLayouts, PipelineInput, Variant, glyph_pipeline};
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
        // Not tessellated yet.
        (Method::Mesh(_), GlyphKind::Superquadric) => (0, 0),
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
        // mesh.wgsl's MESH_CAPSULE: 1 for the unit capsule, 2 for the capsule's box.
        let capsule = match (glyph, method) {
            (GlyphKind::Capsule, Method::Box) => 2.0,
            (GlyphKind::Capsule, _) => 1.0,
            _ => 0.0,
        };
        let input = PipelineInput {
            buffers: &buffers,
            cull_mode: MESH_CULL_MODE,
            constants: &[("MESH_CYLINDER", cylinder), ("MESH_CAPSULE", capsule)],
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
        instances: std::ops::Range<u32>,
    ) {
        // Variant::ALL is in index order.
        pass.set_pipeline(&self.pipelines[variant.index()]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, instances);
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
}
