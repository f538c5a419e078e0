//! Offscreen render targets and their readback (rows padded to 256 bytes for copies).

use crate::error::RenderError;
use crate::render::context::GpuContext;
use crate::request::AuxTarget;

pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The aux target read back for the accuracy check: view normal, view z.
pub const AUX_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The aux target of deferred shading alone: the octahedral view normal.
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The texture format of an aux target, if there is one.
pub fn aux_format(aux: AuxTarget) -> Option<wgpu::TextureFormat> {
    match aux {
        AuxTarget::None => None,
        AuxTarget::Checked => Some(AUX_FORMAT),
        AuxTarget::Normal => Some(NORMAL_FORMAT),
    }
}
/// The colour target seen as sRGB, for sampling it in the viewer.
pub const COLOR_VIEW_SRGB: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Colour, glyph id (0 = background, else instance + 1), optional aux ([`AuxTarget`]) and
/// depth, all the same size.
pub struct Targets {
    pub width: u32,
    pub height: u32,
    pub color: wgpu::Texture,
    pub id: wgpu::Texture,
    pub aux: Option<wgpu::Texture>,
    pub depth: wgpu::Texture,
}

impl Targets {
    pub fn new(
        ctx: &GpuContext,
        width: u32,
        height: u32,
        aux: AuxTarget,
    ) -> Result<Self, RenderError> {
        let max = ctx.limits.max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::BadSize {
                width,
                height,
                reason: format!("each side must be between 1 and {max} (this adapter's limit)"),
            });
        }
        let make =
            |label: &str, format: wgpu::TextureFormat, view_formats: &[wgpu::TextureFormat]| {
                ctx.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    // TEXTURE_BINDING: the viewer shows the colour target in its window.
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::COPY_SRC
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats,
                })
            };
        Ok(Self {
            width,
            height,
            // The sRGB view lets the viewer show the sRGB-encoded colours as they are.
            color: make("color", COLOR_FORMAT, &[COLOR_VIEW_SRGB]),
            id: make("id", ID_FORMAT, &[]),
            aux: aux_format(aux).map(|format| make("aux", format, &[])),
            depth: make("depth", DEPTH_FORMAT, &[]),
        })
    }

    pub fn has_aux(&self) -> bool {
        self.aux.is_some()
    }
}

/// A texture copied into a mappable buffer, to be read after the submission completes.
pub struct Readback {
    buffer: wgpu::Buffer,
    padded_row: u32,
    row: u32,
    height: u32,
}

impl Readback {
    /// Record the copy of a whole single-aspect texture.
    pub fn record(
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        bytes_per_pixel: u32,
    ) -> Self {
        let (width, height) = (texture.width(), texture.height());
        Self::record_region(
            ctx,
            encoder,
            texture,
            bytes_per_pixel,
            [0, 0],
            [width, height],
        )
    }

    /// Record the copy of a `size` region at `origin` (x, y) of a single-aspect texture (the
    /// viewer reads one pixel of the id target under the pointer).
    pub fn record_region(
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        bytes_per_pixel: u32,
        origin: [u32; 2],
        size: [u32; 2],
    ) -> Self {
        let [width, height] = size;
        let row = width * bytes_per_pixel;
        let padded_row =
            row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: origin[0],
                    y: origin[1],
                    z: 0,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        Self {
            buffer,
            padded_row,
            row,
            height,
        }
    }

    /// Map and unpad. Call after the copy was submitted.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read(self, ctx: &GpuContext) -> Result<Vec<u8>, RenderError> {
        pollster::block_on(self.read_async(ctx))
    }

    /// [`Self::read`] without blocking (the browser's way; the desktop's runs at once).
    pub async fn read_async(self, ctx: &GpuContext) -> Result<Vec<u8>, RenderError> {
        map_read(&self.buffer, ctx, "readback").await?;
        let data = self
            .buffer
            .get_mapped_range(..)
            .map_err(|e| RenderError::Gpu(format!("readback failed: {e}")))?;
        let mut out = Vec::with_capacity((self.row * self.height) as usize);
        for r in 0..self.height as usize {
            let start = r * self.padded_row as usize;
            out.extend_from_slice(&data[start..start + self.row as usize]);
        }
        drop(data);
        self.buffer.unmap();
        Ok(out)
    }
}

/// Map `buffer` for reading once the submitted work is done; `what` names it in errors.
pub(crate) async fn map_read(
    buffer: &wgpu::Buffer,
    ctx: &GpuContext,
    what: &str,
) -> Result<(), RenderError> {
    let (tx, rx) = futures_channel::oneshot::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    // The desktop polls the device here, which runs the callback; in the browser the mapping
    // itself waits for the work that writes the buffer.
    #[cfg(not(target_arch = "wasm32"))]
    ctx.wait()?;
    #[cfg(target_arch = "wasm32")]
    let _ = ctx;
    rx.await
        .map_err(|_| RenderError::Gpu(format!("{what} was dropped")))?
        .map_err(|e| RenderError::Gpu(format!("{what} failed: {e}")))
}

/// Views of a [`Targets`]' textures, as a render pass attaches them.
pub struct TargetViews {
    /// Width and height in pixels.
    pub(crate) size: (u32, u32),
    /// The colour texture itself: deferred shading copies the unlit colours out of it.
    pub(crate) color_texture: wgpu::Texture,
    color: wgpu::TextureView,
    pub(crate) id: wgpu::TextureView,
    pub(crate) aux: Option<wgpu::TextureView>,
    pub(crate) depth: wgpu::TextureView,
}

impl TargetViews {
    pub fn new(t: &Targets) -> Self {
        let v = |t: &wgpu::Texture| t.create_view(&Default::default());
        Self {
            size: (t.width, t.height),
            color_texture: t.color.clone(),
            color: v(&t.color),
            id: v(&t.id),
            aux: t.aux.as_ref().map(v),
            depth: v(&t.depth),
        }
    }

    /// A pass over the targets, cleared first when `clear` (else drawing over what is there).
    pub(crate) fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        background: [f64; 4],
        clear: bool,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        let load = |c| {
            if clear {
                wgpu::LoadOp::Clear(c)
            } else {
                wgpu::LoadOp::Load
            }
        };
        let attach = |c: wgpu::Color, view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: load(c),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let [r, g, b, a] = background;
        let mut attachments = vec![
            attach(wgpu::Color { r, g, b, a }, &self.color),
            attach(wgpu::Color::TRANSPARENT, &self.id),
        ];
        if let Some(aux) = &self.aux {
            attachments.push(attach(wgpu::Color::TRANSPARENT, aux));
        }
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("glyphs"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: if clear {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// The colour target, kept as it is (the full-screen pass of deferred shading).
    pub(crate) fn color_view(&self) -> &wgpu::TextureView {
        &self.color
    }

    /// A pass drawing over the colour, id and depth targets as they are (the underlay, after
    /// the method's passes; the aux target keeps the glyphs' values).
    pub(crate) fn begin_overlay_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
    ) -> wgpu::RenderPass<'e> {
        let load = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("underlay"),
            color_attachments: &[load(&self.color), load(&self.id)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}
