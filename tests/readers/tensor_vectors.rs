//! Every `tensors` case of the shared test vectors (`../shared/math/test-vectors.json`), through
//! the f64 math (1e-9, scaled by max |λ| for eigenvalue-derived values) and through the glyph
//! pipeline (f32 glyph data: ~1e-6 relative).

#![allow(clippy::needless_range_loop)] // index-parallel comparisons of small arrays
use serde_json::Value;
use tensorglyph::field::{DatasetKind, Location, Positions, TensorArrayInfo, TensorField};
use tensorglyph::glyph::{ColorScheme, GlyphStyle, Normalize, Scale, derive_glyphs};
use tensorglyph::info::canonical_sign;
use tensorglyph::tensor::eigen::{quat_to_frame, symmetric_eigen, symmetrise};
use tensorglyph::tensor::shape;

const VECTORS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/math/test-vectors.json"
);

fn cases() -> Vec<Value> {
    let text =
        std::fs::read_to_string(VECTORS).unwrap_or_else(|e| panic!("cannot read {VECTORS}: {e}"));
    let v: Value = serde_json::from_str(&text).expect("test-vectors.json is not JSON");
    let cases = v["tensors"].as_array().expect("no tensors section").clone();
    assert_eq!(cases.len(), 8, "expected 8 tensor cases");
    cases
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vec3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [f(&a[0]), f(&a[1]), f(&a[2])]
}

fn mat(v: &Value) -> [f64; 9] {
    let rows = v.as_array().unwrap();
    let mut t = [0.0; 9];
    for r in 0..3 {
        let row = vec3(&rows[r]);
        t[3 * r..3 * r + 3].copy_from_slice(&row);
    }
    t
}

fn assert_close(got: f64, want: f64, tol: f64, what: &str, id: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{id}: {what}: got {got}, want {want} (tol {tol})"
    );
}

fn single_field(t: [f64; 9]) -> TensorField {
    TensorField {
        format: "test".into(),
        dataset: DatasetKind::PolyData,
        dims: None,
        points: 1,
        cells: 0,
        array: TensorArrayInfo {
            name: "t".into(),
            components: 9,
            location: Location::Point,
        },
        positions: Positions::Points(vec![[0.5, -1.0, 2.0]]),
        tensors: vec![t].into(),
        direction: None,
        spacing: None,
        meta: Default::default(),
    }
}

#[test]
fn test_vector_tensors() {
    for case in cases() {
        let id = case["id"].as_str().unwrap();
        let x = &case["expected"];
        let raw = mat(&case["tensor"]);
        let (t, _) = symmetrise(&raw);
        let e = symmetric_eigen(&t);
        let want_ev = vec3(&x["eigenvalues"]);
        let scale = want_ev.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let tol = 1e-9 * scale.max(f64::MIN_POSITIVE);

        // eigenvalues, trace, MD, magnitudes
        for k in 0..3 {
            assert_close(e.values[k], want_ev[k], tol, &format!("λ{}", k + 1), id);
        }
        assert_close(
            e.values.iter().sum(),
            f(&x["trace"]),
            3.0 * tol,
            "trace",
            id,
        );
        assert_close(shape::md(e.values), f(&x["md"]), tol, "md", id);
        let mags = shape::magnitudes_desc(e.values);
        let want_mags = vec3(&x["magnitudes_desc"]);
        for k in 0..3 {
            assert_close(mags[k], want_mags[k], tol, "magnitude", id);
        }
        // FA from eigenvalues and from the tensor
        assert_close(shape::fa(e.values), f(&x["fa"]), 1e-9, "fa", id);
        assert_close(
            shape::fa_of_tensor(&t),
            f(&x["fa"]),
            1e-9,
            "fa (tensor)",
            id,
        );

        // eigenvectors where defined, up to sign (expected: largest component positive)
        for (k, want) in x["eigenvectors"].as_array().unwrap().iter().enumerate() {
            if want.is_null() {
                continue;
            }
            let got = canonical_sign(e.vectors[k]);
            let want = vec3(want);
            for c in 0..3 {
                assert_close(got[c], want[c], 1e-9, &format!("e{}[{c}]", k + 1), id);
            }
        }

        // Westin measures (null for the zero tensor)
        for (key, w) in [
            ("westin_lambda1", shape::westin(e.values)),
            ("westin_trace", shape::westin_trace(e.values)),
        ] {
            if x[key].is_null() {
                assert!(w.is_none(), "{id}: {key} should be undefined");
                continue;
            }
            let w = w.unwrap_or_else(|| panic!("{id}: {key} undefined"));
            for (name, got) in [("cl", w.cl), ("cp", w.cp), ("cs", w.cs)] {
                assert_close(got, f(&x[key][name]), 1e-9, &format!("{key}.{name}"), id);
            }
        }

        // class and its colour
        let class = shape::classify(e.values, 0.5);
        assert_eq!(
            class.glyph_name(),
            x["class_tau_0.5"].as_str().unwrap(),
            "{id}: class"
        );
        assert_eq!(class.color(), vec3(&x["class_color"]), "{id}: class colour");

        // barycentric colours where given
        if let Some(b) = x.get("barycentric_color") {
            let got = shape::barycentric_color(e.values, false);
            let want = vec3(b);
            for c in 0..3 {
                assert_close(got[c], want[c], 1e-9, "barycentric", id);
            }
            let got = shape::barycentric_color(e.values, true);
            let want = vec3(&x["barycentric_color_max1"]);
            for c in 0..3 {
                assert_close(got[c], want[c], 1e-9, "barycentric max1", id);
            }
        }

        // DEC colour (f64)
        let major = shape::major_index(e.values);
        if !x["dec_color"].is_null() {
            let got = shape::dec_color(e.values, e.vectors[major]);
            let want = vec3(&x["dec_color"]);
            for c in 0..3 {
                assert_close(got[c], want[c], 1e-9, "dec colour", id);
            }
        }

        // quadratic form sample s = dᵀ T d / max|λ|
        if let Some(q) = x.get("quadratic_form_sample") {
            let d = vec3(&q["direction"]);
            let td: [f64; 3] = std::array::from_fn(|r| (0..3).map(|c| t[3 * r + c] * d[c]).sum());
            let s = (0..3).map(|k| d[k] * td[k]).sum::<f64>() / scale;
            assert_close(s, f(&q["value"]), 1e-9, "quadratic form", id);
        }

        // ---- through the glyph pipeline (f32 glyph data) ----
        let set = derive_glyphs(&single_field(raw), &tensorglyph::progress::Silent);
        if x["glyph_radii_eps1e-3"].is_null() {
            assert_eq!(
                set.stats.skipped_zero, 1,
                "{id}: zero tensor must be skipped"
            );
            assert!(set.glyphs.is_empty());
            continue;
        }
        assert_eq!(set.glyphs.len(), 1, "{id}: one glyph");
        let g = &set.glyphs[0];
        assert_eq!(g.centre, [0.5, -1.0, 2.0]);
        for k in 0..3 {
            assert_close(
                f64::from(g.eigenvalues[k]),
                want_ev[k],
                1e-6 * scale,
                "glyph λ",
                id,
            );
        }
        let style = GlyphStyle {
            scale: Scale::Factor(1.0),
            normalize: Normalize::None,
            min_radius: Some(1e-3),
            ..GlyphStyle::default()
        };
        let rs = style.resolve(&set, 1.0);
        let radii = rs.radii(g).map(f64::from);
        // Expected radii are listed by magnitude (descending); ours are in frame order.
        let mut sorted = radii;
        sorted.sort_by(|a, b| b.total_cmp(a));
        let want_r = vec3(&x["glyph_radii_eps1e-3"]);
        for k in 0..3 {
            assert_close(sorted[k], want_r[k], 1e-6 * want_r[0], "radius", id);
        }
        // The glyph matrix O diag(r) Oᵀ from the f32 quaternion and frame-order radii.
        let frame = quat_to_frame(g.rotation);
        let want_m = mat(&x["glyph_matrix"]);
        for r in 0..3 {
            for c in 0..3 {
                let got: f64 = (0..3).map(|k| radii[k] * frame[k][r] * frame[k][c]).sum();
                assert_close(got, want_m[3 * r + c], 2e-6 * want_r[0], "glyph matrix", id);
            }
        }
        // Colours through ResolvedStyle (RGBA8, ±1 for rounding of the f32 path).
        let with = |color| {
            GlyphStyle {
                color,
                ..style.clone()
            }
            .resolve(&set, 1.0)
        };
        let q = |v: f64| (v * 255.0).round() as i32;
        let shape_rgba = with(ColorScheme::Shape).color(g);
        let cc = vec3(&x["class_color"]);
        assert_eq!(
            shape_rgba,
            [q(cc[0]) as u8, q(cc[1]) as u8, q(cc[2]) as u8, 255],
            "{id}: shape colour"
        );
        if !x["dec_color"].is_null() {
            let got = with(ColorScheme::Dec).color(g);
            let want = vec3(&x["dec_color"]);
            for c in 0..3 {
                assert!(
                    (i32::from(got[c]) - q(want[c])).abs() <= 1,
                    "{id}: dec rgba {got:?} vs {want:?}"
                );
            }
        }
    }
}
