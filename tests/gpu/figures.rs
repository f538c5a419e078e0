//! Figure export: `--ssaa N` (N×N samples per pixel, box filter), `--transparent` and `--dpi`.
//! Truth: the same scene rendered at N× the size without anti-aliasing (each pixel's alpha is
//! the share of its samples a glyph covers), and the PNG's own chunks read back by `png`.

use std::path::{Path, PathBuf};

use crate::cli::{json, stderr, tg};

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("tg-fig-{}-{name}", std::process::id()))
}

/// RGBA pixels, size and pixels per metre of a PNG.
fn read_png(path: &Path) -> (Vec<u8>, (u32, u32), Option<u32>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let size = (info.width, info.height);
    let ppm = info.pixel_dims.map(|d| {
        assert_eq!(d.unit, png::Unit::Meter);
        assert_eq!(d.xppu, d.yppu);
        d.xppu
    });
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let n = reader.next_frame(&mut buf).unwrap().buffer_size();
    buf.truncate(n);
    (buf, size, ppm)
}

#[test]
fn supersampled_alpha_is_the_covered_share_of_the_samples() {
    for method in ["gumhold", "reference"] {
        let small = tmp(&format!("{method}-ssaa.png"));
        let big = tmp(&format!("{method}-big.png"));
        let common = [
            "--demo",
            "grid:5",
            "--transparent",
            "--method",
            method,
            "-q",
        ];
        let r = tg(&[
            &[
                "render",
                "-o",
                small.to_str().unwrap(),
                "--size",
                "120x90",
                "--ssaa",
                "3",
                "--dpi",
                "300",
            ][..],
            &common[..],
        ]
        .concat());
        assert!(r.status.success(), "{}", stderr(&r));
        let r = tg(&[
            &["render", "-o", big.to_str().unwrap(), "--size", "360x270"][..],
            &common[..],
        ]
        .concat());
        assert!(r.status.success(), "{}", stderr(&r));
        let (s, size, ppm) = read_png(&small);
        let (b, _, no_ppm) = read_png(&big);
        assert_eq!(size, (120, 90));
        assert_eq!(
            ppm,
            Some((300.0f64 / 0.0254).round() as u32),
            "pHYs of 300 dpi"
        );
        assert_eq!(no_ppm, None);
        let mut partial = 0;
        for y in 0..90 {
            for x in 0..120 {
                let covered = (0..9)
                    .filter(|k| {
                        let (sx, sy) = (3 * x + k % 3, 3 * y + k / 3);
                        b[4 * (sy * 360 + sx) + 3] == 255
                    })
                    .count();
                let alpha = s[4 * (y * 120 + x) + 3];
                assert_eq!(
                    alpha,
                    (covered as f64 * 255.0 / 9.0).round() as u8,
                    "{method} pixel ({x}, {y})"
                );
                partial += usize::from(covered > 0 && covered < 9);
            }
        }
        assert!(
            partial > 50,
            "edges are anti-aliased ({partial} partial pixels)"
        );
        // Fully transparent outside: alpha 0 carries no colour.
        assert_eq!(&s[..4], &[0, 0, 0, 0]);
        std::fs::remove_file(&small).ok();
        std::fs::remove_file(&big).ok();
    }
}

#[test]
fn supersampled_frames_are_checked_against_the_reference_sampled_the_same_way() {
    let out = tmp("check.png");
    let r = tg(&[
        "render",
        "--demo",
        "grid:6",
        "-o",
        out.to_str().unwrap(),
        "--size",
        "160x120",
        "--ssaa",
        "2",
        "--reference-check",
        "--json",
        "-q",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let j = json(&r);
    assert!(j["coverage_mismatch"].as_f64().unwrap() <= 1e-3, "{j}");
    assert!(j["id_mismatch"].as_f64().unwrap() <= 1e-3, "{j}");
    assert_eq!(j["width"], 160);
    std::fs::remove_file(&out).ok();
    for (args, what) in [
        (vec!["--ssaa", "0"], "--ssaa"),
        (vec!["--ssaa", "9"], "--ssaa"),
        (vec!["--dpi", "-3"], "--dpi"),
        // The samples may exceed the image cap (they are rendered in tiles); the output may not.
        (vec!["--size", "9000x8000", "--ssaa", "2"], "8192×8192"),
    ] {
        let mut a = vec!["render", "--demo", "grid:2", "-o", out.to_str().unwrap()];
        a.extend(args);
        let r = tg(&a);
        let e = stderr(&r);
        assert_eq!(r.status.code(), Some(2), "{e}");
        assert_eq!(e.trim().lines().count(), 1, "{e}");
        assert!(e.contains(what), "{e}");
        assert!(!out.exists());
    }
}

#[test]
fn a_legend_changes_only_its_opaque_box_in_the_emptiest_corner() {
    let plain = tmp("plain.png");
    let with = tmp("legend.png");
    let base = [
        "render",
        "--demo",
        "grid:6",
        "--size",
        "640x480",
        "--transparent",
        "-q",
    ];
    let r = tg(&[&base[..], &["-o", plain.to_str().unwrap()]].concat());
    assert!(r.status.success(), "{}", stderr(&r));
    let r = tg(&[&base[..], &["-o", with.to_str().unwrap(), "--legend"]].concat());
    assert!(r.status.success(), "{}", stderr(&r));
    let (a, _, _) = read_png(&plain);
    let (b, _, _) = read_png(&with);
    // The changed pixels form one box, opaque, covering no glyph pixel of the plain image.
    let changed: Vec<(usize, usize)> = (0..480)
        .flat_map(|y| (0..640).map(move |x| (x, y)))
        .filter(|&(x, y)| a[4 * (y * 640 + x)..][..4] != b[4 * (y * 640 + x)..][..4])
        .collect();
    assert!(
        changed.len() > 2000,
        "a legend was drawn ({} pixels)",
        changed.len()
    );
    let (x0, x1) = (
        changed.iter().map(|p| p.0).min().unwrap(),
        changed.iter().map(|p| p.0).max().unwrap(),
    );
    let (y0, y1) = (
        changed.iter().map(|p| p.1).min().unwrap(),
        changed.iter().map(|p| p.1).max().unwrap(),
    );
    let mut glyph_pixels_under = 0;
    for y in y0..=y1 {
        for x in x0..=x1 {
            let i = 4 * (y * 640 + x);
            assert_eq!(b[i + 3], 255, "the legend is opaque at ({x}, {y})");
            glyph_pixels_under += usize::from(a[i + 3] == 255);
        }
    }
    // Some corner of the 6³ demo is free of glyphs at this size.
    assert_eq!(glyph_pixels_under, 0, "the legend covers glyphs");
    assert!(x0 < 20 || x1 > 620, "in a corner");
    std::fs::remove_file(&plain).ok();
    std::fs::remove_file(&with).ok();
}

/// 4800×3600 samples need more splat keys than one storage binding holds on lavapipe (128 MiB):
/// the splats give way to drawn glyphs, and the image is the same as drawing every glyph.
#[test]
fn a_figure_beyond_the_splat_buffer_draws_its_glyphs() {
    let a = tmp("big-splat.png");
    let b = tmp("big-drawn.png");
    let base = [
        "render",
        "--demo",
        "grid:4",
        "--size",
        "2400x1800",
        "--ssaa",
        "2",
        "-q",
    ];
    let r = tg(&[&base[..], &["-o", a.to_str().unwrap(), "--json"]].concat());
    assert!(r.status.success(), "{}", stderr(&r));
    let covered = json(&r)["covered_pixels"].as_u64().unwrap();
    assert!(covered > 100_000, "{covered}");
    let r = tg(&[&base[..], &["-o", b.to_str().unwrap(), "--splat", "0"]].concat());
    assert!(r.status.success(), "{}", stderr(&r));
    let (pa, _, _) = read_png(&a);
    let (pb, _, _) = read_png(&b);
    assert!(pa == pb, "splats off by the size limit = --splat 0");
    std::fs::remove_file(&a).ok();
    std::fs::remove_file(&b).ok();
}

/// The viewer's Save figure writes what `render` writes for the same camera, effects, samples,
/// legend and transparency: the same pixels, through the same renderer, filter and legend.
#[test]
fn the_viewers_save_figure_is_renders_figure() {
    use tensorglyph::Silent;
    use tensorglyph::camera::{Camera, Framing};
    use tensorglyph::effects::{Effects, Outlines};
    use tensorglyph::request::{FrameRequest, Method, Preset};
    use tensorglyph::staging::{Demo, Recipe, Source, stage};
    use tensorglyph::viewer::screenshot::{Figure, save_view};
    let Some(gpu) = crate::check::gpu() else {
        return;
    };
    let cli = tmp("render-figure.png");
    let viewer = tmp("viewer-figure.png");
    let r = tg(&[
        "render",
        "--demo",
        "grid:5",
        "-o",
        cli.to_str().unwrap(),
        "--size",
        "160x120",
        "--ssaa",
        "2",
        "--outlines",
        "--legend",
        "--transparent",
        "-q",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let staged = stage(&Source::Demo(Demo { n: 5 }), &Recipe::default(), &Silent).unwrap();
    // render frames the field's box with its defaults; the viewer's camera is given at the
    // output size and scaled to the samples.
    let camera = Camera::frame_box(
        &Framing::default(),
        staged.frame_centre,
        staged.frame_half,
        160,
        120,
    );
    let req = FrameRequest {
        background: [1.0, 1.0, 1.0, 0.0],
        effects: Effects {
            outlines: Some(Outlines::default()),
            ..Effects::default()
        }
        .resolved()
        .supersampled(2),
        ..FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT)
    };
    let figure = Figure {
        size: (160, 120),
        ssaa: 2,
        legend: Some((&staged.style, staged.glyphs_clamped, false)),
    };
    save_view(&gpu, &staged.scene, &camera, &req, &figure, &viewer).unwrap();
    let (a, size, _) = read_png(&cli);
    let (b, _, _) = read_png(&viewer);
    assert_eq!(size, (160, 120));
    let differ = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| x.abs_diff(**y) > 1)
        .count();
    assert_eq!(differ, 0, "the two figures differ in {differ} channels");
    assert!(
        a.chunks_exact(4).any(|p| p[3] == 0),
        "transparent background"
    );
    for p in [&cli, &viewer] {
        std::fs::remove_file(p).ok();
    }
}
