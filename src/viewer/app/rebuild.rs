//! Rebuilding the viewer's scene when what it shows changed: the data, the style, the glyph
//! kind or the selection; the view framed anew only for new data.

use std::sync::Arc;

use glam::DVec3;

use super::{Built, ViewerApp};
use crate::camera::Framing;
use crate::glyph::{ColorScheme, GlyphStyle};
use crate::progress::Silent;
use crate::scene::Scene;
use crate::select::Selection;
use crate::staging::{self, Recipe};
use crate::viewer::navigation::Navigation;

impl ViewerApp {
    /// Rebuild the scene when the data, style, glyph shape or selection changed.
    pub(super) fn rebuild_if_needed(&mut self) {
        let Some(data) = &self.data else { return };
        let key = self.settings.build_key(self.data_generation);
        if self.built.as_ref().is_some_and(|b| b.key == key) {
            return;
        }
        let recipe = Recipe {
            read: self.read.clone(),
            style: key.style.clone(),
            selection: key.selection.clone(),
            glyph: key.glyph,
            underlay: key.underlay.clone(),
            // The panel shows the slicing it draws: the middle slice is set there on load.
            middle_slice: false,
            underlay_side: None,
            odf_normalize: None,
            peaks: false,
            peaks_over: false,
        };
        let volume = data.underlay.as_deref();
        // Series and peaks are selected by their planes only.
        let planes_only = Selection {
            slicing: key.selection.slicing.clone(),
            ..Selection::default()
        };
        let built = match (&data.odf, &data.peaks) {
            // Peaks as sticks, coloured by direction unless solid, as `render` draws them.
            (None, Some(peaks)) => staging::build_peaks(
                peaks,
                &data.name(),
                &Recipe {
                    selection: planes_only,
                    underlay: None,
                    style: GlyphStyle {
                        color: match key.style.color {
                            ColorScheme::Solid => ColorScheme::Solid,
                            _ => ColorScheme::Dec,
                        },
                        ..key.style.clone()
                    },
                    ..recipe.clone()
                },
            ),
            // Series drawn as ODF glyphs.
            (Some(sh), _) => staging::build_sh(
                sh,
                &data.name(),
                &Recipe {
                    selection: planes_only,
                    underlay: None,
                    odf_normalize: Some(key.odf_normalize),
                    // A tensor colouring kept from an earlier file has nothing to read in a
                    // series: such a file opens coloured by direction, as `render` colours it.
                    style: GlyphStyle {
                        color: match key.style.color {
                            c @ (ColorScheme::Amplitude | ColorScheme::Solid) => c,
                            _ => ColorScheme::Dec,
                        },
                        ..key.style.clone()
                    },
                    ..recipe.clone()
                },
                &Silent,
            ),
            (None, None) => staging::build(
                &data.field,
                &data.set,
                data.spacing.clone(),
                &recipe,
                volume,
                &Silent,
            ),
        };
        let built = match built {
            Ok(b) => b,
            Err(e) => {
                // Nothing to draw (an empty selection): say why, keep the data.
                self.status = Some(e.to_string());
                staging::Built {
                    scene: Scene::default(),
                    glyphs_clamped: 0,
                    selected: Vec::new(),
                    frame_centre: DVec3::ZERO,
                    frame_radius: 1.0,
                    frame_half: DVec3::splat(1.0 / 3f64.sqrt()),
                    glyphs_valid: data.set.glyphs.len(),
                    face: None,
                    style: recipe.style.resolve(&data.set, data.spacing.clone()),
                }
            }
        };
        let staging::Built {
            scene,
            selected,
            frame_centre,
            frame_radius,
            frame_half,
            face,
            glyphs_clamped,
            style,
            ..
        } = built;
        let render_framing = match face.filter(|_| self.face_slice) {
            Some(f) => (
                Framing {
                    toward: Some(f.toward),
                    ..self.framing
                },
                f.centre,
                f.half,
            ),
            None => (self.framing, frame_centre, frame_half),
        };
        if let Err(e) = self.view.set_scene(&self.gpu, &scene) {
            self.error = Some(format!(
                "cannot upload {} glyphs: {e}",
                scene.instances.len()
            ));
        }
        self.scene_generation += 1;
        match &mut self.nav {
            Some(nav) => nav.set_bounds(scene.centre, scene.radius),
            None => {
                // Frame the whole field (not the selection) so slicing does not jump the view;
                // one slice of DTI data is seen face-on and close instead.
                let (framing, centre, radius) = match face.filter(|_| self.face_slice) {
                    Some(f) => (
                        Framing {
                            toward: Some(f.toward),
                            ..self.framing
                        },
                        f.centre,
                        f.radius,
                    ),
                    None => (self.framing, frame_centre, frame_radius),
                };
                self.nav = Some(Navigation::from_framing(&framing, centre, radius));
            }
        }
        self.picked = None;
        self.built = Some(Built {
            key,
            scene: Arc::new(scene),
            selected,
            clamped: glyphs_clamped,
            style,
            generation: self.scene_generation,
            render_framing,
        });
    }
}
