//! Measure GPU methods against the exact f64 reference on the same scene and camera: the
//! numbers `tensorglyph render --reference-check` prints, for each method.
//!
//! ```sh
//! cargo run --example compare_to_reference
//! ```

use tensorglyph::{
    Camera, Demo, FrameRequest, Framing, GpuContext, GpuRenderer, Method, Recipe, ReferenceScene,
    Silent, Source, compare, stage,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let staged = stage(&Source::Demo(Demo { n: 12 }), &Recipe::default(), &Silent)?;
    let scene = &staged.scene;
    let camera = Camera::frame(&Framing::default(), scene.centre, scene.radius, 640, 480);
    // The aux target carries normals and depth, which the comparison needs.
    let request = |method| FrameRequest {
        aux: true,
        ..FrameRequest::new(method)
    };
    let reference = ReferenceScene::new(scene, &camera).render(&request(Method::Reference));
    let gpu = GpuRenderer::new(GpuContext::new()?)?;
    println!(
        "{} glyphs on {}",
        staged.glyphs_selected,
        gpu.adapter_name()
    );
    println!("method   coverage   id         depth p99  normal p99 PSNR");
    for method in [Method::Gumhold, Method::Sigg, Method::Mesh(2), Method::Box] {
        let frame = gpu.render(scene, &camera, &request(method))?;
        let a = compare(&frame, &reference, scene);
        println!(
            "{method:<8} {:<10.2e} {:<10.2e} {:<10.2e} {:<10} {:.1} dB",
            a.coverage_mismatch,
            a.id_mismatch,
            a.depth_err_rel_p99,
            format!("{:.4}°", a.normal_err_deg_p99),
            a.color_psnr_db
        );
        // The ray casters are exact: a pixel that differs from the reference is a bug (CI runs
        // this example against the library without its front ends, so it must fail then).
        let exact = matches!(method, Method::Gumhold | Method::Sigg);
        if exact && (a.coverage_mismatch > 1e-4 || a.id_mismatch > 1e-4) {
            return Err(format!("{method} differs from the reference").into());
        }
    }
    Ok(())
}
