//! `tensorglyph report` on ODF maps (issue 39): a BIDS folder whose participants hold DIPY's CSD
//! fit of tests/data/sh under a BEP016 name (`_model-CSD_param-fod_dwimap`) beside a tensor map,
//! alone, with half its voxels zeroed, or where the name lies (a tensor map's six volumes,
//! bytes that are no image). The ODF figures are where the fit's non-zero voxels are (the
//! half-zeroed fit's figure is the whole fit's with the glyphs of the zeroed voxels gone), the
//! page states the file, lmax, basis and why, and a bad ODF map fails its participant in one
//! line naming the file while the others are written. And the files form of an MRtrix image.

use std::io::Read as _;
use std::path::Path;

use crate::cli::{stderr, tg};

const FIT: &str = "sh/dipy_lmax8_descoteaux07_legacy.nii.gz";
const ODF_NAME: &str = "model-CSD_param-fod_dwimap";

/// The fit's NIfTI bytes, uncompressed.
fn fit_bytes() -> Vec<u8> {
    let gz = std::fs::read(crate::data::path(FIT)).unwrap();
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(&gz[..])
        .read_to_end(&mut out)
        .unwrap();
    out
}

/// The fit with every coefficient of the voxels with i < 2 set to zero (float64 values,
/// coefficient after coefficient, x fastest, as NIfTI stores them).
fn half_fit() -> Vec<u8> {
    let mut b = fit_bytes();
    let dim: Vec<usize> = (0..5)
        .map(|k| i16::from_le_bytes([b[40 + 2 * k], b[41 + 2 * k]]) as usize)
        .collect();
    assert_eq!((dim[1], dim[2], dim[3], dim[4]), (4, 4, 4, 45));
    assert_eq!(i16::from_le_bytes([b[70], b[71]]), 64, "float64");
    let offset = f32::from_le_bytes(b[108..112].try_into().unwrap()) as usize;
    for c in 0..45 {
        for v in (0..64).filter(|v| v % 4 < 2) {
            let at = offset + (c * 64 + v) * 8;
            b[at..at + 8].copy_from_slice(&0f64.to_le_bytes());
        }
    }
    b
}

fn dwi(root: &Path, sub: &str) -> std::path::PathBuf {
    let d = root.join(sub).join("dwi");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// sub-01: the tensor map of tests/data/bids' sub-01 and the fit; sub-02: the fit with half
/// its voxels zeroed, alone; sub-03: the tensor map and, under the ODF name, a copy of the
/// tensor map (six volumes); sub-04: an ODF-named MRtrix image that is not one.
fn folder(root: &Path) {
    let bids = crate::data::path("bids/derivatives/sub-01/dwi");
    for sub in ["sub-01", "sub-03"] {
        let d = dwi(root, sub);
        for e in std::fs::read_dir(&bids).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().replace("sub-01", sub);
            std::fs::copy(e.path(), d.join(name)).unwrap();
        }
    }
    std::fs::copy(
        crate::data::path(FIT),
        dwi(root, "sub-01").join(format!("sub-01_{ODF_NAME}.nii.gz")),
    )
    .unwrap();
    std::fs::write(
        dwi(root, "sub-02").join(format!("sub-02_{ODF_NAME}.nii")),
        half_fit(),
    )
    .unwrap();
    std::fs::copy(
        bids.join("sub-01_model-DTI_param-tensor_dwimap.nii.gz"),
        dwi(root, "sub-03").join(format!("sub-03_{ODF_NAME}.nii.gz")),
    )
    .unwrap();
    std::fs::write(
        dwi(root, "sub-04").join("sub-04_model-CSD_param-fod.mif"),
        b"mrtrix image\nnot really\n",
    )
    .unwrap();
}

/// `report INPUT OUT participant`: every participant of the BIDS folder `input`.
fn participants(input: &Path, out: &Path) -> std::process::Output {
    tg(&[
        "report",
        input.to_str().unwrap(),
        out.to_str().unwrap(),
        "participant",
    ])
}

/// Pixels of the figure's tiles (the legend panel, 200 px at the right, left out) that glyphs
/// cover: brighter than the black background and not the labels' white or yellow.
fn glyph_pixels(img: &image::RgbaImage) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for y in 0..img.height() {
        for x in 0..img.width() - 200 {
            let p = img.get_pixel(x, y).0;
            if p[0].max(p[1]).max(p[2]) > 24 {
                out.push((x, y));
            }
        }
    }
    out
}

#[test]
fn odf_maps_are_drawn_beside_tensor_maps_and_a_bad_one_is_named() {
    let input = tempfile::tempdir().unwrap();
    folder(input.path());
    let out = tempfile::tempdir().unwrap();
    let o = participants(input.path(), out.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 2, "{err}");
    assert!(
        errors[0].starts_with("error: sub-03: ")
            && errors[0].contains(&format!("sub-03_{ODF_NAME}.nii.gz"))
            && errors[0].contains("holds no SH series (6 values per voxel"),
        "{err}"
    );
    assert!(
        errors[1].starts_with("error: sub-04: ")
            && errors[1].contains("sub-04_model-CSD_param-fod.mif"),
        "{err}"
    );
    for sub in ["sub-03", "sub-04"] {
        assert!(!out.path().join(format!("{sub}.html")).exists());
        assert!(!out.path().join(sub).exists());
    }

    // Both maps, the tensor map's section first.
    let html = std::fs::read_to_string(out.path().join("sub-01.html")).unwrap();
    let sections: Vec<&str> = html.split("<h2>").skip(1).collect();
    assert_eq!(sections.len(), 2);
    assert!(sections[0].starts_with("sub-01_model-DTI_param-tensor_dwimap.nii.gz"));
    let odf = sections[1];
    assert!(
        odf.starts_with(&format!("sub-01_{ODF_NAME}.nii.gz</h2>")),
        "{odf}"
    );
    for want in [
        "lmax 8, 45 coefficients per voxel",
        "<th>basis</th><td>descoteaux07-legacy (",
        "<th>normalisation</th><td>max: ",
        "64 (4×4×4): 64 with an ODF",
        "directions in voxel axes; world RAS from sform",
    ] {
        assert!(
            odf.contains(want),
            "{want}: {}",
            &odf[..odf.find("<figure>").unwrap()]
        );
    }
    assert_eq!(html.matches("<img ").count(), 6);
    assert!(html.contains("An ODF map's glyphs are each voxel's fibre ODF"));
    let figures = out.path().join("sub-01/figures");
    for o in ["axial", "coronal", "sagittal"] {
        assert!(figures.join(format!("sub-01_{ODF_NAME}_{o}.png")).exists());
    }

    // A participant with an ODF map only.
    let half_html = std::fs::read_to_string(out.path().join("sub-02.html")).unwrap();
    assert_eq!(half_html.matches("<h2>").count(), 1);
    assert!(half_html.contains("64 (4×4×4): 32 with an ODF"));
    assert!(!half_html.contains("ellipsoids"));

    // The glyphs are where the fit's non-zero voxels are: with half the voxels (i < 2) zeroed,
    // a row across i is the whole fit's (same slices, framing, labels) with those glyphs gone,
    // and the row along i keeps only the slices i = 2, 3.
    let mut compared = 0;
    for o in ["axial", "coronal", "sagittal"] {
        let (full_slices, half_slices) = (slices_of(&html, o), slices_of(&half_html, o));
        if half_slices != full_slices {
            assert_eq!(full_slices, "i = 0, 1, 2, 3", "{o}");
            assert_eq!(half_slices, "i = 2, 3", "{o}");
            continue;
        }
        let full = image::open(figures.join(format!("sub-01_{ODF_NAME}_{o}.png")))
            .unwrap()
            .to_rgba8();
        let half = image::open(
            out.path()
                .join(format!("sub-02/figures/sub-02_{ODF_NAME}_{o}.png")),
        )
        .unwrap()
        .to_rgba8();
        assert_eq!(full.dimensions(), half.dimensions(), "{o}");
        let (gf, gh) = (glyph_pixels(&full), glyph_pixels(&half));
        let tiles = f64::from((full.width() - 200) * full.height());
        assert!(
            gf.len() as f64 > 0.02 * tiles,
            "{o}: {} glyph pixels",
            gf.len()
        );
        let share = gh.len() as f64 / gf.len() as f64;
        assert!((0.3..0.7).contains(&share), "{o}: {share}");
        // Where the half figure is not black it is the whole one's, but at glyph edges that
        // a neighbour's silhouette or the splats' order changes.
        let differing = gh
            .iter()
            .filter(|&&(x, y)| half.get_pixel(x, y).0 != full.get_pixel(x, y).0)
            .count();
        assert!(
            (differing as f64) < 0.01 * gh.len() as f64,
            "{o}: {differing} pixels of {} differ",
            gh.len()
        );
        compared += 1;
    }
    assert!(compared >= 2, "{compared}");
}

/// The slices the page's figure of orientation `o` shows: `k = 0, 1, 2, 3`.
fn slices_of(html: &str, o: &str) -> String {
    let caption = html
        .split(&format!("<figcaption>{o}: ODF glyphs"))
        .nth(1)
        .unwrap_or_else(|| panic!("no ODF figure {o}"));
    let at = caption.find("slices ").unwrap() + "slices ".len();
    caption[at..at + caption[at..].find(';').unwrap()].to_string()
}

#[test]
fn the_files_form_draws_a_file_of_sh_series_as_odfs() {
    let out = tempfile::tempdir().unwrap();
    let mif = crate::data::path("sh/mrtrix_lmax8.mif");
    let o = tg(&[
        "report",
        mif.to_str().unwrap(),
        "-o",
        out.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let html = std::fs::read_to_string(out.path().join("mrtrix_lmax8.html")).unwrap();
    let table = &html[..html.find("<figure>").unwrap()];
    for want in [
        "lmax 8, 45 coefficients per voxel",
        "<th>basis</th><td>tournier07 (",
        "<th>format</th><td>mif</td>",
    ] {
        assert!(table.contains(want), "{want}: {table}");
    }
    assert_eq!(html.matches("<img ").count(), 3);
    let axial = image::open(
        out.path()
            .join("mrtrix_lmax8/figures/mrtrix_lmax8_axial.png"),
    )
    .unwrap()
    .to_rgba8();
    assert!(glyph_pixels(&axial).len() > 1000);
}

/// `--sh-basis` names the basis of the report's SH files: DIPY's fit saved in the non-legacy
/// descoteaux07 basis (`dipy_lmax8_descoteaux07.nii.gz`, `convert_sh_from_legacy` of the legacy
/// file's coefficients) reported with `--sh-basis descoteaux07` draws the figures of the legacy
/// file reported by default (DIPY's own basis), the page naming the basis asked for; read in the
/// default basis it draws other ODFs.
#[test]
fn sh_basis_names_the_basis_of_the_reports_series() {
    let report = |file: &str, basis: Option<&str>| {
        let out = tempfile::tempdir().unwrap();
        let path = crate::data::path(&format!("sh/{file}.nii.gz"));
        let mut args = vec![
            "report",
            path.to_str().unwrap(),
            "-o",
            out.path().to_str().unwrap(),
        ];
        if let Some(b) = basis {
            args.extend(["--sh-basis", b]);
        }
        let o = tg(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        let html = std::fs::read_to_string(out.path().join(format!("{file}.html"))).unwrap();
        let axial = image::open(out.path().join(format!("{file}/figures/{file}_axial.png")))
            .unwrap()
            .to_rgba8();
        (html, axial)
    };
    // The tiles' pixels (the legend panel, which names the basis, left out) that differ.
    let differing = |a: &image::RgbaImage, b: &image::RgbaImage| {
        assert_eq!(a.dimensions(), b.dimensions());
        let tiles = a.width() - 200;
        let mut n = 0;
        for y in 0..a.height() {
            for x in 0..tiles {
                let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
                n += usize::from(p.iter().zip(q).any(|(x, y)| x.abs_diff(y) > 2));
            }
        }
        n as f64 / f64::from(tiles * a.height())
    };
    let (_, truth) = report("dipy_lmax8_descoteaux07_legacy", None);
    let (html, asked) = report("dipy_lmax8_descoteaux07", Some("descoteaux07"));
    let table = &html[..html.find("<figure>").unwrap()];
    assert!(
        table.contains("<th>basis</th><td>descoteaux07 ("),
        "{table}"
    );
    let (_, default) = report("dipy_lmax8_descoteaux07", None);
    let same = differing(&truth, &asked);
    let other = differing(&truth, &default);
    assert!(same <= 1e-4, "with --sh-basis: {same} of the pixels differ");
    assert!(
        other >= 1e-2,
        "in the default basis: only {other} of the pixels differ"
    );
    // --odf-normalize scales the figures' ODFs as render's does, and the page says how.
    let out = tempfile::tempdir().unwrap();
    let legacy = crate::data::path("sh/dipy_lmax8_descoteaux07_legacy.nii.gz");
    let o = tg(&[
        "report",
        legacy.to_str().unwrap(),
        "-o",
        out.path().to_str().unwrap(),
        "--odf-normalize",
        "minmax",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let stem = "dipy_lmax8_descoteaux07_legacy";
    let html = std::fs::read_to_string(out.path().join(format!("{stem}.html"))).unwrap();
    assert!(
        html.contains("<th>normalisation</th><td>minmax: "),
        "{}",
        &html[..html.find("<figure>").unwrap()]
    );
    let minmax = image::open(out.path().join(format!("{stem}/figures/{stem}_axial.png")))
        .unwrap()
        .to_rgba8();
    let changed = differing(&truth, &minmax);
    assert!(
        changed >= 1e-2,
        "minmax changed only {changed} of the pixels"
    );
    let o = tg(&[
        "report",
        "x.mif",
        "-o",
        "/nonexistent",
        "--sh-basis",
        "mrtrix",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("invalid value 'mrtrix' for '--sh-basis"),
        "{}",
        stderr(&o)
    );
}

/// The sticks of peaks each ODF figure's inset draws over its ODFs, as its caption states.
fn inset_peaks(html: &str) -> Vec<Option<usize>> {
    ["axial", "coronal", "sagittal"]
        .iter()
        .map(|o| {
            let caption = html
                .split(&format!("<figcaption>{o}: ODF glyphs"))
                .nth(1)
                .unwrap();
            let caption = &caption[..caption.find("</figcaption>").unwrap()];
            let at = caption.find(" peaks (sticks)")?;
            let n = caption[..at].rsplit(", ").next().unwrap();
            Some(n.parse().unwrap())
        })
        .collect()
}

/// The inset each ODF figure's caption states: (region, px per voxel, glyphs drawn, why).
fn odf_insets(html: &str) -> Vec<(String, f64, usize, String)> {
    ["axial", "coronal", "sagittal"]
        .iter()
        .map(|o| {
            let caption = html
                .split(&format!("<figcaption>{o}: ODF glyphs"))
                .nth(1)
                .unwrap_or_else(|| panic!("no ODF figure {o}"));
            let caption = &caption[..caption.find("</figcaption>").unwrap()];
            let inset = caption
                .split("inset (cyan outline): voxels ")
                .nth(1)
                .unwrap_or_else(|| panic!("{o}: no inset in {caption}"));
            let region = inset[..inset.find(" (").unwrap()].to_string();
            let parts: Vec<&str> = inset[inset.find("), ").unwrap() + 3..]
                .split(", ")
                .collect();
            let why = parts[0].to_string();
            let px: f64 = parts[1].trim_end_matches(" px per voxel").parse().unwrap();
            let glyphs: usize = parts[2].trim_end_matches(" glyphs drawn").parse().unwrap();
            (region, px, glyphs, why)
        })
        .collect()
}

/// An ODF figure has the tensor figures' zoomed inset: by default the square of the middle
/// slice where the fibre density sums highest (here, the lattice being 4 voxels across, the
/// whole slice), at 8 px per voxel or more, its glyphs the voxels of the region that hold a
/// series (all 16 of the fit's, 8 of the half-zeroed fit's where i < 2 is cut, all 16 again on
/// the half fit's row along i, whose middle slice is i = 3); `--zoom-region` picks another.
#[test]
fn odf_figures_have_the_zoomed_inset() {
    let dir = tempfile::tempdir().unwrap();
    let half = dir.path().join("half.nii");
    std::fs::write(&half, half_fit()).unwrap();
    let full = crate::data::path(FIT);
    let report = |file: &Path, zoom: Option<&str>| {
        let out = dir.path().join(format!("out{}", zoom.is_some()));
        let mut args = vec![
            "report",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(z) = zoom {
            args.extend(["--zoom-region", z]);
        }
        let o = tg(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let name = file.file_name().unwrap().to_str().unwrap();
        let stem = name.split('.').next().unwrap();
        std::fs::read_to_string(out.join(format!("{stem}.html"))).unwrap()
    };
    let chosen = "where the fibre density (l = 0) is highest on the middle slice";
    let page = report(&full, None);
    let whole = odf_insets(&page);
    // Over the inset's ODFs, the sticks of their peaks: as many as `render --glyph peaks`
    // draws for the same slice (the axial inset is the whole slice k = 2).
    let sticks = {
        let out = dir.path().join("peaks.png");
        let o = tg(&[
            "render",
            full.to_str().unwrap(),
            "--glyph",
            "peaks",
            "--slice",
            "z=2",
            "--method",
            "reference",
            "--size",
            "64x48",
            "--json",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        crate::cli::json(&o)["glyphs_selected"].as_u64().unwrap() as usize
    };
    let peaks = inset_peaks(&page);
    assert_eq!(peaks[0], Some(sticks), "{peaks:?}");
    assert!(
        peaks.iter().all(|p| p.is_some_and(|n| n >= 16)),
        "{peaks:?}"
    );
    for (o, (region, px, glyphs, why)) in ["axial", "coronal", "sagittal"].iter().zip(&whole) {
        assert_eq!((*glyphs, why.as_str()), (16, chosen), "{o}: {region}");
        assert!(*px >= 8.0, "{o}: {px} px per voxel");
    }
    assert_eq!(whole[0].0, "i 0–3, j 0–3, k = 2");
    // Which orientation's slices run along i is the affine's to say: the row along i keeps
    // its 16, the two across it their 8.
    let halved = odf_insets(&report(&half, None));
    for (region, _, glyphs, _) in &halved {
        let along_i = region.ends_with("i = 3");
        assert_eq!(*glyphs, if along_i { 16 } else { 8 }, "{halved:?}");
    }
    assert_eq!(halved.iter().filter(|i| i.0.ends_with("i = 3")).count(), 1);
    let zoomed = odf_insets(&report(&full, Some("0,0,1:2")));
    assert_eq!(zoomed[0].0, "i 0–1, j 0–1, k = 1");
    for (region, _, glyphs, why) in &zoomed {
        assert_eq!(
            (*glyphs, why.as_str()),
            (4, "as asked (zoom region)"),
            "{region}"
        );
    }
}

/// An ODF map's page counts the peaks of its voxels as DIPY's `peak_directions_nl` finds them
/// with `peaks_from_model`'s settings (half the largest, 25° apart): the fit with every voxel
/// zeroed but the 16 whose peaks DIPY found for tests/data/sh/expected.json, so that the
/// page's sample is exactly those 16.
#[test]
fn the_peak_counts_are_dipys() {
    let text = std::fs::read_to_string(crate::data::path("sh/expected.json")).unwrap();
    let truth: serde_json::Value = serde_json::from_str(&text).unwrap();
    let peaks = truth["files"]["dipy_lmax8_descoteaux07_legacy.nii.gz"]["peaks"]
        .as_object()
        .unwrap();
    let kept: Vec<usize> = peaks.keys().map(|k| k.parse().unwrap()).collect();
    let counts: Vec<usize> = peaks
        .values()
        .map(|p| p["directions"].as_array().unwrap().len())
        .collect();
    let mut b = fit_bytes();
    let offset = f32::from_le_bytes(b[108..112].try_into().unwrap()) as usize;
    for c in 0..45 {
        for v in (0..64).filter(|v| !kept.contains(v)) {
            let at = offset + (c * 64 + v) * 8;
            b[at..at + 8].copy_from_slice(&0f64.to_le_bytes());
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sixteen.nii");
    std::fs::write(&file, b).unwrap();
    let out = dir.path().join("out");
    let o = tg(&[
        "report",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let html = std::fs::read_to_string(out.join("sixteen.html")).unwrap();
    let row = html
        .split("<th>peaks</th><td>")
        .nth(1)
        .expect("a peaks row");
    let row = &row[..row.find("</td>").unwrap()];
    let n = counts.len() as f64;
    let share = |k: usize| {
        let c = counts.iter().filter(|&&c| c.min(3) == k).count();
        format!("{:.1} %", 100.0 * c as f64 / n)
    };
    let mean = counts.iter().sum::<usize>() as f64 / n;
    let want = format!(
        "{mean:.2} per voxel; none {}, one {}, two {}, three or more {}; crossing (two or more) \
         {:.1} % — in all 16 voxels with an ODF;",
        share(0),
        share(1),
        share(2),
        share(3),
        100.0 * counts.iter().filter(|&&c| c >= 2).count() as f64 / n
    );
    assert!(row.starts_with(&want), "{row}\nwant {want}");
}

/// `--color amplitude` colours the ODF figures by amplitude (viridis), as `render --color
/// amplitude` does: the same glyphs (the pixels they cover are the DEC figure's), other
/// colours, the page saying so; tensor maps stay DEC; a colouring the report has not is one line.
#[test]
fn color_amplitude_recolours_the_odf_figures_only() {
    let dir = tempfile::tempdir().unwrap();
    let mif = crate::data::path("sh/mrtrix_lmax8.mif");
    let figure = |color: &str| {
        let out = dir.path().join(color);
        let o = tg(&[
            "report",
            mif.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--color",
            color,
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let html = std::fs::read_to_string(out.join("mrtrix_lmax8.html")).unwrap();
        let png = out.join("mrtrix_lmax8/figures/mrtrix_lmax8_axial.png");
        (html, image::open(png).unwrap().to_rgba8())
    };
    let (dec_html, dec) = figure("dec");
    let (amp_html, amp) = figure("amplitude");
    assert!(dec_html.contains("coloured by direction (red R–L"));
    assert!(amp_html.contains("coloured by amplitude (viridis"));
    assert_eq!(dec.dimensions(), amp.dimensions());
    // The tiles and the inset, not the legend panel (its key differs).
    let (gd, ga) = (glyph_pixels(&dec), glyph_pixels(&amp));
    let same_place = gd.iter().filter(|p| ga.contains(p)).count();
    assert!(
        same_place as f64 > 0.97 * gd.len().max(ga.len()) as f64,
        "{same_place} of {} / {}",
        gd.len(),
        ga.len()
    );
    let recoloured = gd
        .iter()
        .filter(|&&(x, y)| dec.get_pixel(x, y).0 != amp.get_pixel(x, y).0)
        .count();
    // The rest are the labels, the tile borders and the inset's outline (16 % of the pixels
    // here), drawn alike in both.
    assert!(
        recoloured as f64 > 0.75 * gd.len() as f64,
        "{recoloured} of {}",
        gd.len()
    );
    let o = tg(&[
        "report",
        mif.to_str().unwrap(),
        "-o",
        dir.path().join("bad").to_str().unwrap(),
        "--color",
        "fa",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the report colours ODFs by dec or amplitude"),
        "{err}"
    );
}

/// How many peaks each voxel of the test data's JSON `file` holds (the object at `pointer`, a
/// voxel's peaks the array `key` of its entry), voxels with none left out.
fn peak_counts(file: &str, pointer: &str, key: &str) -> Vec<usize> {
    let text = std::fs::read_to_string(crate::data::path(file)).unwrap();
    let truth: serde_json::Value = serde_json::from_str(&text).unwrap();
    truth
        .pointer(pointer)
        .and_then(|v| v.as_object())
        .unwrap()
        .values()
        .map(|v| v[key].as_array().unwrap().len())
        .filter(|&n| n > 0)
        .collect()
}

/// The page's peaks row for voxels holding `counts` peaks each (those with none left out), as
/// the counts make it: the mean, the shares with one, two and three or more, the crossing share.
fn peaks_row(counts: &[usize]) -> String {
    let n = counts.len() as f64;
    let share = |k: usize| counts.iter().filter(|&&c| c.min(3) == k).count() as f64 / n;
    let pct = |x: f64| format!("{:.1} %", 100.0 * x);
    format!(
        "{:.2} per voxel; one {}, two {}, three or more {}; crossing (two or more) {} — in all {} \
         voxels with a peak",
        counts.iter().sum::<usize>() as f64 / n,
        pct(share(1)),
        pct(share(2)),
        pct(share(3)),
        pct(share(2) + share(3)),
        counts.len()
    )
}

/// A peaks map's report (DIPY's `peak_dirs` as `peaks_from_model` holds them, X×Y×Z×N×3): its
/// page counts the peaks of every voxel as DIPY found them (`tests/data/sh/dipy_peaks.json`,
/// read back by nibabel), and each figure draws every peak as a stick (the lattice being 4
/// voxels across, every slice), with the zoomed inset.
#[test]
fn a_peaks_map_reports_its_sticks_and_counts() {
    let counts = peak_counts("sh/dipy_peaks.json", "/voxels", "voxel_axes");
    let total: usize = counts.iter().sum();
    let want = peaks_row(&counts);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let file = crate::data::path("sh/dipy5d_peak_dirs.nii.gz");
    let o = tg(&[
        "report",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let html = std::fs::read_to_string(out.join("dipy5d_peak_dirs.html")).unwrap();
    assert!(html.contains(&want), "want {want} in:\n{html}");
    for o in ["axial", "coronal", "sagittal"] {
        let caption = html
            .split(&format!("<figcaption>{o}: peaks (sticks)"))
            .nth(1)
            .unwrap_or_else(|| panic!("no peaks figure {o}"));
        assert!(
            caption.contains(&format!("; {total} sticks drawn;")),
            "{o}: {total} sticks in {caption}"
        );
        assert!(caption.contains("inset (cyan outline)"), "{caption}");
        let png = out
            .join("dipy5d_peak_dirs")
            .join("figures")
            .join(format!("dipy5d_peak_dirs_{o}.png"));
        assert!(std::fs::metadata(png).unwrap().len() > 1000);
    }
}

/// A BIDS participant's peaks map (`param-peaks`): MRtrix's `sh2peaks` image converted to a
/// NIfTI file of 9 volumes, which its header cannot tell from a 3×3 tensor: the name says peaks,
/// and the page counts the peaks `make_sh.py` read back from the same `sh2peaks` output through
/// nibabel (`expected.json`), beside the participant's ODF map.
#[test]
fn a_bids_peaks_map_is_read_as_its_name_says() {
    let counts = peak_counts(
        "sh/expected.json",
        "/files/mrtrix_lmax8.mif/peaks",
        "directions",
    );
    let input = tempfile::tempdir().unwrap();
    let d = dwi(input.path(), "sub-p");
    std::fs::copy(
        crate::data::path("sh/sh2peaks_lmax8.nii.gz"),
        d.join("sub-p_model-CSD_param-peaks_dwimap.nii.gz"),
    )
    .unwrap();
    std::fs::copy(
        crate::data::path("sh/mrtrix_lmax8.nii.gz"),
        d.join("sub-p_model-CSD_param-fod_dwimap.nii.gz"),
    )
    .unwrap();
    let out = tempfile::tempdir().unwrap();
    let o = participants(input.path(), out.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let html = std::fs::read_to_string(out.path().join("sub-p.html")).unwrap();
    let odf = html.find("<h2>sub-p_model-CSD_param-fod_dwimap.nii.gz</h2>");
    let peaks = html.find("<h2>sub-p_model-CSD_param-peaks_dwimap.nii.gz</h2>");
    assert!(
        odf.is_some() && peaks > odf,
        "the ODF map, then the peaks map:\n{html}"
    );
    let want = peaks_row(&counts);
    assert!(html.contains(&want), "want {want} in:\n{html}");
    assert!(html.contains("<figcaption>axial: peaks (sticks)"), "{html}");
}
