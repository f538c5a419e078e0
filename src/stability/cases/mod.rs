//! The GPU cases: each a small scene and camera per value of a swept parameter.
//!
//! Grouped by what they probe: `view` (cases 1, 5, 6, 7: where the camera and the world are),
//! `surface` (2, 3, 4, 8, 9: where rays meet glyphs at their hardest), `degenerate` (10),
//! `superquadric` (11–13), `odf` (14), `lattice` (15: random lattices of thin glyphs through every preset); `probe` holds what every case is made of, `limits` the documented
//! inherent limits.

mod degenerate;
mod lattice;
mod limits;
mod odf;
mod probe;
mod superquadric;
mod surface;
mod view;

pub use degenerate::{Eigen, degenerate, degenerate_tensors, glyph_from_tensor, symmetric_eigen};
pub use lattice::lattice;
pub use limits::documented_limit;
pub use odf::{odf_faint, odf_sharp};
pub use probe::{H, Probe, W, oblique};
pub use superquadric::{class_boundary, indefinite, indefinite_tensors, sharpness};
pub use surface::{anisotropy, eye_approach, grazing, intersecting, is_anisotropy, sub_pixel};
pub use view::{camera_edges, distance, large_world, orthographic};

/// Every GPU probe of the suite.
pub fn all(quick: bool) -> Vec<Probe> {
    let mut v = Vec::new();
    v.extend(distance(quick));
    v.extend(anisotropy(quick));
    v.extend(grazing(quick));
    v.extend(eye_approach(quick));
    v.extend(camera_edges(quick));
    v.extend(orthographic(quick));
    v.extend(large_world(quick));
    v.extend(sub_pixel(quick));
    v.extend(intersecting(quick));
    v.extend(degenerate(quick));
    v.extend(sharpness(quick));
    v.extend(class_boundary(quick));
    v.extend(indefinite(quick));
    v.extend(odf_sharp(quick));
    v.extend(odf_faint(quick));
    v.extend(lattice(quick));
    v
}
