//! The documented inherent limits: the rows whose excess is a known limit of the method, not
//! a fault (the reasons are in docs/book/src/results/stability.md).

use crate::stability::Row;

/// A documented inherent limit that covers this row, if any (the reason is in docs/book/src/results/stability.md).
pub fn documented_limit(row: &Row) -> Option<&'static str> {
    match row.case {
        "9-intersecting" if !row.depth_correction => Some(
            "without depth correction the proxy's depth decides visibility, so the intersection curve of interpenetrating glyphs is wrong",
        ),
        // Only when depth is the sole excess: coverage of sub-pixel glyphs is held to the bounds.
        // The ray casters form their rays next to the glyph (centre_ray) and stay within them;
        // the meshes place their vertices in world space.
        "8-sub-pixel" if row.reason.starts_with("depth_err") && !row.reason.contains(';') => Some(
            "a mesh's vertices are placed in f32 world space relative to the scene origin: a glyph of radius r at distance D from it is placed to ~2⁻²⁴·D, i.e. depth error ~2⁻²⁴·D/r radii",
        ),
        _ => None,
    }
}
