//! A report's HTML page: one self-contained file (the figures embedded as data URLs, the style
//! inline, nothing fetched), stating what was read, assumed and measured.

use std::fmt::Write as _;

use base64::Engine as _;

use super::mosaic::InsetInfo;
use super::stats::Summary;
use super::{FigureReport, MapReport, OdfReport, RunInfo, Section};

/// `s` as HTML text.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn summary(s: &Option<Summary>, digits: usize) -> String {
    s.map_or("none (no valid tensor)".into(), |s| {
        format!(
            "min {:.digits$}, median {:.digits$}, mean {:.digits$}, max {:.digits$}",
            s.min, s.median, s.mean, s.max
        )
    })
}

/// The MD's numbers in the units it is stored in, with 4 significant digits.
fn md_summary(s: &Option<Summary>) -> String {
    s.map_or("none (no valid tensor)".into(), |s| {
        let f = crate::legend::short_number;
        format!(
            "min {}, median {}, mean {}, max {}",
            f(s.min),
            f(s.median),
            f(s.mean),
            f(s.max)
        )
    })
}

/// How many pixels a voxel gets in the overview tiles, and how much of a voxel a pixel spans.
fn overview_scale(px_per_voxel: f64) -> String {
    if !px_per_voxel.is_finite() {
        return String::new();
    }
    format!(
        "overview tiles {px_per_voxel:.1} px per voxel (one pixel spans {:.2} voxel)",
        1.0 / px_per_voxel
    )
}

/// The inset's caption: its voxels, where they are in the world, its scale and glyphs.
fn inset(i: &InsetInfo, anatomical: bool) -> String {
    let unit = if anatomical { " mm" } else { "" };
    let world: Vec<String> = ["x", "y", "z"]
        .iter()
        .zip(i.world)
        .map(|(name, [lo, hi])| {
            if (hi - lo).abs() < 0.05 {
                format!("{name} {lo:.1}")
            } else {
                format!("{name} {lo:.1} to {hi:.1}")
            }
        })
        .collect();
    let why = match i.chosen_by {
        Some(what) => format!("where {what} is highest on the middle slice"),
        None => "as asked (zoom region)".into(),
    };
    let peaks = i
        .peaks
        .map_or(String::new(), |n| format!(", {n} peaks (sticks)"));
    format!(
        "; inset (cyan outline): voxels {} ({}{unit}), {why}, {:.1} px per voxel, {} glyphs \
         drawn{peaks}",
        i.region.describe(),
        world.join(", "),
        i.px_per_voxel,
        i.glyphs_drawn
    )
}

fn section(page: &mut String, map: &MapReport, timings: bool) {
    let _ = writeln!(page, "<h2>{}</h2>\n<table>", esc(&map.name));
    let mut row = |k: &str, v: String| {
        let _ = writeln!(page, "<tr><th>{k}</th><td>{v}</td></tr>");
    };
    row("input", esc(&map.path));
    if let Some(s) = &map.session {
        row("session", esc(s));
    }
    row("format", esc(&map.format));
    if let Some(l) = &map.layout {
        row("layout", esc(l));
    }
    if let Some(f) = &map.frame {
        row("frame", esc(f));
    }
    for n in &map.notes {
        row("note", esc(n));
    }
    row("units", esc(&map.units));
    let [nx, ny, nz] = map.dims;
    row(
        "tensors",
        format!(
            "{} ({nx}×{ny}×{nz}): {} valid; skipped {} NaN, {} Inf, {} zero, {} masked, {} \
             beyond ±3.4e38; {} clamped by <code>--scale auto</code>",
            map.tensors,
            map.valid,
            map.skipped.nan,
            map.skipped.inf,
            map.skipped.zero,
            map.skipped.masked,
            map.skipped.overflow,
            map.clamped
        ),
    );
    row("FA", summary(&map.fa, 4));
    row("MD", md_summary(&map.md));
    let figures: Vec<String> = map
        .figures
        .iter()
        .map(|f| format!("{} {:.0} ms", f.orientation, f.ms))
        .collect();
    if timings {
        row(
            "timings",
            format!(
                "read {:.0} ms, decompose {:.0} ms; figures: {}",
                map.read_ms,
                map.decompose_ms,
                figures.join(", ")
            ),
        );
    }
    let _ = writeln!(page, "</table>");
    for f in &map.figures {
        let axis = ["i", "j", "k"][f.lattice_axis];
        let slices: Vec<String> = f.slices.iter().map(|s| s.to_string()).collect();
        let underlay = f.underlay_missing.as_ref().map_or(String::new(), |why| {
            format!(
                "; no FA underlay ({})",
                esc(why.trim_start_matches("--underlay "))
            )
        });
        let caption = format!(
            "slices {axis} = {s}; {n} glyphs drawn{underlay}; {scale}{inset}",
            s = slices.join(", "),
            n = f.glyphs_drawn,
            scale = overview_scale(f.overview_px_per_voxel),
            inset = f
                .inset
                .as_ref()
                .map_or(String::new(), |i| inset(i, map.anatomical)),
        );
        embed(page, f, &caption);
    }
}

/// A figure, embedded, with its caption.
fn embed(page: &mut String, f: &FigureReport, caption: &str) {
    let _ = writeln!(
        page,
        "<figure><img alt=\"{o}\" width=\"{w}\" height=\"{h}\" \
         src=\"data:image/png;base64,{b64}\"><figcaption>{o}: {caption}</figcaption></figure>",
        o = f.orientation,
        w = f.width,
        h = f.height,
        b64 = base64::engine::general_purpose::STANDARD.encode(&f.png),
    );
}

fn odf_section(page: &mut String, map: &OdfReport, timings: bool) {
    let _ = writeln!(page, "<h2>{}</h2>\n<table>", esc(&map.name));
    let mut row = |k: &str, v: String| {
        let _ = writeln!(page, "<tr><th>{k}</th><td>{v}</td></tr>");
    };
    row("input", esc(&map.path));
    if let Some(s) = &map.session {
        row("session", esc(s));
    }
    row("format", esc(&map.format));
    row("content", "ODF map: SH coefficients (fibre ODFs)".into());
    row(
        "series",
        format!(
            "lmax {}, {} coefficients per voxel; {}",
            map.lmax,
            map.count,
            esc(&map.recognised)
        ),
    );
    row(
        "basis",
        format!("{} ({})", esc(&map.basis), esc(&map.basis_reason)),
    );
    row("frame", esc(&map.frame));
    let [nx, ny, nz] = map.dims;
    row(
        "voxels",
        format!(
            "{} ({nx}×{ny}×{nz}): {} with an ODF (a series not all zero), drawn",
            nx * ny * nz,
            map.held
        ),
    );
    if let Some(p) = &map.peaks {
        let pct = |x: f64| format!("{:.1} %", 100.0 * x);
        let sample = if p.sampled == p.of {
            format!("all {} voxels with an ODF", p.of)
        } else {
            format!(
                "{} of the {} voxels with an ODF (every k-th)",
                p.sampled, p.of
            )
        };
        row(
            "peaks",
            format!(
                "{:.2} per voxel; none {}, one {}, two {}, three or more {}; crossing (two or \
                 more) {} — in {sample}; a peak is a maximum at least half the largest, 25° from \
                 a larger one (DIPY's peaks_from_model settings)",
                p.mean,
                pct(p.shares[0]),
                pct(p.shares[1]),
                pct(p.shares[2]),
                pct(p.shares[3]),
                pct(p.crossing_share()),
            ),
        );
    }
    row(
        "normalisation",
        format!(
            "{}: {}",
            map.normalize.name(),
            match map.normalize {
                crate::scene::odf::OdfNormalize::Max =>
                    "each voxel's ODF scaled to its own largest value (DIPY's odf_slicer norm)",
                crate::scene::odf::OdfNormalize::MinMax =>
                    "each voxel's [min, max] mapped to [0, 1]",
                crate::scene::odf::OdfNormalize::None => "one scale for every voxel",
            }
        ),
    );
    let figures: Vec<String> = map
        .figures
        .iter()
        .map(|f| format!("{} {:.0} ms", f.orientation, f.ms))
        .collect();
    if timings {
        row(
            "timings",
            format!(
                "read {:.0} ms; peaks {:.0} ms; figures: {}",
                map.read_ms,
                map.peaks_ms,
                figures.join(", ")
            ),
        );
    }
    let _ = writeln!(page, "</table>");
    for f in &map.figures {
        let axis = ["i", "j", "k"][f.lattice_axis];
        let slices: Vec<String> = f.slices.iter().map(|s| s.to_string()).collect();
        let caption = format!(
            "ODF glyphs (lmax {}, {}, normalised {}), slices {axis} = {}; {} glyphs drawn; \
             no underlay; {}{}",
            map.lmax,
            esc(&map.basis),
            map.normalize.name(),
            slices.join(", "),
            f.glyphs_drawn,
            overview_scale(f.overview_px_per_voxel),
            f.inset
                .as_ref()
                .map_or(String::new(), |i| inset(i, map.anatomical)),
        );
        embed(page, f, &caption);
    }
}

fn peaks_section(page: &mut String, map: &super::peaks::PeaksReport, timings: bool) {
    let _ = writeln!(page, "<h2>{}</h2>\n<table>", esc(&map.name));
    let mut row = |k: &str, v: String| {
        let _ = writeln!(page, "<tr><th>{k}</th><td>{v}</td></tr>");
    };
    row("input", esc(&map.path));
    if let Some(s) = &map.session {
        row("session", esc(s));
    }
    row("format", esc(&map.format));
    row(
        "content",
        format!(
            "peaks map: fibre directions, up to {} a voxel",
            map.per_voxel
        ),
    );
    row("frame", esc(&map.frame));
    let [nx, ny, nz] = map.dims;
    let c = &map.counts;
    row(
        "voxels",
        format!(
            "{} ({nx}×{ny}×{nz}): {} with a peak, drawn",
            nx * ny * nz,
            c.held
        ),
    );
    let pct = |x: f64| format!("{:.1} %", 100.0 * x);
    row(
        "peaks",
        format!(
            "{:.2} per voxel; one {}, two {}, three or more {}; crossing (two or more) {} — in \
             all {} voxels with a peak, as the file holds them",
            c.mean,
            pct(c.shares[0]),
            pct(c.shares[1]),
            pct(c.shares[2]),
            pct(c.crossing_share()),
            c.held
        ),
    );
    if timings {
        let figures: Vec<String> = map
            .figures
            .iter()
            .map(|f| format!("{} {:.0} ms", f.orientation, f.ms))
            .collect();
        row(
            "timings",
            format!(
                "read {:.0} ms; figures: {}",
                map.read_ms,
                figures.join(", ")
            ),
        );
    }
    let _ = writeln!(page, "</table>");
    for f in &map.figures {
        let axis = ["i", "j", "k"][f.lattice_axis];
        let slices: Vec<String> = f.slices.iter().map(|s| s.to_string()).collect();
        let caption = format!(
            "peaks (sticks), slices {axis} = {}; {} sticks drawn; no underlay; {}{}",
            slices.join(", "),
            f.glyphs_drawn,
            overview_scale(f.overview_px_per_voxel),
            f.inset
                .as_ref()
                .map_or(String::new(), |i| inset(i, map.anatomical)),
        );
        embed(page, f, &caption);
    }
}

/// The page of `label` (a participant's `sub-<label>`, or a file's name) and its maps.
pub fn html(title: &str, maps: &[Section], run: &RunInfo) -> String {
    let mut body = String::new();
    for m in maps {
        match m {
            Section::Tensor(m) => section(&mut body, m, run.timings),
            Section::Odf(m) => odf_section(&mut body, m, run.timings),
            Section::Peaks(m) => peaks_section(&mut body, m, run.timings),
        }
    }
    let mut glyphs = String::new();
    if maps.iter().any(|m| matches!(m, Section::Tensor(_))) {
        glyphs.push_str(
            "A tensor map's glyphs are ellipsoids of the same size, coloured by the direction \
             of the largest eigenvector (DEC: red R–L, green A–P, blue S–I, scaled by FA), over \
             the FA of each slice. ",
        );
    }
    for m in maps {
        let Section::Odf(m) = m else { continue };
        let colour = match m.coloring {
            crate::shape::odf::OdfColoring::Amplitude => {
                "coloured by amplitude (viridis, 0 to the full radius)"
            }
            _ => "coloured by direction (red R–L, green A–P, blue S–I)",
        };
        glyphs.push_str(&format!(
            "An ODF map's glyphs are each voxel's fibre ODF (its SH series' radius in every \
             direction, negative values not drawn), sized to the voxel and {colour}, on black. "
        ));
        break;
    }
    if maps.iter().any(|m| matches!(m, Section::Peaks(_))) {
        glyphs.push_str(
            "A peaks map's glyphs are sticks, one a peak, through their voxel's centre along              the peak, as long as its amplitude (the map's largest one voxel step), coloured by              direction (red R–L, green A–P, blue S–I), on black. ",
        );
    }
    let peak = run
        .peak_rss_bytes
        .map_or("not known on this system".into(), |b| {
            format!("{:.0} MiB (the process's, so far)", b as f64 / 1048576.0)
        });
    let cost = if run.timings {
        format!(
            "<p>Time for this page {:.0} ms; peak memory {peak}.</p>\n",
            run.total_ms
        )
    } else {
        String::new()
    };
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{title}: tensorglyph report</title>\n<style>body{{font-family:sans-serif;\
         margin:2em;max-width:1600px}}th{{text-align:left;padding-right:1em;\
         vertical-align:top}}figure{{margin:1em 0}}img{{background:#000;max-width:100%;\
         height:auto}}</style></head><body>\n<h1>{title}</h1>\n\
         <p>tensorglyph {version}; rendered with {backend}. {glyphs}Views follow the \
         neurological convention: the subject's right on the image's right in axial and \
         coronal slices, anterior on the left in sagittal ones; the letters at each tile's \
         edges name the world directions (RAS, from the file's affine) that lie there.</p>\n\
         {cost}{body}</body></html>\n",
        title = esc(title),
        version = env!("CARGO_PKG_VERSION"),
        backend = esc(&run.backend),
    )
}
