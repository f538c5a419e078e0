//! `--prepass` and `--splat` for Gumhold ellipsoids and superquadrics. A compute pass
//! (`cs_frames`) works out each glyph's proxy frame once (instead of once per proxy vertex) and
//! writes the frames of the glyphs to draw, compacted, counting them into draw-indirect
//! arguments; the draw reads the frames as per-instance vertex attributes. A culled glyph costs
//! one compute invocation and nothing in the draw. Superquadrics keep only the drawn glyphs'
//! instance indices ([`glyph_list_layout`]): their quad is cheap to rebuild, and what they save
//! is the splats' ray casting per pixel centre rather than per 4x4 block of the rasteriser.
//! (The book's account, with the presets: docs/book/src/concepts/doing-less-work.md.)
//!
//! With `--splat N`, glyphs whose proxy spans at most N×N pixels are not drawn at all: the
//! compute pass ray casts their pixels itself (keeping each pixel's nearest depth with an atomic
//! max), a second pass (`cs_splat_ids`) records which splat won each pixel, and a quad per
//! 16×16 tile of pixels that some splat touches (listed by the compute pass) shades those
//! pixels, depth-tested against the drawn glyphs. Small glyphs then skip the rasteriser's
//! per-triangle setup, which on lavapipe is most of a frame. (One triangle over the splats'
//! bounding rectangle, as before the tiles, shaded every pixel between a few scattered splats:
//! on grid:6, 9 ms of an 18 ms frame.)
//!
//! Frames are 176 bytes, so large scenes go through in slices of at most [`SLICE_GLYPHS`]
//! glyphs sharing the frame buffers: each slice is its compute passes and a render pass.

use std::collections::HashMap;
use std::sync::Mutex;

use crate::camera::Camera;
use crate::render::bricks::BRICK;
use crate::render::context::GpuContext;
use crate::render::gumhold::occlusion::{self, SceneCulling, SliceDraw};
use crate::render::pipeline::{PipelineInput, Variant, buffer_entry, glyph_pipeline, glyphs_and};
use crate::render::scene_buffers::{BrickBuffers, Needs};
use crate::render::strip::StripRenderer;
use crate::request::{AuxTarget, Proxy};

pub use super::frames::{
    FRAME_ATTRIBUTES, FRAME_SIZE, GlyphFrame, frame_buffer_layout, glyph_list_layout,
};

/// Glyphs per slice: each frame buffer holds this many (46 MB).
pub const SLICE_GLYPHS: u32 = 1 << 18;
/// `@workgroup_size` of the compute entry points.
const WORKGROUP: u32 = 64;
/// Bytes of `SplatInfo` (shaders/prepass.wgsl).
pub const SPLAT_INFO_SIZE: u64 = 20;
/// `SPLAT_TILE` (shaders/prepass.wgsl): the splats are shaded by a quad per tile of this many
/// pixels square that one touches.
pub const SPLAT_TILE: u32 = 16;
/// Bytes of `Slice` (shaders/prepass.wgsl), a read-only storage buffer.
const SLICE_PARAMS_SIZE: u64 = 16;
/// `SLICE_BRICKS` (shaders/prepass.wgsl): the slice's glyphs are the bricks its culling listed.
const SLICE_BRICKS: u32 = 1;

/// Bind group 1 of the compute passes and of the splat tiles' draw, and their pipeline
/// layouts (group 0 is the glyph group every method uses).
#[derive(Clone)]
pub struct PrepassLayouts {
    compute_group: wgpu::BindGroupLayout,
    resolve_group: wgpu::BindGroupLayout,
    pub compute: wgpu::PipelineLayout,
    pub resolve: wgpu::PipelineLayout,
}

impl PrepassLayouts {
    pub fn new(ctx: &GpuContext, glyphs: &wgpu::BindGroupLayout) -> Self {
        let compute = wgpu::ShaderStages::COMPUTE;
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let device = &ctx.device;
        let compute_group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("prepass compute"),
            entries: &[
                // Storage, not uniform: see flag_index in shaders/common.wgsl.
                buffer_entry(0, compute, ro),
                buffer_entry(1, compute, rw),
                buffer_entry(2, compute, rw),
                buffer_entry(3, compute, rw),
                buffer_entry(4, compute, rw),
                buffer_entry(5, compute, rw),
                buffer_entry(6, compute, rw),
                buffer_entry(7, compute, rw),
                buffer_entry(10, compute, rw),
                // Occlusion culling (occlusion.rs): the bricks' glyphs and the bricks the
                // slice listed.
                buffer_entry(12, compute, ro),
                buffer_entry(13, compute, ro),
            ],
        });
        let resolve_group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat resolve"),
            entries: &[
                buffer_entry(8, wgpu::ShaderStages::FRAGMENT, ro),
                buffer_entry(9, wgpu::ShaderStages::VERTEX, ro),
                // The depth keys, for 32-bit atomics (64-bit ones read them at binding 8).
                buffer_entry(11, wgpu::ShaderStages::FRAGMENT, ro),
            ],
        });
        Self {
            compute: glyphs_and(device, "prepass compute", glyphs, &compute_group),
            resolve: glyphs_and(device, "splat resolve", glyphs, &resolve_group),
            compute_group,
            resolve_group,
        }
    }
}

/// Compute pipelines: the frames and, without 64-bit atomics, the splats' id pass.
type ComputePipelines = (wgpu::ComputePipeline, Option<wgpu::ComputePipeline>);

/// The prepass's compute pipelines (per proxy and `SQ_GENERAL`) and the splat tiles
/// draw (per variant and `SQ_GENERAL`), built on first use from the glyph's Gumhold shader.
pub struct PrepassCache {
    pub layouts: PrepassLayouts,
    compute: Mutex<HashMap<(Proxy, Needs), ComputePipelines>>,
    resolves: Mutex<HashMap<(Variant, Needs), wgpu::RenderPipeline>>,
    /// Splats with 64-bit atomics (splat64.wgsl).
    int64_atomics: bool,
}

impl PrepassCache {
    pub fn new(ctx: &GpuContext, glyphs: &wgpu::BindGroupLayout) -> Self {
        Self {
            layouts: PrepassLayouts::new(ctx, glyphs),
            compute: Mutex::new(HashMap::new()),
            resolves: Mutex::new(HashMap::new()),
            int64_atomics: ctx.int64_atomics,
        }
    }

    /// The pipelines of a frame with `variant` and `proxy`, from `strips`' shader, for a chunk
    /// of glyphs that need `needs`.
    pub fn pipelines(
        &self,
        strips: &StripRenderer,
        variant: Variant,
        proxy: Proxy,
        needs: Needs,
    ) -> PrepassPipelines {
        let layouts = &self.layouts;
        let needs = strips.needs_key(needs);
        // The frames do not depend on the fragment stage's early-depth declaration.
        let key = Proxy {
            early_depth: false,
            ..proxy
        };
        let mut compute = self.compute.lock().unwrap_or_else(|e| e.into_inner());
        let (frames, splat_ids) = compute
            .entry((key, needs))
            .or_insert_with(|| {
                let constants = strips.constants(key, needs);
                let make = |entry| {
                    let module = strips.module(false);
                    strips
                        .builder
                        .compute(&layouts.compute, module, entry, &constants)
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
            .get(&(variant, needs))
            .cloned();
        let resolve = resolve.unwrap_or_else(|| {
            let constants = strips.constants(key, needs);
            let p = glyph_pipeline(
                &strips.builder,
                &layouts.resolve,
                strips.module(false),
                "splat resolve",
                wgpu::PrimitiveTopology::TriangleStrip,
                variant,
                &PipelineInput {
                    vertex_entry: Some("vs_splat_tile"),
                    fragment_entry: Some(match (variant.shadow, variant.aux) {
                        (true, _) => "fs_splat_shadow",
                        (false, AuxTarget::Checked) => "fs_splat_aux",
                        (false, AuxTarget::Normal) => "fs_splat_normal",
                        (false, AuxTarget::None) => "fs_splat",
                    }),
                    constants: &constants,
                    ..Default::default()
                },
            );
            self.resolves
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert((variant, needs), p.clone());
            p
        });
        PrepassPipelines {
            frames,
            splat_ids,
            draw: strips.pipeline(variant, proxy, true, needs),
            resolve,
        }
    }
}

/// The prepass pipelines of one request.
pub struct PrepassPipelines {
    pub frames: wgpu::ComputePipeline,
    /// The second splat pass, without 64-bit atomics.
    pub splat_ids: Option<wgpu::ComputePipeline>,
    /// Draws the frames `cs_frames` kept.
    pub draw: wgpu::RenderPipeline,
    /// The splat tiles' draw.
    pub resolve: wgpu::RenderPipeline,
}

/// One slice: `count` glyphs from `first` of chunk `chunk` (with bricks, what a frame's
/// [`SliceDraw`] says).
pub struct Slice {
    pub chunk: usize,
    pub first: u32,
    pub count: u32,
    params: wgpu::Buffer,
}

/// Per-pixel splat buffers for one target size, and the bind groups that use them.
struct PixelBuffers {
    size: (u32, u32),
    depth_keys: wgpu::Buffer,
    splat_ids: wgpu::Buffer,
    /// Per tile: listed yet (the bind groups hold the list of tiles).
    tile_marks: wgpu::Buffer,
    /// Occlusion culling's depth tiles ([`occlusion::HIZ_TILE`] pixels square).
    hiz: wgpu::Buffer,
    /// One per slice.
    compute_groups: Vec<wgpu::BindGroup>,
    resolve_group: wgpu::BindGroup,
}

/// A scene's prepass buffers: the frame buffers, counters, slices and (per target size) the
/// per-pixel splat buffers.
pub struct PrepassBuffers {
    device: wgpu::Device,
    /// 64-bit splat keys holding the ids (splat64.wgsl), else 32-bit keys and an id buffer.
    int64_atomics: bool,
    layouts: PrepassLayouts,
    args: wgpu::Buffer,
    /// `SplatInfo`: the splat count and the splat tiles' draw arguments.
    splat_info: wgpu::Buffer,
    frames: wgpu::Buffer,
    splat_list: wgpu::Buffer,
    /// Bricks a slice holds at most, with occlusion culling.
    brick_capacity: u32,
    /// The slices of a frame in file order (the first of `slices`).
    plain: usize,
    pub slices: Vec<Slice>,
    /// With occlusion culling: the scene's bricks and the slices' lists of them.
    bricks: Option<SceneCulling>,
    pixels: Mutex<Option<PixelBuffers>>,
}

impl PrepassBuffers {
    /// Buffers for chunks of `chunk_counts` glyphs each; with `bricks` (one chunk's glyphs in
    /// bricks), slices of the bricks in each frame's order, culled against what the slices
    /// before drew.
    pub fn new(
        ctx: &GpuContext,
        layouts: &PrepassLayouts,
        chunk_counts: &[u32],
        bricks: Option<&BrickBuffers>,
    ) -> Self {
        let device = &ctx.device;
        let most = chunk_counts.iter().copied().max().unwrap_or(0);
        let capacity = most.clamp(1, SLICE_GLYPHS);
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let frames_size = u64::from(capacity) * FRAME_SIZE as u64;
        let storage = wgpu::BufferUsages::STORAGE;
        let frames = buffer(
            "glyph frames",
            frames_size,
            storage | wgpu::BufferUsages::VERTEX,
        );
        let splat_list = buffer("splat list", u64::from(capacity) * 4, storage);
        let counter = storage | wgpu::BufferUsages::COPY_DST;
        let args = buffer(
            "prepass draw args",
            16,
            counter | wgpu::BufferUsages::INDIRECT,
        );
        let splat_info = buffer(
            "splat info",
            SPLAT_INFO_SIZE,
            counter | wgpu::BufferUsages::INDIRECT,
        );
        let params = || {
            buffer(
                "prepass slice",
                SLICE_PARAMS_SIZE,
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            )
        };
        let mut slices = Vec::new();
        for (chunk, &count) in chunk_counts.iter().enumerate() {
            let mut first = 0;
            while first < count {
                let n = (count - first).min(capacity);
                slices.push(Slice {
                    chunk,
                    first,
                    count: n,
                    params: params(),
                });
                first += n;
            }
        }
        // In file order a frame draws `plain` slices; by bricks (one chunk) it may need more.
        let plain = slices.len();
        let brick_capacity = (capacity / BRICK).max(1);
        if let Some(b) = bricks {
            while slices.len() < occlusion::most_slices(b.bricks.count() as u32, brick_capacity) {
                slices.push(Slice {
                    chunk: 0,
                    first: 0,
                    count: 0,
                    params: params(),
                });
            }
        }
        let bricks = bricks
            .map(|b| SceneCulling::new(device, &b.bricks, &b.glyphs, slices.len(), brick_capacity));
        Self {
            device: device.clone(),
            int64_atomics: ctx.int64_atomics,
            layouts: layouts.clone(),
            args,
            splat_info,
            frames,
            splat_list,
            brick_capacity,
            plain,
            slices,
            bricks,
            pixels: Mutex::new(None),
        }
    }

    /// The slices of a frame of `camera` (scene origin `origin`): every slice as made, or, with
    /// bricks, the bricks `bricks` orders for the camera, the first slice those in front and
    /// each later one culled against the slices before. Writes the brick order for the next
    /// submission.
    pub fn frame_slices(
        &self,
        queue: &wgpu::Queue,
        bricks: Option<&BrickBuffers>,
        camera: &Camera,
        origin: glam::DVec3,
    ) -> Vec<SliceDraw> {
        let by_bricks = self.bricks.as_ref().zip(bricks).and_then(|(culling, b)| {
            let order = b.bricks.frame_order(camera, origin);
            b.bricks
                .pay_for(order.order.len())
                .then_some((culling, order))
        });
        let Some((culling, order)) = by_bricks else {
            return (0..self.plain)
                .map(|k| SliceDraw {
                    k,
                    first: self.slices[k].first,
                    count: self.slices[k].count,
                    bricks: false,
                    occluded: false,
                })
                .collect();
        };
        let draws = occlusion::plan(
            order.front as u32,
            order.order.len() as u32,
            self.brick_capacity,
        );
        culling.write(queue, &order.order, &draws);
        draws
    }

    /// Write the slices' parameters for the next submission: splats up to `splat_max` pixels
    /// across.
    pub fn write_params(&self, queue: &wgpu::Queue, splat_max: u32, draws: &[SliceDraw]) {
        for d in draws {
            // A slice of bricks reads its glyphs from the bricks it listed; its count bounds
            // the splats' second pass.
            let words = if d.bricks {
                [0, d.count * BRICK, splat_max, SLICE_BRICKS]
            } else {
                [d.first, d.count, splat_max, 0]
            };
            queue.write_buffer(&self.slices[d.k].params, 0, bytemuck::cast_slice(&words));
        }
    }

    /// The per-pixel buffers and bind groups for targets of `size`, made when the size changes.
    fn pixels_for(&self, size: (u32, u32)) -> std::sync::MutexGuard<'_, Option<PixelBuffers>> {
        let mut pixels = self.pixels.lock().unwrap_or_else(|e| e.into_inner());
        if pixels.as_ref().is_none_or(|p| p.size != size) {
            let count = u64::from(size.0) * u64::from(size.1);
            let buffer = |label, bytes: u64| {
                self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: (count * bytes).max(8),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let key_bytes = if self.int64_atomics { 8 } else { 4 };
            let depth_keys = buffer("splat depth keys", key_bytes);
            // Unused with 64-bit keys (binding 6 stays bound).
            let splat_ids = buffer("splat ids", if self.int64_atomics { 0 } else { 4 });
            let tiles =
                u64::from(size.0.div_ceil(SPLAT_TILE)) * u64::from(size.1.div_ceil(SPLAT_TILE));
            let tile_buffer = |label| {
                self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: tiles.max(1) * 4,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let tile_marks = tile_buffer("splat tile marks");
            let tile_list = tile_buffer("splat tile list");
            let hiz_tiles = occlusion::hiz_len(size);
            let hiz = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("occlusion depth tiles"),
                size: hiz_tiles.max(1) * 4,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            });

            fn bind(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
                wgpu::BindGroupEntry {
                    binding,
                    resource: buffer.as_entire_binding(),
                }
            }
            let compute_groups = self
                .slices
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    // Without bricks nothing reads them: the tiles stand in for both.
                    let (glyphs, visible) = match &self.bricks {
                        Some(c) => (&c.glyphs, c.slices[k].visible()),
                        None => (&hiz, &hiz),
                    };
                    self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("prepass compute"),
                        layout: &self.layouts.compute_group,
                        entries: &[
                            bind(0, &s.params),
                            bind(1, &self.frames),
                            bind(2, &self.args),
                            bind(3, &self.splat_list),
                            bind(4, &self.splat_info),
                            bind(5, &depth_keys),
                            bind(6, &splat_ids),
                            bind(7, &tile_marks),
                            bind(10, &tile_list),
                            bind(12, glyphs),
                            bind(13, visible),
                        ],
                    })
                })
                .collect();
            let resolve_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("splat resolve"),
                layout: &self.layouts.resolve_group,
                entries: &[
                    bind(
                        8,
                        if self.int64_atomics {
                            &depth_keys
                        } else {
                            &splat_ids
                        },
                    ),
                    bind(9, &tile_list),
                    bind(11, &depth_keys),
                ],
            });
            *pixels = Some(PixelBuffers {
                size,
                depth_keys,
                splat_ids,
                tile_marks,
                hiz,
                compute_groups,
                resolve_group,
            });
        }
        pixels
    }

    /// Record the compute passes of `slice` (bind group 0 is its chunk's), into targets of
    /// `size`.
    #[allow(clippy::too_many_arguments)]
    pub fn record_compute(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &PrepassPipelines,
        chunk_group: &wgpu::BindGroup,
        slice: &SliceDraw,
        size: (u32, u32),
        splats: bool,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        // Without splats no pixel is keyed: a one-pixel buffer keeps the bindings valid (an
        // image-sized one could exceed the binding limit for nothing).
        // Occlusion culling reads its depth tiles at the image's size.
        let keyed = splats || self.bricks.is_some();
        let pixels = self.pixels_for(if keyed { size } else { (1, 1) });
        let pixels = pixels.as_ref().expect("made above");
        encoder.clear_buffer(&self.args, 0, None);
        if splats {
            encoder.clear_buffer(&self.splat_info, 0, None);
            encoder.clear_buffer(&pixels.depth_keys, 0, None);
            encoder.clear_buffer(&pixels.tile_marks, 0, None);
            if !self.int64_atomics {
                encoder.clear_buffer(&pixels.splat_ids, 0, None);
            }
        }
        let k = slice.k;
        let invocations = if slice.bricks {
            slice.count * BRICK
        } else {
            slice.count
        };
        // A slice of bricks runs BRICK invocations for each brick its culling listed.
        let indirect = self
            .bricks
            .as_ref()
            .filter(|_| slice.bricks)
            .map(|c| c.slices[k].dispatch());
        let mut run = |label, pipeline, timestamp_writes, indirect: Option<&wgpu::Buffer>| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, chunk_group, &[]);
            pass.set_bind_group(1, &pixels.compute_groups[k], &[]);
            match indirect {
                Some(args) => pass.dispatch_workgroups_indirect(args, 0),
                None => pass.dispatch_workgroups(invocations.div_ceil(WORKGROUP), 1, 1),
            }
        };
        run(
            "glyph frames",
            &pipelines.frames,
            timestamp_writes,
            indirect,
        );
        // A pass of its own: every depth key is final before any is compared.
        if let (true, Some(ids)) = (splats, &pipelines.splat_ids) {
            run("splat ids", ids, None, None);
        }
    }

    /// Record the occlusion culling of `slice`, a slice of bricks, against what the slices
    /// before drew into `depth` (targets of `size`).
    pub fn record_culling(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: &occlusion::OcclusionPass,
        chunk_group: &wgpu::BindGroup,
        depth: &wgpu::TextureView,
        slice: &SliceDraw,
        size: (u32, u32),
    ) {
        let Some(culling) = &self.bricks else {
            return;
        };
        let pixels = self.pixels_for(size);
        let pixels = pixels.as_ref().expect("made above");
        pass.record(
            encoder,
            chunk_group,
            depth,
            &pixels.hiz,
            culling,
            slice,
            size,
        );
    }

    /// Draw what the last compute passes left (bind group 0 is already set): the frames, then
    /// the splats.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipelines: &PrepassPipelines,
        splats: bool,
    ) {
        pass.set_pipeline(&pipelines.draw);
        pass.set_vertex_buffer(0, self.frames.slice(..));
        pass.draw_indirect(&self.args, 0);
        if splats {
            let pixels = self.pixels.lock().unwrap_or_else(|e| e.into_inner());
            let pixels = pixels.as_ref().expect("record_compute made them");
            pass.set_pipeline(&pipelines.resolve);
            pass.set_bind_group(1, &pixels.resolve_group, &[]);
            pass.draw_indirect(&self.splat_info, 4);
        }
    }
}
