//! The ray casters' pipelines for one shader: each draws a triangle strip per instance (glyph)
//! with no vertex buffer, the shader placing the proxy's corners. Pipelines are built on first
//! use per output variant and proxy (lavapipe compiles one in tens of milliseconds), so a run
//! builds only the ones its frames draw with.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::render::context::GpuContext;
use crate::render::pipeline::{GlyphLayouts, PipelineInput, Variant, glyph_pipeline};
use crate::render::pipeline_cache::Pipelines;
use crate::render::scene_buffers::{ChunkBuffers, Needs};
use crate::render::shaders::{ShaderDefs, ShaderSource};
use crate::request::Proxy;

pub struct StripRenderer {
    device: wgpu::Device,
    pub(crate) builder: Arc<Pipelines>,
    layout: wgpu::PipelineLayout,
    source: ShaderSource,
    modules: [OnceLock<wgpu::ShaderModule>; 2],
    /// Keyed by variant, proxy, whether the vertices come from `instance_input`, and what the
    /// chunk's glyphs need ([`Needs`]).
    pipelines: Mutex<HashMap<(Variant, Proxy, bool, Needs), wgpu::RenderPipeline>>,
    /// Per-instance vertex input of the `vs_frames` entry point, for shaders that have one.
    instance_input: Option<wgpu::VertexBufferLayout<'static>>,
    /// The shader's splats use 64-bit atomics (splat64.wgsl).
    int64_atomics: bool,
}

impl StripRenderer {
    pub fn new(
        ctx: &GpuContext,
        layouts: &GlyphLayouts,
        source: ShaderSource,
        instance_input: Option<wgpu::VertexBufferLayout<'static>>,
    ) -> Self {
        let r = Self {
            device: ctx.device.clone(),
            builder: ctx.pipelines.clone(),
            layout: layouts.pipeline.clone(),
            source,
            modules: Default::default(),
            pipelines: Mutex::new(HashMap::new()),
            instance_input,
            int64_atomics: ctx.int64_atomics,
        };
        // Parse the shader now, so that its errors surface where the drawer is made; the
        // pipelines wait for the frames that use them (the prepass and splats draw with others
        // than the default variant).
        r.module(false);
        r
    }

    /// The shader module, without or with the early-depth declaration (built on first use).
    pub(crate) fn module(&self, early_depth: bool) -> &wgpu::ShaderModule {
        self.modules[usize::from(early_depth)].get_or_init(|| {
            self.device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&self.source.name()),
                    source: wgpu::ShaderSource::Wgsl(
                        self.source
                            .text_with(ShaderDefs {
                                early_depth,
                                int64_atomics: self.int64_atomics,
                            })
                            .into(),
                    ),
                })
        })
    }

    /// Values of the shader's `override`s: the proxy's, and what the glyphs of a chunk need
    /// (`needs`), for the shaders that have them.
    pub(crate) fn constants(&self, proxy: Proxy, needs: Needs) -> Vec<(&'static str, f64)> {
        let mut c = Vec::new();
        if self.source.has_proxy_constants() {
            c.push(("PROXY_VERTICES", f64::from(proxy.vertices())));
            c.push((
                "CONSERVATIVE_DEPTH",
                if proxy.conservative { 1.0 } else { 0.0 },
            ));
        }
        if let Some(name) = self.source.general_override() {
            c.push((name, if needs.general { 1.0 } else { 0.0 }));
        }
        if self.source.has_thin_path() {
            c.push(("THIN_EXACT", if needs.thin { 1.0 } else { 0.0 }));
        }
        c
    }

    /// `needs` as pipelines are keyed: a flag changes only the shaders that read it, so one
    /// pipeline serves both values for the others.
    pub(crate) fn needs_key(&self, needs: Needs) -> Needs {
        Needs {
            general: needs.general || self.source.general_override().is_none(),
            thin: needs.thin && self.source.has_thin_path(),
        }
    }

    /// The strip pipeline of `variant` and `proxy`; with `from_instances`, its vertices come
    /// from the per-instance input (`vs_frames`) instead of the glyph storage buffer; `needs`
    /// says which of the searches and paths of [`Needs`] the shader keeps.
    pub(crate) fn pipeline(
        &self,
        variant: Variant,
        proxy: Proxy,
        from_instances: bool,
        needs: Needs,
    ) -> wgpu::RenderPipeline {
        let needs = self.needs_key(needs);
        let key = (variant, proxy, from_instances, needs);
        if let Some(p) = self
            .pipelines
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            return p.clone();
        }
        // early_depth_test only means something where the fragment writes depth.
        let module = self.module(proxy.early_depth && variant.depth_correction);
        let constants = self.constants(proxy, needs);
        let instance_buffers = [self.instance_input.clone()];
        let (entry, buffers): (_, &[_]) = if from_instances {
            ("vs_frames", &instance_buffers)
        } else {
            ("vs_main", &[])
        };
        let p = glyph_pipeline(
            &self.builder,
            &self.layout,
            module,
            &self.source.name(),
            wgpu::PrimitiveTopology::TriangleStrip,
            variant,
            &PipelineInput {
                vertex_entry: Some(entry),
                buffers,
                constants: &constants,
                ..Default::default()
            },
        );
        self.pipelines
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(key, p.clone());
        p
    }

    /// Draw the instances of `chunk` with `proxy` (callers pass the proxy their shader
    /// supports).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        chunk: &ChunkBuffers,
    ) {
        pass.set_pipeline(&self.pipeline(variant, proxy, false, chunk.needs));
        pass.draw(0..proxy.vertices(), chunk.instances());
    }
}
