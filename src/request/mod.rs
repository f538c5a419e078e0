//! What to draw and how: the method, the glyph shape, the proxy options and the request a back
//! end renders. Shared by the GPU renderer, the exact reference, the CLI, the viewer and the
//! bench, below all of them.

use std::fmt;
use std::num::NonZeroU32;
use std::str::FromStr;

use crate::effects::Effects;
use crate::frame::Lighting;
use crate::shape::Capabilities;

/// `render --splat`'s default, and the viewer's: on grid40 at 1024x768 splatting every glyph up
/// to 32 px across measured fastest in every view (docs/book/src/concepts/doing-less-work.md).
pub const DEFAULT_SPLAT: u32 = 32;

/// How glyphs are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Gumhold's perspective-correct silhouette quad, ray cast per fragment.
    Gumhold,
    /// Sigg et al.'s screen-space bounding box of the projected quadric, ray cast per fragment.
    Sigg,
    /// The exact f64 CPU ray caster (accuracy truth, and the fallback without a GPU).
    Reference,
    /// Baseline: an instanced triangle mesh (icosphere / prism subdivided N times, 0..=6).
    Mesh(u8),
    /// Baseline: the glyph's oriented box, flat shaded (a "cuboid" glyph).
    Box,
}

impl Method {
    /// Every GPU method, in the order reports list them.
    pub fn gpu_methods() -> Vec<Method> {
        let mut m = vec![Method::Gumhold, Method::Sigg];
        m.extend((0..=Method::MAX_MESH_LEVEL).map(Method::Mesh));
        m.push(Method::Box);
        m
    }

    /// The finest `mesh:N` level (an icosphere of 81 920 triangles).
    pub const MAX_MESH_LEVEL: u8 = 6;

    pub fn is_gpu(self) -> bool {
        !matches!(self, Method::Reference)
    }
}

impl fmt::Display for Method {
    // `pad`, so that width and alignment (`{:<8}`) apply.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Method::Gumhold => f.pad("gumhold"),
            Method::Sigg => f.pad("sigg"),
            Method::Reference => f.pad("reference"),
            Method::Mesh(n) => f.pad(&format!("mesh:{n}")),
            Method::Box => f.pad("box"),
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "gumhold" => Ok(Method::Gumhold),
            "sigg" => Ok(Method::Sigg),
            "reference" => Ok(Method::Reference),
            "box" => Ok(Method::Box),
            _ if s.starts_with("mesh:") => {
                let max = Method::MAX_MESH_LEVEL;
                let level = &s["mesh:".len()..];
                let digits = !level.is_empty() && level.bytes().all(|b| b.is_ascii_digit());
                match level.parse::<u8>() {
                    Ok(n) if digits && n <= max => Ok(Method::Mesh(n)),
                    _ => Err(format!(
                        "invalid mesh level in '{s}': use mesh:N with N an integer from 0 to {max}"
                    )),
                }
            }
            _ => Err(format!(
                "unknown method '{s}': use gumhold, sigg, reference, mesh:N (N = 0..={}) or box",
                Method::MAX_MESH_LEVEL
            )),
        }
    }
}

impl serde::Serialize for Method {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

pub use crate::shape::GlyphKind;

mod options;

pub use options::{DrawOptions, Preset};

/// The polygon around the unit circle that Gumhold's proxy is made of (gumhold-ellipsoid.md §10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ProxyShape {
    /// Gumhold's quad: 4 vertices, 2 triangles, 4/π = 1.27 of the silhouette's area.
    #[default]
    Quad,
    /// The circumscribed octagon: 8 vertices, 6 triangles, 1.05 of the area.
    Octagon,
    /// The circumscribed triangle: 3 vertices, 1 triangle, 3√3/π = 1.65 of the area.
    Triangle,
}

crate::names::named_values!(ProxyShape {
    Quad => "quad",
    Octagon => "octagon",
    Triangle => "triangle",
});

impl ProxyShape {
    pub fn vertices(self) -> u32 {
        match self {
            ProxyShape::Quad => 4,
            ProxyShape::Octagon => 8,
            ProxyShape::Triangle => 3,
        }
    }
}

/// How the ray casters bound each glyph, as the GPU pipelines are keyed: derived from a
/// [`MethodConfig`] (Gumhold takes all of it, conservative depth only for ellipsoids; Sigg's
/// screen boxes and the meshes use [`Proxy::BASELINE`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Proxy {
    pub shape: ProxyShape,
    /// Place the proxy on the glyph's nearest view plane (rasterised depth ≤ ray-cast depth).
    pub conservative: bool,
    /// Declare it to the GPU (`@early_depth_test(greater_equal)`): only with `conservative`, an
    /// adapter with SHADER_EARLY_DEPTH_TEST and every glyph far enough in front of the near plane
    /// for the move ([`crate::scene::Scene::conservative_depth_holds`]).
    pub early_depth: bool,
}

impl Proxy {
    /// Gumhold's quad at the silhouette plane.
    pub const BASELINE: Proxy = Proxy {
        shape: ProxyShape::Quad,
        conservative: false,
        early_depth: false,
    };

    pub fn vertices(self) -> u32 {
        self.shape.vertices()
    }
}

impl Default for Proxy {
    fn default() -> Self {
        Self::BASELINE
    }
}

/// How Gumhold's method draws ellipsoids and superquadrics (with their ray-cast depth, for
/// splats).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DrawPath {
    /// A proxy per glyph built in the vertex stage.
    Direct,
    /// Proxy frames built once per glyph in a compute pass; only the glyphs it keeps are drawn.
    Prepass,
    /// The prepass, and glyphs whose proxy spans at most this many pixels across are ray cast
    /// per pixel in compute ("splats") instead of drawn.
    Splat(NonZeroU32),
}

/// Gumhold's depth: the proxy's own, or the ray-cast one (which conservative proxies and splats
/// need).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GumholdDepth {
    /// The proxy's rasterised depth (`--no-depth-correction`), optionally from the prepass.
    Proxy { prepass: bool },
    /// Per-pixel ray-cast depth.
    RayCast {
        /// Proxies on the glyph's nearest view plane.
        conservative: bool,
        /// Conservative depth declared to the GPU ([`Proxy::early_depth`]).
        early_depth: bool,
        path: DrawPath,
    },
}

/// Gumhold's method with the options it takes. A glyph kind takes those its [`Capabilities`]
/// allow ([`MethodConfig::for_kind`]): every kind the proxy polygon, conservative depth and the
/// prepass and splats only where the table says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GumholdConfig {
    pub shape: ProxyShape,
    pub depth: GumholdDepth,
}

/// A method with the options it takes, and only those: a request for Sigg's method with splats
/// cannot be written. Independent of the glyph kind, which is the scene's
/// ([`crate::scene::Scene::kind`]): back ends draw [`MethodConfig::for_kind`] of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MethodConfig {
    Gumhold(GumholdConfig),
    Sigg {
        depth_correction: bool,
    },
    /// The triangle-mesh baselines: `Method::Mesh(level)` or `Method::Box`; a mesh's depth is
    /// its rasterised depth.
    Mesh {
        method: MeshMethod,
    },
    /// The exact CPU reference.
    Reference,
}

/// Which tessellated baseline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshMethod {
    /// The kind's unit mesh at this level, 0..=[`Method::MAX_MESH_LEVEL`].
    Level(u8),
    /// The glyph's oriented box.
    Box,
}

impl MethodConfig {
    pub fn method(&self) -> Method {
        match self {
            MethodConfig::Gumhold(_) => Method::Gumhold,
            MethodConfig::Sigg { .. } => Method::Sigg,
            MethodConfig::Mesh {
                method: MeshMethod::Level(n),
            } => Method::Mesh(*n),
            MethodConfig::Mesh {
                method: MeshMethod::Box,
            } => Method::Box,
            MethodConfig::Reference => Method::Reference,
        }
    }

    /// This configuration without Gumhold's compute prepass (and so without splats): each glyph
    /// drawn directly, as in a frame of two kinds ([`crate::render::drawer::Layered`]).
    pub fn without_prepass(self) -> Self {
        let MethodConfig::Gumhold(GumholdConfig { shape, depth }) = self else {
            return self;
        };
        let depth = match depth {
            GumholdDepth::Proxy { .. } => GumholdDepth::Proxy { prepass: false },
            GumholdDepth::RayCast {
                conservative,
                early_depth,
                ..
            } => GumholdDepth::RayCast {
                conservative,
                early_depth,
                path: DrawPath::Direct,
            },
        };
        MethodConfig::Gumhold(GumholdConfig { shape, depth })
    }

    /// This configuration as glyphs of `kind` are drawn with it: the options the kind does not
    /// take (its [`Capabilities`]) left out.
    pub fn for_kind(self, kind: GlyphKind) -> Self {
        let caps: Capabilities = kind.caps();
        let MethodConfig::Gumhold(GumholdConfig { shape, depth }) = self else {
            return self;
        };
        let depth = match depth {
            GumholdDepth::Proxy { prepass } => GumholdDepth::Proxy {
                prepass: prepass && caps.prepass,
            },
            GumholdDepth::RayCast {
                conservative,
                early_depth,
                path,
            } => GumholdDepth::RayCast {
                conservative: conservative && caps.conservative_depth,
                early_depth: early_depth && caps.conservative_depth,
                path: match path {
                    DrawPath::Splat(_) if !caps.splats && caps.prepass => DrawPath::Prepass,
                    DrawPath::Splat(_) | DrawPath::Prepass if !caps.prepass => DrawPath::Direct,
                    path => path,
                },
            },
        };
        MethodConfig::Gumhold(GumholdConfig { shape, depth })
    }

    /// Whether fragments write the ray-cast depth (meshes and the reference write their exact
    /// surface depth, which counts as corrected).
    pub fn depth_correction(&self) -> bool {
        match self {
            MethodConfig::Gumhold(g) => matches!(g.depth, GumholdDepth::RayCast { .. }),
            MethodConfig::Sigg { depth_correction } => *depth_correction,
            MethodConfig::Mesh { .. } | MethodConfig::Reference => true,
        }
    }

    /// The proxy the GPU pipelines are keyed by.
    pub fn proxy(&self) -> Proxy {
        match self {
            MethodConfig::Gumhold(GumholdConfig { shape, depth }) => match depth {
                GumholdDepth::Proxy { .. } => Proxy {
                    shape: *shape,
                    ..Proxy::BASELINE
                },
                GumholdDepth::RayCast {
                    conservative,
                    early_depth,
                    ..
                } => Proxy {
                    shape: *shape,
                    conservative: *conservative,
                    early_depth: *early_depth,
                },
            },
            _ => Proxy::BASELINE,
        }
    }

    /// Whether frames come from Gumhold's compute prepass.
    pub fn uses_prepass(&self) -> bool {
        match self {
            MethodConfig::Gumhold(g) => match g.depth {
                GumholdDepth::Proxy { prepass } => prepass,
                GumholdDepth::RayCast { path, .. } => path != DrawPath::Direct,
            },
            _ => false,
        }
    }

    /// The splat size in pixels (0: none).
    pub fn splat_pixels(&self) -> u32 {
        match self {
            MethodConfig::Gumhold(GumholdConfig {
                depth:
                    GumholdDepth::RayCast {
                        path: DrawPath::Splat(px),
                        ..
                    },
                ..
            }) => px.get(),
            _ => 0,
        }
    }

    /// Draw every glyph from the prepass instead of splatting the small ones (what an image
    /// too large for the splats' per-pixel buffer gets).
    pub fn drop_splats(&mut self) {
        if let MethodConfig::Gumhold(GumholdConfig {
            depth: GumholdDepth::RayCast { path, .. },
            ..
        }) = self
            && matches!(path, DrawPath::Splat(_))
        {
            *path = DrawPath::Prepass;
        }
    }

    /// Gumhold's proxies built in the vertex stage, without the compute prepass or splats (for
    /// devices that cannot bind the prepass's buffers).
    pub fn drop_prepass(&mut self) {
        if let MethodConfig::Gumhold(GumholdConfig { depth, .. }) = self {
            match depth {
                GumholdDepth::Proxy { prepass } => *prepass = false,
                GumholdDepth::RayCast { path, .. } => *path = DrawPath::Direct,
            }
        }
    }

    /// Declare (or not) conservative depth to the GPU, where the configuration is conservative.
    pub fn set_early_depth(&mut self, on: bool) {
        if let MethodConfig::Gumhold(GumholdConfig {
            depth:
                GumholdDepth::RayCast {
                    conservative,
                    early_depth,
                    ..
                },
            ..
        }) = self
        {
            *early_depth = on && *conservative;
        }
    }
}

/// What to draw and what to read back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRequest {
    /// The method, glyph shape and the options that method takes.
    pub method: MethodConfig,
    /// Read back view normals and view z (for `--reference-check`).
    pub aux: bool,
    /// Linear RGBA in [0, 1].
    pub background: [f64; 4],
    /// Frames to render and time (the targets of the last one are read back).
    pub frames: u32,
    pub lighting: Lighting,
    /// Cull glyphs outside the view frustum (or wholly in front of the near plane) in the
    /// vertex stage (every GPU method).
    pub cull: bool,
    /// Skip glyphs whose projected bounding sphere has a radius below this many pixels (0: none).
    pub min_pixel_radius: f32,
    /// How the scene's underlay, if it has one, is shown.
    pub underlay: UnderlayView,
    /// Deferred shading, outlines and shadows.
    pub effects: Effects,
}

/// How a scene's underlay is shown: a frame-time choice, so the viewer's toggle and window do
/// not rebuild the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnderlayView {
    pub shown: bool,
    /// Values at or below the first are black, at or above the second white (`None`: the
    /// scene's default window).
    pub window: Option<[f32; 2]>,
}

impl Default for UnderlayView {
    fn default() -> Self {
        Self {
            shown: true,
            window: None,
        }
    }
}

impl FrameRequest {
    /// `method` with depth correction on the baseline path (a proxy drawn for every glyph, no
    /// culling), the rest as [`FrameRequest::default`].
    pub fn new(method: Method) -> Self {
        Self::with_options(method, true, &Preset::Baseline.options())
    }

    /// `method` with these options.
    pub fn with_options(method: Method, depth_correction: bool, options: &DrawOptions) -> Self {
        Self {
            method: options.config(method, depth_correction),
            cull: options.cull,
            min_pixel_radius: options.min_pixel_radius,
            ..Self::default()
        }
    }

    /// `method` with a preset's options.
    pub fn preset(method: Method, depth_correction: bool, preset: Preset) -> Self {
        Self::with_options(method, depth_correction, &preset.options())
    }

    /// This request as glyphs of `kind` are drawn with it ([`MethodConfig::for_kind`]).
    pub fn for_kind(&self, kind: GlyphKind) -> Self {
        Self {
            method: self.method.for_kind(kind),
            ..*self
        }
    }

    pub fn depth_correction(&self) -> bool {
        self.method.depth_correction()
    }

    pub fn proxy(&self) -> Proxy {
        self.method.proxy()
    }

    /// Whether frames come from the compute prepass.
    pub fn uses_prepass(&self) -> bool {
        self.method.uses_prepass()
    }

    /// The splat size in effect (0: none).
    pub fn splat_pixels(&self) -> u32 {
        self.method.splat_pixels()
    }

    /// What the method's shaders write into the aux target: everything the accuracy check
    /// reads back, else deferred shading's normals alone.
    pub fn aux_target(&self) -> AuxTarget {
        if self.aux {
            AuxTarget::Checked
        } else if self.effects.deferred() {
            AuxTarget::Normal
        } else {
            AuxTarget::None
        }
    }
}

/// What a frame's aux target holds (the G-buffer's share beyond colour, id and depth).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AuxTarget {
    /// No aux target.
    #[default]
    None,
    /// The view normal and view z, an f32 each (16 bytes a pixel), read back for the accuracy
    /// check.
    Checked,
    /// The view normal alone in octahedral coordinates, two f32 (8 bytes a pixel): all deferred
    /// shading reads, and as exact as `Checked`'s (the encoding's error is f32 rounding, about
    /// 10⁻⁷ rad, against the 10⁻³° the accuracy check holds normals to).
    Normal,
}

impl Default for FrameRequest {
    /// Gumhold ellipsoids with depth correction, the baseline path, white background, one frame.
    fn default() -> Self {
        Self {
            method: MethodConfig::Gumhold(GumholdConfig {
                shape: ProxyShape::Quad,
                depth: GumholdDepth::RayCast {
                    conservative: false,
                    early_depth: false,
                    path: DrawPath::Direct,
                },
            }),
            aux: false,
            background: [1.0, 1.0, 1.0, 1.0],
            frames: 1,
            lighting: Lighting::default(),
            cull: false,
            min_pixel_radius: 0.0,
            underlay: UnderlayView::default(),
            effects: Effects::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_round_trip_through_their_names() {
        for m in [
            Method::Gumhold,
            Method::Sigg,
            Method::Reference,
            Method::Box,
        ] {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
        }
        for n in 0..=Method::MAX_MESH_LEVEL {
            assert_eq!(format!("mesh:{n}").parse::<Method>(), Ok(Method::Mesh(n)));
        }
        assert!("voodoo".parse::<Method>().unwrap_err().contains("voodoo"));
        for bad in ["mesh:7", "mesh:x", "mesh:", "mesh:-1", "mesh:+3", "mesh"] {
            let e = bad.parse::<Method>().unwrap_err();
            assert!(e.contains(bad) && e.contains("mesh:N"), "{bad}: {e}");
        }
    }

    /// Every kind with splats takes the prepass and splats as ellipsoids do: splats only with
    /// depth correction, the prepass drawing them without it, and only with Gumhold's method.
    /// A kind without them is drawn directly, and the options are refused for it.
    #[test]
    fn kinds_take_the_prepass_and_splats_their_table_gives() {
        let splat = Preset::Splat.options();
        let base = Preset::Baseline.options();
        for &kind in GlyphKind::VALUES {
            let caps = kind.caps();
            let with = |depth| splat.config(Method::Gumhold, depth).for_kind(kind);
            let mut m = with(true);
            assert_eq!(m.uses_prepass(), caps.prepass, "{kind}");
            if !caps.splats {
                assert_eq!(m.splat_pixels(), 0, "{kind}");
                assert_eq!(
                    splat
                        .check(&base, Method::Gumhold, kind, true)
                        .unwrap_err()
                        .0,
                    "--splat",
                    "{kind}"
                );
                assert!(!Preset::Splat.applies_to(Method::Gumhold, kind) || caps.prepass);
                continue;
            }
            assert_eq!(m.splat_pixels(), DEFAULT_SPLAT);
            m.drop_splats();
            assert_eq!((m.splat_pixels(), m.uses_prepass()), (0, true));
            let flat = with(false);
            assert_eq!((flat.splat_pixels(), flat.uses_prepass()), (0, true));
            assert!(
                !base
                    .config(Method::Gumhold, true)
                    .for_kind(kind)
                    .uses_prepass()
            );
            assert!(splat.check(&base, Method::Gumhold, kind, true).is_ok());
            assert_eq!(
                splat.check(&base, Method::Sigg, kind, true).unwrap_err().0,
                "--splat"
            );
            assert_eq!(
                splat
                    .check(&base, Method::Gumhold, kind, false)
                    .unwrap_err()
                    .0,
                "--splat"
            );
            for p in [Preset::Prepass, Preset::Splat] {
                assert!(p.applies_to(Method::Gumhold, kind));
                assert!(!p.applies_to(Method::Sigg, kind));
            }
            assert_eq!(
                Preset::Conservative.applies_to(Method::Gumhold, kind),
                caps.conservative_depth
            );
        }
        // The refusals name the kinds that take the option.
        let conservative = DrawOptions {
            conservative: true,
            ..base
        };
        let (flag, who) = conservative
            .check(&base, Method::Gumhold, GlyphKind::Ellipsoid, false)
            .unwrap_err();
        assert_eq!(flag, "--conservative-depth");
        assert!(who.starts_with("Gumhold ellipsoids") && who.ends_with("with depth correction"));
    }
}
