//! Legends: what a colour scheme means (class swatches and the Westin triangle, colour bars,
//! tension and compression, direction encoding), the scale in effect, and where the world axes
//! point. The viewer draws them in its panel; [`raster`] burns them into a PNG (`--legend`).

pub mod raster;

use glam::DVec3;

use crate::glyph::colormap::scale_color;
use crate::glyph::{ColorScheme, ResolvedStyle};

/// Which legend a colour scheme has.
#[derive(Debug, Clone, PartialEq)]
pub enum Legend {
    /// Class colours and the barycentric (cl, cp, cs) triangle.
    Shape,
    /// A scalar colouring's bar from `lo` to `hi`, under its title (the measure and its units),
    /// sequential or diverging about zero.
    Bar {
        lo: f64,
        hi: f64,
        title: String,
        diverging: bool,
    },
    /// Tension / compression.
    Sign,
    /// Direction encoding: |e1| as RGB, scaled by FA.
    Dec,
    /// Direction encoding of each point of an ODF glyph: |u| as RGB for its direction u from
    /// the glyph's centre (no FA: a series has none).
    Direction,
    Solid,
}

impl Legend {
    /// The legend of a style whose field's numbers are fixed.
    pub fn of(style: &ResolvedStyle) -> Self {
        legend(style.color, style.color_range, style.units.as_deref())
    }

    /// The legend of a scene of ODF glyphs of SH series coloured by `scheme`: a point's
    /// direction, not a tensor's e1 and FA.
    pub fn of_odf(scheme: ColorScheme) -> Self {
        match scheme {
            ColorScheme::Dec => Legend::Direction,
            other => legend(other, [0.0, 1.0], None),
        }
    }

    /// A bar's colour at `t` in [0, 1] along it (`None` for legends without a bar).
    pub fn bar_color(&self, t: f64) -> Option<[f64; 3]> {
        match self {
            Legend::Bar {
                lo, hi, diverging, ..
            } => Some(scale_color(lo + t * (hi - lo), [*lo, *hi], *diverging)),
            Legend::Sign => Some(scale_color(-1.0 + t * 2.0, [-1.0, 1.0], true)),
            _ => None,
        }
    }
}

/// The amplitude colouring's bar title: 1 is the glyph's full radius, which the normalisation
/// gives each voxel's largest value (`max`), or the field's (`none`).
pub const AMPLITUDE_TITLE: &str = "ODF amplitude (1: full radius)";

/// The legend of `scheme` coloured over `range` (a scalar colouring's), in `units`.
pub fn legend(scheme: ColorScheme, range: [f64; 2], units: Option<&str>) -> Legend {
    if let Some(m) = scheme.measure() {
        return Legend::Bar {
            lo: range[0],
            hi: range[1],
            title: m.title(units),
            diverging: m.signed(),
        };
    }
    match scheme {
        ColorScheme::Amplitude => Legend::Bar {
            lo: 0.0,
            hi: 1.0,
            title: AMPLITUDE_TITLE.into(),
            diverging: false,
        },
        ColorScheme::Sign => Legend::Sign,
        ColorScheme::Dec => Legend::Dec,
        ColorScheme::Solid => Legend::Solid,
        _ => Legend::Shape,
    }
}

/// A number as a colour bar's end shows it: up to four significant digits, in exponent form
/// beyond 1e-3 … 1e5 (stress in pascals).
pub fn short_number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{x:.3e}");
        // 5.200e7 → 5.2e7
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
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
        assert_eq!(legend(ColorScheme::Shape, [0.0, 1.0], None), Legend::Shape);
        assert_eq!(
            legend(ColorScheme::Md, [0.5, 2.0], Some("mm²/s")),
            Legend::Bar {
                lo: 0.5,
                hi: 2.0,
                title: "MD (mm²/s)".into(),
                diverging: false,
            }
        );
        assert_eq!(
            legend(ColorScheme::Sigma1, [-3.0, 9.0], Some("MPa")),
            Legend::Bar {
                lo: -3.0,
                hi: 9.0,
                title: "σ1 (MPa)".into(),
                diverging: true,
            }
        );
        assert_eq!(legend(ColorScheme::Sign, [0.0, 1.0], None), Legend::Sign);
        // An ODF scene's direction key is the point's direction, not e1 and FA.
        assert_eq!(Legend::of_odf(ColorScheme::Dec), Legend::Direction);
        assert_eq!(
            Legend::of_odf(ColorScheme::Amplitude),
            legend(ColorScheme::Amplitude, [0.0, 1.0], None)
        );
        assert_eq!(Legend::of_odf(ColorScheme::Solid), Legend::Solid);
        assert_eq!(
            legend(ColorScheme::Amplitude, [-3.0, 9.0], None),
            Legend::Bar {
                lo: 0.0,
                hi: 1.0,
                title: AMPLITUDE_TITLE.into(),
                diverging: false,
            }
        );
        // Every scalar colouring has a bar, and its bar shows its colours; the amplitude's
        // bar is 0 to 1 whatever the range.
        for &c in ColorScheme::VALUES {
            let l = legend(c, [-2.0, 6.0], None);
            assert_eq!(
                matches!(l, Legend::Bar { .. }),
                c.measure().is_some() || c == ColorScheme::Amplitude,
                "{c}"
            );
            if let Legend::Bar { diverging, .. } = l {
                let end = l.bar_color(1.0).unwrap();
                assert_eq!(end, scale_color(6.0, [-2.0, 6.0], diverging));
            }
        }
    }

    #[test]
    fn short_numbers() {
        assert_eq!(short_number(52069056.99), "5.207e7");
        assert_eq!(short_number(-4.2e7), "-4.2e7");
        assert_eq!(short_number(237.8709), "237.9");
        assert_eq!(short_number(0.0), "0");
        assert_eq!(short_number(1.0), "1");
        assert_eq!(short_number(0.00071234), "7.123e-4");
        assert_eq!(short_number(0.0123456), "0.01235");
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
