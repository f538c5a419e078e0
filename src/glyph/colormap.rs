//! Colour maps: a compact viridis LUT (perceptually uniform, colour-blind safe), a simple
//! diverging map, and a scalar's colour on either over a range ([`scale_color`]).

/// Matplotlib's viridis (CC0, van der Walt and Smith) sampled at table indices
/// 0, 16, 32, …, 240 and 255 of its 256 entries; linear interpolation between nodes is within
/// about 0.002 of the full table.
const VIRIDIS: [[f32; 3]; 17] = [
    [0.267004, 0.004874, 0.329415],
    [0.282327, 0.094955, 0.417331],
    [0.278826, 0.175490, 0.483397],
    [0.258965, 0.251537, 0.524736],
    [0.229739, 0.322361, 0.545706],
    [0.199430, 0.387607, 0.554642],
    [0.172719, 0.448791, 0.557885],
    [0.149039, 0.508051, 0.557250],
    [0.127568, 0.566949, 0.550556],
    [0.120638, 0.625828, 0.533488],
    [0.157851, 0.683765, 0.501686],
    [0.246070, 0.738910, 0.452024],
    [0.369214, 0.788888, 0.382914],
    [0.515992, 0.831158, 0.294279],
    [0.678489, 0.863742, 0.189503],
    [0.845561, 0.887322, 0.099702],
    [0.993248, 0.906157, 0.143936],
];

/// Viridis at `t` in [0, 1] (clamped; NaN maps to 0), as RGB in [0, 1].
pub fn viridis(t: f64) -> [f64; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * 255.0; // position in the 256-entry table
    let seg = ((x / 16.0) as usize).min(15);
    let x0 = (seg * 16) as f64;
    let x1 = if seg == 15 { 255.0 } else { x0 + 16.0 };
    let f = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
    let (a, b) = (VIRIDIS[seg], VIRIDIS[seg + 1]);
    std::array::from_fn(|k| f64::from(a[k]) + f * (f64::from(b[k]) - f64::from(a[k])))
}

/// [`viridis`] as a WGSL function `viridis(t: f32) -> vec3<f32>` for the shaders that colour per
/// pixel (odf.wgsl's amplitude), made from the same table so that the two cannot drift. Each
/// node is a literal picked by comparisons: lavapipe copies a constant array out at every
/// run-time index, which made a table of constants 20x slower in odf.wgsl.
pub fn viridis_wgsl() -> &'static str {
    static TEXT: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| {
        let node = |k: usize| {
            let [r, g, b] = VIRIDIS[k];
            format!("vec3<f32>({r:?}, {g:?}, {b:?})")
        };
        let mut s = String::from(
            "// Viridis at t in [0, 1] (clamped; NaN maps to 0): src/glyph/colormap.rs's table.\n\
             fn viridis(t: f32) -> vec3<f32> {\n    \
             let x = select(0.0, clamp(t, 0.0, 1.0), t == t) * 255.0;\n",
        );
        s += &format!(
            "    var lo = {};\n    var hi = {};\n    var x0 = 0.0;\n    var x1 = 16.0;\n",
            node(0),
            node(1)
        );
        for seg in 1..16 {
            let x1 = if seg == 15 {
                255.0
            } else {
                (seg * 16 + 16) as f64
            };
            s += &format!(
                "    if x >= {:?} {{ lo = {}; hi = {}; x0 = {:?}; x1 = {x1:?}; }}\n",
                (seg * 16) as f64,
                node(seg),
                node(seg + 1),
                (seg * 16) as f64,
            );
        }
        s += "    return mix(lo, hi, clamp((x - x0) / (x1 - x0), 0.0, 1.0));\n}\n";
        s
    });
    TEXT.as_str()
}

/// Diverging blue–white–red at `s` in [−1, 1]: −1 blue (compression), 0 white, +1 red (tension).
pub fn diverging(s: f64) -> [f64; 3] {
    let s = if s.is_nan() { 0.0 } else { s.clamp(-1.0, 1.0) };
    const RED: [f64; 3] = [0.80, 0.10, 0.10];
    const BLUE: [f64; 3] = [0.10, 0.25, 0.80];
    let (end, f) = if s >= 0.0 { (RED, s) } else { (BLUE, -s) };
    end.map(|c| 1.0 + f * (c - 1.0))
}

/// The colour of `v` on a scale over `[lo, hi]`: sequential (viridis, `lo` dark, `hi` yellow)
/// or `diverging` (centred on zero: white at 0, full red or blue at ±max(|lo|, |hi|), so that
/// the sign reads whatever the range). Values beyond the range take its ends; NaN takes the
/// scale's start (sequential) or white (diverging).
pub fn scale_color(v: f64, [lo, hi]: [f64; 2], diverging_about_zero: bool) -> [f64; 3] {
    if diverging_about_zero {
        let v = if lo <= hi { v.clamp(lo, hi) } else { v };
        let m = lo.abs().max(hi.abs());
        diverging(if m > 0.0 { v / m } else { 0.0 })
    } else {
        viridis(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
    }
}

/// RGB in [0, 1] to RGBA8 (rounded, clamped, opaque).
#[inline]
pub fn to_rgba8(c: [f64; 3]) -> [u8; 4] {
    let q = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(c[0]), q(c[1]), q(c[2]), 255]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_nodes() {
        assert_eq!(viridis(0.0), VIRIDIS[0].map(f64::from));
        assert_eq!(viridis(1.0), VIRIDIS[16].map(f64::from));
        let mid = viridis(128.0 / 255.0);
        for k in 0..3 {
            assert!((mid[k] - f64::from(VIRIDIS[8][k])).abs() < 1e-12);
        }
        // lightness increases monotonically (approximated by the sum of channels' luma)
        let luma = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let mut last = -1.0;
        for i in 0..=100 {
            let l = luma(viridis(i as f64 / 100.0));
            assert!(l > last);
            last = l;
        }
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(2.0), viridis(1.0));
    }

    #[test]
    fn scales() {
        // Sequential: the range's ends are viridis's; FA's 0–1 is the identity.
        assert_eq!(scale_color(10.0, [10.0, 30.0], false), viridis(0.0));
        assert_eq!(scale_color(99.0, [10.0, 30.0], false), viridis(1.0));
        assert_eq!(scale_color(0.3, [0.0, 1.0], false), viridis(0.3));
        // Diverging: zero is white wherever it sits in the range, and the larger end is full.
        assert_eq!(scale_color(0.0, [-10.0, 40.0], true), [1.0; 3]);
        assert_eq!(scale_color(40.0, [-10.0, 40.0], true), diverging(1.0));
        assert_eq!(scale_color(-99.0, [-10.0, 40.0], true), diverging(-0.25));
        assert_eq!(
            scale_color(f64::INFINITY, [-1.0, 2.0], true),
            diverging(1.0)
        );
        assert_eq!(scale_color(f64::NAN, [-1.0, 2.0], true), [1.0; 3]);
        assert_eq!(scale_color(5.0, [0.0, 0.0], true), [1.0; 3]);
    }

    #[test]
    fn diverging_ends() {
        assert_eq!(diverging(0.0), [1.0, 1.0, 1.0]);
        let red = to_rgba8(diverging(1.0));
        assert!(red[0] == 204 && red[1] < 30 && red[2] < 30);
        assert_eq!(to_rgba8(diverging(-1.0))[2], 204);
    }
}
