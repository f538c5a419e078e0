//! Which glyphs any method draws: one rule for every GPU shader, the exact reference and the
//! CPU twins, so that a glyph one of them skips is not counted as another's error.

/// Same constant as `EYE_INSIDE_E2` in shaders/gumhold_ellipsoid.wgsl.
pub const EYE_INSIDE_E2: f64 = 1.00001;

/// Same rule as `drawable` in shaders/common.wgsl: every radius finite, positive and at least
/// 2⁻²⁴ of the largest (f32 cannot resolve a thinner glyph at its own scale); others are not
/// drawn by any method.
pub const MIN_RADIUS_RATIO: f32 = 5.960_464_5e-8;

/// Same constant as `PROXY_MARGIN_PX` in shaders/common.wgsl: how far, in pixels, Gumhold's
/// ellipsoid quads and Sigg's boxes reach beyond the silhouette they touch (a rasteriser may
/// place edges that much inside; the fragments outside are discarded). The CPU twins widen
/// their proxies by it when they predict what a frame shades.
pub const PROXY_MARGIN_PX: f64 = 0.125;

pub fn drawable_radii(r: [f32; 3]) -> bool {
    let rmax = r[0].max(r[1]).max(r[2]);
    let rmin = r[0].min(r[1]).min(r[2]);
    // NaN fails every comparison (f32::max/min skip NaN, so test each radius too).
    r.iter().all(|&x| x > 0.0 && x <= 3.0e38) && rmin >= rmax * MIN_RADIUS_RATIO
}

#[cfg(test)]
mod tests {
    /// The constants above against the WGSL they copy (shaders/common.wgsl's text).
    #[test]
    fn constants_are_the_shaders() {
        let wgsl = include_str!("../../shaders/common.wgsl");
        let value = |name: &str| -> f64 {
            let line = wgsl
                .lines()
                .find(|l| l.trim_start().starts_with(&format!("const {name}:")))
                .unwrap_or_else(|| panic!("{name} not in common.wgsl"));
            let v = line.split('=').nth(1).unwrap().trim().trim_end_matches(';');
            v.parse().unwrap()
        };
        assert_eq!(value("PROXY_MARGIN_PX"), super::PROXY_MARGIN_PX);
        assert_eq!(value("MIN_RADIUS_RATIO") as f32, super::MIN_RADIUS_RATIO);
    }
}
