//! The documented inherent limits: the rows whose excess is a known limit of the method, not
//! a fault (the reasons are in docs/book/src/results/stability.md).

use super::surface::is_anisotropy;
use crate::stability::Row;

/// A documented inherent limit that covers this row, if any (the reason is in docs/book/src/results/stability.md).
pub fn documented_limit(row: &Row) -> Option<&'static str> {
    match row.case {
        "9-intersecting" if !row.depth_correction => Some(
            "without depth correction the proxy's depth decides visibility, so the intersection curve of interpenetrating glyphs is wrong",
        ),
        // Meshes only, and only up to the normal target (0.5°): the ray casters have no
        // limit here since they cast thin glyphs in double-f32 (THIN_EXACT; before, cigars at
        // k ≥ 1e3 were 0.11–0.39° from the reference, and 0.11–2.5° before that).
        c if is_anisotropy(c)
            && c.contains("cigar")
            && row.method.starts_with("mesh:")
            && row.value >= 1e3
            && row
                .metrics
                .get("normal_err_deg_p99")
                .is_none_or(|&n| n <= 0.5) =>
        {
            Some(
                "a mesh's vertices are placed in f32 world space, to ~2⁻²⁴ of the cigar's length, which its section, k times thinner, sees as ~2⁻²⁴·k of itself: the finest meshes (mesh:5, mesh:6), whose own facet error is smaller, have normal p99 within 0.5° at k = 1e3–1e4; at k ≥ 1e6 a cigar covers no pixel centre here, at k > 2²⁴ it is culled",
            )
        }
        c if is_anisotropy(c) && c.contains("pancake") && row.value >= 1e7 => Some(
            "at k = 1e7 a pancake is 1e-7 thin, within a few f32 steps of its own size: where two cross, the intersection curve is a tie (id 1.05e-3 for both ray casters, orthographic); at k > 2²⁴ it is culled",
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
