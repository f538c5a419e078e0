//! WGSL sources. WGSL has no includes, so every method's shader is `common.wgsl`, the shared
//! parts it needs (`cylinder_slab.wgsl` for cylinders, `capsule.wgsl` for capsules,
//! `superquadric.wgsl` for the ray-cast superquadrics, `superquadric_mesh.wgsl` for the
//! tessellated ones, `sigg.wgsl` for Sigg's method), its own
//! file and `outputs.wgsl` (the shared fragment entry points); `tests::all_shaders_validate`
//! runs naga's validator over each composition.
//!
//! Specialisation has two kinds, each with one mechanism: what changes which WGSL is valid (an
//! entry point's attribute, 64-bit atomics) is a [`ShaderDefs`] flag, applied from the one table
//! [`SWAPS`] when the module's text is composed; values a pipeline picks (the proxy polygon,
//! conservative placement, the mesh's glyph shape) are WGSL `override` constants set per
//! pipeline.

pub const COMMON: &str = include_str!("../../shaders/common.wgsl");
const OUTPUTS: &str = include_str!("../../shaders/outputs.wgsl");
const GUMHOLD_ELLIPSOID: &str = include_str!("../../shaders/gumhold_ellipsoid.wgsl");
const GUMHOLD_CYLINDER: &str = include_str!("../../shaders/gumhold_cylinder.wgsl");
const MESH: &str = include_str!("../../shaders/mesh.wgsl");
const CYLINDER_SLAB: &str = include_str!("../../shaders/cylinder_slab.wgsl");
const SIGG: &str = include_str!("../../shaders/sigg.wgsl");
const SIGG_ELLIPSOID: &str = include_str!("../../shaders/sigg_ellipsoid.wgsl");
const SIGG_CYLINDER: &str = include_str!("../../shaders/sigg_cylinder.wgsl");
const CAPSULE: &str = include_str!("../../shaders/capsule.wgsl");
const GUMHOLD_CAPSULE: &str = include_str!("../../shaders/gumhold_capsule.wgsl");
const GUMHOLD_SOLID: &str = include_str!("../../shaders/gumhold_solid.wgsl");
const SIGG_CAPSULE: &str = include_str!("../../shaders/sigg_capsule.wgsl");
const SUPERQUADRIC: &str = include_str!("../../shaders/superquadric.wgsl");
const SUPERQUADRIC_MESH: &str = include_str!("../../shaders/superquadric_mesh.wgsl");
const GUMHOLD_SUPERQUADRIC: &str = include_str!("../../shaders/gumhold_superquadric.wgsl");
const SIGG_SUPERQUADRIC: &str = include_str!("../../shaders/sigg_superquadric.wgsl");
const SUPERQUADRIC_SPLAT: &str = include_str!("../../shaders/superquadric_splat.wgsl");
const PREPASS: &str = include_str!("../../shaders/prepass.wgsl");
const SPLAT32: &str = include_str!("../../shaders/splat32.wgsl");
const SPLAT64: &str = include_str!("../../shaders/splat64.wgsl");

/// A method's complete shader source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderSource {
    GumholdEllipsoid,
    GumholdCylinder,
    SiggEllipsoid,
    SiggCylinder,
    GumholdCapsule,
    SiggCapsule,
    GumholdSuperquadric,
    SiggSuperquadric,
    /// The triangle-mesh baselines (`mesh:N`, `box`), every glyph shape.
    Mesh,
}

impl ShaderSource {
    pub const ALL: [ShaderSource; 9] = [
        ShaderSource::GumholdEllipsoid,
        ShaderSource::GumholdCylinder,
        ShaderSource::SiggEllipsoid,
        ShaderSource::SiggCylinder,
        ShaderSource::GumholdCapsule,
        ShaderSource::SiggCapsule,
        ShaderSource::GumholdSuperquadric,
        ShaderSource::SiggSuperquadric,
        ShaderSource::Mesh,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ShaderSource::GumholdEllipsoid => "gumhold_ellipsoid.wgsl",
            ShaderSource::GumholdCylinder => "gumhold_cylinder.wgsl",
            ShaderSource::SiggEllipsoid => "sigg_ellipsoid.wgsl",
            ShaderSource::SiggCylinder => "sigg_cylinder.wgsl",
            ShaderSource::GumholdCapsule => "gumhold_capsule.wgsl",
            ShaderSource::SiggCapsule => "sigg_capsule.wgsl",
            ShaderSource::GumholdSuperquadric => "gumhold_superquadric.wgsl",
            ShaderSource::SiggSuperquadric => "sigg_superquadric.wgsl",
            ShaderSource::Mesh => "mesh.wgsl",
        }
    }

    /// Whether the shader reads the proxy `override`s (PROXY_VERTICES, CONSERVATIVE_DEPTH).
    pub fn has_proxy_constants(self) -> bool {
        matches!(
            self,
            ShaderSource::GumholdEllipsoid
                | ShaderSource::GumholdCylinder
                | ShaderSource::GumholdCapsule
                | ShaderSource::GumholdSuperquadric
        )
    }

    /// Whether the shader ray casts superquadrics (and has their `SQ_GENERAL` override).
    pub fn is_superquadric(self) -> bool {
        matches!(
            self,
            ShaderSource::GumholdSuperquadric | ShaderSource::SiggSuperquadric
        )
    }

    /// The composed source, specialised by `defs`.
    pub fn text_with(self, defs: ShaderDefs) -> String {
        let mut text = self.text();
        // A def changes the shaders that have its text (splats are Gumhold ellipsoids' and
        // superquadrics').
        for (on, from, to) in SWAPS {
            if on(&defs) {
                text = text.replace(from, to);
            }
        }
        text
    }

    pub fn text(self) -> String {
        let parts: &[&str] = match self {
            ShaderSource::GumholdEllipsoid => &[GUMHOLD_ELLIPSOID, PREPASS, SPLAT32],
            ShaderSource::GumholdCylinder => &[CYLINDER_SLAB, GUMHOLD_CYLINDER, GUMHOLD_SOLID],
            ShaderSource::SiggEllipsoid => &[SIGG, SIGG_ELLIPSOID],
            ShaderSource::SiggCylinder => &[CYLINDER_SLAB, SIGG, SIGG_CYLINDER],
            ShaderSource::GumholdCapsule => &[CAPSULE, GUMHOLD_CAPSULE, GUMHOLD_SOLID],
            ShaderSource::SiggCapsule => &[CAPSULE, SIGG, SIGG_CAPSULE],
            ShaderSource::GumholdSuperquadric => &[
                SUPERQUADRIC,
                GUMHOLD_SUPERQUADRIC,
                GUMHOLD_SOLID,
                SUPERQUADRIC_SPLAT,
                PREPASS,
                SPLAT32,
            ],
            ShaderSource::SiggSuperquadric => &[SUPERQUADRIC, SIGG, SIGG_SUPERQUADRIC],
            ShaderSource::Mesh => &[CAPSULE, SUPERQUADRIC_MESH, MESH],
        };
        let body = parts.join("\n");
        format!("{COMMON}\n{body}\n{OUTPUTS}")
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
        for s in ShaderSource::ALL {
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
        let text = ShaderSource::GumholdEllipsoid.text_with(ShaderDefs {
            early_depth: true,
            ..ShaderDefs::default()
        });
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
