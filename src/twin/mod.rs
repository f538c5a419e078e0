//! CPU twins of the shaders, one file per WGSL file and with its name: the same formulas in
//! f64 (with the math notes' names), so each shader's arithmetic can be checked against
//! `shared/math/test-vectors.json` without a GPU, and so the reference and the tests can
//! predict what a shader does (its proxies, its fragment counts, its shading). The exception is
//! `superquadric`, in f32 like its shader: it twins a root finder, whose iterations, caps and
//! answers depend on the precision.

pub mod capsule;
pub mod common;
pub mod composite;
pub mod gumhold_ellipsoid;
pub mod sigg;
pub mod superquadric;
