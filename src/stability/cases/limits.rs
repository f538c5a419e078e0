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
        "3-grazing" | "3-grazing-persp" => Some(
            "pixel centres within f32 rounding of a silhouette or of a contact between glyphs are ties and may flip; at the rim the hit moves infinitely fast with the ray, so f32 rounding of q̃ shows in the depth p99 of small glyphs",
        ),
        // Only up to the normal error the limit explains (2.5° measured): beyond it a row is a
        // defect, as Gumhold's orthographic capsules were (8–14° before capsule_slide).
        c if is_anisotropy(c)
            && c.contains("cigar")
            && row.value >= 1e3
            && row
                .metrics
                .get("normal_err_deg_p99")
                .is_none_or(|&n| n <= 3.0) =>
        {
            Some(
                "a cigar's normal turns with where the ray crosses its section, 2/k of its length wide, and f32 places a pixel's ray relative to a glyph only to ~2⁻²⁴ of the eye's distance (the camera, the pixel's direction, the glyph's view position): normal p99 0.12° at k = 1e3–1e4, 1.1–2.5° at 1e5; at k ≥ 1e6 it covers no pixel centre here, at k > 2²⁴ it is culled",
            )
        }
        c if is_anisotropy(c) && c.contains("pancake") && row.value >= 1e7 => Some(
            "at k = 1e7 a pancake is 1e-7 thin, within a few f32 steps of its own size: where two cross, the intersection curve is a tie (id 1.2e-3 for both ray casters); at k > 2²⁴ it is culled",
        ),
        // Only when depth is the sole excess: coverage of sub-pixel glyphs is held to the bounds.
        "8-sub-pixel" if row.reason.starts_with("depth_err") && !row.reason.contains(';') => Some(
            "instances are f32 relative to the scene origin: a glyph of radius r at distance D from it is placed to ~2⁻²⁴·D, i.e. depth error ~2⁻²⁴·D/r radii (1.4e-4 radii for 1 px superquadrics)",
        ),
        _ => None,
    }
}
