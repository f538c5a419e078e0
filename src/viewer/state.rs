//! What the user chose, and what must be redone when it changes.
//!
//! The viewer keeps two keys: a [`BuildKey`] (style, glyph shape and selection: the scene's
//! instances depend on these) and a [`RenderKey`] (camera, request, target size and scene
//! generation: the frame depends on these). A frame is drawn only when its key differs from the
//! last one drawn, so an idle viewer costs nothing on lavapipe.

use crate::camera::Camera;
use crate::effects::Effects;
use crate::glyph::GlyphStyle;
use crate::request::{DrawOptions, FrameRequest, GlyphKind, Method, UnderlayView};
use crate::scene::UnderlaySource;
use crate::scene::odf::OdfNormalize;
use crate::select::{Selection, Slicing};

/// Every option the side panel changes.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub method: Method,
    pub glyph: GlyphKind,
    pub depth_correction: bool,
    pub style: GlyphStyle,
    pub selection: Selection,
    /// Linear RGB in [0, 1], as `render --background` takes it.
    pub background: [f32; 3],
    /// `render --proxy`, `--conservative-depth`, culling (`--no-cull`), `--prepass` and
    /// `--splat` (0: off), with `render`'s defaults; the panel shows those the method takes.
    pub draw: DrawOptions,
    /// The scalar image under the slices (`--underlay`), and how it is shown.
    pub underlay: Option<UnderlaySource>,
    pub underlay_view: UnderlayView,
    /// Deferred shading, outlines and shadows (outline widths in window pixels).
    pub effects: Effects,
    /// Samples per pixel across of the view (1, or 2: the 2×2 box filter is the texture's
    /// bilinear filter at the pixel centre).
    pub ssaa: u32,
    /// Coarser frames while the camera moves over a slow scene ([`crate::viewer::draft`]).
    pub draft: bool,
    /// How the ODF glyphs of a file of SH series are scaled (`render --odf-normalize`).
    pub odf_normalize: OdfNormalize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            method: Method::Gumhold,
            glyph: GlyphKind::Ellipsoid,
            depth_correction: true,
            style: GlyphStyle::default(),
            selection: Selection::default(),
            background: [1.0, 1.0, 1.0],
            draw: DrawOptions::default(),
            underlay: None,
            underlay_view: UnderlayView::default(),
            effects: Effects::default(),
            ssaa: 1,
            draft: true,
            odf_normalize: OdfNormalize::default(),
        }
    }
}

/// What the scene's instances depend on.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildKey {
    pub generation: u64,
    pub style: GlyphStyle,
    pub glyph: GlyphKind,
    pub selection: Selection,
    pub underlay: Option<UnderlaySource>,
    pub odf_normalize: OdfNormalize,
}

/// What a drawn frame depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderKey {
    pub scene: u64,
    pub camera: Camera,
    pub request: FrameRequest,
}

impl Settings {
    pub fn build_key(&self, data_generation: u64) -> BuildKey {
        BuildKey {
            generation: data_generation,
            style: self.style.clone(),
            glyph: self.glyph,
            selection: self.selection.clone(),
            underlay: self.underlay.clone(),
            odf_normalize: self.odf_normalize,
        }
    }

    /// The request `render --ssaa ssaa` would get for these settings.
    pub fn request(&self, ssaa: u32) -> FrameRequest {
        let [r, g, b] = self.background.map(f64::from);
        // Declaring early depth needs a check over the scene per camera: the viewer does
        // without (conservative placement alone is still correct).
        FrameRequest {
            background: [r, g, b, 1.0],
            underlay: self.underlay_view,
            effects: self.effects.resolved().supersampled(ssaa),
            ..FrameRequest::with_options(self.method, self.depth_correction, &self.draw)
        }
    }

    /// Take a kind of data's defaults, as `view` starts with them for its file: colours, size
    /// and background.
    pub fn adopt(&mut self, defaults: &crate::defaults::Defaults) {
        self.style.color = defaults.color;
        self.style.size_by = defaults.size_by;
        let [r, g, b, _] = defaults.background;
        self.background = [r, g, b].map(|c| c as f32);
    }

    /// Keep the slice indices inside a lattice of `dims` (after loading another file).
    pub fn clamp_to_lattice(&mut self, dims: Option<[usize; 3]>) {
        let Some(d) = dims else {
            self.selection.slicing = Slicing::Whole;
            return;
        };
        let last = d.map(|n| n.max(1) - 1);
        match &mut self.selection.slicing {
            Slicing::Whole => {}
            Slicing::Slice { axis, index } => {
                *axis = (*axis).min(2);
                *index = (*index).min(last[*axis]);
            }
            Slicing::Orthogonal { at } => {
                for a in 0..3 {
                    at[a] = at[a].min(last[a]);
                }
            }
            Slicing::Planes(planes) => {
                for p in planes.iter_mut() {
                    p.axis = p.axis.min(2);
                    p.index = p.index.min(last[p.axis]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::request::ProxyShape;
    use crate::select::Plane;

    #[test]
    fn view_only_changes_keep_the_scene() {
        let s = Settings::default();
        let mut t = s.clone();
        t.background = [0.0, 0.0, 0.0];
        t.depth_correction = false;
        t.method = Method::Box;
        assert_eq!(s.build_key(1), t.build_key(1));
        assert_ne!(s.request(1), t.request(1));
        let mut p = s.clone();
        p.draw.proxy = ProxyShape::Octagon;
        p.draw.cull = false;
        p.draw.conservative = true;
        p.draw.splat = 0;
        p.draw.prepass = true;
        assert_eq!(s.build_key(1), p.build_key(1), "proxy options only redraw");
        let req = p.request(1);
        assert_eq!(req.proxy().shape, ProxyShape::Octagon);
        assert!(!req.cull && req.proxy().conservative && !req.proxy().early_depth);
        assert!(req.uses_prepass() && req.splat_pixels() == 0);
        let d = s.request(1);
        assert!(
            d.cull && d.splat_pixels() == crate::request::DEFAULT_SPLAT,
            "render's defaults"
        );
        t.selection.stride = 2;
        assert_ne!(s.build_key(1), t.build_key(1));
        let mut r = s.clone();
        r.selection.roi = Some([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        assert_ne!(s.build_key(1), r.build_key(1), "an ROI rebuilds");
        let mut u = s.clone();
        u.style.min_radius = Some(0.2);
        assert_ne!(s.build_key(1), u.build_key(1));
        let mut o = s.clone();
        o.odf_normalize = OdfNormalize::MinMax;
        assert_ne!(s.build_key(1), o.build_key(1), "ODF scaling rebuilds");
        assert_ne!(s.build_key(1), s.build_key(2), "a new file rebuilds");
    }

    #[test]
    fn slices_are_clamped_to_a_new_lattice() {
        let mut s = Settings::default();
        s.selection.slicing = Slicing::Slice { axis: 1, index: 30 };
        s.clamp_to_lattice(Some([40, 10, 5]));
        assert_eq!(s.selection.slicing, Slicing::Slice { axis: 1, index: 9 });
        s.selection.slicing = Slicing::Orthogonal { at: [50, 50, 1] };
        s.clamp_to_lattice(Some([4, 3, 2]));
        assert_eq!(s.selection.slicing, Slicing::Orthogonal { at: [3, 2, 1] });
        s.selection.slicing = Slicing::Planes(vec![
            Plane { axis: 0, index: 7 },
            Plane { axis: 2, index: 1 },
        ]);
        s.clamp_to_lattice(Some([4, 3, 2]));
        assert_eq!(
            s.selection.slicing,
            Slicing::Planes(vec![
                Plane { axis: 0, index: 3 },
                Plane { axis: 2, index: 1 }
            ])
        );
        s.clamp_to_lattice(None);
        assert_eq!(s.selection.slicing, Slicing::Whole);
    }
}
