//! Write the whole-brain-sized DTI volume `tensorglyph bench --brain` times (128×128×70
//! float32 tensors in FSL's order, a gzip NIfTI) to a file, to open it elsewhere: the web
//! page's `?url=` (the browser test's `TENSORGLYPH_WEB_BRAIN`), the viewer, other tools.
//!
//! ```sh
//! cargo run --example brain_volume -- brain.nii.gz
//! ```

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args_os()
        .nth(1)
        .ok_or("usage: brain_volume OUT.nii.gz")?;
    tensorglyph::bench::brain::write(std::path::Path::new(&out))?;
    Ok(())
}
