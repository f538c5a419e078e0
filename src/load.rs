//! Where a scene comes from: a VTK file or a built-in demo field; and the spacing that
//! `--scale auto` fits glyphs to.

use std::path::PathBuf;
use std::str::FromStr;

use crate::error::LoadError;
use crate::field::TensorField;
use crate::field::vtk::{ReadOptions, read_field};

/// A built-in analytic field: `grid40` (the canonical 64,000-glyph demo) or `grid:N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Demo {
    pub n: usize,
}

impl FromStr for Demo {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let n = match s {
            "grid40" => 40,
            _ => s
                .strip_prefix("grid:")
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|&n| (1..=1024).contains(&n))
                .ok_or_else(|| {
                    format!("unknown demo '{s}': use grid40 or grid:N (1 ≤ N ≤ 1024)")
                })?,
        };
        Ok(Demo { n })
    }
}

impl std::fmt::Display for Demo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.n == 40 {
            write!(f, "grid40")
        } else {
            write!(f, "grid:{}", self.n)
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    File(PathBuf),
    Demo(Demo),
}

impl Source {
    pub fn load(&self, opts: &ReadOptions) -> Result<TensorField, LoadError> {
        match self {
            Source::File(p) => read_field(p, opts),
            Source::Demo(d) => Ok(crate::field::synthetic::grid(d.n)),
        }
    }
}

/// The neighbour distance `--scale auto` fits the largest glyph to: the grid spacing, else the
/// median nearest-neighbour distance of the positions.
pub fn field_spacing(field: &TensorField) -> f64 {
    field
        .spacing
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or_else(|| crate::glyph::style::median_nn_distance(&field.positions))
}
