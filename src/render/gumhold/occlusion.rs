//! Occlusion culling in the prepass (Grottel et al. 2010: cost follows what is seen, not the
//! glyph count). A large scene's glyphs are kept in bricks of nearby ones
//! ([`crate::render::bricks`]). Each frame orders the bricks for the camera (those a coarse
//! estimate finds in front first, then the rest nearest first) and draws them in slices; before
//! each slice's compute pass, `cs_bricks` (`shaders/method/occlusion.wgsl`) tests every brick of
//! the slice, one invocation a brick, and lists those that may show something: inside the
//! frustum and, after the first slice, not behind the farthest depth the slices before left in
//! every [`HIZ_TILE`]-pixel tile the brick reaches (`cs_hiz` keeps those tiles; a brick too
//! large on screen is tested against a coarser level, tiles of `HIZ_TILE`² pixels). The slice's
//! `cs_frames` is dispatched indirectly over the listed bricks only, so a hidden brick costs one
//! invocation instead of 256. (A per-glyph test, tried first, left a million glyphs at 4.1×
//! grid40's frame even with every tested glyph culled: docs/notes/occlusion-culling.md.)
//!
//! Only what cannot be seen goes: the tiles bound every depth drawn, and every hit of a glyph
//! in a brick lies at or beyond the near face of the brick's ball's view-aligned cube. The brick
//! order decides how much is culled, never what is drawn (`tests/gpu/less_work.rs` holds ids
//! and depths to the unculled frame's). The key light's shadow map draws unculled.

use std::sync::OnceLock;

use crate::render::bricks::Bricks;
use crate::render::context::GpuContext;
use crate::render::pipeline::{buffer_entry, glyphs_and};
use crate::render::shaders::COMMON;

/// Pixels per side of a depth tile (`HIZ_TILE` in shaders/method/occlusion.wgsl); the second
/// level's tiles are `HIZ_TILE` of these a side.
pub const HIZ_TILE: u32 = 8;

/// Depth tiles of both levels for targets of `size` (the `hiz` buffer's length).
pub fn hiz_len(size: (u32, u32)) -> u64 {
    let fine = (size.0.div_ceil(HIZ_TILE), size.1.div_ceil(HIZ_TILE));
    let coarse = (fine.0.div_ceil(HIZ_TILE), fine.1.div_ceil(HIZ_TILE));
    u64::from(fine.0) * u64::from(fine.1) + u64::from(coarse.0) * u64::from(coarse.1)
}

/// `BRICKS_OCCLUDED` of shaders/method/occlusion.wgsl.
const BRICKS_OCCLUDED: u32 = 1;

/// Bytes of `BrickSlice` and of `Dispatch` (shaders/method/occlusion.wgsl).
const BRICK_SLICE_SIZE: u64 = 16;
const DISPATCH_SIZE: u64 = 12;

pub const OCCLUSION_SHADER: &str = include_str!("../../../shaders/method/occlusion.wgsl");

/// The culling passes' shader: common.wgsl (its camera), then occlusion.wgsl.
pub fn occlusion_source() -> String {
    format!("{COMMON}\n{OCCLUSION_SHADER}")
}

/// What one slice of a frame draws: slice `k`'s buffers and `count` glyphs from `first`, or,
/// with `bricks`, `count` bricks from position `first` of the frame's brick order, tested
/// against the depth the slices before drew when `occluded`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SliceDraw {
    pub k: usize,
    pub first: u32,
    pub count: u32,
    pub bricks: bool,
    pub occluded: bool,
}

/// The slices of a frame of `bricks` bricks in this frame's order, of which the first `front`
/// are those in front, each slice at most `capacity` bricks: the front first (one slice or
/// more), then the rest; every slice after the first is tested against the ones before.
pub fn plan(front: u32, bricks: u32, capacity: u32) -> Vec<SliceDraw> {
    debug_assert!(front <= bricks && capacity > 0);
    let mut draws = Vec::new();
    let mut cut = |from: u32, to: u32| {
        let mut first = from;
        while first < to {
            let count = (to - first).min(capacity);
            draws.push(SliceDraw {
                k: draws.len(),
                first,
                count,
                bricks: true,
                occluded: !draws.is_empty(),
            });
            first += count;
        }
    };
    cut(0, front);
    cut(front, bricks);
    draws
}

/// Slices a scene of `bricks` bricks may take ([`plan`]'s most).
pub fn most_slices(bricks: u32, capacity: u32) -> usize {
    bricks.div_ceil(capacity.max(1)) as usize + 1
}

/// One slice's culling buffers: its range of bricks (`BrickSlice`), the bricks it lists and the
/// indirect dispatch of its `cs_frames`.
pub struct SliceCulling {
    params: wgpu::Buffer,
    visible: wgpu::Buffer,
    dispatch: wgpu::Buffer,
}

impl SliceCulling {
    /// The bricks this slice listed (`visible_bricks` of shaders/method/prepass.wgsl).
    pub fn visible(&self) -> &wgpu::Buffer {
        &self.visible
    }

    /// The slice's `cs_frames` dispatch arguments.
    pub fn dispatch(&self) -> &wgpu::Buffer {
        &self.dispatch
    }
}

/// A scene's culling buffers in one prepass: the bricks' glyphs and balls, this frame's order,
/// and per slice its [`SliceCulling`].
pub struct SceneCulling {
    pub glyphs: wgpu::Buffer,
    balls: wgpu::Buffer,
    order: wgpu::Buffer,
    pub slices: Vec<SliceCulling>,
}

impl SceneCulling {
    /// Buffers for `slices` slices of at most `capacity` bricks over `bricks`, whose glyphs
    /// are already on the GPU as `glyphs`.
    pub fn new(
        device: &wgpu::Device,
        bricks: &Bricks,
        glyphs: &wgpu::Buffer,
        slices: usize,
        capacity: u32,
    ) -> Self {
        use wgpu::util::DeviceExt;
        let storage = wgpu::BufferUsages::STORAGE;
        let copy = wgpu::BufferUsages::COPY_DST;
        let buffer = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        let balls = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("brick balls"),
            contents: bytemuck::cast_slice(&bricks.balls_f32()),
            usage: storage,
        });
        let order = buffer("brick order", bricks.count() as u64 * 4, storage | copy);
        let slices = (0..slices)
            .map(|_| SliceCulling {
                params: buffer("brick slice", BRICK_SLICE_SIZE, storage | copy),
                visible: buffer("visible bricks", u64::from(capacity) * 4, storage),
                dispatch: buffer(
                    "brick dispatch",
                    DISPATCH_SIZE,
                    storage | copy | wgpu::BufferUsages::INDIRECT,
                ),
            })
            .collect();
        Self {
            glyphs: glyphs.clone(),
            balls,
            order,
            slices,
        }
    }

    /// Write this frame's brick order and the ranges of `draws` for the next submission.
    pub fn write(&self, queue: &wgpu::Queue, order: &[u32], draws: &[SliceDraw]) {
        queue.write_buffer(&self.order, 0, bytemuck::cast_slice(order));
        for d in draws {
            let words = [
                d.first,
                d.count,
                if d.occluded { BRICKS_OCCLUDED } else { 0 },
                0,
            ];
            queue.write_buffer(&self.slices[d.k].params, 0, bytemuck::cast_slice(&words));
        }
    }
}

/// The culling passes' bind group layout and pipelines, built on first use.
pub struct OcclusionPass {
    device: wgpu::Device,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: OnceLock<[wgpu::ComputePipeline; 3]>,
    builder: std::sync::Arc<crate::render::pipeline_cache::Pipelines>,
}

impl OcclusionPass {
    /// The passes for the glyph group `glyphs` (group 0: the camera).
    pub fn new(ctx: &GpuContext, glyphs: &wgpu::BindGroupLayout) -> Self {
        let device = &ctx.device;
        let compute = wgpu::ShaderStages::COMPUTE;
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("occlusion culling"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: compute,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                buffer_entry(1, compute, rw),
                buffer_entry(2, compute, ro),
                buffer_entry(3, compute, ro),
                buffer_entry(4, compute, ro),
                buffer_entry(5, compute, rw),
                buffer_entry(6, compute, rw),
            ],
        });
        let pipeline_layout = glyphs_and(device, "occlusion culling", glyphs, &layout);
        Self {
            device: device.clone(),
            layout,
            pipeline_layout,
            pipelines: OnceLock::new(),
            builder: ctx.pipelines.clone(),
        }
    }

    /// The depth-tile pipelines (both levels) and the brick test's.
    fn pipelines(&self) -> &[wgpu::ComputePipeline; 3] {
        self.pipelines.get_or_init(|| {
            let module = self
                .device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("occlusion.wgsl"),
                    source: wgpu::ShaderSource::Wgsl(occlusion_source().into()),
                });
            let make = |entry| {
                self.builder
                    .compute(&self.pipeline_layout, &module, entry, &[])
            };
            [make("cs_hiz"), make("cs_hiz_coarse"), make("cs_bricks")]
        })
    }

    /// Record slice `draw`'s culling: the depth tiles of what the slices so far drew into
    /// `depth` (targets of `size`), when it is tested against them, then its bricks' test
    /// into its list and dispatch arguments. `chunk_group` binds the camera.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        chunk_group: &wgpu::BindGroup,
        depth: &wgpu::TextureView,
        hiz: &wgpu::Buffer,
        scene: &SceneCulling,
        draw: &SliceDraw,
        size: (u32, u32),
    ) {
        let slice = &scene.slices[draw.k];
        fn bind(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("occlusion culling"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(depth),
                },
                bind(1, hiz),
                bind(2, &scene.balls),
                bind(3, &scene.order),
                bind(4, &slice.params),
                bind(5, &slice.visible),
                bind(6, &slice.dispatch),
            ],
        });
        encoder.clear_buffer(&slice.dispatch, 0, None);
        let [hiz_pipeline, coarse_pipeline, bricks_pipeline] = self.pipelines();
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("occlusion culling"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, chunk_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        if draw.occluded {
            pass.set_pipeline(hiz_pipeline);
            // 8 × 8 tiles a workgroup.
            let tiles = (size.0.div_ceil(HIZ_TILE), size.1.div_ceil(HIZ_TILE));
            pass.dispatch_workgroups(tiles.0.div_ceil(8), tiles.1.div_ceil(8), 1);
            pass.set_pipeline(coarse_pipeline);
            let coarse = (tiles.0.div_ceil(HIZ_TILE), tiles.1.div_ceil(HIZ_TILE));
            pass.dispatch_workgroups(coarse.0.div_ceil(8), coarse.1.div_ceil(8), 1);
        }
        pass.set_pipeline(bricks_pipeline);
        pass.dispatch_workgroups(draw.count.div_ceil(64), 1, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The span of WGSL struct `name` in `module`.
    fn span(module: &wgpu::naga::Module, name: &str) -> u32 {
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("struct {name}"));
        match ty.inner {
            wgpu::naga::TypeInner::Struct { span, .. } => span,
            _ => panic!("{name} is not a struct"),
        }
    }

    #[test]
    fn the_shader_validates_and_its_buffers_match() {
        let source = occlusion_source();
        if let Err(e) = crate::render::shaders::validate(&source) {
            panic!("occlusion.wgsl does not validate:\n{e}");
        }
        let module = crate::render::shaders::parse(&source).expect("parses");
        assert_eq!(u64::from(span(&module, "BrickSlice")), BRICK_SLICE_SIZE);
        assert_eq!(u64::from(span(&module, "Dispatch")), DISPATCH_SIZE);
        // wgpu's indirect dispatch arguments are three u32.
        assert_eq!(DISPATCH_SIZE as usize, std::mem::size_of::<[u32; 3]>());
        // The shader's BRICK and HIZ_TILE are the Rust ones.
        assert!(source.contains(&format!(
            "const BRICK: u32 = {}u;",
            crate::render::bricks::BRICK
        )));
        assert!(source.contains(&format!("const HIZ_TILE: u32 = {HIZ_TILE}u;")));
    }

    #[test]
    fn the_front_comes_first_untested_and_every_brick_once() {
        let draws = plan(3, 40, 16);
        assert!(!draws[0].occluded);
        assert_eq!((draws[0].first, draws[0].count), (0, 3));
        assert!(draws.iter().all(|d| d.bricks));
        assert!(draws[1..].iter().all(|d| d.occluded));
        let mut next = 0;
        for (k, d) in draws.iter().enumerate() {
            assert_eq!((d.k, d.first), (k, next));
            assert!(d.count > 0 && d.count <= 16);
            next += d.count;
        }
        assert_eq!(next, 40);
        assert!(draws.len() <= most_slices(40, 16));
        // Nothing in front: the first slice is drawn untested all the same.
        assert!(!plan(0, 40, 16)[0].occluded);
        // Everything in front: one slice per capacity, the later ones tested.
        let all = plan(40, 40, 16);
        assert_eq!(all.len(), 3);
        assert!(all.len() <= most_slices(40, 16));
    }
}
