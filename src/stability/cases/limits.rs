//! The documented inherent limits: the rows whose excess is a known limit of the method, not
//! a fault (the reasons are in docs/book/src/results/stability.md).

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
        "2-anisotropy-cigar" | "2-anisotropy-pancake" if row.value >= 1e4 => Some(
            "T⁻¹ in f32 has condition k = r_max/r_min: normal and depth errors grow ∝ 2⁻²⁴·k (about 1° normal p99 at k = 1e5); at k ≥ 1e6 the glyph is thinner than a pixel and at k > 2²⁴ it is culled",
        ),
        // Only when depth is the sole excess: coverage of sub-pixel glyphs is held to the bounds.
        "8-sub-pixel" if row.reason.starts_with("depth_err") && !row.reason.contains(';') => Some(
            "instances are f32 relative to the scene origin: a glyph of radius r at distance D from it is placed to ~2⁻²⁴·D, i.e. depth error ~2⁻²⁴·D/r radii (1.4e-4 radii for 1 px superquadrics)",
        ),
        _ => None,
    }
}
