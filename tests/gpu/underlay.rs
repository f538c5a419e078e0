//! `--underlay`: an FA/MD image under a slice, on the GPU and in the reference. Truth: numpy's
//! eigenvalues of the test tensors (tests/data/dti/expected.json) give each texel's FA; the glyphs
//! of the slice stay whole in front of it from either side; GPU and reference agree pixel for
//! pixel.

use std::path::PathBuf;

use glam::DVec3;
use serde_json::Value;
use tensorglyph::camera::{Camera, Framing, ViewPreset};
use tensorglyph::field::{ReadOptions, read_field};
use tensorglyph::frame::Frame;
use tensorglyph::progress::Silent;
use tensorglyph::reference::ReferenceScene;
use tensorglyph::request::{FrameRequest, Method, Preset, UnderlayView};
use tensorglyph::scene::UnderlaySource;
use tensorglyph::select::{Plane, Selection, Slicing};
use tensorglyph::staging::{Recipe, Source, Staged, stage};
use tensorglyph::tensor::measure::Measure;

use crate::cli::{stderr, tg};
use crate::data;

fn dti(name: &str) -> PathBuf {
    data::path("dti").join(name)
}

const FILE: &str = "fsl4d_oblique.nii.gz";

fn staged(underlay: Option<UnderlaySource>, plane: Plane) -> Staged {
    let recipe = Recipe {
        selection: Selection {
            slicing: Slicing::Planes(vec![plane]),
            ..Selection::default()
        },
        underlay,
        ..Recipe::default()
    };
    stage(&Source::File(dti(FILE)), &recipe, &Silent).expect("stages")
}

fn numpy_fa(ev: &[f64]) -> f64 {
    let m = ev.iter().sum::<f64>() / 3.0;
    let num: f64 = ev.iter().map(|l| (l - m).powi(2)).sum();
    let den: f64 = ev.iter().map(|l| l * l).sum();
    (1.5 * num / den).sqrt()
}

#[test]
fn fa_texels_are_numpys_fa_of_each_voxel() {
    let exp: Value =
        serde_json::from_str(&std::fs::read_to_string(dti("expected.json")).unwrap()).unwrap();
    let evs = exp["files"][FILE]["eigenvalues"].as_array().unwrap();
    let dims = [5, 4, 3];
    for plane in [Plane { axis: 2, index: 1 }, Plane { axis: 0, index: 3 }] {
        let s = staged(Some(UnderlaySource::Measure(Measure::Fa)), plane);
        let u = s.scene.underlay.as_ref().expect("an underlay");
        assert_eq!(u.planes.len(), 1);
        let p = &u.planes[0];
        // The two in-plane lattice axes, in order, are the image's columns and rows.
        let (a, b) = if plane.axis == 2 { (0, 1) } else { (1, 2) };
        assert_eq!(p.size, [dims[a] as u32, dims[b] as u32]);
        for jb in 0..dims[b] {
            for ia in 0..dims[a] {
                let mut ijk = [0; 3];
                ijk[plane.axis] = plane.index;
                ijk[a] = ia;
                ijk[b] = jb;
                let n = ijk[0] + 5 * (ijk[1] + 4 * ijk[2]);
                let ev: Vec<f64> = evs[n]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect();
                let got = f64::from(p.values[ia + dims[a] * jb]);
                assert!(
                    (got - numpy_fa(&ev)).abs() < 1e-6,
                    "{plane} texel ({ia}, {jb}): {got} vs numpy {}",
                    numpy_fa(&ev)
                );
            }
        }
        // The default window is within the values' range.
        let lo = p.values.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = p.values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        assert!(u.window[0] <= u.window[1]);
        assert!(u.window[0] >= lo - 0.5 && u.window[1] <= hi + 0.5);
    }
}

#[test]
fn the_image_lies_on_the_slice_lattice_half_a_voxel_beyond_its_centres() {
    let plane = Plane { axis: 2, index: 1 };
    let s = staged(Some(UnderlaySource::Measure(Measure::Md)), plane);
    let field = read_field(&dti(FILE), &ReadOptions::default()).unwrap();
    let g = s.scene.underlay.as_ref().unwrap().planes[0].geometry;
    // Voxel centres of the plane's corners, from the reader's positions.
    let at = |i: usize, j: usize| DVec3::from(field.position(i + 5 * (j + 4 * plane.index)));
    let step_u = (at(4, 0) - at(0, 0)) / 4.0;
    let step_v = (at(0, 3) - at(0, 0)) / 3.0;
    let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-9 * (1.0 + b.length());
    assert!(close(g.corner, at(0, 0) - 0.5 * (step_u + step_v)));
    assert!(close(g.u, step_u * 5.0) && close(g.v, step_v * 4.0));
    assert!((g.normal.length() - 1.0).abs() < 1e-12);
    assert!(g.behind > 0.0);
    // The face-on view looks along the plane's normal (the voxel z axis, mostly world z: axial).
    let face = s.face.expect("one slice is seen face-on");
    assert!(face.toward.0.dot(g.normal).abs() > 1.0 - 1e-12);
    assert!(face.toward.0.z < 0.0, "axial: from superior");
}

fn gpu_and_reference(s: &Staged, camera: &Camera, req: &FrameRequest) -> Option<(Frame, Frame)> {
    let gpu = crate::check::gpu()?;
    let frame = gpu.render(&s.scene, camera, req).expect("renders");
    let reference = ReferenceScene::new(&s.scene, camera).render(req);
    Some((frame, reference))
}

fn cameras(s: &Staged) -> Vec<Camera> {
    [
        ViewPreset::NegZ,
        ViewPreset::PosZ,
        ViewPreset::Iso,
        ViewPreset::PosX,
    ]
    .into_iter()
    .flat_map(|view| {
        [false, true].map(|ortho| {
            Camera::frame(
                &Framing {
                    view,
                    ortho,
                    ..Framing::default()
                },
                s.frame_centre,
                s.frame_radius,
                160,
                120,
            )
        })
    })
    .collect()
}

#[test]
fn gpu_and_reference_draw_the_same_underlay_and_it_hides_no_glyph_of_its_slice() {
    let plane = Plane { axis: 2, index: 1 };
    let with = staged(Some(UnderlaySource::Measure(Measure::Fa)), plane);
    let without = staged(None, plane);
    let req = FrameRequest {
        aux: true,
        ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
    };
    for camera in cameras(&with) {
        let Some((frame, reference)) = gpu_and_reference(&with, &camera, &req) else {
            return;
        };
        let n = frame.ids.len();
        let same_id = (0..n).filter(|&i| frame.ids[i] == reference.ids[i]).count();
        assert!(
            n - same_id <= n / 1000,
            "ids differ at {} of {n} pixels",
            n - same_id
        );
        // Underlay pixels (id 0, not background) match the reference's grey to one level,
        // except a texel boundary crossed by a rounding.
        let bg = [255u8, 255, 255, 255];
        let mut under = 0;
        let mut off = 0;
        for i in 0..n {
            let (g, r) = (
                &frame.color[4 * i..4 * i + 4],
                &reference.color[4 * i..4 * i + 4],
            );
            if frame.ids[i] == 0 && reference.ids[i] == 0 && r != bg {
                under += 1;
                if (i32::from(g[0]) - i32::from(r[0])).abs() > 1 {
                    off += 1;
                }
            }
        }
        assert!(under > 0, "the underlay shows");
        assert!(off <= under / 50, "{off} of {under} underlay pixels differ");
        // Every glyph pixel drawn without the underlay is still that glyph with it.
        let bare = crate::check::gpu()
            .unwrap()
            .render(&without.scene, &camera, &req)
            .unwrap();
        let hidden = (0..n)
            .filter(|&i| bare.ids[i] != 0 && frame.ids[i] != bare.ids[i])
            .count();
        assert_eq!(hidden, 0, "the underlay hides {hidden} glyph pixels");
    }
}

#[test]
fn the_window_maps_values_to_grey_and_the_underlay_can_be_hidden() {
    let s = staged(
        Some(UnderlaySource::Measure(Measure::Fa)),
        Plane { axis: 2, index: 1 },
    );
    let camera = cameras(&s)[1];
    // Every FA is above 1e-9: a window ending there draws the whole image white.
    let white = FrameRequest {
        background: [0.0, 0.0, 0.0, 1.0],
        underlay: UnderlayView {
            shown: true,
            window: Some([0.0, 1e-9]),
        },
        ..FrameRequest::default()
    };
    let hidden = FrameRequest {
        underlay: UnderlayView {
            shown: false,
            window: None,
        },
        ..white
    };
    let reference = ReferenceScene::new(&s.scene, &camera);
    for frame in [
        Some(reference.render(&white)),
        crate::check::gpu().map(|g| g.render(&s.scene, &camera, &white).unwrap()),
    ]
    .into_iter()
    .flatten()
    {
        let under: Vec<&[u8]> = (0..frame.ids.len())
            .filter(|&i| frame.ids[i] == 0)
            .map(|i| &frame.color[4 * i..4 * i + 4])
            .filter(|c| c[..3] != [0, 0, 0])
            .collect();
        assert!(!under.is_empty());
        assert!(under.iter().all(|c| c[..3] == [255, 255, 255]));
    }
    for frame in [
        Some(reference.render(&hidden)),
        crate::check::gpu().map(|g| g.render(&s.scene, &camera, &hidden).unwrap()),
    ]
    .into_iter()
    .flatten()
    {
        assert!(
            (0..frame.ids.len())
                .filter(|&i| frame.ids[i] == 0)
                .all(|i| frame.color[4 * i..4 * i + 3] == [0, 0, 0]),
            "hidden: background only"
        );
    }
}

#[test]
fn the_underlay_on_the_command_line() {
    let file = dti(FILE);
    let file = file.to_str().unwrap();
    let out = std::env::temp_dir().join(format!("tg-underlay-{}.png", std::process::id()));
    let o = out.to_str().unwrap();
    // No --slice: the middle z plane (index 1 of 3), its 20 glyphs.
    let r = tg(&[
        "render",
        file,
        "--underlay",
        "fa",
        "-o",
        o,
        "--size",
        "120x90",
        "--json",
        "-q",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let j = crate::cli::json(&r);
    assert_eq!(j["glyphs_selected"], 20);
    // DTI defaults: black background.
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0, 255]);
    std::fs::remove_file(&out).ok();
    // A window needs an underlay; a bad window and an unstructured field are refused in a line.
    for (args, what) in [
        (vec!["--underlay-range", "0,1"], "--underlay"),
        (vec!["--underlay", "fa", "--underlay-range", "1,0"], "LO,HI"),
        (vec!["--underlay", "", "--size", "10x10"], "--underlay"),
    ] {
        let mut a = vec!["render", file, "-o", o];
        a.extend(args);
        let r = tg(&a);
        let e = stderr(&r);
        assert_eq!(r.status.code(), Some(2), "{e}");
        assert_eq!(e.trim().lines().count(), 1, "{e}");
        assert!(e.contains(what), "{e}");
    }
    let poly = data::path("vtk/legacy42_ascii_poly_T9.vtk");
    let r = tg(&[
        "render",
        poly.to_str().unwrap(),
        "--underlay",
        "md",
        "-o",
        o,
    ]);
    let e = stderr(&r);
    assert_eq!(r.status.code(), Some(2), "{e}");
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    assert!(e.contains("needs a lattice"), "{e}");
    assert!(!out.exists(), "nothing written on an error");
}

#[test]
fn glyph_style_is_unchanged_by_the_underlay() {
    // The underlay is an image only: the same instances with and without it.
    let plane = Plane { axis: 1, index: 2 };
    let a = staged(Some(UnderlaySource::Measure(Measure::Md)), plane);
    let b = staged(None, plane);
    assert_eq!(a.scene.instances, b.scene.instances);
}
