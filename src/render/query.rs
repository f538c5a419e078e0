//! A GPU query set of u64 results (timestamps, or pipeline statistics with any counters),
//! resolved into a buffer and read after submission.

use crate::error::RenderError;
use crate::render::context::GpuContext;

pub struct Queries {
    pub set: wgpu::QuerySet,
    count: u32,
    bytes: u64,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl Queries {
    /// `count` queries of type `ty`.
    pub fn new(device: &wgpu::Device, label: &str, ty: wgpu::QueryType, count: u32) -> Self {
        let values = match ty {
            wgpu::QueryType::PipelineStatistics(t) => u64::from(t.bits().count_ones()),
            _ => 1,
        };
        let bytes = 8 * values * u64::from(count);
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some(label),
            ty,
            count,
        });
        let buf = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            set,
            count,
            bytes,
            resolve: buf(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buf(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ),
        }
    }

    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..self.count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, self.bytes);
    }

    /// Every value (query by query, counter by counter), after the submission that resolved
    /// them.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read(&self, ctx: &GpuContext) -> Result<Vec<u64>, RenderError> {
        pollster::block_on(self.read_async(ctx))
    }

    /// [`Self::read`] without blocking.
    pub async fn read_async(&self, ctx: &GpuContext) -> Result<Vec<u64>, RenderError> {
        crate::render::targets::map_read(&self.readback, ctx, "query readback").await?;
        let out = {
            let data = self
                .readback
                .get_mapped_range(..)
                .map_err(|e| RenderError::Gpu(format!("query readback: {e}")))?;
            bytemuck::pod_collect_to_vec::<u8, u64>(&data)
        };
        self.readback.unmap();
        Ok(out)
    }
}
