//! Picking: the id under the pointer, read from the id target and mapped to its glyph.

use glam::DVec3;

use super::ViewerApp;
use crate::error::RenderError;
use crate::viewer::pending::Pending;
use crate::viewer::picking::{PickInfo, read_id_async};

/// What an id read under the pointer is for.
#[derive(Clone, Copy)]
pub(super) enum PickFor {
    Hover,
    /// A double click: centre the view on the glyph.
    Centre,
}

/// An id being read: the scene it was read from, and what for.
pub(super) struct PickJob {
    generation: u64,
    purpose: PickFor,
    id: Pending<Result<u32, RenderError>>,
}

impl ViewerApp {
    /// Read the id under the pointer (at once on the desktop, a frame or so later in the
    /// browser); [`Self::poll_pick`] takes it.
    pub(super) fn start_pick(&mut self, ctx: &egui::Context, purpose: PickFor) {
        let Some((x, y)) = self.hover else { return };
        let (Some(targets), Some(built)) = (self.view.targets.as_ref(), self.built.as_ref()) else {
            return;
        };
        // The targets hold n×n samples per window pixel (n×n, or 1/d across for a draft):
        // read the sample at the pixel's centre.
        let (pw, ph) = self.pixels;
        let at = |x: u32, pw: u32, tw: u32| {
            ((u64::from(2 * x + 1) * u64::from(tw)) / (2 * u64::from(pw.max(1)))) as u32
        };
        let (x, y) = (
            at(x, pw, targets.width).min(targets.width.saturating_sub(1)),
            at(y, ph, targets.height).min(targets.height.saturating_sub(1)),
        );
        let (gpu, id) = (self.gpu.clone(), targets.id.clone());
        let read = async move { read_id_async(&gpu.ctx, &id, x, y).await };
        self.pick_job = Some(PickJob {
            generation: built.generation,
            purpose,
            id: Pending::spawn(read, ctx),
        });
        self.poll_pick();
    }

    pub(super) fn poll_pick(&mut self) {
        let Some(job) = &self.pick_job else { return };
        let Some(id) = job.id.take() else { return };
        let job = self.pick_job.take().expect("checked above");
        let info = match (&self.built, &self.data, id) {
            (Some(built), Some(data), Ok(id)) if built.generation == job.generation => {
                PickInfo::of(
                    id,
                    &built.scene,
                    &built.selected,
                    data,
                    self.settings.style.class_threshold,
                )
            }
            _ => None,
        };
        match job.purpose {
            PickFor::Hover => self.picked = info.filter(|_| self.hover.is_some()),
            PickFor::Centre => {
                if let (Some(p), Some(nav)) = (info, &mut self.nav) {
                    nav.centre_on(DVec3::from(p.position));
                }
            }
        }
    }
}
