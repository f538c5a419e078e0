//! BIDS BEP016 tensor maps (tests/data/bids/, written by make_bids.py from DIPY's shipped DWI
//! sets, fitted by DIPY and by MRtrix3's dwi2tensor): the sidecar's `ReferenceAxes` decides the
//! frame, so that `ijk` and `xyz` maps of the same data give numpy's world eigenvectors; a map
//! without a usable sidecar is read with the default and says so in one line.

use std::path::{Path, PathBuf};

use tensorglyph::field::{ReadOptions, TensorFrame, read_field};
use tensorglyph::tensor::eigen::{symmetric_eigen, symmetrise};
use tensorglyph::tensor::shape::fa;

use crate::cli::{stderr, tg};

fn bids(rel: &str) -> PathBuf {
    crate::data::path("bids/derivatives").join(rel)
}

fn map(sub: &str) -> String {
    match sub {
        "sub-03_ses-1" | "sub-03_ses-2" => {
            let ses = &sub[7..];
            format!("sub-03/{ses}/dwi/{sub}_model-DTI_param-tensor_dwimap.nii.gz")
        }
        _ => format!("{sub}/dwi/{sub}_model-DTI_param-tensor_dwimap.nii.gz"),
    }
}

/// numpy's truth for a map: world principal eigenvectors and FA per voxel, file order.
fn truth(rel: &str) -> (Vec<[f64; 3]>, Vec<f64>) {
    let text = std::fs::read_to_string(crate::data::path("bids/expected.json")).unwrap();
    let all: serde_json::Value = serde_json::from_str(&text).unwrap();
    let t = &all[rel];
    let e1 = t["e1_world"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| std::array::from_fn(|i| v[i].as_f64().unwrap()))
        .collect();
    let fa = t["fa"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    (e1, fa)
}

/// The world principal eigenvector and FA of every tensor tensorglyph reads from `path`.
fn read_e1(path: &Path, opts: &ReadOptions) -> (Vec<[f64; 3]>, Vec<f64>) {
    let f = read_field(path, opts).unwrap();
    (0..f.tensors.len())
        .map(|i| {
            let e = symmetric_eigen(&symmetrise(&f.world_tensor(i)).0);
            (e.vectors[0], fa(e.values))
        })
        .unzip()
}

/// The largest angle, in degrees, between the axes `a` and `b` where both FA are above 0.5.
fn worst_angle(a: &(Vec<[f64; 3]>, Vec<f64>), b: &(Vec<[f64; 3]>, Vec<f64>)) -> (f64, usize) {
    let mut worst = 0.0f64;
    let mut n = 0;
    for ((ea, fa_a), (eb, fa_b)) in a.0.iter().zip(&a.1).zip(b.0.iter().zip(&b.1)) {
        if *fa_a > 0.5 && *fa_b > 0.5 {
            let dot: f64 = (0..3).map(|i| ea[i] * eb[i]).sum();
            worst = worst.max(dot.abs().min(1.0).acos().to_degrees());
            n += 1;
        }
    }
    (worst, n)
}

#[test]
fn ijk_and_xyz_maps_of_the_same_data_give_the_same_world_eigenvectors() {
    let opts = ReadOptions::default();
    let ijk = read_e1(&bids(&map("sub-01")), &opts);
    let xyz = read_e1(&bids(&map("sub-02")), &opts);
    let mrtrix = read_e1(&bids(&map("sub-05")), &opts);
    // Each against numpy's eigenvectors of the world tensors make_bids.py stored.
    for (sub, got) in [("sub-01", &ijk), ("sub-02", &xyz), ("sub-05", &mrtrix)] {
        let (angle, n) = worst_angle(got, &truth(&map(sub)));
        assert!(n > 100, "{sub}: {n} voxels of FA > 0.5");
        // float32 storage of rotated tensors: well below a tenth of a degree.
        assert!(angle < 0.1, "{sub}: {angle}° from numpy");
    }
    // DIPY's ijk fit (WLS) and MRtrix's xyz fit (IWLS) of the same DWI: 2.0° at most on the
    // 212 voxels both fit with FA > 0.5 (numpy, expected.json).
    let (angle, n) = worst_angle(&ijk, &mrtrix);
    assert!(
        n > 100 && angle <= 3.0,
        "DIPY ijk vs MRtrix xyz: {angle}° on {n}"
    );
    let (angle, _) = worst_angle(&ijk, &xyz);
    assert!(angle < 0.1, "ijk vs xyz: {angle}°");
    // Without the sidecar's word the xyz map would be taken as image axes: far off.
    let as_ijk = read_e1(
        &bids(&map("sub-02")),
        &ReadOptions {
            tensor_frame: Some(TensorFrame::Voxel),
            ..Default::default()
        },
    );
    let (angle, _) = worst_angle(&as_ijk, &truth(&map("sub-02")));
    assert!(angle > 10.0, "the frame made no difference: {angle}°");
}

#[test]
fn maps_of_sessions_read_as_numpy_says() {
    for sub in ["sub-03_ses-1", "sub-03_ses-2"] {
        let got = read_e1(&bids(&map(sub)), &ReadOptions::default());
        let want = truth(&map(sub));
        assert_eq!(got.0.len(), want.0.len());
        let (angle, n) = worst_angle(&got, &want);
        assert!(n > 0 && angle < 0.1, "{sub}: {angle}° on {n}");
    }
}

#[test]
fn info_says_the_sidecar_decided_and_a_broken_map_is_one_line() {
    let o = tg(&["info", bids(&map("sub-02")).to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        out.contains("layout: fsl (from the BEP016 sidecar)"),
        "{out}"
    );
    assert!(
        out.contains("tensors in world axes (ReferenceAxes xyz, from the BEP016 sidecar)"),
        "{out}"
    );
    assert_eq!(stderr(&o), "");
    let o = tg(&["info", bids(&map("sub-04")).to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("gzip data is corrupt or truncated"), "{err}");
}

#[test]
fn a_map_without_a_usable_sidecar_is_read_with_the_default_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let name = "sub-01_model-DTI_param-tensor_dwimap.nii.gz";
    let nii = dir.path().join(name);
    std::fs::copy(bids(&map("sub-01")), &nii).unwrap();
    let sidecar = dir.path().join("sub-01_model-DTI_dwimap.json");
    let ijk = read_e1(&bids(&map("sub-01")), &ReadOptions::default());
    for (content, why) in [
        (None, "no BEP016 sidecar (sub-01_model-DTI_dwimap.json)"),
        (Some("{\"ReferenceAxes\": "), "not valid JSON"),
        (
            Some("{\"ReferenceAxes\": \"ras\"}"),
            "ReferenceAxes is \"ras\"",
        ),
        (
            Some("{\"OrientationRepresentation\": \"param\"}"),
            "no ReferenceAxes",
        ),
    ] {
        let _ = std::fs::remove_file(&sidecar);
        if let Some(c) = content {
            std::fs::write(&sidecar, c).unwrap();
        }
        let o = tg(&["info", nii.to_str().unwrap(), "--quiet"]);
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("notice: ") && err.contains(why), "{err}");
        assert!(err.contains("read with the default"), "{err}");
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("layout: fsl (the default)"), "{out}");
        // The default is the image axes: what this ijk map holds.
        let got = read_e1(&nii, &ReadOptions::default());
        let a = worst_angle(&got, &ijk);
        // acos near 1 is good to about 1e-6 degrees.
        assert!(a.0 < 1e-4, "{a:?}");
    }
}

#[test]
fn outputs_never_replace_the_sidecar() {
    let dir = tempfile::tempdir().unwrap();
    let nii = dir
        .path()
        .join("sub-02_model-DTI_param-tensor_dwimap.nii.gz");
    let sidecar = dir.path().join("sub-02_model-DTI_dwimap.json");
    std::fs::copy(bids(&map("sub-02")), &nii).unwrap();
    std::fs::copy(bids("sub-02/dwi/sub-02_model-DTI_dwimap.json"), &sidecar).unwrap();
    let before = std::fs::read(&sidecar).unwrap();
    let o = tg(&[
        "render",
        nii.to_str().unwrap(),
        "-o",
        sidecar.to_str().unwrap(),
        "--size",
        "32x32",
        "--method",
        "reference",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("is the input file"), "{err}");
    assert_eq!(std::fs::read(&sidecar).unwrap(), before);
}
