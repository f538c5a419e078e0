//! Legends: what a colour scheme means (class swatches and the Westin triangle, colour bars,
//! tension and compression, direction encoding), the scale in effect, and where the world axes
//! point. The viewer draws them in its panel; [`raster`] burns them into a PNG (`--legend`).

pub mod raster;

use glam::DVec3;

use crate::glyph::ColorScheme;

/// Which legend a colour scheme has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Legend {
    /// Class colours and the barycentric (cl, cp, cs) triangle.
    Shape,
    /// A colour bar from `lo` to `hi`.
    Bar {
        lo: f64,
        hi: f64,
        label: &'static str,
    },
    /// Tension / compression.
    Sign,
    /// Direction encoding: |e1| as RGB, scaled by FA.
    Dec,
    Solid,
}

/// The legend of `scheme` for a field whose MD runs over `md_range`.
pub fn legend(scheme: ColorScheme, md_range: (f64, f64)) -> Legend {
    match scheme {
        ColorScheme::Shape => Legend::Shape,
        ColorScheme::Fa => Legend::Bar {
            lo: 0.0,
            hi: 1.0,
            label: "FA",
        },
        ColorScheme::Md => Legend::Bar {
            lo: md_range.0,
            hi: md_range.1,
            label: "MD",
        },
        ColorScheme::Sign => Legend::Sign,
        ColorScheme::Dec => Legend::Dec,
        ColorScheme::Solid => Legend::Solid,
    }
}

/// (positive end, negative end) labels of the x, y and z axes: R/L, A/P, S/I when the world
/// is anatomical (RAS, as NIfTI and NRRD files give it), else +x … −z.
pub fn axis_labels(anatomical: bool) -> [[&'static str; 2]; 3] {
    if anatomical {
        [["R", "L"], ["A", "P"], ["S", "I"]]
    } else {
        [["+x", "−x"], ["+y", "−y"], ["+z", "−z"]]
    }
}

/// Each world axis on screen for a camera looking along `forward` with `up`: (right, down)
/// components of its unit vector and its depth towards the viewer (positive: towards).
pub fn screen_axes(forward: DVec3, up: DVec3) -> [([f32; 2], f32); 3] {
    let right = forward.cross(up).normalize();
    let up = right.cross(forward).normalize();
    [DVec3::X, DVec3::Y, DVec3::Z].map(|a| {
        (
            [a.dot(right) as f32, -a.dot(up) as f32],
            -a.dot(forward) as f32,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ViewPreset;

    #[test]
    fn every_scheme_has_its_legend() {
        assert_eq!(legend(ColorScheme::Shape, (0.0, 1.0)), Legend::Shape);
        assert_eq!(
            legend(ColorScheme::Md, (0.5, 2.0)),
            Legend::Bar {
                lo: 0.5,
                hi: 2.0,
                label: "MD"
            }
        );
        assert!(matches!(
            legend(ColorScheme::Fa, (0.0, 0.0)),
            Legend::Bar {
                lo: 0.0,
                hi: 1.0,
                ..
            }
        ));
        assert_eq!(legend(ColorScheme::Sign, (0.0, 1.0)), Legend::Sign);
    }

    #[test]
    fn axial_shows_the_subject_right_on_the_right_and_anterior_up() {
        let (f, u) = ViewPreset::Axial.direction_up();
        let axes = screen_axes(f, u);
        // x (R) to the right, y (A) up (screen y grows down), z (S) towards the viewer.
        assert!((axes[0].0[0] - 1.0).abs() < 1e-6);
        assert!((axes[1].0[1] + 1.0).abs() < 1e-6);
        assert!((axes[2].1 - 1.0).abs() < 1e-6);
        let (f, u) = ViewPreset::Coronal.direction_up();
        let axes = screen_axes(f, u);
        assert!((axes[0].0[0] - 1.0).abs() < 1e-6, "coronal: R on the right");
        assert!((axes[2].0[1] + 1.0).abs() < 1e-6, "coronal: S up");
        let (f, u) = ViewPreset::Sagittal.direction_up();
        let axes = screen_axes(f, u);
        assert!((axes[1].0[0] + 1.0).abs() < 1e-6, "sagittal: A on the left");
        assert!((axes[2].0[1] + 1.0).abs() < 1e-6, "sagittal: S up");
        assert_eq!(axis_labels(true)[0], ["R", "L"]);
    }
}
