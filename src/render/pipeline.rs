//! Pipeline state every glyph method shares: one bind group (camera + glyph instances), the same
//! targets, depth test and no culling (impostor winding depends on the view).

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use crate::render::context::GpuContext;
use crate::render::prepass::{PrepassLayouts, PrepassPipelines};
use crate::render::targets::{AUX_FORMAT, COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT};

/// Which fragment outputs a pipeline writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Variant {
    /// Write the ray-cast depth (`frag_depth`); otherwise the proxy's own depth stands.
    pub depth_correction: bool,
    /// Also write the aux target (view normal, view z) for accuracy checks.
    pub aux: bool,
}

impl Variant {
    pub const ALL: [Variant; 4] = [
        Variant {
            depth_correction: true,
            aux: false,
        },
        Variant {
            depth_correction: true,
            aux: true,
        },
        Variant {
            depth_correction: false,
            aux: false,
        },
        Variant {
            depth_correction: false,
            aux: true,
        },
    ];

    /// The fragment entry point of this variant (same names in every method's shader).
    pub fn fragment_entry(self) -> &'static str {
        match (self.depth_correction, self.aux) {
            (true, false) => "fs_depth",
            (true, true) => "fs_depth_aux",
            (false, false) => "fs_flat",
            (false, true) => "fs_flat_aux",
        }
    }

    pub fn index(self) -> usize {
        usize::from(self.depth_correction) * 2 + usize::from(self.aux)
    }
}

/// A bind group layout entry for a buffer (uniform or storage) without dynamic offsets.
pub fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bind group layout of every glyph shader: @binding(0) camera, @binding(1) glyphs (one
/// chunk), @binding(2) the chunk's base instance and culling parameters. Compute stages see it
/// too (the `--prepass` reads the glyphs there).
pub fn glyph_bind_group_layout(ctx: &GpuContext) -> wgpu::BindGroupLayout {
    let all = wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE);
    let uniform = wgpu::BufferBindingType::Uniform;
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("glyphs"),
            entries: &[
                buffer_entry(0, all, uniform),
                buffer_entry(1, all, wgpu::BufferBindingType::Storage { read_only: true }),
                buffer_entry(2, all, uniform),
            ],
        })
}

/// The polygon around the unit circle that Gumhold's proxy is made of (gumhold-ellipsoid.md §10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum)]
pub enum ProxyShape {
    /// Gumhold's quad: 4 vertices, 2 triangles, 4/π = 1.27 of the silhouette's area.
    #[default]
    Quad,
    /// The circumscribed octagon: 8 vertices, 6 triangles, 1.05 of the area.
    Octagon,
    /// The circumscribed triangle: 3 vertices, 1 triangle, 3√3/π = 1.65 of the area.
    Triangle,
}

impl ProxyShape {
    pub fn vertices(self) -> u32 {
        match self {
            ProxyShape::Quad => 4,
            ProxyShape::Octagon => 8,
            ProxyShape::Triangle => 3,
        }
    }
}

/// How the ray casters bound each glyph. Gumhold's methods take all of it (conservative depth
/// only for ellipsoids); Sigg's screen boxes and the meshes ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Proxy {
    pub shape: ProxyShape,
    /// Place the proxy on the glyph's nearest view plane (rasterised depth ≤ ray-cast depth).
    pub conservative: bool,
    /// Declare it to the GPU (`@early_depth_test(greater_equal)`): only with `conservative`, an
    /// adapter with SHADER_EARLY_DEPTH_TEST and every glyph far enough in front of the near plane
    /// for the move ([`crate::scene::Scene::conservative_depth_holds`]).
    pub early_depth: bool,
}

impl Proxy {
    /// Gumhold's quad at the silhouette plane: the path before issue 7, and the default (see
    /// the README's measurements: on lavapipe the other shapes and the conservative move do not
    /// pay for themselves in the whole-field view).
    pub const BASELINE: Proxy = Proxy {
        shape: ProxyShape::Quad,
        conservative: false,
        early_depth: false,
    };

    pub fn vertices(self) -> u32 {
        self.shape.vertices()
    }
}

impl Default for Proxy {
    fn default() -> Self {
        Self::BASELINE
    }
}

/// What besides the shader and variant a glyph pipeline needs: vertex buffers and face culling
/// (the triangle meshes), values for the shader's `override` constants (the ray casters).
#[derive(Debug, Clone, Default)]
pub struct PipelineInput<'a> {
    /// The vertex entry point (`vs_main` when `None`).
    pub vertex_entry: Option<&'a str>,
    /// The fragment entry point (the variant's when `None`).
    pub fragment_entry: Option<&'a str>,
    pub topology: Option<wgpu::PrimitiveTopology>,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// Only for closed, outward-wound (counter-clockwise) meshes.
    pub cull_mode: Option<wgpu::Face>,
    pub constants: &'a [(&'a str, f64)],
}

/// A render pipeline for one method and output variant.
pub fn glyph_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    label: &str,
    topology: wgpu::PrimitiveTopology,
    variant: Variant,
    input: &PipelineInput<'_>,
) -> wgpu::RenderPipeline {
    let options = wgpu::PipelineCompilationOptions {
        constants: input.constants,
        ..Default::default()
    };
    let mut targets = vec![
        Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Some(wgpu::ColorTargetState {
            format: ID_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
    ];
    if variant.aux {
        targets.push(Some(wgpu::ColorTargetState {
            format: AUX_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }));
    }
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(input.vertex_entry.unwrap_or("vs_main")),
            compilation_options: options.clone(),
            buffers: input.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: input.topology.unwrap_or(topology),
            cull_mode: input.cull_mode,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(input.fragment_entry.unwrap_or(variant.fragment_entry())),
            compilation_options: options,
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The ray casters' pipelines for one shader: each draws a triangle strip per instance (glyph)
/// with no vertex buffer, the shader placing the proxy's corners. Pipelines are built on first
/// use per output variant and proxy (lavapipe compiles one in tens of milliseconds). With
/// [`PrepassLayouts`], also the `--prepass` pipelines (compute `cs_frames`, draw `vs_frames`).
pub struct StripRenderer {
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    source: crate::render::shaders::ShaderSource,
    modules: [OnceLock<wgpu::ShaderModule>; 2],
    /// Keyed by variant, proxy and whether the vertices come from the prepass's frames.
    pipelines: Mutex<HashMap<(Variant, Proxy, bool), wgpu::RenderPipeline>>,
    prepass: Option<PrepassLayouts>,
    /// Splats with 64-bit atomics (splat64.wgsl).
    int64_atomics: bool,
    compute: Mutex<HashMap<Proxy, (wgpu::ComputePipeline, Option<wgpu::ComputePipeline>)>>,
    /// The splats' full-screen draw, per variant.
    resolves: Mutex<HashMap<Variant, wgpu::RenderPipeline>>,
}

impl StripRenderer {
    pub fn new(
        ctx: &GpuContext,
        layout: &wgpu::PipelineLayout,
        source: crate::render::shaders::ShaderSource,
        prepass: Option<PrepassLayouts>,
    ) -> Self {
        let r = Self {
            device: ctx.device.clone(),
            layout: layout.clone(),
            source,
            modules: Default::default(),
            pipelines: Mutex::new(HashMap::new()),
            prepass,
            int64_atomics: ctx.int64_atomics,
            compute: Mutex::new(HashMap::new()),
            resolves: Mutex::new(HashMap::new()),
        };
        // Build the default variant now, so shader errors surface where the drawer is made.
        r.pipeline(Variant::ALL[0], Proxy::default(), false);
        r
    }

    /// The shader module, without or with the early-depth declaration (built on first use).
    fn module(&self, early_depth: bool) -> &wgpu::ShaderModule {
        self.modules[usize::from(early_depth)].get_or_init(|| {
            self.device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(self.source.name()),
                    source: wgpu::ShaderSource::Wgsl(
                        self.source.text_for(early_depth, self.int64_atomics).into(),
                    ),
                })
        })
    }

    /// Values of the proxy `override`s, for shaders that have them.
    fn constants(&self, proxy: Proxy) -> Vec<(&'static str, f64)> {
        if !self.source.has_proxy_constants() {
            return Vec::new();
        }
        vec![
            ("PROXY_VERTICES", f64::from(proxy.vertices())),
            (
                "CONSERVATIVE_DEPTH",
                if proxy.conservative { 1.0 } else { 0.0 },
            ),
        ]
    }

    fn pipeline(&self, variant: Variant, proxy: Proxy, frames: bool) -> wgpu::RenderPipeline {
        let key = (variant, proxy, frames);
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
        let constants = self.constants(proxy);
        let frame_buffers = [Some(crate::render::prepass::frame_buffer_layout())];
        let (entry, buffers): (_, &[_]) = if frames {
            ("vs_frames", &frame_buffers)
        } else {
            ("vs_main", &[])
        };
        let p = glyph_pipeline(
            &self.device,
            &self.layout,
            module,
            self.source.name(),
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

    /// Draw `instances` with `proxy` (callers pass the proxy their shader supports).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        variant: Variant,
        proxy: Proxy,
        instances: std::ops::Range<u32>,
    ) {
        pass.set_pipeline(&self.pipeline(variant, proxy, false));
        pass.draw(0..proxy.vertices(), instances);
    }

    /// The `--prepass` pipelines, where this shader has them.
    pub fn prepass_pipelines(&self, variant: Variant, proxy: Proxy) -> Option<PrepassPipelines> {
        let layouts = self.prepass.as_ref()?;
        // The frames do not depend on the fragment stage's early-depth declaration.
        let key = Proxy {
            early_depth: false,
            ..proxy
        };
        let mut compute = self.compute.lock().unwrap_or_else(|e| e.into_inner());
        let (frames, splat_ids) = compute
            .entry(key)
            .or_insert_with(|| {
                let constants = self.constants(key);
                let make = |entry| {
                    self.device
                        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                            label: Some(entry),
                            layout: Some(&layouts.compute),
                            module: self.module(false),
                            entry_point: Some(entry),
                            compilation_options: wgpu::PipelineCompilationOptions {
                                constants: &constants,
                                ..Default::default()
                            },
                            cache: None,
                        })
                };
                // With 64-bit atomics cs_frames keeps the ids too.
                let ids = (!self.int64_atomics).then(|| make("cs_splat_ids"));
                (make("cs_frames"), ids)
            })
            .clone();
        drop(compute);
        let resolve = self
            .resolves
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&variant)
            .cloned();
        let resolve = resolve.unwrap_or_else(|| {
            let p = glyph_pipeline(
                &self.device,
                &layouts.resolve,
                self.module(false),
                "splat resolve",
                wgpu::PrimitiveTopology::TriangleList,
                variant,
                &PipelineInput {
                    vertex_entry: Some("vs_splat_rect"),
                    fragment_entry: Some(if variant.aux {
                        "fs_splat_aux"
                    } else {
                        "fs_splat"
                    }),
                    ..Default::default()
                },
            );
            self.resolves
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert(variant, p.clone());
            p
        });
        Some(PrepassPipelines {
            frames,
            splat_ids,
            draw: self.pipeline(variant, proxy, true),
            resolve,
        })
    }
}
