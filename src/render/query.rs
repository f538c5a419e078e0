//! A GPU query set whose results are two u64 values (16 bytes): pipeline statistics with two
//! counters, or a begin/end timestamp pair. Resolved into a buffer and read after submission.

use crate::error::RenderError;
use crate::render::context::GpuContext;

pub struct QueryPair {
    pub set: wgpu::QuerySet,
    count: u32,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl QueryPair {
    /// `count` queries of type `ty` whose resolved results fill exactly 16 bytes.
    pub fn new(device: &wgpu::Device, label: &str, ty: wgpu::QueryType, count: u32) -> Self {
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some(label),
            ty,
            count,
        });
        let buf = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            set,
            count,
            resolve: buf(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buf(wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ),
        }
    }

    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..self.count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, 16);
    }

    /// The two values, after the submission that resolved them.
    pub fn read(&self, ctx: &GpuContext) -> Result<[u64; 2], RenderError> {
        let (tx, rx) = std::sync::mpsc::channel();
        self.readback.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        ctx.wait()?;
        rx.recv()
            .map_err(|_| RenderError::Gpu("query readback dropped".into()))?
            .map_err(|e| RenderError::Gpu(format!("query readback: {e}")))?;
        let out = {
            let data = self
                .readback
                .get_mapped_range(..)
                .map_err(|e| RenderError::Gpu(format!("query readback: {e}")))?;
            bytemuck::pod_read_unaligned::<[u64; 2]>(&data[..16])
        };
        self.readback.unmap();
        Ok(out)
    }
}
