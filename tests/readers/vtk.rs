//! The VTK reader against VTK's own read-back values (tests/data/vtk/expected.json, written by
//! tests/data/vtk/make_vtk_files.py with Debian's VTK 9.1).

use std::path::{Path, PathBuf};

use serde_json::Value;
use tensorglyph::error::LoadErrorKind;
use tensorglyph::field::vtk::{ReadOptions, read_field};
use tensorglyph::field::{ComponentOrder, Location};

fn data_dir() -> PathBuf {
    crate::data::path("vtk")
}

fn expected() -> serde_json::Map<String, Value> {
    let text = std::fs::read_to_string(data_dir().join("expected.json")).unwrap();
    match serde_json::from_str(&text).unwrap() {
        Value::Object(m) => m,
        _ => panic!("expected.json is not an object"),
    }
}

fn num(v: &Value) -> f64 {
    match v {
        Value::String(s) if s == "nan" => f64::NAN,
        v => v.as_f64().unwrap(),
    }
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    if want.is_nan() {
        return got.is_nan();
    }
    if rel == 0.0 {
        // Exact: the very value VTK read (float32 arrays stay exact in f64).
        return got == want;
    }
    (got - want).abs() <= rel * want.abs().max(1e-3)
}

fn opts(array: Option<&str>) -> ReadOptions {
    ReadOptions {
        array: array.map(str::to_string),
        order: Some(ComponentOrder::Vtk),
        ..ReadOptions::default()
    }
}

/// Check one array of one file against VTK's values.
fn check_array(file: &str, e: &Value, arr: &Value, by_name: bool) {
    let path = data_dir().join(file);
    let name = arr["name"].as_str().unwrap();
    let f = read_field(&path, &opts(by_name.then_some(name)))
        .unwrap_or_else(|err| panic!("{file} ({name}): {err}"));
    let ctx = format!("{file} array {name}");
    assert_eq!(f.format, e["format"].as_str().unwrap(), "{ctx}");
    assert_eq!(f.dataset.as_str(), e["dataset"].as_str().unwrap(), "{ctx}");
    assert_eq!(f.points as u64, e["points"].as_u64().unwrap(), "{ctx}");
    assert_eq!(f.cells as u64, e["cells"].as_u64().unwrap(), "{ctx}");
    let dims = e["dims"]
        .as_array()
        .map(|d| [0, 1, 2].map(|a| d[a].as_u64().unwrap() as usize));
    assert_eq!(f.dims, dims, "{ctx}");
    assert_eq!(f.array.name, name, "{ctx}");
    assert_eq!(
        f.array.components as u64,
        arr["components"].as_u64().unwrap(),
        "{ctx}"
    );
    let loc = match arr["location"].as_str().unwrap() {
        "point" => Location::Point,
        _ => Location::Cell,
    };
    assert_eq!(f.array.location, loc, "{ctx}");
    assert_eq!(f.len() as u64, arr["tuples"].as_u64().unwrap(), "{ctx}");
    assert_eq!(f.positions.len(), f.tensors.len(), "{ctx}");
    let ascii = f.format == "legacy-ascii";
    let trel = if ascii { 1e-6 } else { 0.0 };
    let prel = if ascii { 1e-6 } else { 1e-9 };
    for s in arr["samples"].as_array().unwrap() {
        let i = s["index"].as_u64().unwrap() as usize;
        let p = s["position"].as_array().unwrap();
        for a in 0..3 {
            assert!(
                close(f.position(i)[a], num(&p[a]), prel),
                "{ctx} position {i}: {:?} vs {p:?}",
                f.position(i)
            );
        }
        let t = s["tensor"].as_array().unwrap();
        for k in 0..9 {
            assert!(
                close(f.tensor(i)[k], num(&t[k]), trel),
                "{ctx} tensor {i}[{k}]: {:?} vs {t:?}",
                f.tensor(i)
            );
        }
    }
    if let Some(sp) = e.get("spacing") {
        let want = sp
            .as_array()
            .unwrap()
            .iter()
            .map(num)
            .filter(|s| *s > 0.0)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(f.spacing, Some(want), "{ctx}");
        let d = &e["direction"];
        let identity =
            (0..3).all(|i| (0..3).all(|j| num(&d[i][j]) == if i == j { 1.0 } else { 0.0 }));
        if !identity {
            let r = f.direction.unwrap_or_else(|| panic!("{ctx}: no direction"));
            for i in 0..3 {
                for j in 0..3 {
                    assert!(close(r[i][j], num(&d[i][j]), 1e-12), "{ctx}: direction");
                }
            }
        }
    }
}

#[test]
fn every_file_matches_vtk() {
    let exp = expected();
    assert!(exp.len() >= 90, "only {} files", exp.len());
    for (file, e) in &exp {
        let arrays = e["arrays"].as_array().unwrap();
        let default = e["default"]
            .as_str()
            .expect("every test file has a tensor array");
        let d = arrays.iter().find(|a| a["name"] == default).unwrap();
        check_array(file, e, d, false);
        for a in arrays {
            check_array(file, e, a, true);
        }
    }
}

#[test]
fn all_formats_and_kinds_are_covered() {
    let exp = expected();
    for fmt in [
        "legacy-ascii",
        "legacy-binary",
        "vti",
        "vtr",
        "vts",
        "vtu",
        "vtp",
        "pvti",
    ] {
        assert!(exp.values().any(|e| e["format"] == fmt), "{fmt}");
    }
    for ds in [
        "ImageData",
        "RectilinearGrid",
        "StructuredGrid",
        "UnstructuredGrid",
        "PolyData",
    ] {
        for loc in ["point", "cell"] {
            assert!(
                exp.values().any(|e| e["dataset"] == ds
                    && e["arrays"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .any(|a| a["location"] == loc)),
                "{ds} {loc}"
            );
        }
    }
}

#[test]
fn rectilinear_spacing_is_smallest_step() {
    let f = read_field(
        &data_dir().join("xml_rect_binary_none_u32.vtr"),
        &opts(None),
    )
    .unwrap();
    assert_eq!(
        f.spacing,
        Some((0.3f32 as f64 - 0.0).min(1.2f32 as f64 - 1.0f32 as f64))
    );
    let f = read_field(
        &data_dir().join("xml_ugrid_binary_none_u32.vtu"),
        &opts(None),
    )
    .unwrap();
    assert_eq!(f.spacing, None);
    assert_eq!(f.dims, None);
}

#[test]
fn component_orders_expand_six_component_arrays() {
    let path = data_dir().join("legacy42_bin_image_T6.vtk");
    let vtk = read_field(&path, &opts(None)).unwrap();
    assert_eq!(vtk.array.name, "dti");
    assert_eq!(vtk.array.components, 6);
    for order in [ComponentOrder::Fsl, ComponentOrder::Nifti] {
        let o = ReadOptions {
            order: Some(order),
            ..ReadOptions::default()
        };
        let f = read_field(&path, &o).unwrap();
        for (a, b) in vtk.tensors.iter().zip(f.tensors.iter()) {
            // The stored components, recovered from the VTK-order expansion.
            let c = [a[0], a[4], a[8], a[1], a[5], a[2]];
            let want = order.expand(&c);
            for k in 0..9 {
                assert!(want[k] == b[k] || (want[k].is_nan() && b[k].is_nan()));
            }
        }
    }
}

#[test]
fn default_pick_prefers_active_tensors_then_first_array() {
    // Active 6-component point tensors win over the 9-component FIELD array.
    let f = read_field(&data_dir().join("legacy51_ascii_image_T6.vtk"), &opts(None)).unwrap();
    assert_eq!((f.array.name.as_str(), f.array.components), ("dti", 6));
    // Active cell tensors win over point arrays.
    let f = read_field(
        &data_dir().join("legacy42_ascii_image_cellT9.vtk"),
        &opts(None),
    )
    .unwrap();
    assert_eq!(f.array.name, "cellstress");
    assert_eq!(f.array.location, Location::Cell);
    assert_eq!(f.lattice_dims(), Some([3, 2, 2]));
    // No active tensors: the first 9/6-component point array.
    let f = read_field(
        &data_dir().join("legacy42_bin_image_field.vtk"),
        &opts(None),
    )
    .unwrap();
    assert_eq!(f.array.name, "stress");
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn err_of(path: &Path, array: Option<&str>) -> (LoadErrorKind, String) {
    let e = read_field(path, &opts(array)).expect_err("must fail");
    let msg = e.to_string();
    let fname = path.file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        msg.contains(&fname),
        "message '{msg}' does not name {fname}"
    );
    (e.kind, msg)
}

#[test]
fn errors_name_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let (k, _) = err_of(&dir.path().join("nope.vtk"), None);
    assert!(matches!(k, LoadErrorKind::Missing), "{k:?}");

    let p = write(dir.path(), "garbage.vtk", b"\x89PNG\r\n not a vtk file");
    assert!(matches!(err_of(&p, None).0, LoadErrorKind::NotVtk(_)));
    let p = write(dir.path(), "empty.vti", b"");
    assert!(matches!(err_of(&p, None).0, LoadErrorKind::NotVtk(_)));

    for f in [
        "legacy42_bin_ugrid_T9.vtk",
        "legacy51_ascii_image_T9.vtk",
        "xml_poly_appraw_zlib_u32.vtp",
        "xml_image_binary_lzma_u32.vti",
    ] {
        let b = std::fs::read(data_dir().join(f)).unwrap();
        let p = write(dir.path(), &format!("truncated_{f}"), &b[..b.len() * 2 / 3]);
        let (k, msg) = err_of(&p, None);
        assert!(matches!(k, LoadErrorKind::Malformed(_)), "{f}: {msg}");
    }

    let no_tensors = b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 1 1\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 2\nSCALARS p float 1\nLOOKUP_TABLE default\n1 2\nVECTORS v float\n1 2 3 4 5 6\n";
    let p = write(dir.path(), "scalars.vtk", no_tensors);
    let (k, msg) = err_of(&p, None);
    assert!(matches!(k, LoadErrorKind::NoTensorArray(_)), "{msg}");
    assert!(msg.contains("'p'") && msg.contains("'v'"), "{msg}");

    let (k, _) = err_of(&p, Some("v"));
    assert!(
        matches!(k, LoadErrorKind::ComponentCount { components: 3, .. }),
        "{k:?}"
    );

    let (k, msg) = err_of(
        &data_dir().join("xml_image_binary_none_u32.vti"),
        Some("nosuch"),
    );
    assert!(matches!(k, LoadErrorKind::ArrayNotFound { .. }), "{k:?}");
    assert!(msg.contains("stress") && msg.contains("celldti"), "{msg}");

    let mismatch = b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 1\nORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 2\nTENSORS t float\n1 0 0 0 1 0 0 0 1\n2 0 0 0 2 0 0 0 2\n";
    let p = write(dir.path(), "mismatch.vtk", mismatch);
    let (k, _) = err_of(&p, None);
    assert!(
        matches!(
            k,
            LoadErrorKind::TupleCount {
                found: 2,
                expected: 4,
                ..
            }
        ),
        "{k:?}"
    );

    // XML: tensor array shorter than the points.
    let vti = br#"<?xml version="1.0"?>
<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" header_type="UInt32">
  <ImageData WholeExtent="0 1 0 0 0 0" Origin="0 0 0" Spacing="1 1 1">
  <Piece Extent="0 1 0 0 0 0">
    <PointData Tensors="t">
      <DataArray type="Float32" Name="t" NumberOfComponents="6" format="ascii">1 2 3 4 5 6</DataArray>
    </PointData>
  </Piece>
  </ImageData>
</VTKFile>
"#;
    let p = write(dir.path(), "short.vti", vti);
    let (k, _) = err_of(&p, None);
    assert!(
        matches!(
            k,
            LoadErrorKind::TupleCount {
                found: 1,
                expected: 2,
                ..
            }
        ),
        "{k:?}"
    );

    // A bit-flipped count must not allocate 4e9 points.
    let huge = b"# vtk DataFile Version 4.2\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4000000000 float\n\0\0\0\0";
    let p = write(dir.path(), "huge.vtk", huge);
    assert!(matches!(err_of(&p, None).0, LoadErrorKind::Malformed(_)));

    // pvti with a missing piece.
    let pv = std::fs::read_to_string(data_dir().join("pvti_3pieces_binary.pvti")).unwrap();
    let p = write(dir.path(), "lonely.pvti", pv.as_bytes());
    let (k, msg) = err_of(&p, None);
    assert!(
        matches!(k, LoadErrorKind::Malformed(_)) && msg.contains("pvti_3pieces_binary_0.vti"),
        "{msg}"
    );
}

#[test]
fn input_files_are_not_modified() {
    let p = data_dir().join("xml_image_appraw_lz4_u64.vti");
    let before = std::fs::read(&p).unwrap();
    read_field(&p, &opts(None)).unwrap();
    assert_eq!(before, std::fs::read(&p).unwrap());
}
