//! A scene on the GPU: its packed instances in chunks that each fit one storage binding, the
//! camera and each chunk's parameters, and the per-scene state a method keeps (Gumhold's prepass
//! buffers). Built by upload, drawn by [`crate::render::GpuRenderer`] as often as the camera or
//! the request change.

use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::camera::Camera;
use crate::error::RenderError;
use wgpu::util::DeviceExt;

use crate::render::ao_volume::AoVolume;
use crate::render::bricks::Bricks;
use crate::render::context::GpuContext;
use crate::render::gpu_data::{CameraUniform, ChunkParams, GPU_GLYPH_SIZE, GpuGlyph};
use crate::render::underlay::{UnderlayBuffers, UnderlayPipeline};
use crate::request::{FrameRequest, Method};
use crate::scene::{GlyphInstance, GlyphKind, Scene};
use crate::shape::Payload;

/// A scene's instances and camera uniform on the GPU, bound for drawing.
pub struct SceneBuffers {
    /// The scene's kind: what the drawers draw the instances as.
    pub kind: GlyphKind,
    /// The kinds its chunks hold, in their order: the scene's own, then an overlay's
    /// ([`crate::scene::Overlay`]).
    pub kinds: Vec<GlyphKind>,
    origin: glam::DVec3,
    /// The scene's box (centre, half extents): the key light's shadow map covers it.
    bounds: (glam::DVec3, glam::DVec3),
    /// How far the `box` baseline's boxes may reach past the scene's bounding sphere, which
    /// cameras fit their depth planes to: a box's corners lie up to √3 times its largest half
    /// extent from its centre, the glyph only that extent.
    box_reach: f64,
    count: u32,
    camera_buffer: wgpu::Buffer,
    /// The key light's camera, for drawing the shadow map (bound in each chunk's light group).
    light_buffer: wgpu::Buffer,
    pub(crate) chunks: Vec<ChunkBuffers>,
    /// The scene's underlay images, if it has any.
    pub(crate) underlay: Option<UnderlayBuffers>,
    /// What ambient occlusion marches (the composite pass binds it).
    pub(crate) ao_volume: AoVolume,
    /// A large single-chunk scene's bricks, for the prepass's occlusion culling.
    pub(crate) bricks: Option<BrickBuffers>,
    /// What methods keep per scene, made on the first frame that needs it.
    method_state: Mutex<HashMap<TypeId, Arc<dyn Any + Send + Sync>>>,
}

/// What the glyphs of a chunk need beyond the default pipelines: each is an `override` of the
/// shaders that have it, set per pipeline, so that chunks without such glyphs run none of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Needs {
    /// The kind's general search ([`crate::shape::Shape::is_general`]: a superquadric the
    /// convex finder cannot draw).
    pub general: bool,
    /// The double-f32 rays of thin glyphs (`THIN_EXACT`, [`GlyphInstance::is_thin`]).
    pub thin: bool,
}

/// A scene's [`Bricks`] and their glyphs on the GPU (`brick_glyphs` in shaders/method/prepass.wgsl).
pub struct BrickBuffers {
    pub(crate) bricks: Bricks,
    pub(crate) glyphs: wgpu::Buffer,
}

/// One storage buffer of packed instances and its parameters, bound as group 0.
pub struct ChunkBuffers {
    /// The kind its glyphs are drawn as.
    pub(crate) kind: GlyphKind,
    pub(crate) base: u32,
    pub(crate) count: u32,
    /// What its glyphs need of the shaders; the pipelines leave the rest out.
    pub(crate) needs: Needs,
    _glyphs: wgpu::Buffer,
    _shapes: wgpu::Buffer,
    params: wgpu::Buffer,
    pub(crate) bind_group: wgpu::BindGroup,
    /// The same chunk seen by the key light's camera (the shadow map's pass).
    pub(crate) light_bind_group: wgpu::BindGroup,
}

impl SceneBuffers {
    /// Upload `scene` in buffers of at most `chunk` glyphs each, bound with `layout` (the glyph
    /// group every method shares). The instances are packed straight into each buffer's
    /// mapping (no second copy of the scene on the CPU).
    pub(crate) fn upload(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        underlay: &UnderlayPipeline,
        scene: &Scene,
        chunk: usize,
    ) -> Result<Self, RenderError> {
        let device = &ctx.device;
        // Per-glyph values travel in the chunk's shape buffer after its words, indexed in f32
        // by the shaders: at most 2²⁴ pairs of words (128 MiB) a chunk keeps the index exact.
        let chunk = match &scene.payload {
            Some(p) => {
                let limits = &ctx.limits;
                let bytes = limits
                    .max_storage_buffer_binding_size
                    .min(limits.max_buffer_size)
                    .min(1 << 27);
                let per = 8 + 4 * p.stride() as u64;
                chunk.min((bytes / per).max(1) as usize)
            }
            None => chunk,
        };
        let chunk = chunk.max(1);
        if scene.instances.len() > u32::MAX as usize - 1 {
            return Err(RenderError::Unsupported(format!(
                "{} glyphs: at most {} can be drawn",
                scene.instances.len(),
                u32::MAX - 1
            )));
        }
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let camera_uniform = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<CameraUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let camera_buffer = camera_uniform("camera");
        let light_buffer = camera_uniform("light camera");
        // A binding may not be empty: an empty scene gets one chunk with an unused instance.
        // A chunk holds glyphs of one kind (an overlay's start a chunk of their own).
        let pieces: Vec<(GlyphKind, &[GlyphInstance])> = if scene.instances.is_empty() {
            vec![(scene.kind, &[])]
        } else {
            scene
                .parts()
                .into_iter()
                .flat_map(|(kind, run)| {
                    scene.instances[run]
                        .chunks(chunk)
                        .map(move |piece| (kind, piece))
                })
                .collect()
        };
        let mut chunks = Vec::with_capacity(pieces.len());
        let mut base = 0u32;
        for (kind, piece) in pieces {
            // Only the scene's own kind reads the payload.
            let payload = scene.payload.as_deref().filter(|_| kind == scene.kind);
            chunks.push(ChunkBuffers::upload(
                ctx,
                layout,
                kind,
                piece,
                payload,
                base,
                [&camera_buffer, &light_buffer],
            )?);
            base += piece.len() as u32;
        }
        let mut kinds: Vec<GlyphKind> = chunks.iter().map(|c| c.kind).collect();
        kinds.dedup();
        let underlay = match &scene.underlay {
            Some(u) => Some(UnderlayBuffers::upload(ctx, underlay, u)?),
            None => None,
        };
        let ao_volume = AoVolume::upload(ctx, scene);
        // Occlusion culling works within one chunk and only where the prepass draws.
        let bricks = (chunks.len() == 1
            && chunks[0].kind.caps().prepass
            && Bricks::pays(scene.instances.len()))
        .then(|| {
            let bricks = Bricks::new(&scene.instances);
            let glyphs = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("brick glyphs"),
                contents: bytemuck::cast_slice(&bricks.glyphs),
                usage: wgpu::BufferUsages::STORAGE,
            });
            BrickBuffers { bricks, glyphs }
        });
        let what = format!("uploading {} glyph instances", scene.instances.len());
        let oom = ctx.scope_error(oom, &what);
        if let Some(e) = oom.or(ctx.scope_error(scope, &what)) {
            return Err(RenderError::Gpu(e));
        }
        Ok(Self {
            kind: scene.kind,
            kinds,
            origin: scene.origin,
            bounds: (scene.centre, scene.half),
            box_reach: (3f64.sqrt() - 1.0)
                * scene
                    .instances
                    .iter()
                    .map(|g| f64::from(g.radii[0].max(g.radii[1]).max(g.radii[2])))
                    .filter(|r| r.is_finite())
                    .fold(0.0, f64::max),
            count: base,
            camera_buffer,
            light_buffer,
            chunks,
            underlay,
            ao_volume,
            bricks,
            method_state: Mutex::new(HashMap::new()),
        })
    }

    /// Number of glyph instances drawn.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Number of storage buffers the instances were split into.
    pub fn chunks(&self) -> usize {
        self.chunks.len()
    }

    /// Write the camera uniform and the chunks' parameters of a frame (through the queue: they
    /// take effect at the next submit).
    pub(crate) fn write_uniforms(&self, queue: &wgpu::Queue, camera: &Camera, req: &FrameRequest) {
        let camera = &self.depth_camera(camera, req);
        let mut uniform = CameraUniform::new(camera, self.origin, &req.lighting);
        uniform.pixels[3] = if req.effects.deferred() { 1.0 } else { 0.0 };
        queue.write_buffer(&self.camera_buffer, 0, bytemuck::bytes_of(&uniform));
        for c in &self.chunks {
            let u = ChunkParams {
                base: c.base,
                min_pixel_radius: req.min_pixel_radius,
                cull: u32::from(req.cull),
                _pad: 0,
            };
            queue.write_buffer(&c.params, 0, bytemuck::bytes_of(&u));
        }
        if let Some(u) = &self.underlay {
            u.write_uniforms(queue, camera, self.origin, &req.underlay);
        }
    }

    /// Write the key light's camera, which the chunks' light groups bind.
    pub(crate) fn write_light_uniform(
        &self,
        queue: &wgpu::Queue,
        light: &Camera,
        req: &FrameRequest,
    ) {
        let light = &self.depth_camera(light, req);
        let uniform = CameraUniform::new(light, self.origin, &req.lighting);
        queue.write_buffer(&self.light_buffer, 0, bytemuck::bytes_of(&uniform));
    }

    /// The camera a frame's depth planes come from: `camera`'s own, except for the `box`
    /// baseline, whose boxes reach past the glyphs the planes were fitted to: there the planes
    /// move apart by the boxes' reach, so that no box is clipped (a clipped box loses the far
    /// corner and, where rasterisers clip triangles one by one, pixels inside it).
    fn depth_camera(&self, camera: &Camera, req: &FrameRequest) -> Camera {
        let mut camera = *camera;
        if req.method.method() == Method::Box {
            camera.widen_depth_range(self.box_reach);
        }
        camera
    }

    /// The scene's box: centre and half extents (world).
    pub(crate) fn bounds(&self) -> (glam::DVec3, glam::DVec3) {
        self.bounds
    }

    /// Whether Gumhold's prepass draws frames from `camera` by bricks, culled
    /// ([`crate::render::gumhold::occlusion`]): a single-chunk scene of at least
    /// [`crate::render::bricks::MIN_GLYPHS`] glyphs whose frustum leaves out enough of them.
    pub fn culls_bricks(&self, camera: &Camera) -> bool {
        self.bricks.as_ref().is_some_and(|b| {
            b.bricks
                .pay_for(b.bricks.frame_order(camera, self.origin).order.len())
        })
    }

    /// The scene origin every uniform is relative to.
    pub(crate) fn origin(&self) -> glam::DVec3 {
        self.origin
    }

    /// The state of type `T` a method keeps for this scene, made by `make` on first use.
    pub(crate) fn method_state<T: Any + Send + Sync>(&self, make: impl FnOnce() -> T) -> Arc<T> {
        let mut map = self.method_state.lock().unwrap_or_else(|e| e.into_inner());
        let entry = map
            .entry(TypeId::of::<T>())
            .or_insert_with(|| Arc::new(make()));
        Arc::clone(entry)
            .downcast::<T>()
            .unwrap_or_else(|_| unreachable!("keyed by its own type"))
    }
}

impl ChunkBuffers {
    /// The instance_index values of this chunk's glyphs.
    pub(crate) fn instances(&self) -> std::ops::Range<u32> {
        self.base..self.base + self.count
    }

    /// A storage buffer of `piece` packed straight into its mapping, its uniform and its bind
    /// group.
    fn upload(
        ctx: &GpuContext,
        layout: &wgpu::BindGroupLayout,
        kind: GlyphKind,
        piece: &[GlyphInstance],
        payload: Option<&Payload>,
        base: u32,
        [camera_buffer, light_buffer]: [&wgpu::Buffer; 2],
    ) -> Result<Self, RenderError> {
        use rayon::prelude::*;
        let device = &ctx.device;
        let glyphs = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("glyph instances"),
            size: (piece.len().max(1) * GPU_GLYPH_SIZE) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: true,
        });
        {
            let mut view = glyphs
                .slice(..)
                .get_mapped_range_mut()
                .map_err(|e| RenderError::Gpu(format!("mapping a glyph buffer for upload: {e}")))?;
            // The mapping is write-only: pack in blocks (in parallel) and copy each in.
            const BLOCK: usize = 1 << 16;
            let mut packed: Vec<GpuGlyph> = Vec::with_capacity(BLOCK.min(piece.len()));
            for (k, block) in piece.chunks(BLOCK).enumerate() {
                block
                    .par_iter()
                    .map(GpuGlyph::pack)
                    .collect_into_vec(&mut packed);
                let at = k * BLOCK * GPU_GLYPH_SIZE;
                view.slice(at..at + block.len() * GPU_GLYPH_SIZE)
                    .copy_from_slice(bytemuck::cast_slice(&packed));
            }
        }
        glyphs.unmap();
        // The kind's parameter words, where the chunk has any (a binding may not be empty);
        // with a payload, each glyph's series follows the words, and word 0 is where.
        let words: Vec<[u32; 2]> = match payload {
            Some(p) if piece.iter().any(|g| g.shape[0] != 0) => payload_words(piece, p),
            _ if piece.iter().any(|g| g.shape != [0; 2]) => piece.iter().map(|g| g.shape).collect(),
            _ => vec![[0; 2]],
        };
        let shapes = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("shape words"),
                contents: bytemuck::cast_slice(&words),
                usage: wgpu::BufferUsages::STORAGE,
            },
        );
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("chunk"),
            size: std::mem::size_of::<ChunkParams>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = |camera: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("glyphs"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: camera.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: glyphs.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: shapes.as_entire_binding(),
                    },
                ],
            })
        };
        Ok(Self {
            kind,
            base,
            count: piece.len() as u32,
            bind_group: group(camera_buffer),
            light_bind_group: group(light_buffer),
            needs: Needs {
                // A series index past the payload is drawn as a profile (payload_words).
                general: piece.iter().any(|g| {
                    kind.shape().is_general(g)
                        || payload.is_some_and(|p| g.shape[0] as usize > p.len())
                }),
                thin: piece.iter().any(GlyphInstance::is_thin),
            },
            _glyphs: glyphs,
            _shapes: shapes,
            params,
        })
    }
}

/// A chunk's shape buffer with per-glyph series: one pair of words per glyph (word 0: where its
/// series starts, in pairs from the buffer's start, 0 for none; word 1 as the instance has it),
/// then the series of the chunk's glyphs in their order, each `stride` floats (odf.wgsl reads
/// them).
fn payload_words(piece: &[GlyphInstance], p: &Payload) -> Vec<[u32; 2]> {
    let stride = p.stride();
    let mut words = Vec::with_capacity(piece.len());
    let mut tail: Vec<u32> = Vec::new();
    let mut next = piece.len() as u32;
    for g in piece {
        let k = g.shape[0] as usize;
        if k == 0 || k > p.len() {
            words.push([0, g.shape[1]]);
            continue;
        }
        words.push([next, g.shape[1]]);
        tail.extend(
            p.values[(k - 1) * stride..k * stride]
                .iter()
                .map(|v| v.to_bits()),
        );
        next += (stride / 2) as u32;
    }
    words.extend(tail.chunks_exact(2).map(|c| [c[0], c[1]]));
    words
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each glyph's first word points at its own series after the words, whatever the order.
    #[test]
    fn payload_words_point_at_each_series() {
        let mut p = Payload::new(2).unwrap();
        let q = glam::DQuat::from_rotation_y(0.5);
        let bound = glam::DVec3::new(1.0, 0.5, 0.25);
        p.push(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 0.5, 1.0, q, bound);
        p.push(&[7.0, 8.0, 9.0, 10.0, 11.0, 12.0], 0.25, 1.5, q, bound);
        let inst = |k: u32| GlyphInstance {
            centre: [0.0; 3],
            color: 0,
            rotation: [0.0, 0.0, 0.0, 1.0],
            radii: [1.0; 3],
            glyph: 0,
            shape: [k, 1],
        };
        let words = payload_words(&[inst(2), inst(0), inst(1)], &p);
        assert_eq!(words[1], [0, 1]);
        for (w, k) in [(words[0], 2usize), (words[2], 1)] {
            let start = w[0] as usize;
            let float = |i: usize| f32::from_bits(words[start + i / 2][i % 2]);
            let want = p.series(k - 1);
            for (i, &v) in want.iter().enumerate() {
                assert_eq!(float(i), v);
            }
            assert_eq!(float(1 + p.count), p.amplitude_scale(k - 1));
            assert_eq!(float(2 + p.count + 5) as f64, p.bound(k - 1).y);
        }
    }
}
