//! Render a tensor file to a PNG the way `tensorglyph render` does by default: Gumhold's
//! ellipsoids on the GPU (the exact CPU reference where there is no GPU), coloured by shape.
//!
//! ```sh
//! cargo run --example render_file -- tests/data/vtk/xml_image_appraw_zlib_u32.vti field.png
//! ```

use tensorglyph::{
    Backend, Camera, FrameRequest, Framing, Method, Preset, Recipe, Silent, Source, stage,
    write_png_atomic,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        return Err("usage: render_file INPUT OUTPUT.png".into());
    };
    // File → field → glyphs → scene, with the bounds the camera frames.
    let staged = stage(&Source::File(input.into()), &Recipe::default(), &Silent)?;
    let camera = Camera::frame(
        &Framing::default(),
        staged.frame_centre,
        staged.frame_radius,
        800,
        600,
    );
    let (backend, fell_back) = Backend::for_method(Method::Gumhold)?;
    if fell_back {
        eprintln!("no GPU adapter: rendering with the exact reference");
    }
    let request = FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT);
    let request = backend.adapt(request, &staged.scene, &camera);
    let mut timings = staged.timings;
    let frame = backend.render(&staged.scene, &camera, &request, &mut timings, &Silent)?;
    write_png_atomic(output.as_ref(), frame.width, frame.height, &frame.color)?;
    println!(
        "{output}: {} glyphs, {} pixels covered, first frame {:.0} ms",
        staged.glyphs_selected,
        frame.covered_pixels(),
        timings.first_frame
    );
    Ok(())
}
