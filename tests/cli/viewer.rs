//! End to end: start `tensorglyph view` under Xvfb in scripted mode (grid40; a DIPY CSD fit of
//! SH series), take the whole-window screenshot and check that the 3D area shows glyphs and the
//! panel is drawn.
//!
//! Without Xvfb (and without `CI` set) the test is skipped with a message; under `CI` it must run.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn pixel(img: &image::RgbaImage, x: u32, y: u32) -> [u8; 4] {
    img.get_pixel(x, y).0
}

/// The scripted window of `view ARGS --size 1100x700 --frames 3` on an X server of displays
/// from `base` (each test its own: they run at once), or `None` (skipped) without one outside
/// CI.
fn screenshot(base: u32, args: &[&str]) -> Option<image::RgbaImage> {
    let Some((_xvfb, display)) = crate::xvfb::start_xvfb(base) else {
        if std::env::var_os("CI").is_some() {
            panic!("CI is set but Xvfb could not be started (is the xvfb package installed?)");
        }
        eprintln!("skipped: no X server could be started (install xvfb to run this test)");
        return None;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("viewer.png");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .arg("view")
        .args(args)
        .args(["--size", "1100x700", "--frames", "3", "--screenshot"])
        .arg(&out)
        .env("DISPLAY", &display)
        .env_remove("WAYLAND_DISPLAY")
        .env("WGPU_BACKEND", "vulkan")
        .env("XDG_RUNTIME_DIR", dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run tensorglyph view");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(300) {
            let _ = child.kill();
            panic!("the viewer did not exit within 300 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(status.success(), "viewer failed: {status}\n{stderr}");
    let img = image::open(&out).expect("a readable PNG").to_rgba8();
    let (w, h) = img.dimensions();
    assert!(w >= 800 && h >= 500, "window screenshot is {w}x{h}");
    Some(img)
}

/// The panel (left 250 points) is egui's dark panel with text on it.
fn assert_panel(img: &image::RgbaImage) {
    let (w, h) = img.dimensions();
    let mut panel_colours = std::collections::HashSet::new();
    let mut dark = 0usize;
    let mut n = 0usize;
    for y in (0..h).step_by(3) {
        for x in (0..250.min(w)).step_by(3) {
            let p = pixel(img, x, y);
            panel_colours.insert(p);
            n += 1;
            if p[0] < 80 && p[1] < 80 && p[2] < 80 {
                dark += 1;
            }
        }
    }
    assert!(
        dark * 2 > n,
        "the panel should be mostly dark: {dark} of {n} samples"
    );
    assert!(
        panel_colours.len() > 20,
        "the panel should have text and widgets ({} colours)",
        panel_colours.len()
    );
}

#[test]
fn scripted_screenshot_shows_glyphs_and_panel() {
    let Some(img) = screenshot(90, &["--demo", "grid40"]) else {
        return;
    };
    assert_panel(&img);
    // The 3D area (right half) has a white background and coloured glyphs.
    let (white, coloured, m) = view_area(&img, |p| p[0] > 245 && p[1] > 245 && p[2] > 245);
    assert!(white * 10 > m, "background visible: {white} of {m}");
    assert!(
        coloured * 10 > m,
        "glyphs visible: {coloured} coloured of {m} samples"
    );
}

/// A file of SH series opens in the viewer as `render` draws it: ODF glyphs of the middle axial
/// slice on DTI's black background, coloured by direction (red, green and blue lobes all there).
#[test]
fn sh_series_open_as_odf_glyphs() {
    let file = crate::data::path("sh/dipy_lmax8_descoteaux07_legacy.nii.gz");
    let Some(img) = screenshot(220, &[file.to_str().unwrap()]) else {
        return;
    };
    assert_panel(&img);
    let (black, coloured, m) = view_area(&img, |p| p[0] < 10 && p[1] < 10 && p[2] < 10);
    assert!(black * 2 > m, "background visible: {black} of {m}");
    assert!(
        coloured * 50 > m,
        "glyphs visible: {coloured} coloured of {m} samples"
    );
    let (w, h) = img.dimensions();
    let mut dominant = [0usize; 3];
    for y in (0..h).step_by(2) {
        for x in (w / 2..w).step_by(2) {
            let p = pixel(&img, x, y);
            let (k, &top) = p[..3].iter().enumerate().max_by_key(|(_, c)| **c).unwrap();
            let rest = p[..3].iter().map(|&c| u32::from(c)).sum::<u32>() - u32::from(top);
            if top > 120 && u32::from(top) > rest {
                dominant[k] += 1;
            }
        }
    }
    assert!(
        dominant.iter().all(|&n| n > 20),
        "lobes of every direction (red, green, blue pixels): {dominant:?}"
    );
}

/// A file of peaks (MRtrix's sh2peaks image) opens in the viewer as `render` draws it: sticks
/// of the middle axial slice on black, coloured by direction.
#[test]
fn peaks_open_as_sticks() {
    let file = crate::data::path("sh/sh2peaks_lmax8.mif");
    let Some(img) = screenshot(230, &[file.to_str().unwrap()]) else {
        return;
    };
    assert_panel(&img);
    let (black, coloured, m) = view_area(&img, |p| p[0] < 10 && p[1] < 10 && p[2] < 10);
    assert!(black * 2 > m, "background visible: {black} of {m}");
    assert!(
        coloured * 100 > m,
        "sticks visible: {coloured} coloured of {m} samples"
    );
}

/// Samples of the 3D area (the window's right half): those `background` accepts, those with
/// colour (channels apart by more than 60), and all.
fn view_area(
    img: &image::RgbaImage,
    background: impl Fn([u8; 4]) -> bool,
) -> (usize, usize, usize) {
    let (w, h) = img.dimensions();
    let (mut bg, mut coloured, mut m) = (0, 0, 0);
    for y in (0..h).step_by(2) {
        for x in (w / 2..w).step_by(2) {
            let p = pixel(img, x, y);
            m += 1;
            bg += usize::from(background(p));
            let max = p[0].max(p[1]).max(p[2]);
            let min = p[0].min(p[1]).min(p[2]);
            coloured += usize::from(max - min > 60);
        }
    }
    (bg, coloured, m)
}
