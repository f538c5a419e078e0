//! `tensorglyph report` on the BEP016 derivatives of tests/data/bids (DIPY's and MRtrix's fits
//! of DIPY's DWI sets): every good participant's mosaics and page, the broken one named, exit
//! status 1; pages that need nothing but themselves, whose FA and MD are numpy's
//! (tests/data/bids/expected.json); nothing left of a report that failed; the files form; the
//! anatomical labels of a field whose affine flips an axis; the inset's outline where the affine
//! puts its region, and its sides, with and without the flip; bad `--zoom-region` and
//! `--tile-size` values.

use std::path::Path;

use base64::Engine as _;

use crate::cli::{stderr, tg};

fn bids() -> String {
    crate::data::path("bids/derivatives")
        .to_string_lossy()
        .into_owned()
}

/// The PNG images a page embeds, decoded from their data URLs.
fn embedded(html: &str) -> Vec<Vec<u8>> {
    html.split("src=\"data:image/png;base64,")
        .skip(1)
        .map(|s| {
            let b64 = &s[..s.find('"').unwrap()];
            base64::engine::general_purpose::STANDARD
                .decode(b64)
                .unwrap()
        })
        .collect()
}

#[test]
fn every_good_participant_is_written_and_the_broken_one_is_named() {
    let out = tempfile::tempdir().unwrap();
    let o = tg(&[
        "report",
        &bids(),
        out.path().to_str().unwrap(),
        "participant",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(errors[0].starts_with("error: sub-04: "), "{err}");
    assert!(
        errors[0].contains("gzip data is corrupt or truncated"),
        "{err}"
    );
    // Nothing of the broken one.
    assert!(!out.path().join("sub-04.html").exists());
    assert!(!out.path().join("sub-04").exists());
    let description: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("dataset_description.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(description["DatasetType"], "derivative");
    for (label, maps, axes) in [
        ("01", 1, "ijk"),
        ("02", 1, "xyz"),
        ("03", 2, "ijk"),
        ("05", 1, "xyz"),
    ] {
        let html = std::fs::read_to_string(out.path().join(format!("sub-{label}.html"))).unwrap();
        // Self-contained: nothing fetched from anywhere.
        assert!(
            !html.contains("http:") && !html.contains("https:"),
            "sub-{label}"
        );
        assert_eq!(html.matches("src=").count(), 3 * maps, "sub-{label}");
        assert!(
            html.contains(&format!("ReferenceAxes {axes} from the BEP016 sidecar")),
            "sub-{label}"
        );
        assert!(
            html.contains("fsl (from the BEP016 sidecar)"),
            "sub-{label}"
        );
        // The figures on disk are the images on the page: rows of 256-pixel tiles, the inset
        // (at least 400 px) and the legend.
        let images = embedded(&html);
        let mut files: Vec<_> = std::fs::read_dir(out.path().join(format!("sub-{label}/figures")))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        assert_eq!(files.len(), 3 * maps);
        for f in &files {
            let png = std::fs::read(f).unwrap();
            assert!(images.contains(&png), "{} not on the page", f.display());
            let img = image::load_from_memory(&png).unwrap();
            let side = img.height();
            assert!(side >= 400, "{}", f.display());
            assert_eq!((img.width() - 200 - side) % 256, 0, "{}", f.display());
            assert!(img.width() >= 200 + 256 + side, "{}", f.display());
        }
        for (k, (path, truth)) in expected().iter().enumerate() {
            if !path.starts_with(&format!("sub-{label}/")) {
                continue;
            }
            let section = html.split("<h2>").nth(1 + k - first_of(label)).unwrap();
            check_stats(section, truth, path);
        }
    }
    let sub3 = std::fs::read_to_string(out.path().join("sub-03.html")).unwrap();
    assert!(sub3.contains("<th>session</th><td>1</td>") && sub3.contains("<td>2</td>"));
}

/// numpy's truth of each good map, in the order the report lists them.
fn expected() -> Vec<(String, serde_json::Value)> {
    let text = std::fs::read_to_string(crate::data::path("bids/expected.json")).unwrap();
    let map: serde_json::Map<String, serde_json::Value> = serde_json::from_str(&text).unwrap();
    let mut all: Vec<_> = map.into_iter().collect();
    all.sort_by(|a, b| a.0.cmp(&b.0));
    all
}

/// The index in [`expected`] of the first map of participant `label`.
fn first_of(label: &str) -> usize {
    expected()
        .iter()
        .position(|(p, _)| p.starts_with(&format!("sub-{label}/")))
        .unwrap()
}

/// The numbers of a row of the page's table: "min a, median b, mean c, max d".
fn row(section: &str, name: &str) -> [f64; 4] {
    let start = section.find(&format!("<th>{name}</th><td>")).unwrap();
    let text = &section[start..];
    let text = &text[text.find("<td>").unwrap() + 4..text.find("</td>").unwrap()];
    let numbers: Vec<f64> = text
        .split(", ")
        .map(|part| part.rsplit(' ').next().unwrap().parse().unwrap())
        .collect();
    numbers.try_into().unwrap()
}

/// FA and MD as the page states them against numpy's over the valid (non-zero) voxels.
fn check_stats(section: &str, truth: &serde_json::Value, path: &str) {
    let md_all: Vec<f64> = serde_json::from_value(truth["md"].clone()).unwrap();
    let fa_all: Vec<f64> = serde_json::from_value(truth["fa"].clone()).unwrap();
    let valid: Vec<usize> = (0..md_all.len()).filter(|&i| md_all[i] != 0.0).collect();
    for (name, all, tol) in [("FA", &fa_all, 1e-4), ("MD", &md_all, 2e-3)] {
        let mut v: Vec<f64> = valid.iter().map(|&i| all[i]).collect();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            (v[n / 2 - 1] + v[n / 2]) / 2.0
        };
        let mean = v.iter().sum::<f64>() / n as f64;
        let want = [v[0], median, mean, v[n - 1]];
        let got = row(section, name);
        for (g, w) in got.iter().zip(want) {
            // The page rounds (FA to 4 decimals, MD to 4 significant digits).
            assert!(
                (g - w).abs() <= tol * w.abs().max(1.0),
                "{path} {name}: {got:?} vs {want:?}"
            );
        }
    }
    assert!(
        section.contains(&format!("{} valid", valid.len())),
        "{path}"
    );
}

#[test]
fn chosen_participants_only_and_usage_errors() {
    let out = tempfile::tempdir().unwrap();
    let o = tg(&[
        "report",
        &bids(),
        out.path().to_str().unwrap(),
        "participant",
        "--participant-label",
        "sub-01",
        "02",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(out.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "dataset_description.json",
            "sub-01",
            "sub-01.html",
            "sub-01.json",
            "sub-02",
            "sub-02.html",
            "sub-02.json"
        ]
    );
    for (args, want) in [
        (vec!["groups"], "analysis level groups: participant"),
        (
            vec!["participant", "--participant-label", "99"],
            "no participant 99",
        ),
    ] {
        let b = bids();
        let mut all = vec!["report", &b, out.path().to_str().unwrap()];
        all.extend(args.iter().copied());
        let o = tg(&all);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(want), "{err}");
    }
    assert!(!Path::new(&bids()).join("sub-01.html").exists());
    // Reports among the data they are made of: refused before anything is written.
    let input = tempfile::tempdir().unwrap();
    with_broken_second_map(input.path());
    let dir = input.path().to_str().unwrap();
    let o = tg(&["report", dir, dir, "participant"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the output folder is the BIDS folder read"),
        "{err}"
    );
    assert!(!input.path().join("sub-01.html").exists());
    assert!(!input.path().join("dataset_description.json").exists());
}

/// A copy of tests/data/bids/derivatives with participant 06, whose first session is good and
/// whose second is the broken map of participant 04.
fn with_broken_second_map(root: &Path) {
    let src = Path::new(&bids()).to_path_buf();
    for sub in ["sub-01"] {
        let dir = root.join(sub).join("dwi");
        std::fs::create_dir_all(&dir).unwrap();
        for e in std::fs::read_dir(src.join(sub).join("dwi")).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
        }
    }
    for (ses, from) in [("1", "sub-01"), ("2", "sub-04")] {
        let dir = root.join("sub-06").join(format!("ses-{ses}")).join("dwi");
        std::fs::create_dir_all(&dir).unwrap();
        for ext in ["json", "nii.gz"] {
            let name = |sub: &str, ses: Option<&str>| {
                let ses = ses.map_or(String::new(), |s| format!("_ses-{s}"));
                let param = if ext == "json" { "" } else { "_param-tensor" };
                format!("{sub}{ses}_model-DTI{param}_dwimap.{ext}")
            };
            std::fs::copy(
                src.join(from).join("dwi").join(name(from, None)),
                dir.join(name("sub-06", Some(ses))),
            )
            .unwrap();
        }
    }
}

#[test]
fn a_participant_whose_second_map_is_broken_leaves_nothing() {
    let input = tempfile::tempdir().unwrap();
    with_broken_second_map(input.path());
    let out = tempfile::tempdir().unwrap();
    let o = tg(&[
        "report",
        input.path().to_str().unwrap(),
        out.path().to_str().unwrap(),
        "participant",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: sub-06: ") && err.contains("ses-2"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!out.path().join("sub-06.html").exists());
    assert!(!out.path().join("sub-06").exists());
    assert!(out.path().join("sub-01.html").exists());
}

#[test]
fn files_form_one_report_per_file_and_a_bad_one_named() {
    let out = tempfile::tempdir().unwrap();
    let good = crate::data::path(
        "bids/derivatives/sub-02/dwi/sub-02_model-DTI_param-tensor_dwimap.nii.gz",
    );
    let nrrd = crate::data::path("dti/nrrd_masked.nrrd");
    let bad = crate::data::path(
        "bids/derivatives/sub-04/dwi/sub-04_model-DTI_param-tensor_dwimap.nii.gz",
    );
    let o = tg(&[
        "report",
        good.to_str().unwrap(),
        bad.to_str().unwrap(),
        nrrd.to_str().unwrap(),
        "-o",
        out.path().to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: sub-04_model-DTI_param-tensor_dwimap: "),
        "{err}"
    );
    let mut names: Vec<String> = std::fs::read_dir(out.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "nrrd_masked",
            "nrrd_masked.html",
            "sub-02_model-DTI_param-tensor_dwimap",
            "sub-02_model-DTI_param-tensor_dwimap.html"
        ]
    );
    let html = std::fs::read_to_string(out.path().join("nrrd_masked.html")).unwrap();
    assert_eq!(embedded(&html).len(), 3);
    for o in ["axial", "coronal", "sagittal"] {
        assert!(
            out.path()
                .join(format!("nrrd_masked/figures/nrrd_masked_{o}.png"))
                .exists()
        );
    }
    // The BIDS map named alone is read through its sidecar all the same.
    let html =
        std::fs::read_to_string(out.path().join("sub-02_model-DTI_param-tensor_dwimap.html"))
            .unwrap();
    assert!(html.contains("ReferenceAxes xyz from the BEP016 sidecar"));
    assert!(html.contains("µm²/ms"));
    // Usage errors: both forms at once, a missing -o, the same name twice.
    for args in [
        vec![
            "report",
            good.to_str().unwrap(),
            "-o",
            "x",
            "--participant-label",
            "01",
        ],
        vec!["report", good.to_str().unwrap()],
        vec![
            "report",
            good.to_str().unwrap(),
            good.to_str().unwrap(),
            "-o",
            out.path().to_str().unwrap(),
        ],
    ] {
        let o = tg(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    }
}

/// A NRRD volume of `n`³ voxels, 2 mm, whose i axis runs along `sign` × the world's x: tensors
/// prolate along the world's x (red in DEC) in the first half of i, along y (green) in the
/// second.
fn half_volume(path: &Path, n: usize, sign: f64) {
    let mut bytes = format!(
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 7 {n} {n} {n}\n\
         kinds: 3D-masked-symmetric-matrix space space space\n\
         space: right-anterior-superior\n\
         space directions: none ({},0,0) (0,2,0) (0,0,2)\nspace origin: (0,0,0)\n\
         measurement frame: (1,0,0) (0,1,0) (0,0,1)\nencoding: raw\nendian: little\n\n",
        2.0 * sign
    )
    .into_bytes();
    for _k in 0..n {
        for _j in 0..n {
            for i in 0..n {
                let t: [f32; 7] = if i < n / 2 {
                    [1.0, 1.7e-3, 0.0, 0.0, 0.3e-3, 0.0, 0.3e-3]
                } else {
                    [1.0, 0.3e-3, 0.0, 0.0, 1.7e-3, 0.0, 0.3e-3]
                };
                for v in t {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// Glyph pixels (red, DEC of a tensor along x) in the left and right halves of the mosaic's
/// first tile.
fn red_in_halves(png: &Path) -> (usize, usize) {
    let img = image::open(png).unwrap().to_rgba8();
    let mut halves = (0, 0);
    for y in 0..256 {
        for x in 0..256 {
            let p = img.get_pixel(x, y).0;
            if p[0] > 60 && u32::from(p[0]) > 2 * u32::from(p[1]) + 10 {
                if x < 128 {
                    halves.0 += 1;
                } else {
                    halves.1 += 1;
                }
            }
        }
    }
    halves
}

#[test]
fn labels_follow_the_affine_when_it_flips_an_axis() {
    // With direction +2 mm along i, the red half (small i) is at small x: the subject's left,
    // on the left of an axial tile, labelled L there (neurological convention). With −2 mm it
    // is at large x, the right, and the tile shows it on the side labelled R.
    let dir = tempfile::tempdir().unwrap();
    for (name, sign, left_heavy) in [("plain", 1.0, true), ("flipped", -1.0, false)] {
        let file = dir.path().join(format!("{name}.nrrd"));
        half_volume(&file, 8, sign);
        let out = dir.path().join(format!("out-{name}"));
        let o = tg(&[
            "report",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let png = out.join(format!("{name}/figures/{name}_axial.png"));
        let (left, right) = red_in_halves(&png);
        if left_heavy {
            assert!(left > 100 && right < left / 20, "{name}: {left} {right}");
        } else {
            assert!(right > 100 && left < right / 20, "{name}: {left} {right}");
        }
        let html = std::fs::read_to_string(out.join(format!("{name}.html"))).unwrap();
        assert!(html.contains("neurological convention"), "{name}");
    }
}

#[test]
fn vtk_lattices_are_reported_and_points_refused() {
    // An image (regular lattice), a rectilinear grid (no FA image under its glyphs: its planes
    // are not evenly spaced) and a point set (no slices to show).
    let out = tempfile::tempdir().unwrap();
    let files = ["image_T6", "rect_T9", "poly_T9"]
        .map(|k| crate::data::path(&format!("vtk/legacy42_bin_{k}.vtk")));
    let mut args = vec!["report"];
    args.extend(files.iter().map(|f| f.to_str().unwrap()));
    args.extend(["-o", out.path().to_str().unwrap()]);
    let o = tg(&args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: legacy42_bin_poly_T9: ") && err.contains("not a lattice"),
        "{err}"
    );
    let image = std::fs::read_to_string(out.path().join("legacy42_bin_image_T6.html")).unwrap();
    assert!(!image.contains("no FA underlay"));
    // VTK's world is not anatomical: the page says so by its units and labels.
    assert!(image.contains("as stored in the file"));
    let rect = std::fs::read_to_string(out.path().join("legacy42_bin_rect_T9.html")).unwrap();
    assert_eq!(
        rect.matches("no FA underlay (needs a regular lattice")
            .count(),
        3
    );
    assert_eq!(embedded(&rect).len(), 3);
}

/// The share of pixels of two PNGs of one size whose channels differ by more than 16 levels.
fn differing(a: &Path, b: &Path) -> f64 {
    let (a, b) = (
        image::open(a).unwrap().to_rgba8(),
        image::open(b).unwrap().to_rgba8(),
    );
    assert_eq!(a.dimensions(), b.dimensions());
    let n = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 16))
        .count();
    n as f64 / f64::from(a.width() * a.height())
}

#[test]
fn without_a_vulkan_driver_the_cpu_reference_draws_the_same_figures() {
    let run = |out: &Path, hide: bool| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_tensorglyph"));
        c.args([
            "report",
            &bids(),
            out.to_str().unwrap(),
            "participant",
            "--participant-label",
            "01",
            "05",
        ])
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
        if hide {
            c.env("VK_ICD_FILENAMES", "/nonexistent/icd.json");
        }
        c.output().unwrap()
    };
    let dir = tempfile::tempdir().unwrap();
    let (gpu, cpu) = (dir.path().join("gpu"), dir.path().join("cpu"));
    let o = run(&gpu, false);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    if stderr(&o).contains("no GPU adapter") {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI needs a GPU adapter (lavapipe counts)"
        );
        eprintln!("skipped: no GPU adapter to compare the CPU reference with");
        return;
    }
    let o = run(&cpu, true);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("no GPU adapter"), "{}", stderr(&o));
    for label in ["01", "05"] {
        let page = std::fs::read_to_string(cpu.join(format!("sub-{label}.html"))).unwrap();
        assert!(page.contains("rendered with the exact CPU reference"));
        let figures = gpu.join(format!("sub-{label}/figures"));
        for f in std::fs::read_dir(&figures).unwrap() {
            let f = f.unwrap().path();
            let other = cpu.join(f.strip_prefix(&gpu).unwrap());
            // Bounded by the glyph edges where the GPU's f32 ray cast and the f64 reference
            // disagree on coverage: 0.005 % of the pixels measured on lavapipe.
            let share = differing(&f, &other);
            assert!(share <= 1e-3, "{}: {share}", f.display());
        }
    }
}

/// A NRRD volume of `n`³ voxels, 2 mm, whose i axis runs along `sign` × the world's x:
/// tensors prolate along x (red in DEC) where i < `red`, along y (green) elsewhere; their FA
/// in ten steps along a diagonal, so that the FA underlay's window (its 2nd to 98th
/// percentiles) leaves most voxels grey, not black.
fn split_volume(path: &Path, n: usize, red: usize, sign: f64) {
    let mut bytes = format!(
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 7 {n} {n} {n}\n\
         kinds: 3D-masked-symmetric-matrix space space space\n\
         space: right-anterior-superior\n\
         space directions: none ({},0,0) (0,2,0) (0,0,2)\nspace origin: (0,0,0)\n\
         measurement frame: (1,0,0) (0,1,0) (0,0,1)\nencoding: raw\nendian: little\n\n",
        2.0 * sign
    )
    .into_bytes();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let minor = 0.3e-3 + 0.2e-3 * ((i + 3 * j + 7 * k) % 10) as f32 / 10.0;
                let t: [f32; 7] = if i < red {
                    [1.0, 1.7e-3, 0.0, 0.0, minor, 0.0, minor]
                } else {
                    [1.0, minor, 0.0, 0.0, 1.7e-3, 0.0, minor]
                };
                for v in t {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// The bounding box `[x0, y0, x1, y1]` (pixel centres) of the pixels of `img` in columns `xs`
/// and rows `ys` that `keep` accepts.
fn bbox(
    img: &image::RgbaImage,
    xs: std::ops::Range<u32>,
    ys: std::ops::Range<u32>,
    keep: impl Fn([u8; 4]) -> bool,
) -> Option<[f64; 4]> {
    let mut b: Option<[f64; 4]> = None;
    for y in ys {
        for x in xs.clone() {
            if keep(img.get_pixel(x, y).0) {
                let (x, y) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                b = Some(match b {
                    None => [x, y, x, y],
                    Some([a, c, d, e]) => [a.min(x), c.min(y), d.max(x), e.max(y)],
                });
            }
        }
    }
    b
}

fn is_red(p: [u8; 4]) -> bool {
    p[0] > 60 && u32::from(p[0]) > 2 * u32::from(p[1].max(p[2])) + 10
}

fn is_outline(p: [u8; 4]) -> bool {
    p[0] == 0 && p[1] == 255 && p[2] == 255
}

#[test]
fn the_inset_is_outlined_where_the_affine_puts_its_voxels_and_keeps_its_sides() {
    // 24³ voxels of 2 mm; the inset's region is voxels i 4–11, j 8–15 of slice k = 12 (the
    // voxel 8,12,12 and 8 voxels around it): its cells span i 3.5–11.5, j 7.5–15.5. The world
    // x of voxel i is 2i (plain) or −2i (flipped), y is 2j: the expected outline is worked out
    // from that alone, placed in the tile by where the slice is drawn (its FA underlay and
    // glyphs, cells i and j −0.5–23.5: x −1–47 mm or −47–1 mm, y −1–47 mm), +x to the right
    // and +y up as the neurological convention puts them.
    let dir = tempfile::tempdir().unwrap();
    let tile = 320u32;
    for (name, sign) in [("plain", 1.0), ("flipped", -1.0)] {
        let file = dir.path().join(format!("{name}.nrrd"));
        split_volume(&file, 24, 8, sign);
        let out = dir.path().join(format!("out-{name}"));
        let o = tg(&[
            "report",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--zoom-region",
            "8,12,12:8",
            "--tile-size",
            &tile.to_string(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let html = std::fs::read_to_string(out.join(format!("{name}.html"))).unwrap();
        let axial = html
            .split("<figcaption>axial: ")
            .nth(1)
            .unwrap()
            .split("</figcaption>")
            .next()
            .unwrap();
        // The slice of the region is among the overview's.
        let slices: Vec<u32> = axial["slices k = ".len()..axial.find(';').unwrap()]
            .split(", ")
            .map(|s| s.parse().unwrap())
            .collect();
        let n = slices.iter().position(|&s| s == 12).expect(axial) as u32;
        let (x_range, lattice_x, region_x) = if sign > 0.0 {
            ("x 8.0 to 22.0", [-1.0, 47.0], [7.0, 23.0])
        } else {
            ("x -22.0 to -8.0", [-47.0, 1.0], [-23.0, -7.0])
        };
        assert!(
            axial.contains(&format!(
                "voxels i 4–11, j 8–15, k = 12 ({x_range}, y 16.0 to 30.0, z 24.0 mm), as asked"
            )),
            "{axial}"
        );
        let img = image::open(out.join(format!("{name}/figures/{name}_axial.png")))
            .unwrap()
            .to_rgba8();
        let side = img.width() - 200 - slices.len() as u32 * tile;
        assert!(side >= 400, "{}", img.width());
        assert_eq!(img.height(), tile.max(side));
        // The slice, away from the labels at the tile's edges.
        let (x0, margin) = (n * tile, 30);
        let drawn = bbox(
            &img,
            x0 + margin..x0 + tile - margin,
            margin..tile - margin,
            |p| !is_outline(p) && p[0].max(p[1]).max(p[2]) > 24,
        )
        .unwrap();
        let px_x = |x: f64| {
            let (left, right) = (drawn[0] - 0.5, drawn[2] + 0.5);
            left + (x - lattice_x[0]) / (lattice_x[1] - lattice_x[0]) * (right - left)
        };
        let px_y = |y: f64| {
            let (top, bottom) = (drawn[1] - 0.5, drawn[3] + 0.5);
            bottom - (y + 1.0) / 48.0 * (bottom - top)
        };
        let want = [px_x(region_x[0]), px_y(31.0), px_x(region_x[1]), px_y(15.0)];
        let got = bbox(&img, x0..x0 + tile, 0..tile, is_outline)
            .expect("no outline on the region's slice");
        // The outline is 2 px wide, centred on the region's edge.
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 2.0,
                "{name}: outline {got:?}, from the affine {want:?} (slice drawn at {drawn:?})"
            );
        }
        // No outline on the other tiles.
        for m in (0..slices.len() as u32).filter(|&m| m != n) {
            assert!(bbox(&img, m * tile..(m + 1) * tile, 0..tile, is_outline).is_none());
        }
        // The inset: the red voxels (i 4–7) at small x, on the subject's left, shown on the
        // left (neurological, as the overview); flipped, at the larger x, on the right.
        let x0 = slices.len() as u32 * tile;
        let count = |xs: std::ops::Range<u32>| {
            let mut c = 0;
            for y in 0..side {
                for x in xs.clone() {
                    c += usize::from(is_red(img.get_pixel(x, y).0));
                }
            }
            c
        };
        let (left, right) = (count(x0..x0 + side / 2), count(x0 + side / 2..x0 + side));
        if sign > 0.0 {
            assert!(left > 1000 && right < left / 20, "{name}: {left} {right}");
        } else {
            assert!(right > 1000 && left < right / 20, "{name}: {left} {right}");
        }
    }
}

#[test]
fn bad_zoom_regions_and_tile_sizes_are_one_line_each() {
    let file = crate::data::path("dti/nrrd_masked.nrrd");
    let out = tempfile::tempdir().unwrap();
    let o_dir = out.path().join("q");
    for (option, value, want) in [
        ("--zoom-region", "4,4:8", "is not I,J,K:SIZE"),
        ("--zoom-region", "4,4,4,4:8", "is not I,J,K:SIZE"),
        ("--zoom-region", "a,4,4:8", "is not I,J,K:SIZE"),
        (
            "--zoom-region",
            "4,4,4:1",
            "the side must be 2 to 128 voxels",
        ),
        (
            "--zoom-region",
            "4,4,4:500",
            "the side must be 2 to 128 voxels",
        ),
        (
            "--tile-size",
            "64",
            "the tile side must be 128 to 1024 pixels",
        ),
        ("--tile-size", "wide", "is not a whole number of pixels"),
    ] {
        let o = tg(&[
            "report",
            file.to_str().unwrap(),
            "-o",
            o_dir.to_str().unwrap(),
            option,
            value,
        ]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{option} {value}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(option) && err.contains(want), "{err}");
        assert!(!o_dir.exists());
    }
    // A voxel outside the volume: that report fails, naming the region and the lattice.
    let o = tg(&[
        "report",
        file.to_str().unwrap(),
        "-o",
        o_dir.to_str().unwrap(),
        "--zoom-region",
        "4,4,999:8",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.starts_with(
            "error: nrrd_masked: zoom region 4,4,999:8: voxel 4,4,999 is outside the lattice"
        ),
        "{err}"
    );
    assert!(!o_dir.join("nrrd_masked.html").exists());
}
