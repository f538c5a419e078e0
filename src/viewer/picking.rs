//! What is under the pointer: the id target's pixel (instance + 1, 0 for background), mapped
//! back through the selection to the glyph and its tensor.

use crate::error::RenderError;
use crate::render::GpuContext;
use crate::render::targets::Readback;
#[cfg(not(target_arch = "wasm32"))]
use crate::render::targets::Targets;
use crate::scene::Scene;
use crate::tensor::shape;
use crate::viewer::loader::Loaded;

/// A glyph's details, as the hover tooltip shows them.
#[derive(Debug, Clone, PartialEq)]
pub struct PickInfo {
    /// Index of the tensor in file order.
    pub index: usize,
    pub position: [f64; 3],
    /// World-space tensor as stored (before symmetrisation), row-major.
    pub tensor: [f64; 9],
    pub eigenvalues: [f64; 3],
    pub fa: f64,
    pub class: shape::ShapeClass,
}

impl PickInfo {
    /// The glyph behind id `id` (0 = background) when `scene` holds `selected` glyphs of
    /// `data.set` (an instance's `glyph` is its place in `selected`; a glyph may be several
    /// instances).
    pub fn of(
        id: u32,
        scene: &Scene,
        selected: &[usize],
        data: &Loaded,
        class_threshold: f64,
    ) -> Option<Self> {
        let instance = scene.instances.get((id as usize).checked_sub(1)?)?;
        let g = data
            .set
            .glyphs
            .get(*selected.get(instance.glyph as usize)?)?;
        let ev = g.eigenvalues.map(f64::from);
        let index = g.index as usize;
        Some(Self {
            index,
            position: g.centre,
            tensor: data.field.world_tensor(index),
            eigenvalues: ev,
            fa: shape::fa(ev),
            class: shape::classify(ev, class_threshold),
        })
    }

    /// Multi-line text for the tooltip.
    pub fn text(&self) -> String {
        let [x, y, z] = self.position;
        let t = &self.tensor;
        let [l1, l2, l3] = self.eigenvalues;
        format!(
            "glyph #{}\nposition ({x:.4}, {y:.4}, {z:.4})\ntensor\n  {:>11.4e} {:>11.4e} {:>11.4e}\n  {:>11.4e} {:>11.4e} {:>11.4e}\n  {:>11.4e} {:>11.4e} {:>11.4e}\nλ = {l1:.4e}, {l2:.4e}, {l3:.4e}\nFA {:.4}   class {}",
            self.index,
            t[0],
            t[1],
            t[2],
            t[3],
            t[4],
            t[5],
            t[6],
            t[7],
            t[8],
            self.fa,
            self.class.glyph_name()
        )
    }
}

/// Read the id target at pixel (x, y): one pixel copied and mapped, nothing else.
#[cfg(not(target_arch = "wasm32"))]
pub fn read_id(ctx: &GpuContext, targets: &Targets, x: u32, y: u32) -> Result<u32, RenderError> {
    pollster::block_on(read_id_async(ctx, &targets.id, x, y))
}

/// [`read_id`] of the id texture `id`, without blocking (the browser's way).
pub async fn read_id_async(
    ctx: &GpuContext,
    id: &wgpu::Texture,
    x: u32,
    y: u32,
) -> Result<u32, RenderError> {
    if x >= id.width() || y >= id.height() {
        return Ok(0);
    }
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let rb = Readback::record_region(ctx, &mut encoder, id, 4, [x, y], [1, 1]);
    ctx.queue.submit([encoder.finish()]);
    let bytes = rb.read_async(ctx).await?;
    Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::ReadOptions;
    use crate::staging::{Demo, Source};
    use crate::viewer::loader::load_now;

    #[test]
    fn ids_map_through_the_selection() {
        let data = load_now(
            &Source::Demo(Demo { n: 3 }),
            &ReadOptions::default(),
            &None,
            &crate::progress::Silent,
        )
        .unwrap();
        let selected = vec![4, 7];
        // Two instances of glyph 0 of the selection, one of glyph 1.
        let instance = |glyph| crate::scene::GlyphInstance {
            centre: [0.0; 3],
            color: 0,
            rotation: [0.0, 0.0, 0.0, 1.0],
            radii: [1.0; 3],
            glyph,
            shape: [0; 2],
        };
        let scene = Scene::from_instances(
            glam::DVec3::ZERO,
            vec![instance(0), instance(0), instance(1)],
        );
        assert_eq!(
            PickInfo::of(0, &scene, &selected, &data, 0.5),
            None,
            "background"
        );
        assert_eq!(
            PickInfo::of(4, &scene, &selected, &data, 0.5),
            None,
            "no such instance"
        );
        assert_eq!(
            PickInfo::of(2, &scene, &selected, &data, 0.5)
                .unwrap()
                .index,
            data.set.glyphs[4].index as usize
        );
        let p = PickInfo::of(3, &scene, &selected, &data, 0.5).unwrap();
        let g = data.set.glyphs[7];
        assert_eq!(p.index, g.index as usize);
        assert_eq!(p.position, g.centre);
        assert!((0.0..=1.0).contains(&p.fa));
        let text = p.text();
        assert!(text.contains(&format!("glyph #{}", g.index)) && text.contains("FA"));
    }
}
