//! Coarser frames while the camera moves, as ParaView's interactive render resolution and VTK's
//! desired update rate: a scene whose whole frame takes longer than [`BUDGET_MS`] is drawn at
//! 1/d of the resolution across (d² fewer pixels) while the camera changes, shown stretched
//! over the view, and whole again once the camera has been still for [`SETTLE`]. Ray-cast
//! frames cost per pixel, so d follows from the last whole frame's time. Nothing else of the
//! frame changes: the same scene, request and glyphs (the pixel-size cull scaled with d).

use web_time::{Duration, Instant};

use crate::viewer::state::RenderKey;

/// The frame time a moving view aims at (15 frames a second).
pub const BUDGET_MS: f64 = 66.0;

/// How long the camera stays still before the whole frame is drawn.
pub const SETTLE: Duration = Duration::from_millis(250);

/// The coarsest draft: 1/8 of the resolution across.
pub const MAX_DIVISOR: u32 = 8;

/// The divisor d for a scene whose whole frame took `full_ms`: the smallest whose d² fewer
/// pixels bring it within [`BUDGET_MS`], 1 (no draft) when it already is.
pub fn divisor(full_ms: f64) -> u32 {
    if full_ms.is_nan() || full_ms <= BUDGET_MS {
        return 1;
    }
    ((full_ms / BUDGET_MS).sqrt().ceil() as u32).clamp(1, MAX_DIVISOR)
}

/// A target size `d` times coarser across than `full`, at least one sample.
pub fn coarse_size(full: (u32, u32), d: u32) -> (u32, u32) {
    (full.0.div_ceil(d).max(1), full.1.div_ceil(d).max(1))
}

/// What the view shows and what the next frame should be.
#[derive(Default)]
pub struct Draft {
    /// The last whole frame's time (ms).
    pub full_ms: Option<f64>,
    /// The draft on screen: its key (at the whole resolution's camera), its divisor and when its
    /// camera was set.
    pub shown: Option<(RenderKey, u32, Instant)>,
}

/// The next frame to draw for `key`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// Nothing: the frame on screen is `key`'s whole frame, or a draft of it still settling.
    Nothing,
    /// A draft at 1/d of the resolution across.
    Draft(u32),
    /// The whole frame.
    Full,
}

impl Draft {
    /// Decide the next frame for `key`, given the whole frame on screen (`last_full`, if that
    /// is what the view shows).
    pub fn next(&self, key: &RenderKey, last_full: Option<&RenderKey>, enabled: bool) -> Next {
        if let Some((shown, _, at)) = &self.shown {
            if shown == key {
                return if at.elapsed() >= SETTLE {
                    Next::Full
                } else {
                    Next::Nothing
                };
            }
        } else if last_full == Some(key) {
            return Next::Nothing;
        }
        let on_screen = self.shown.as_ref().map(|s| &s.0).or(last_full);
        let camera_only = on_screen.is_some_and(|k| {
            k.scene == key.scene && k.request == key.request && k.camera != key.camera
        });
        let d = self.full_ms.map_or(1, divisor);
        if enabled && camera_only && d > 1 {
            Next::Draft(d)
        } else {
            Next::Full
        }
    }

    /// How long until the draft on screen is due to be drawn whole (`None`: no draft shown).
    pub fn due_in(&self) -> Option<Duration> {
        self.shown
            .as_ref()
            .map(|(_, _, at)| SETTLE.saturating_sub(at.elapsed()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Framing};
    use crate::request::{FrameRequest, Method};

    fn key(azimuth: f64) -> RenderKey {
        let mut camera = Camera::frame_box(
            &Framing::default(),
            glam::DVec3::ZERO,
            glam::DVec3::ONE,
            1024,
            768,
        );
        camera.eye.x += azimuth;
        RenderKey {
            scene: 1,
            camera,
            request: FrameRequest::preset(Method::Gumhold, true, crate::request::Preset::Baseline),
        }
    }

    /// d² fewer pixels bring the frame within the budget; fast frames are never drafted.
    #[test]
    fn the_divisor_brings_the_frame_within_budget() {
        assert_eq!(divisor(10.0), 1);
        assert_eq!(divisor(BUDGET_MS), 1);
        assert_eq!(divisor(f64::NAN), 1);
        for ms in [70.0, 200.0, 1900.0, 4000.0] {
            let d = divisor(ms);
            assert!(ms / f64::from(d * d) <= BUDGET_MS, "{ms} ms: d = {d}");
            assert!(
                d == 1 || ms / f64::from((d - 1) * (d - 1)) > BUDGET_MS,
                "{ms}: {d}"
            );
        }
        assert_eq!(divisor(1e6), MAX_DIVISOR);
        assert_eq!(coarse_size((1024, 768), 6), (171, 128));
        assert_eq!(coarse_size((1, 1), 8), (1, 1));
    }

    /// Only a camera that moves over a slow scene gets drafts; a still camera gets its whole
    /// frame after SETTLE, and any other change gets it at once.
    #[test]
    fn drafts_only_while_the_camera_moves() {
        let slow = Draft {
            full_ms: Some(1900.0),
            shown: None,
        };
        let (a, b) = (key(0.0), key(0.1));
        assert_eq!(slow.next(&a, Some(&a), true), Next::Nothing);
        assert_eq!(slow.next(&b, Some(&a), true), Next::Draft(6));
        assert_eq!(slow.next(&b, Some(&a), false), Next::Full);
        assert_eq!(slow.next(&a, None, true), Next::Full);
        let mut other = b.clone();
        other.request.min_pixel_radius += 1.0;
        assert_eq!(slow.next(&other, Some(&a), true), Next::Full);
        let fast = Draft {
            full_ms: Some(20.0),
            shown: None,
        };
        assert_eq!(fast.next(&b, Some(&a), true), Next::Full);
        let settling = Draft {
            full_ms: Some(1900.0),
            shown: Some((b.clone(), 6, Instant::now())),
        };
        assert_eq!(settling.next(&b, Some(&a), true), Next::Nothing);
        assert!(settling.due_in().is_some_and(|d| d <= SETTLE));
        assert_eq!(settling.next(&key(0.2), Some(&a), true), Next::Draft(6));
        let settled = Draft {
            full_ms: Some(1900.0),
            shown: Some((b.clone(), 6, Instant::now() - SETTLE)),
        };
        assert_eq!(settled.next(&b, Some(&a), true), Next::Full);
    }
}
