//! Figure effects after Sigg et al. (2006, §4): deferred shading, silhouette and crease outlines,
//! soft shadows from a key light, and ambient occlusion ([`ao`]: Grottel et al. 2012). The options a [`crate::request::FrameRequest`] carries,
//! and what both back ends apply the same way: the outline filter ([`outline`]) and the key light's
//! direction and shadow camera ([`light`]); the shading that combines them has its f64 twin in
//! [`crate::twin::composite`]. The
//! GPU runs them in one full-screen pass over its geometry buffer (`shaders/composite.wgsl`); the
//! reference over its exact f64 buffers, with exact shadow rays.

pub mod ao;
pub mod light;
pub mod outline;

use std::fmt;

/// Where glyphs are lit: in each method's fragment shader, or once per pixel after all glyphs
/// are drawn (the geometry buffer keeps base colour, normal, depth and id).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Shading {
    #[default]
    Direct,
    Deferred,
}

crate::names::named_values!(Shading {
    Direct => "direct",
    Deferred => "deferred",
});

/// Dark lines where the glyph under a pixel changes (silhouettes, touching glyphs of one
/// colour) and at creases of the surface ([`outline`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outlines {
    /// How far the outline colour replaces the shaded colour, in [0, 1].
    pub strength: f32,
    /// The filter's reach in samples: the outline width in pixels times the supersampling.
    pub width: u32,
    /// Linear RGB in [0, 1].
    pub color: [f32; 3],
}

impl Outlines {
    /// `--outlines` without a value.
    pub const DEFAULT_STRENGTH: f32 = 0.85;
}

impl Default for Outlines {
    fn default() -> Self {
        Self {
            strength: Self::DEFAULT_STRENGTH,
            width: 1,
            color: [0.0; 3],
        }
    }
}

/// The share of the diffuse light the key light gives when shadows are on (the headlight gives
/// the rest, so the eye's side of every glyph stays readable).
pub const KEY_SHARE: f64 = 0.65;

/// Shadows cast by a directional key light, from a shadow map filtered by percentage-closer
/// filtering (PCF).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shadows {
    /// Direction towards the key light in view space (x right, y up, z towards the viewer);
    /// any length above zero.
    pub light: [f64; 3],
    /// Shadow map side in texels: the map holds `map_size`² texels, fitted to the part of the
    /// scene the eye sees.
    pub map_size: u32,
    /// PCF kernel radius in texels (a (2r+1)² kernel).
    pub pcf_radius: u32,
    /// Sigg's adaptive test: the kernel's four corners and centre decide whether a pixel is in
    /// a penumbra, and only there is the whole kernel read.
    pub adaptive: bool,
    /// Let the glyphs raise the map side, up to twice `map_size`: until the scene's mean glyph
    /// spans [`Shadows::TEXELS_PER_GLYPH`] texels ([`light::shadow_camera`]). Off where the
    /// side was asked for (`--shadow-map`).
    pub glyph_fit: bool,
}

impl Shadows {
    /// Above-left of the camera, a little towards the viewer.
    pub const DEFAULT_LIGHT: [f64; 3] = [-0.5, 0.8, 0.35];

    /// Texels the mean glyph diameter spans in a map the glyphs fit ([`Self::glyph_fit`]).
    pub const TEXELS_PER_GLYPH: f64 = 9.0;

    /// The largest map side [`Self::glyph_fit`] or [`Self::map_for`] gives.
    pub const MAX_MAP: u32 = 8192;

    /// The shadow map side for an image of `width`×`height` samples: the map, fitted to what
    /// the eye sees ([`light::shadow_camera`]), holds no more texels than the image has samples
    /// (at least 512², which costs little and keeps thin casters in small images). Where a shadow's edge falls within a texel is decided by exact shadow
    /// rays (composite.wgsl): on grid40 at 1024x768 this 886² map differs from the exact
    /// shadows on 0.27 % of the covered pixels, where the whole-field 2048² map without the
    /// exact rays differed on 0.81 % (docs/notes/measurements.md).
    ///
    /// Small glyphs need more: the map names one caster a texel, and where the mean glyph
    /// spans fewer texels the exact re-test misses casters hidden in others' texels.
    /// Measured (`render --demo grid:52 --azimuth 20 --shadows --reference-check`, 400x300,
    /// texels per mean glyph diameter → mismatch): 4.1 → 5.2 %, 7.06 → 0.84 % (886², at
    /// 1024x768), 8.2 → 0.45 %, 9.3 → 0.21 %; grid40 at 1024x768 has 9.2 → 0.20 %. Hence
    /// [`Self::TEXELS_PER_GLYPH`], which leaves that grid40 map as it was.
    pub fn map_for(width: u32, height: u32) -> u32 {
        let samples = u64::from(width) * u64::from(height);
        ((samples as f64).sqrt().floor() as u32).clamp(512, Self::MAX_MAP)
    }
}

impl Default for Shadows {
    fn default() -> Self {
        Self {
            light: Self::DEFAULT_LIGHT,
            map_size: 1024,
            pcf_radius: 1,
            adaptive: true,
            glyph_fit: true,
        }
    }
}

/// The effects a frame is drawn with. Any effect implies deferred shading.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Effects {
    pub shading: Shading,
    pub outlines: Option<Outlines>,
    pub shadows: Option<Shadows>,
    pub ao: Option<ao::AmbientOcclusion>,
}

impl Effects {
    /// Whether the frame is shaded in the full-screen pass.
    pub fn deferred(&self) -> bool {
        self.shading == Shading::Deferred || self.any()
    }

    /// Whether an effect is on (beyond deferred shading itself).
    pub fn any(&self) -> bool {
        self.outlines.is_some() || self.shadows.is_some() || self.ao.is_some()
    }

    /// `self` with deferred shading wherever an effect needs it.
    pub fn resolved(self) -> Self {
        Self {
            shading: if self.deferred() {
                Shading::Deferred
            } else {
                Shading::Direct
            },
            ..self
        }
    }

    /// The outline reach scaled for `n`×`n` supersampling (outlines keep their width in output
    /// pixels).
    pub fn supersampled(self, n: u32) -> Self {
        Self {
            outlines: self.outlines.map(|o| Outlines {
                width: o.width.saturating_mul(n.max(1)),
                ..o
            }),
            ..self
        }
    }
}

impl Effects {
    /// Effects by name, each at its defaults: `outlines`, `shadows`, `ao`, comma-separated
    /// (`deferred` alone: deferred shading without effects).
    pub fn from_names(names: &str) -> Result<Self, String> {
        let mut fx = Effects {
            shading: Shading::Deferred,
            ..Effects::default()
        };
        for name in names.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            match name {
                "deferred" => {}
                "outlines" => fx.outlines = Some(Outlines::default()),
                "shadows" => fx.shadows = Some(Shadows::default()),
                "ao" => fx.ao = Some(ao::AmbientOcclusion::default()),
                other => {
                    return Err(format!(
                        "unknown effect '{}': use deferred, outlines, shadows or ao",
                        other.escape_debug()
                    ));
                }
            }
        }
        Ok(fx)
    }
}

impl fmt::Display for Effects {
    /// `deferred+outlines+shadows`, `direct`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = self.resolved().shading.to_string();
        if self.outlines.is_some() {
            s.push_str("+outlines");
        }
        if self.shadows.is_some() {
            s.push_str("+shadows");
        }
        if self.ao.is_some() {
            s.push_str("+ao");
        }
        f.pad(&s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effects_by_name_are_the_defaults_and_refuse_what_is_unknown() {
        let fx = Effects::from_names("outlines, shadows,ao").unwrap();
        assert_eq!(fx.outlines, Some(Outlines::default()));
        assert_eq!(fx.shadows, Some(Shadows::default()));
        assert_eq!(fx.ao, Some(ao::AmbientOcclusion::default()));
        assert_eq!(fx.to_string(), "deferred+outlines+shadows+ao");
        assert_eq!(
            Effects::from_names("deferred").unwrap().to_string(),
            "deferred"
        );
        let e = Effects::from_names("shadows,glow\n").unwrap_err();
        assert!(e.contains("'glow'") && !e.contains('\n'), "{e}");
    }
}
