//! Build a tensor field in code and render it: the stress around a circular hole in a plate
//! pulled along x (Kirsch's solution, plane strain), coloured by the sign of the largest
//! principal stress (tension red, compression blue). Near the hole the hoop stress reaches
//! three times the applied stress at the top and bottom, and compression at the sides.
//!
//! ```sh
//! cargo run --example field_in_code -- kirsch.png
//! ```

use tensorglyph::{
    Backend, Camera, ColorScheme, FrameRequest, Framing, GlyphStyle, Method, Preset, Recipe,
    Silent, TensorField, ViewPreset, build, decompose, field_spacing, write_png_atomic,
};

/// Applied stress, hole radius and Poisson's ratio.
const SIGMA: f64 = 1.0;
const HOLE: f64 = 1.0;
const NU: f64 = 0.3;

/// The Cauchy stress at (x, y) outside the hole (Kirsch 1898), row-major.
fn kirsch(x: f64, y: f64) -> [f64; 9] {
    let r2 = x * x + y * y;
    let (a2, a4) = (HOLE * HOLE / r2, HOLE.powi(4) / (r2 * r2));
    let theta = y.atan2(x);
    let (c2, s2) = ((2.0 * theta).cos(), (2.0 * theta).sin());
    let h = SIGMA / 2.0;
    let srr = h * (1.0 - a2) + h * (1.0 - 4.0 * a2 + 3.0 * a4) * c2;
    let stt = h * (1.0 + a2) - h * (1.0 + 3.0 * a4) * c2;
    let srt = -h * (1.0 + 2.0 * a2 - 3.0 * a4) * s2;
    // Polar → Cartesian.
    let (c, s) = (theta.cos(), theta.sin());
    let sxx = srr * c * c + stt * s * s - 2.0 * srt * s * c;
    let syy = srr * s * s + stt * c * c + 2.0 * srt * s * c;
    let sxy = (srr - stt) * s * c + srt * (c * c - s * s);
    let szz = NU * (sxx + syy);
    [sxx, sxy, 0.0, sxy, syy, 0.0, 0.0, 0.0, szz]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "kirsch.png".into());
    let (mut positions, mut tensors) = (Vec::new(), Vec::new());
    for i in -16..=16 {
        for j in -16..=16 {
            let (x, y) = (f64::from(i) * 0.25, f64::from(j) * 0.25);
            if x * x + y * y > 1.1 * HOLE * HOLE {
                positions.push([x, y, 0.0]);
                tensors.push(kirsch(x, y));
            }
        }
    }
    let field = TensorField::from_points(positions, tensors);
    let set = decompose(&field, &Silent);
    let recipe = Recipe {
        style: GlyphStyle {
            color: ColorScheme::Sign,
            ..GlyphStyle::default()
        },
        ..Recipe::default()
    };
    let built = build(&field, &set, field_spacing(&field), &recipe, None, &Silent)?;
    let framing = Framing {
        view: ViewPreset::NegZ,
        ..Framing::default()
    };
    let camera = Camera::frame(&framing, built.frame_centre, built.frame_radius, 800, 800);
    let (backend, _) = Backend::for_method(Method::Gumhold)?;
    let request = FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT);
    let request = backend.adapt(request, &built.scene, &camera);
    let frame = backend.render(
        &built.scene,
        &camera,
        &request,
        &mut Default::default(),
        &Silent,
    )?;
    write_png_atomic(output.as_ref(), frame.width, frame.height, &frame.color)?;
    println!(
        "{output}: {} glyphs around the hole, {} pixels covered",
        built.scene.instances.len(),
        frame.covered_pixels()
    );
    Ok(())
}
