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
    /// Baseline: an instanced triangle mesh (icosphere / prism subdivided N times, 0..=6).
    Mesh(u8),
    /// Baseline: the glyph's oriented box, flat shaded (a "cuboid" glyph).
    Box,
}

impl Method {
    /// Every GPU method, in the order reports list them.
    pub fn gpu_methods() -> Vec<Method> {
        let mut m = vec![Method::Gumhold, Method::Sigg];
        m.extend((0..=Method::MAX_MESH_LEVEL).map(Method::Mesh));
        m.push(Method::Box);
        m
    }

    /// The finest `mesh:N` level (an icosphere of 81 920 triangles).
    pub const MAX_MESH_LEVEL: u8 = 6;

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
            Method::Mesh(n) => write!(f, "mesh:{n}"),
            Method::Box => write!(f, "box"),
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
            "box" => Ok(Method::Box),
            _ if s.starts_with("mesh:") => {
                let max = Method::MAX_MESH_LEVEL;
                let level = &s["mesh:".len()..];
                let digits = !level.is_empty() && level.bytes().all(|b| b.is_ascii_digit());
                match level.parse::<u8>() {
                    Ok(n) if digits && n <= max => Ok(Method::Mesh(n)),
                    _ => Err(format!(
                        "invalid mesh level in '{s}': use mesh:N with N an integer from 0 to {max}"
                    )),
                }
            }
            _ => Err(format!(
                "unknown method '{s}': use gumhold, sigg, reference, mesh:N (N = 0..={}) or box",
                Method::MAX_MESH_LEVEL
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

/// Triangles per glyph of a tessellated method (`None` for impostors, whose cost does not grow
/// with a level).
pub fn triangles_per_glyph(method: Method, glyph: GlyphKind) -> Option<u64> {
    match method {
        Method::Mesh(_) | Method::Box => {
            Some(crate::render::mesh::mesh_stats(method, glyph).1 as u64)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_round_trip_through_their_names() {
        for m in [
            Method::Gumhold,
            Method::Sigg,
            Method::Reference,
            Method::Box,
        ] {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
        }
        for n in 0..=Method::MAX_MESH_LEVEL {
            assert_eq!(format!("mesh:{n}").parse::<Method>(), Ok(Method::Mesh(n)));
        }
        assert!("voodoo".parse::<Method>().unwrap_err().contains("voodoo"));
        for bad in ["mesh:7", "mesh:x", "mesh:", "mesh:-1", "mesh:+3", "mesh"] {
            let e = bad.parse::<Method>().unwrap_err();
            assert!(e.contains(bad) && e.contains("mesh:N"), "{bad}: {e}");
        }
    }
}
