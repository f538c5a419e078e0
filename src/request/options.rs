//! The options a user sets and the named ways of drawing: one flat [`DrawOptions`] set (the
//! command line's flags, the viewer's widgets) that becomes a [`MethodConfig`] for a method,
//! checked against what each glyph kind takes ([`crate::shape::Capabilities`]), and the
//! [`Preset`]s `render`, the viewer and the bench share.

use std::num::NonZeroU32;

use super::{
    DEFAULT_SPLAT, DrawPath, GlyphKind, GumholdConfig, GumholdDepth, MeshMethod, Method,
    MethodConfig, ProxyShape,
};
use crate::shape::Capabilities;

/// The options a user sets (command-line flags, the viewer's widgets, a [`Preset`]), as one flat
/// set: [`DrawOptions::config`] turns them into the [`MethodConfig`] of a method, glyph and depth
/// setting, leaving out what that method does not take; [`DrawOptions::check`] says which of
/// them it does not take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawOptions {
    /// Gumhold: the proxy polygon.
    pub proxy: ProxyShape,
    /// Gumhold ellipsoids with depth correction: proxies on the glyph's nearest plane.
    pub conservative: bool,
    /// Gumhold ellipsoids and superquadrics: the compute prepass (always on with splats).
    pub prepass: bool,
    /// Gumhold ellipsoids and superquadrics with depth correction: splats up to this many
    /// pixels (0: none).
    pub splat: u32,
    /// Cull glyphs outside the view frustum (or wholly in front of the near plane).
    pub cull: bool,
    /// Skip glyphs whose projected bounding sphere has a radius below this many pixels.
    pub min_pixel_radius: f32,
}

impl Default for DrawOptions {
    /// `render`'s default path ([`Preset::Splat`]).
    fn default() -> Self {
        Preset::DEFAULT.options()
    }
}

impl DrawOptions {
    /// The path of the glyphs that have the prepass: splats need the ray-cast depth, so without
    /// it (`depth_correction` false) the prepass draws them.
    fn path(&self, depth_correction: bool) -> DrawPath {
        match NonZeroU32::new(self.splat) {
            Some(px) if depth_correction => DrawPath::Splat(px),
            _ if self.prepass || self.splat > 0 => DrawPath::Prepass,
            _ => DrawPath::Direct,
        }
    }

    /// The configuration of `method` with these options, for any glyph kind.
    pub fn config(&self, method: Method, depth_correction: bool) -> MethodConfig {
        match method {
            Method::Gumhold => MethodConfig::Gumhold(GumholdConfig {
                shape: self.proxy,
                depth: if depth_correction {
                    GumholdDepth::RayCast {
                        conservative: self.conservative,
                        early_depth: false,
                        path: self.path(true),
                    }
                } else {
                    GumholdDepth::Proxy {
                        prepass: self.path(false) != DrawPath::Direct,
                    }
                },
            }),
            Method::Sigg => MethodConfig::Sigg { depth_correction },
            Method::Mesh(level) => MethodConfig::Mesh {
                method: MeshMethod::Level(level),
            },
            Method::Box => MethodConfig::Mesh {
                method: MeshMethod::Box,
            },
            Method::Reference => MethodConfig::Reference,
        }
    }

    /// The first option set away from `baseline` that `method` drawing `kind` does not take, as
    /// (option name, what takes it): for refusing explicit options that would be ignored.
    pub fn check(
        &self,
        baseline: &DrawOptions,
        method: Method,
        kind: GlyphKind,
        depth_correction: bool,
    ) -> Result<(), (&'static str, String)> {
        let gumhold = method == Method::Gumhold;
        let caps = kind.caps();
        let rules: [Rule; 4] = [
            (
                "--proxy",
                self.proxy != baseline.proxy,
                gumhold,
                |_| true,
                "",
            ),
            (
                "--conservative-depth",
                self.conservative != baseline.conservative,
                gumhold && caps.conservative_depth && depth_correction,
                |c| c.conservative_depth,
                " with depth correction",
            ),
            (
                "--prepass",
                self.prepass != baseline.prepass,
                gumhold && caps.prepass,
                |c| c.prepass,
                "",
            ),
            (
                "--splat",
                self.splat != baseline.splat && self.splat > 0,
                gumhold && caps.splats && depth_correction,
                |c| c.splats,
                " with depth correction",
            ),
        ];
        match rules
            .into_iter()
            .find(|(_, set, takes, _, _)| *set && !*takes)
        {
            Some((name, _, _, has, with)) => Err((name, takers(has, with))),
            None => Ok(()),
        }
    }
}

/// An option's name, whether it is set, whether the kind takes it, which capability does, and
/// what else it needs.
type Rule = (
    &'static str,
    bool,
    bool,
    fn(&Capabilities) -> bool,
    &'static str,
);

/// "Gumhold's method", or "Gumhold ellipsoids and superquadrics" and what else they need, from
/// the kinds whose capabilities pass `has`.
fn takers(has: fn(&Capabilities) -> bool, with: &str) -> String {
    let kinds: Vec<String> = GlyphKind::VALUES
        .iter()
        .filter(|k| has(&k.caps()))
        .map(|k| format!("{k}s"))
        .collect();
    if kinds.len() == GlyphKind::VALUES.len() {
        return format!("Gumhold's method{with}");
    }
    let list = match kinds.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => kinds.concat(),
    };
    format!("Gumhold {list}{with}")
}

/// Named ways of drawing, shared by `render` (`--preset`), the viewer and the bench (its `path`
/// column): [`Preset::Baseline`] is the path before the work-saving options (a quad drawn for
/// every glyph in file order), [`Preset::Splat`] `render`'s default, the others one option each
/// on top of the baseline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Preset {
    /// Quads, no culling, file order.
    Baseline,
    /// The baseline with frustum culling in the vertex stage.
    Culled,
    /// The baseline with the octagon proxy.
    Octagon,
    /// The baseline with the triangle proxy.
    Triangle,
    /// The baseline with conservative depth (Gumhold ellipsoids).
    Conservative,
    /// The baseline drawn front to back.
    Sorted,
    /// The compute prepass with culling (Gumhold ellipsoids and superquadrics).
    Prepass,
    /// Splats up to [`DEFAULT_SPLAT`] pixels across from the prepass, with culling (Gumhold
    /// ellipsoids and superquadrics; other methods are culled), front to back in depth layers
    /// (the viewer draws them in file order): `render`'s and the viewer's default.
    #[default]
    Splat,
}

impl Preset {
    pub const DEFAULT: Preset = Preset::Splat;
    /// The options of this preset.
    pub fn options(self) -> DrawOptions {
        let baseline = DrawOptions {
            proxy: ProxyShape::Quad,
            conservative: false,
            prepass: false,
            splat: 0,
            cull: false,
            min_pixel_radius: 0.0,
        };
        match self {
            Preset::Baseline | Preset::Sorted => baseline,
            Preset::Culled => DrawOptions {
                cull: true,
                ..baseline
            },
            Preset::Octagon => DrawOptions {
                proxy: ProxyShape::Octagon,
                ..baseline
            },
            Preset::Triangle => DrawOptions {
                proxy: ProxyShape::Triangle,
                ..baseline
            },
            Preset::Conservative => DrawOptions {
                conservative: true,
                ..baseline
            },
            Preset::Prepass => DrawOptions {
                cull: true,
                prepass: true,
                ..baseline
            },
            Preset::Splat => DrawOptions {
                cull: true,
                splat: DEFAULT_SPLAT,
                ..baseline
            },
        }
    }

    /// Whether the instances are drawn front to back (sorted on the CPU before upload,
    /// [`crate::scene::Scene::sort_front_to_back`]): `sorted` for early depth tests, `splat` so
    /// that its compute pass meets nearer glyphs first and skips pixels they have won.
    pub fn sorts(self) -> bool {
        matches!(self, Preset::Sorted | Preset::Splat)
    }

    /// Whether this preset changes anything for `method` drawing `kind` (with depth
    /// correction) beyond what the baseline does.
    pub fn applies_to(self, method: Method, kind: GlyphKind) -> bool {
        let gumhold = method == Method::Gumhold;
        let caps = kind.caps();
        match self {
            Preset::Baseline => true,
            Preset::Culled | Preset::Octagon | Preset::Triangle | Preset::Sorted => gumhold,
            Preset::Conservative => gumhold && caps.conservative_depth,
            Preset::Prepass | Preset::Splat => gumhold && caps.prepass,
        }
    }
}

crate::names::named_values!(Preset {
    Baseline => "baseline",
    Culled => "culled",
    Octagon => "octagon",
    Triangle => "triangle",
    Conservative => "conservative",
    Sorted => "sorted",
    Prepass => "prepass",
    Splat => "splat",
});
