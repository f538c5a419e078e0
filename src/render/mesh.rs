//! The triangle-mesh baselines other tools use: `mesh:N` draws one shared unit mesh per scene,
//! instanced once per glyph (each kind's own, [`crate::shape::Shape::unit_mesh`]: an icosphere
//! subdivided N times for ellipsoids, a prism with 6·2^N sides and flat caps for cylinders, two
//! hemispheres joined by a tube for capsules, a θ × φ grid of 6·2^N × 3·2^N steps for
//! superquadrics) and `box` the glyph's oriented box, flat shaded. The vertex shader
//! (shaders/method/mesh.wgsl) places each unit-mesh point and normal in the glyph's frame through
//! its kind's `shape_mesh_point` (for most kinds c + O diag(r) p and O diag(1/r) n, the inverse
//! transpose); the fragment shader shades the renormalised, interpolated normal with the shared
//! `shade()`. Depth is the rasterised depth of the mesh.

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::render::drawer::Drawer;
use crate::render::gpu_data::GPU_GLYPH_SIZE;
use crate::render::pipeline::{GlyphLayouts, PipelineInput, Variant, glyph_pipeline};
use crate::render::scene_buffers::ChunkBuffers;
use crate::render::shaders::{MethodShader, ShaderSource};
use crate::request::{GlyphKind, Method, Proxy};
use crate::shape::mesh::{Mesh, MeshVertex, cube};

/// Mesh pipelines cull back faces: every unit mesh is closed and wound outward, and the glyph
/// transform c + O diag(r) p keeps orientation (O a rotation, r > 0). Culling halves the
/// triangles rasterised and matches the reference, which does not draw a glyph the eye is in.
pub const MESH_CULL_MODE: Option<wgpu::Face> = Some(wgpu::Face::Back);

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

/// The unit mesh a method draws for a glyph kind, or `None` for ray-cast methods.
pub fn unit_mesh(method: Method, glyph: GlyphKind) -> Option<Mesh> {
    match method {
        Method::Mesh(n) => Some(glyph.shape().unit_mesh(n)),
        Method::Box => Some(cube()),
        _ => None,
    }
}

/// (vertices, triangles) per glyph: the unit mesh's for the mesh methods, the 4-vertex strip
/// (2 triangles) of the Gumhold and Sigg proxies, nothing for the CPU reference. Without building
/// the mesh.
pub fn mesh_stats(method: Method, glyph: GlyphKind) -> (usize, usize) {
    match method {
        Method::Mesh(n) => glyph.shape().mesh_stats(n),
        Method::Box => (24, 12),
        Method::Gumhold | Method::Sigg => (4, 2),
        Method::Reference => (0, 0),
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
    builder: std::sync::Arc<crate::render::pipeline_cache::Pipelines>,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    label: String,
    /// `MESH_BOX`'s value.
    boxes: bool,
    /// Per variant ([`Variant::index`]), built on first use.
    pipelines: [std::sync::OnceLock<wgpu::RenderPipeline>; Variant::COUNT],
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
        let source = ShaderSource::new(MethodShader::Mesh, glyph);
        let module = ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&source.name()),
                source: wgpu::ShaderSource::Wgsl(source.text().into()),
            });
        let label = format!("{method} {glyph}");
        let buffer = |contents: &[u8], usage| {
            ctx.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&label),
                    contents,
                    usage,
                })
        };
        let vertices = buffer(
            bytemuck::cast_slice(&mesh.vertices),
            wgpu::BufferUsages::VERTEX,
        );
        let indices = buffer(
            bytemuck::cast_slice(&mesh.indices),
            wgpu::BufferUsages::INDEX,
        );
        Ok(Self {
            builder: ctx.pipelines.clone(),
            layout: layout.clone(),
            module,
            label,
            boxes: method == Method::Box,
            pipelines: Default::default(),
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
        })
    }
}

impl MeshRenderer {
    /// The pipeline of `variant`, built on first use.
    fn pipeline(&self, variant: Variant) -> &wgpu::RenderPipeline {
        self.pipelines[variant.index()].get_or_init(|| {
            let buffers = [Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<MeshVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &VERTEX_ATTRIBUTES,
            })];
            let input = PipelineInput {
                buffers: &buffers,
                cull_mode: MESH_CULL_MODE,
                constants: &[("MESH_BOX", f64::from(u8::from(self.boxes)))],
                ..Default::default()
            };
            glyph_pipeline(
                &self.builder,
                &self.layout,
                &self.module,
                &self.label,
                wgpu::PrimitiveTopology::TriangleList,
                variant,
                &input,
            )
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
        pass.set_pipeline(self.pipeline(variant));
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, chunk.instances());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The renderer's stats are the unit meshes' for every kind and level, and the box's.
    #[test]
    fn stats_and_bytes_are_the_unit_meshes() {
        for &glyph in GlyphKind::VALUES {
            let mut methods: Vec<Method> = (0..=Method::MAX_MESH_LEVEL).map(Method::Mesh).collect();
            methods.push(Method::Box);
            for method in methods {
                let m = unit_mesh(method, glyph).unwrap();
                let name = format!("{method} {glyph}");
                assert_eq!(
                    mesh_stats(method, glyph),
                    (m.vertices.len(), m.triangles()),
                    "{name}"
                );
                assert_eq!(shared_mesh_bytes(method, glyph), m.bytes(), "{name}");
            }
            assert_eq!(mesh_stats(Method::Box, glyph), (24, 12));
            assert!(unit_mesh(Method::Gumhold, glyph).is_none());
        }
    }
}
