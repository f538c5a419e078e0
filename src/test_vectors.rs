//! The shared math test vectors (`../shared/math/test-vectors.json`) for the unit tests, and
//! the helpers that read their vectors and matrices.

use glam::{DMat3, DMat4, DVec3};
use serde_json::Value;

/// Every case of the test vectors.
pub(crate) fn cases() -> Vec<Value> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/math/test-vectors.json"
    ))
    .expect("shared/math/test-vectors.json beside the repository");
    let all: Value = serde_json::from_str(&text).unwrap();
    all["cases"].as_array().unwrap().clone()
}

/// The superquadric worked cases (`tests/data/superquadric/superquadric_vectors.json`, made at 50
/// digits by `tests/data/superquadric/make_superquadric_vectors.py`).
pub(crate) fn superquadric_vectors() -> Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/superquadric/superquadric_vectors.json"
    ))
    .unwrap();
    serde_json::from_str(&text).unwrap()
}

/// A vector `[x, y, z]`.
pub(crate) fn v3(v: &Value) -> DVec3 {
    DVec3::new(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

/// A 3x3 matrix given as rows.
pub(crate) fn m3(v: &Value) -> DMat3 {
    DMat3::from_cols(v3(&v[0]), v3(&v[1]), v3(&v[2])).transpose()
}

/// A 4x4 matrix given as 16 numbers, column by column.
pub(crate) fn m4(v: &Value) -> DMat4 {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    DMat4::from_cols_slice(&a)
}
