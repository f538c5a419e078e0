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
        // Only up to the normal target (0.5°): beyond it a row is a defect, as
        // Gumhold's orthographic capsules were (8–14° before capsule_slide), and as every
        // cigar at k ≥ 1e4 was (0.11–2.5°) while the reference cast the unstored rotation and
        // the pixel's offset from the glyph's centre ray was rounded in f32 (centre_ray).
        c if is_anisotropy(c)
            && c.contains("cigar")
            && row.value >= 1e3
            && row
                .metrics
                .get("normal_err_deg_p99")
                .is_none_or(|&n| n <= 0.5) =>
        {
            Some(
                "a cigar's normal turns with where the ray crosses its section, 2/k of its length wide, and the thin axes' directions in view space (the glyph's rotation times the camera's, formed per glyph in f32) are good to ~2⁻²⁴, which the cigar's length turns into ~2⁻²⁴·k of its section: normal p99 ≤ 0.17° at k = 1e3, ≤ 0.39° at 1e4–1e5 (2–26 pixels, next to a rim); at k ≥ 1e6 it covers no pixel centre here, at k > 2²⁴ it is culled",
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
