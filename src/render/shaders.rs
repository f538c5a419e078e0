//! WGSL sources. WGSL has no includes, so every glyph shader is composed from one list:
//! `common.wgsl`, `shape/screen_box.wgsl`, the kind's shape file(s) (the shape interface
//! documented in common.wgsl, [`crate::shape::Shape::wgsl`]), the method's file(s) and
//! `outputs.wgsl` (the shared fragment entry points) — a method × kind table, [`ShaderSource`];
//! `tests::all_shaders_validate` runs naga's validator over every composition.
//!
//! Specialisation has two kinds, each with one mechanism: what changes which WGSL is valid (an
//! entry point's attribute, 64-bit atomics) is a [`ShaderDefs`] flag, applied from the one table
//! [`SWAPS`] when the module's text is composed; values a pipeline picks (the proxy polygon,
//! conservative placement, the box baseline, a kind's general search) are WGSL `override`
//! constants set per pipeline.

use crate::shape::GlyphKind;

pub const COMMON: &str = include_str!("../../shaders/common.wgsl");
const OUTPUTS: &str = include_str!("../../shaders/outputs.wgsl");
pub(crate) const SCREEN_BOX: &str = include_str!("../../shaders/shape/screen_box.wgsl");
const GUMHOLD_ELLIPSOID: &str = include_str!("../../shaders/method/gumhold_ellipsoid.wgsl");
const GUMHOLD_SOLID: &str = include_str!("../../shaders/method/gumhold_solid.wgsl");
const SIGG: &str = include_str!("../../shaders/method/sigg.wgsl");
const MESH: &str = include_str!("../../shaders/method/mesh.wgsl");
const PREPASS: &str = include_str!("../../shaders/method/prepass.wgsl");
const SPLAT32: &str = include_str!("../../shaders/method/splat32.wgsl");
const SPLAT64: &str = include_str!("../../shaders/method/splat64.wgsl");

/// The method half of a shader.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MethodShader {
    /// Gumhold's quad: the ellipsoid's exact quad, or every other kind's bounding ellipsoid's
    /// (with the compute prepass and splats where the kind takes them).
    Gumhold,
    /// Sigg et al.'s screen boxes.
    Sigg,
    /// The triangle-mesh baselines (`mesh:N`, `box`).
    Mesh,
}

impl MethodShader {
    pub const ALL: [MethodShader; 3] = [
        MethodShader::Gumhold,
        MethodShader::Sigg,
        MethodShader::Mesh,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MethodShader::Gumhold => "gumhold",
            MethodShader::Sigg => "sigg",
            MethodShader::Mesh => "mesh",
        }
    }
}

/// A glyph shader: a method drawing a kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ShaderSource {
    pub method: MethodShader,
    pub kind: GlyphKind,
}

impl ShaderSource {
    pub fn new(method: MethodShader, kind: GlyphKind) -> Self {
        Self { method, kind }
    }

    /// Every glyph shader: each method for each kind of the registry.
    pub fn all() -> Vec<ShaderSource> {
        MethodShader::ALL
            .iter()
            .flat_map(|&m| {
                GlyphKind::VALUES
                    .iter()
                    .map(move |&k| ShaderSource::new(m, k))
            })
            .collect()
    }

    /// `method/kind`, the label of its modules and pipelines.
    pub fn name(self) -> String {
        format!("{}/{}", self.method.name(), self.kind)
    }

    /// Whether the shader reads the proxy `override`s (PROXY_VERTICES, CONSERVATIVE_DEPTH).
    pub fn has_proxy_constants(self) -> bool {
        self.method == MethodShader::Gumhold
    }

    /// The `override` keeping the kind's general search, if it has one
    /// ([`crate::shape::Shape::general_override`]).
    pub fn general_override(self) -> Option<&'static str> {
        self.kind.shape().general_override()
    }

    /// Whether the shader has the double-f32 rays of thin glyphs (`THIN_EXACT`: the ray
    /// casters, Gumhold's and Sigg's, splats included; common.wgsl's `thin_pixel_ray`).
    pub fn has_thin_path(self) -> bool {
        self.method != MethodShader::Mesh
    }

    /// Whether this is Gumhold's ellipsoid, whose exact quad is a method file of its own.
    fn exact_quad(self) -> bool {
        self.method == MethodShader::Gumhold && self.kind == GlyphKind::Ellipsoid
    }

    /// The composed source, specialised by `defs`.
    pub fn text_with(self, defs: ShaderDefs) -> String {
        let mut text = self.text();
        // A def changes the shaders that have its text (splats are Gumhold's).
        for (on, from, to) in SWAPS {
            if on(&defs) {
                text = text.replace(from, to);
            }
        }
        text
    }

    pub fn text(self) -> String {
        let shape = self.kind.shape();
        let mut parts: Vec<&str> = vec![COMMON, SCREEN_BOX];
        parts.extend(shape.wgsl());
        match self.method {
            MethodShader::Gumhold if self.exact_quad() => {
                parts.extend([GUMHOLD_ELLIPSOID, PREPASS, SPLAT32])
            }
            MethodShader::Gumhold => {
                parts.push(GUMHOLD_SOLID);
                if let Some(splats) = shape.splat_wgsl().filter(|_| shape.caps().prepass) {
                    parts.extend([splats, PREPASS, SPLAT32]);
                }
            }
            MethodShader::Sigg => parts.push(SIGG),
            MethodShader::Mesh => parts.push(MESH),
        }
        parts.push(OUTPUTS);
        parts.join("\n")
    }
}

/// Module-level variants of a shader (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ShaderDefs {
    /// The depth-writing fragment entry points declared `@early_depth_test(greater_equal)`: the
    /// written depth is never less than the rasterised one (conservative proxies).
    pub early_depth: bool,
    /// Gumhold ellipsoids' and superquadrics' splats keep depth and id in one 64-bit atomic per
    /// pixel (splat64.wgsl) instead of two 32-bit passes (splat32.wgsl).
    pub int64_atomics: bool,
}

/// Every shader def: when it is on, this text of the composition is replaced by that one.
type Swap = (fn(&ShaderDefs) -> bool, &'static str, &'static str);
pub const SWAPS: [Swap; 2] = [
    (|d| d.int64_atomics, SPLAT32, SPLAT64),
    (
        |d| d.early_depth,
        "@fragment\nfn fs_depth",
        "@fragment @early_depth_test(greater_equal)\nfn fs_depth",
    ),
];

/// Parse WGSL with naga (the same front end wgpu uses). Not in the web build, where wgpu hands
/// WGSL to the browser, which compiles it itself (naga's front end would only add weight).
#[cfg(not(target_arch = "wasm32"))]
pub fn parse(text: &str) -> Result<wgpu::naga::Module, String> {
    wgpu::naga::front::wgsl::parse_str(text).map_err(|e| e.emit_to_string(text))
}

/// Parse and validate with every capability wgpu may use.
#[cfg(not(target_arch = "wasm32"))]
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
        for s in ShaderSource::all() {
            for early in [false, true] {
                for int64 in [false, true] {
                    let defs = ShaderDefs {
                        early_depth: early,
                        int64_atomics: int64,
                    };
                    if let Err(e) = validate(&s.text_with(defs)) {
                        panic!(
                            "{} (early depth {early}, 64-bit atomics {int64}) does not validate:\n{e}",
                            s.name()
                        );
                    }
                }
            }
        }
    }

    /// common.wgsl's constants that the CPU twins share have the CPU's values.
    #[test]
    fn shared_constants_match_the_cpu() {
        let m = wgpu::naga::front::wgsl::parse_str(COMMON).unwrap();
        let value = |name: &str| {
            let (_, c) = m
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("{name} in common.wgsl"));
            match m.global_expressions[c.init] {
                Expression::Literal(wgpu::naga::Literal::F32(v)) => v,
                ref e => panic!("{name} = {e:?}"),
            }
        };
        assert_eq!(value("THIN_RATIO"), crate::shape::geometry::THIN_RATIO);
        assert_eq!(value("QUAT_STEP"), crate::shape::geometry::QUAT_STEP);
    }

    use wgpu::naga::{AddressSpace, Block, Expression, Function, Handle, Module, Statement};

    /// What `e` in `f` depends on: `None` if on something varying, else whether on some
    /// uniform-buffer word at a fixed offset (beside constants). `Some(true)` deciding an `if` is
    /// what lavapipe inlines (flag_index in shaders/common.wgsl). Arguments and local variables
    /// count as varying, so this sees the direct cases only (a uniform passed through an argument
    /// or a local is missed).
    fn uniform_words(m: &Module, f: &Function, e: Handle<Expression>, depth: u32) -> Option<bool> {
        use Expression as E;
        if depth > 64 {
            return None;
        }
        let all = |xs: &[Handle<Expression>]| {
            xs.iter().try_fold(false, |any, &x| {
                uniform_words(m, f, x, depth + 1).map(|u| any || u)
            })
        };
        match f.expressions[e] {
            E::Literal(_) | E::Constant(_) | E::Override(_) | E::ZeroValue(_) => Some(false),
            E::GlobalVariable(g) => {
                (m.global_variables[g].space == AddressSpace::Uniform).then_some(true)
            }
            E::AccessIndex { base, .. } => all(&[base]),
            E::Access { base, index } => match f.expressions[index] {
                E::Literal(_) | E::Constant(_) => all(&[base]),
                _ => None,
            },
            E::Load { pointer } => all(&[pointer]),
            E::Unary { expr, .. } | E::As { expr, .. } => all(&[expr]),
            E::Binary { left, right, .. } => all(&[left, right]),
            E::Select {
                condition,
                accept,
                reject,
            } => all(&[condition, accept, reject]),
            E::Relational { argument, .. } => all(&[argument]),
            E::Math {
                arg,
                arg1,
                arg2,
                arg3,
                ..
            } => all(&[Some(arg), arg1, arg2, arg3]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()),
            E::Splat { value, .. } => all(&[value]),
            E::Swizzle { vector, .. } => all(&[vector]),
            E::Compose { ref components, .. } => all(components),
            E::CallResult(g) => {
                let g = &m.functions[g];
                let mut values = Vec::new();
                returns(&g.body, &mut values);
                if values.is_empty() {
                    return None;
                }
                values.into_iter().try_fold(false, |any, v| {
                    uniform_words(m, g, v, depth + 1).map(|u| any || u)
                })
            }
            _ => None,
        }
    }

    /// Every statement of `block`, nested ones included, in order.
    fn visit(block: &Block, each: &mut dyn FnMut(&Statement)) {
        for s in block.iter() {
            each(s);
            match s {
                Statement::Block(b) => visit(b, each),
                Statement::If { accept, reject, .. } => {
                    visit(accept, each);
                    visit(reject, each);
                }
                Statement::Loop {
                    body, continuing, ..
                } => {
                    visit(body, each);
                    visit(continuing, each);
                }
                Statement::Switch { cases, .. } => cases.iter().for_each(|c| visit(&c.body, each)),
                _ => {}
            }
        }
    }

    /// The values `block` returns.
    fn returns(block: &Block, out: &mut Vec<Handle<Expression>>) {
        visit(block, &mut |s| {
            if let Statement::Return { value: Some(v) } = s {
                out.push(*v);
            }
        });
    }

    /// The conditions in `block` (of `f`) that uniform words alone decide.
    fn uniform_conditions(m: &Module, f: &Function, block: &Block, out: &mut Vec<String>) {
        visit(block, &mut |s| {
            let condition = match s {
                Statement::If { condition, .. } => Some(*condition),
                Statement::Loop { break_if, .. } => *break_if,
                Statement::Switch { selector, .. } => Some(*selector),
                _ => None,
            };
            if let Some(c) = condition.filter(|&c| uniform_words(m, f, c, 0) == Some(true)) {
                out.push(format!("{:?}", f.expressions[c]));
            }
        });
    }

    /// Every function's conditions that uniform words alone decide, named by function.
    fn uniform_decided(text: &str) -> Vec<String> {
        let m = parse(text).expect("parses");
        let functions = m.functions.iter().map(|(_, f)| f);
        let entries = m.entry_points.iter().map(|e| &e.function);
        let mut found = Vec::new();
        for f in functions.chain(entries) {
            let mut out = Vec::new();
            uniform_conditions(&m, f, &f.body, &mut out);
            let name = f.name.as_deref().unwrap_or("?");
            found.extend(out.into_iter().map(|c| format!("{name}: {c}")));
        }
        found
    }

    #[test]
    fn the_uniform_condition_finder_finds_them() {
        let text = "struct U { v: vec4<f32>, n: u32 }
            @group(0) @binding(0) var<uniform> u: U;
            fn flag() -> bool { return u.v.w > 0.5; }
            fn hidden() -> bool { return u.v[3u + u32(u.v.w > 2.0)] > 0.5; }
            @compute @workgroup_size(1) fn main(@builtin(global_invocation_id) id: vec3<u32>) {
                var x = 0u;
                if flag() { x = 1u; }
                if u.n > 2u { x = 2u; }
                if hidden() { x = 3u; }
                if id.x > u.n { x = 4u; }
            }";
        let found = uniform_decided(text);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert!(found.iter().all(|f| f.starts_with("main: ")));
    }

    #[test]
    fn no_if_decided_by_uniform_words_alone() {
        for s in ShaderSource::all() {
            for int64 in [false, true] {
                let defs = ShaderDefs {
                    int64_atomics: int64,
                    ..ShaderDefs::default()
                };
                let found = uniform_decided(&s.text_with(defs));
                assert!(found.is_empty(), "{}: {found:#?}", s.name());
            }
        }
    }

    #[test]
    fn early_depth_declared_on_both_depth_entry_points() {
        let text =
            ShaderSource::new(MethodShader::Gumhold, GlyphKind::Ellipsoid).text_with(ShaderDefs {
                early_depth: true,
                ..ShaderDefs::default()
            });
        assert_eq!(text.matches("@early_depth_test(greater_equal)").count(), 3);
        let module = parse(&text).expect("parses");
        let declared = module
            .entry_points
            .iter()
            .filter(|e| e.early_depth_test.is_some())
            .map(|e| e.name.as_str())
            .collect::<Vec<_>>();
        assert_eq!(declared, ["fs_depth", "fs_depth_aux", "fs_depth_normal"]);
    }
}
