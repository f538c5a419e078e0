//! WGSL sources. WGSL has no includes, so every method's shader is `common.wgsl`, the shared
//! parts it needs (`cylinder_slab.wgsl` for cylinders, `sigg.wgsl` for Sigg's method), its own
//! file and `outputs.wgsl` (the shared fragment entry points); [`tests::all_shaders_validate`]
//! runs naga's validator over each composition.

pub const COMMON: &str = include_str!("../../shaders/common.wgsl");
const OUTPUTS: &str = include_str!("../../shaders/outputs.wgsl");
const GUMHOLD_ELLIPSOID: &str = include_str!("../../shaders/gumhold_ellipsoid.wgsl");
const GUMHOLD_CYLINDER: &str = include_str!("../../shaders/gumhold_cylinder.wgsl");
const MESH: &str = include_str!("../../shaders/mesh.wgsl");
const CYLINDER_SLAB: &str = include_str!("../../shaders/cylinder_slab.wgsl");
const SIGG: &str = include_str!("../../shaders/sigg.wgsl");
const SIGG_ELLIPSOID: &str = include_str!("../../shaders/sigg_ellipsoid.wgsl");
const SIGG_CYLINDER: &str = include_str!("../../shaders/sigg_cylinder.wgsl");
const SPLAT32: &str = include_str!("../../shaders/splat32.wgsl");
const SPLAT64: &str = include_str!("../../shaders/splat64.wgsl");

/// A method's complete shader source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderSource {
    GumholdEllipsoid,
    GumholdCylinder,
    SiggEllipsoid,
    SiggCylinder,
    /// The triangle-mesh baselines (`mesh:N`, `box`), every glyph shape.
    Mesh,
}

impl ShaderSource {
    pub const ALL: [ShaderSource; 5] = [
        ShaderSource::GumholdEllipsoid,
        ShaderSource::GumholdCylinder,
        ShaderSource::SiggEllipsoid,
        ShaderSource::SiggCylinder,
        ShaderSource::Mesh,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ShaderSource::GumholdEllipsoid => "gumhold_ellipsoid.wgsl",
            ShaderSource::GumholdCylinder => "gumhold_cylinder.wgsl",
            ShaderSource::SiggEllipsoid => "sigg_ellipsoid.wgsl",
            ShaderSource::SiggCylinder => "sigg_cylinder.wgsl",
            ShaderSource::Mesh => "mesh.wgsl",
        }
    }

    /// Whether the shader reads the proxy `override`s (PROXY_VERTICES, CONSERVATIVE_DEPTH).
    pub fn has_proxy_constants(self) -> bool {
        matches!(
            self,
            ShaderSource::GumholdEllipsoid | ShaderSource::GumholdCylinder
        )
    }

    /// The source with the depth-writing fragment entry points declared conservative
    /// (`@early_depth_test(greater_equal)`: the written depth is never less than the
    /// rasterised one), for pipelines whose proxy guarantees that.
    pub fn text_with(self, early_depth: bool) -> String {
        self.text_for(early_depth, false)
    }

    /// [`Self::text_with`], and with `int64_atomics` Gumhold ellipsoids' splats use one 64-bit
    /// atomic per pixel (splat64.wgsl) instead of two 32-bit passes (splat32.wgsl).
    pub fn text_for(self, early_depth: bool, int64_atomics: bool) -> String {
        let mut text = self.text();
        if int64_atomics && self == ShaderSource::GumholdEllipsoid {
            text = text.replace(SPLAT32, SPLAT64);
        }
        if early_depth {
            text.replace(
                "@fragment\nfn fs_depth",
                "@fragment @early_depth_test(greater_equal)\nfn fs_depth",
            )
        } else {
            text
        }
    }

    pub fn text(self) -> String {
        let parts: &[&str] = match self {
            ShaderSource::GumholdEllipsoid => &[GUMHOLD_ELLIPSOID, SPLAT32],
            ShaderSource::GumholdCylinder => &[CYLINDER_SLAB, GUMHOLD_CYLINDER],
            ShaderSource::SiggEllipsoid => &[SIGG, SIGG_ELLIPSOID],
            ShaderSource::SiggCylinder => &[CYLINDER_SLAB, SIGG, SIGG_CYLINDER],
            ShaderSource::Mesh => &[MESH],
        };
        let body = parts.join("\n");
        format!("{COMMON}\n{body}\n{OUTPUTS}")
    }
}

/// Parse WGSL with naga (the same front end wgpu uses).
pub fn parse(text: &str) -> Result<wgpu::naga::Module, String> {
    wgpu::naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))
}

/// Parse and validate with every capability wgpu may use.
pub fn validate(text: &str) -> Result<(), String> {
    use wgpu::naga::valid::{Capabilities, ValidationFlags, Validator};
    let module = parse(text)?;
    Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map(|_| ())
        .map_err(|e| e.emit_to_string(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_shaders_validate() {
        for s in ShaderSource::ALL {
            for early in [false, true] {
                for int64 in [false, true] {
                    if let Err(e) = validate(&s.text_for(early, int64)) {
                        panic!(
                            "{} (early depth {early}, 64-bit atomics {int64}) does not validate:\n{e}",
                            s.name()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn early_depth_declared_on_both_depth_entry_points() {
        let text = ShaderSource::GumholdEllipsoid.text_with(true);
        assert_eq!(text.matches("@early_depth_test(greater_equal)").count(), 2);
        let module = parse(&text).expect("parses");
        let declared = module
            .entry_points
            .iter()
            .filter(|e| e.early_depth_test.is_some())
            .map(|e| e.name.as_str())
            .collect::<Vec<_>>();
        assert_eq!(declared, ["fs_depth", "fs_depth_aux"]);
    }
}
