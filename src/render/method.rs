//! The rendering methods and glyph shapes users choose between; every method draws every shape
//! with the same camera, lighting, colours, depth and id targets.

use std::fmt;
use std::str::FromStr;

/// How glyphs are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Gumhold's perspective-correct silhouette quad, ray cast per fragment.
    Gumhold,
    /// Sigg et al.'s screen-space bounding box of the projected quadric, ray cast per fragment.
    Sigg,
    /// The exact f64 CPU ray caster (accuracy truth, and the fallback without a GPU).
    Reference,
}

impl Method {
    /// Every GPU method, in the order reports list them.
    pub fn gpu_methods() -> Vec<Method> {
        vec![Method::Gumhold, Method::Sigg]
    }

    pub fn is_gpu(self) -> bool {
        !matches!(self, Method::Reference)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Method::Gumhold => write!(f, "gumhold"),
            Method::Sigg => write!(f, "sigg"),
            Method::Reference => write!(f, "reference"),
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "gumhold" => Ok(Method::Gumhold),
            "sigg" => Ok(Method::Sigg),
            "reference" => Ok(Method::Reference),
            _ => Err(format!(
                "unknown method '{s}': use gumhold, sigg or reference"
            )),
        }
    }
}

impl serde::Serialize for Method {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The glyph shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum GlyphKind {
    #[default]
    Ellipsoid,
    /// Capped elliptic cylinder along the principal axis (or along e3 for planar tensors).
    Cylinder,
}

impl fmt::Display for GlyphKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GlyphKind::Ellipsoid => write!(f, "ellipsoid"),
            GlyphKind::Cylinder => write!(f, "cylinder"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_round_trip_through_their_names() {
        for m in [Method::Gumhold, Method::Sigg, Method::Reference] {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
        }
        assert!("voodoo".parse::<Method>().unwrap_err().contains("voodoo"));
    }
}
