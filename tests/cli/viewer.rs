//! End to end: start `tensorglyph view --demo grid40` under Xvfb in scripted mode, take the
//! whole-window screenshot and check that the 3D area shows glyphs and the panel is drawn.
//!
//! Without Xvfb (and without `CI` set) the test is skipped with a message; under `CI` it must run.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn pixel(img: &image::RgbaImage, x: u32, y: u32) -> [u8; 4] {
    img.get_pixel(x, y).0
}

#[test]
fn scripted_screenshot_shows_glyphs_and_panel() {
    let Some((_xvfb, display)) = crate::xvfb::start_xvfb(90) else {
        if std::env::var_os("CI").is_some() {
            panic!("CI is set but Xvfb could not be started (is the xvfb package installed?)");
        }
        eprintln!("skipped: no X server could be started (install xvfb to run this test)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("viewer.png");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tensorglyph"))
        .args([
            "view",
            "--demo",
            "grid40",
            "--size",
            "1100x700",
            "--frames",
            "3",
            "--screenshot",
            out.to_str().unwrap(),
        ])
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

    // The panel (left 250 points) is egui's dark panel with text on it.
    let mut panel_colours = std::collections::HashSet::new();
    let mut dark = 0usize;
    let mut n = 0usize;
    for y in (0..h).step_by(3) {
        for x in (0..250.min(w)).step_by(3) {
            let p = pixel(&img, x, y);
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

    // The 3D area (right half) has a white background and coloured glyphs.
    let mut white = 0usize;
    let mut coloured = 0usize;
    let mut m = 0usize;
    for y in (0..h).step_by(2) {
        for x in (w / 2..w).step_by(2) {
            let p = pixel(&img, x, y);
            m += 1;
            if p[0] > 245 && p[1] > 245 && p[2] > 245 {
                white += 1;
            }
            let max = p[0].max(p[1]).max(p[2]);
            let min = p[0].min(p[1]).min(p[2]);
            if max - min > 60 {
                coloured += 1;
            }
        }
    }
    assert!(white * 10 > m, "background visible: {white} of {m}");
    assert!(
        coloured * 10 > m,
        "glyphs visible: {coloured} coloured of {m} samples"
    );
}
