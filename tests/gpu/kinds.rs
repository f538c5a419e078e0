//! Every glyph kind of the registry ([`GlyphKind::VALUES`]) drawn by every GPU method on the same
//! scenes, against the exact f64 reference: a kind added to the registry is tested here by every
//! method without a line of this file changing, and a method added to
//! [`Method::gpu_methods`] fails [`every_gpu_method_has_a_row`] until [`ROWS`] says how it is
//! judged.
//!
//! The scenes ([`shots`]): the demo grid `grid:6` (216 glyphs: cigars, pancakes, balls and the
//! unclassified tensors between them) staged as `render` stages it ([`stage`], with
//! [`Recipe::glyph`] the kind), at 256x192, in three views: the whole field in perspective, a
//! closer view (glyphs large on screen and cut by the image's edges, the eye outside the field)
//! and the whole field orthographic. Each (kind, view) is rendered once by the reference and
//! shared by every row.
//!
//! The rows ([`ROWS`]): a method, the preset it is drawn with, the kinds it takes (a filter on
//! the kind's [`Capabilities`]: the prepass and splat rows run for the kinds that have them)
//! and how it is judged, with the bounds as data and the reason for each. A failure lists every
//! row, kind and view out of bounds, then the reasons of the bounds they broke.
//!
//! Run: `cargo test --test gpu kinds` (`-- --nocapture` prints every measurement).

use std::sync::OnceLock;

use crate::check::gpu;
use tensorglyph::Silent;
use tensorglyph::camera::{Camera, Framing};
use tensorglyph::frame::Frame;
use tensorglyph::metrics::{Accuracy, compare};
use tensorglyph::reference::ReferenceScene;
use tensorglyph::request::{FrameRequest, GlyphKind, Method, Preset};
use tensorglyph::scene::Scene;
use tensorglyph::shape::Capabilities;
use tensorglyph::staging::{Demo, Recipe, Source, stage};

/// The image size of every shot: small enough that the whole table stays fast on lavapipe.
const SIZE: (u32, u32) = (256, 192);

/// How close a method's frame must come to the reference, each bound with its reason.
#[derive(Debug)]
struct Bounds {
    /// Share of all pixels where one frame shows a glyph and the other background.
    coverage: f64,
    /// Share of the pixels covered in both whose front-most glyph differs.
    id: f64,
    /// 99th percentile of the depth error, relative to the glyph's largest radius.
    depth_p99: f64,
    /// 99th percentile of the normal's error, in degrees.
    normal_p99_deg: f64,
    why: &'static str,
}

/// How a row is judged against the reference.
#[derive(Debug)]
enum Judge {
    /// Within these bounds.
    Close(Bounds),
    /// A proxy drawn for itself (the `box` baseline): no glyph pixel of the reference is missed
    /// and more pixels are covered, because the proxy holds the glyph.
    Encloses { why: &'static str },
}

/// The exact ray casters (Gumhold's solids and quads, Sigg's boxes), drawn or splatted.
const RAY_CAST: Bounds = Bounds {
    coverage: 1e-4,
    id: 5e-4,
    depth_p99: 1e-4,
    normal_p99_deg: 0.5,
    why: "the release bounds (book: results/accuracy.md), bounded by f32: only a pixel centre \
          within f32 rounding of a silhouette or an intersection curve may flip its coverage or \
          its glyph, and depth and normals err at the rims, by the f32 interpolation of the \
          proxy's ray or the splat's f32 pixel ray, which the 99th percentile keeps (measured \
          on lavapipe: at most one pixel of either, depth p99 <= 2.5e-5 radii, normal p99 <= \
          0.004 deg)",
};

/// The tessellated baseline at level 4.
const MESH: Bounds = Bounds {
    coverage: 1e-3,
    id: 2e-3,
    depth_p99: 1e-2,
    normal_p99_deg: 2.5,
    why: "bounded by the tessellation: the inscribed mesh lies up to ~1e-3 of a radius inside \
          the surface at level 4, so rim pixels flip, an intersection curve moves by that \
          depth, and a grazing ray's depth gap grows like its square root; interpolated vertex \
          normals err by a fraction of the few degrees between neighbouring vertices, most \
          where a superquadric's profile turns fastest (measured on lavapipe: coverage <= \
          5.1e-4, id <= 7e-4, depth p99 <= 5.8e-3; normal p99 <= 1.0 deg, 1.8 deg for \
          superquadrics)",
};

/// One method as the table draws and judges it.
struct Row {
    method: Method,
    preset: Preset,
    /// The kinds it draws, by their capabilities.
    takes: fn(Capabilities) -> bool,
    judge: Judge,
}

fn every_kind(_: Capabilities) -> bool {
    true
}

fn with_prepass(c: Capabilities) -> bool {
    c.prepass
}

fn with_splats(c: Capabilities) -> bool {
    c.splats
}

/// Every GPU method, and the prepass and splat paths of the kinds that have them.
const ROWS: &[Row] = &[
    Row {
        method: Method::Gumhold,
        preset: Preset::Baseline,
        takes: every_kind,
        judge: Judge::Close(RAY_CAST),
    },
    Row {
        method: Method::Gumhold,
        preset: Preset::Prepass,
        takes: with_prepass,
        judge: Judge::Close(RAY_CAST),
    },
    Row {
        method: Method::Gumhold,
        preset: Preset::Splat,
        takes: with_splats,
        judge: Judge::Close(RAY_CAST),
    },
    Row {
        method: Method::Sigg,
        preset: Preset::Baseline,
        takes: every_kind,
        judge: Judge::Close(RAY_CAST),
    },
    Row {
        method: Method::Mesh(4),
        preset: Preset::Baseline,
        takes: every_kind,
        judge: Judge::Close(MESH),
    },
    Row {
        method: Method::Box,
        preset: Preset::Baseline,
        takes: every_kind,
        judge: Judge::Encloses {
            why: "the box is the glyph's oriented bounding box, drawn with back faces culled: \
                  with the eye outside every box it covers every pixel of its glyph",
        },
    },
];

/// One scene and view of one kind, with the reference's frame of it.
struct Shot {
    kind: GlyphKind,
    view: &'static str,
    scene: Scene,
    camera: Camera,
    reference: Frame,
}

/// The views: (name, framing).
fn views() -> [(&'static str, Framing); 3] {
    [
        ("whole", Framing::default()),
        (
            "close",
            Framing {
                zoom: 2.0,
                azimuth: 20.0,
                ..Framing::default()
            },
        ),
        (
            "ortho",
            Framing {
                ortho: true,
                azimuth: 30.0,
                ..Framing::default()
            },
        ),
    ]
}

/// The request every frame is drawn with: the row's method and preset, with the aux target.
fn request(method: Method, preset: Preset) -> FrameRequest {
    FrameRequest {
        aux: true,
        ..FrameRequest::preset(method, true, preset)
    }
}

/// Every kind in every view, rendered once by the reference (shared by the tests of this
/// module, which run at once).
fn shots() -> &'static [Shot] {
    static SHOTS: OnceLock<Vec<Shot>> = OnceLock::new();
    SHOTS.get_or_init(|| {
        let mut shots = Vec::new();
        for &kind in GlyphKind::VALUES {
            let recipe = Recipe {
                glyph: kind,
                ..Recipe::default()
            };
            let staged = stage(&Source::Demo(Demo { n: 6 }), &recipe, &Silent).expect("grid:6");
            assert_eq!(staged.scene.kind, kind);
            for (view, framing) in views() {
                let camera = Camera::frame_box(
                    &framing,
                    staged.frame_centre,
                    staged.frame_half,
                    SIZE.0,
                    SIZE.1,
                );
                // The eye outside the field's box: no glyph holds it or is cut by the near
                // plane, so the box baseline's enclosure and every method's pixels are
                // comparable.
                let lo = staged.frame_centre - staged.frame_half;
                let hi = staged.frame_centre + staged.frame_half;
                assert!(
                    camera.eye.cmplt(lo).any() || camera.eye.cmpgt(hi).any(),
                    "{kind} {view}: the eye is inside the field"
                );
                let reference = ReferenceScene::new(&staged.scene, &camera)
                    .render(&request(Method::Reference, Preset::Baseline));
                // 4 % of the image: principal-stress bars, the thinnest kind, cover ~3,800
                // pixels of the whole view; the others cover several times more.
                assert!(
                    reference.covered_pixels() > 2_000,
                    "{kind} {view}: the reference shows too little"
                );
                shots.push(Shot {
                    kind,
                    view,
                    scene: staged.scene.clone(),
                    camera,
                    reference,
                });
            }
        }
        shots
    })
}

/// What `frame` (drawn by `row`) gets wrong against the shot's reference (empty: nothing), and
/// its accuracy.
fn judge(row: &Row, shot: &Shot, frame: &Frame) -> (Accuracy, Vec<String>) {
    let a = compare(frame, &shot.reference, &shot.scene);
    let mut wrong = Vec::new();
    match &row.judge {
        Judge::Close(b) => {
            for (what, got, bound) in [
                ("coverage", a.coverage_mismatch, b.coverage),
                ("id", a.id_mismatch, b.id),
                ("depth p99", a.depth_err_rel_p99, b.depth_p99),
                ("normal p99", a.normal_err_deg_p99, b.normal_p99_deg),
            ] {
                // NaN (nothing to compare) fails too.
                if got.is_nan() || got > bound {
                    wrong.push(format!("{what} {got:.2e} > {bound:.0e}"));
                }
            }
        }
        Judge::Encloses { .. } => {
            let missed = frame
                .ids
                .iter()
                .zip(&shot.reference.ids)
                .filter(|&(&f, &r)| r != 0 && f == 0)
                .count();
            if missed > 0 {
                wrong.push(format!("misses {missed} glyph pixels"));
            }
            if frame.covered_pixels() <= shot.reference.covered_pixels() {
                wrong.push(format!(
                    "covers {} pixels, the reference {}",
                    frame.covered_pixels(),
                    shot.reference.covered_pixels()
                ));
            }
        }
    }
    (a, wrong)
}

/// Draws every shot of every kind each row of `method` takes, and fails with every row, kind
/// and view that misses its bounds (and the reasons of those bounds).
fn run(method: Method) {
    let Some(gpu) = gpu() else { return };
    let mut failures = Vec::new();
    let mut reasons = Vec::new();
    let mut drawn = 0;
    for row in ROWS.iter().filter(|r| r.method == method) {
        let label = format!("{method} {:?}", row.preset);
        for shot in shots().iter().filter(|s| (row.takes)(s.kind.caps())) {
            let req = request(row.method, row.preset);
            let frame = gpu
                .render(&shot.scene, &shot.camera, &req)
                .unwrap_or_else(|e| panic!("{label} {}: {e}", shot.kind));
            let (a, wrong) = judge(row, shot, &frame);
            let label = format!("{label} {} {}", shot.kind, shot.view);
            eprintln!(
                "{label}: coverage {:.2e} id {:.2e} depth p99 {:.2e} normal p99 {:.3}° \
                 (covered {}, reference {})",
                a.coverage_mismatch,
                a.id_mismatch,
                a.depth_err_rel_p99,
                a.normal_err_deg_p99,
                frame.covered_pixels(),
                shot.reference.covered_pixels()
            );
            if !wrong.is_empty() {
                failures.push(format!("{label}: {}", wrong.join(", ")));
            }
            drawn += 1;
        }
        if failures.iter().any(|f| f.starts_with(&label)) {
            let why = match &row.judge {
                Judge::Close(b) => b.why,
                Judge::Encloses { why } => why,
            };
            reasons.push(format!("{label}'s bounds: {why}"));
        }
    }
    assert!(drawn > 0, "no row draws {method}");
    assert!(
        failures.is_empty(),
        "{}\n\n{}",
        failures.join("\n"),
        reasons.join("\n")
    );
}

#[test]
fn gumhold_draws_every_kind() {
    run(Method::Gumhold);
}

#[test]
fn sigg_draws_every_kind() {
    run(Method::Sigg);
}

#[test]
fn mesh_draws_every_kind() {
    run(Method::Mesh(4));
}

#[test]
fn box_encloses_every_kind() {
    run(Method::Box);
}

/// A method the renderer gains needs a row here, or this table would pass without it.
#[test]
fn every_gpu_method_has_a_row() {
    use std::mem::discriminant;
    for method in Method::gpu_methods() {
        assert!(
            ROWS.iter()
                .any(|r| discriminant(&r.method) == discriminant(&method)),
            "{method}: no row in kinds::ROWS"
        );
    }
    // And every row's method has its test above.
    for row in ROWS {
        assert!(
            [Method::Gumhold, Method::Sigg, Method::Mesh(4), Method::Box].contains(&row.method),
            "{}: no test runs this row",
            row.method
        );
    }
}
