//! The CPU twin of shaders/shape/screen_box.wgsl: the screen-space bounding box of a projected
//! quadric (Sigg et al. eq. 5) in f64 with the notes' names (shared/math/sigg-quadric.md §2),
//! checked against every case of shared/math/test-vectors.json, and the proxy Sigg's vertex
//! stage draws from such boxes, with the fragments it shades (the GPU tests predict fragment
//! counts with it).

use glam::{DMat4, DVec2, DVec3, DVec4};

use crate::scene::GlyphGeometry;

/// An axis-aligned box in NDC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NdcBox {
    /// (xmin, ymin).
    pub lo: DVec2,
    /// (xmax, ymax).
    pub hi: DVec2,
}

impl NdcBox {
    /// `[xmin, xmax, ymin, ymax]`, the layout of the test vectors.
    pub fn to_array(self) -> [f64; 4] {
        [self.lo.x, self.hi.x, self.lo.y, self.hi.y]
    }

    pub fn union(self, o: NdcBox) -> NdcBox {
        NdcBox {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// The pixels of a `width` x `height` target whose centres lie in the box: the fragments
    /// rasterising it shades (up to pixel centres exactly on its edges).
    pub fn pixels(self, width: u32, height: u32) -> u64 {
        // x_ndc = 2 (i + 0.5)/W − 1 in [lo, hi]  <=>  i in [(lo + 1) W/2 − 0.5, (hi + 1) W/2 − 0.5].
        let span = |lo: f64, hi: f64, n: u32| -> u64 {
            let n_f = f64::from(n);
            let a = ((lo + 1.0) * n_f / 2.0 - 0.5).ceil().max(0.0);
            let b = ((hi + 1.0) * n_f / 2.0 - 0.5).floor().min(n_f - 1.0);
            if b >= a { (b - a) as u64 + 1 } else { 0 }
        };
        // NDC y is up, rows count down: the count is symmetric.
        span(self.lo.x, self.hi.x, width) * span(self.lo.y, self.hi.y, height)
    }

    /// The box widened by `px` pixels on each side of a `width` x `height` target, as the
    /// vertex stage widens it ([`PROXY_MARGIN_PX`](crate::shape::rules::PROXY_MARGIN_PX)).
    pub fn widened(self, px: f64, width: u32, height: u32) -> NdcBox {
        let m = 2.0 * px * DVec2::new(1.0 / f64::from(width), 1.0 / f64::from(height));
        NdcBox {
            lo: self.lo - m,
            hi: self.hi + m,
        }
    }

    /// The box clipped to the viewport, as the vertex stage emits it.
    pub fn clamped(self) -> NdcBox {
        NdcBox {
            lo: self.lo.clamp(DVec2::NEG_ONE, DVec2::ONE),
            hi: self.hi.clamp(DVec2::NEG_ONE, DVec2::ONE),
        }
    }

    /// Fragment-shader invocations reported by a rasteriser that shades whole `block` x `block`
    /// pixel tiles per triangle (llvmpipe/lavapipe: 4x4, every lane counted): 16 per tile that
    /// holds a covered pixel centre of either triangle of the strip (mm, pm, mp), (pm, mp, pp).
    /// Tiles on the box's border and along its diagonal are what makes this exceed
    /// [`NdcBox::pixels`] (by about 4 (width + height + diagonal) / (box area) in pixels).
    pub fn strip_tile_invocations(self, width: u32, height: u32, block: u32) -> u64 {
        let b = self.clamped();
        let (pm, mp) = (DVec2::new(b.hi.x, b.lo.y), DVec2::new(b.lo.x, b.hi.y));
        let side = |p: DVec2| (mp - pm).perp_dot(p - pm);
        let first = side(b.lo) >= 0.0;
        let (tw, th) = (width.div_ceil(block), height.div_ceil(block));
        let mut tiles = vec![[false; 2]; (tw * th) as usize];
        for j in 0..height {
            let y = 1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(height);
            if y < b.lo.y || y > b.hi.y {
                continue;
            }
            for i in 0..width {
                let x = 2.0 * (f64::from(i) + 0.5) / f64::from(width) - 1.0;
                if x < b.lo.x || x > b.hi.x {
                    continue;
                }
                let s = side(DVec2::new(x, y));
                let tile = &mut tiles[((j / block) * tw + i / block) as usize];
                if s == 0.0 || (s > 0.0) == first {
                    tile[0] = true;
                }
                if s == 0.0 || (s > 0.0) != first {
                    tile[1] = true;
                }
            }
        }
        let n: u64 = tiles
            .iter()
            .map(|t| u64::from(t[0]) + u64::from(t[1]))
            .sum();
        n * u64::from(block * block)
    }
}

/// Eq. 5 for one ellipsoid (or flat disc) with variance matrix `T = [[u, v, w, c], [0, 0, 0, 1]]`.
#[derive(Debug, Clone, Copy)]
pub struct QuadricBox {
    /// r4ᵀ D r4: negative iff the camera plane misses the quadric.
    pub r4dr4: f64,
    /// Box centre (r1ᵀDr4, r2ᵀDr4) / r4ᵀDr4 (None when r4ᵀDr4 = 0).
    pub centre: Option<DVec2>,
    /// w_clip of the centre c: positive in front of the camera plane.
    pub w_centre: f64,
    /// NDC depth of the centre (the box's depth in the flat variants).
    pub depth: f64,
    /// The box, when r4ᵀDr4 < 0 and the centre is in front.
    pub bbox: Option<NdcBox>,
    /// Largest value over the quadric of the clip-space planes w + x, w − x, w + y, w − y, z,
    /// w − z (negative: wholly outside that frustum plane).
    pub reach: [f64; 6],
}

impl QuadricBox {
    pub fn outside_frustum(&self) -> bool {
        self.reach.iter().any(|&r| r < 0.0)
    }
}

/// max over the unit ball of the parameter-space plane n: n.w + |n.xyz|.
fn reach(n: DVec4) -> f64 {
    n.w + n.truncate().length()
}

/// Minkowski product with D = diag(1, 1, 1, −1).
fn ddot(a: DVec4, b: DVec4) -> f64 {
    a.truncate().dot(b.truncate()) - a.w * b.w
}

/// `quadric_box` in sigg.wgsl: M = P View T, rows r1, r2, r4; the half-widths are taken around
/// the centre b0 as √(−nᵀDn / r4ᵀDr4), n = r1 − b0 r4 (algebraically eq. 5's roots).
pub fn quadric_box(view_proj: &DMat4, u: DVec3, v: DVec3, w: DVec3, c: DVec3) -> QuadricBox {
    let mu = *view_proj * u.extend(0.0);
    let mv = *view_proj * v.extend(0.0);
    let mw = *view_proj * w.extend(0.0);
    let mc = *view_proj * c.extend(1.0);
    let r1 = DVec4::new(mu.x, mv.x, mw.x, mc.x);
    let r2 = DVec4::new(mu.y, mv.y, mw.y, mc.y);
    let r3 = DVec4::new(mu.z, mv.z, mw.z, mc.z);
    let r4 = DVec4::new(mu.w, mv.w, mw.w, mc.w);
    let r44 = ddot(r4, r4);
    let reach = [r4 + r1, r4 - r1, r4 + r2, r4 - r2, r3, r4 - r3].map(reach);
    let centre = (r44 != 0.0).then(|| DVec2::new(ddot(r1, r4), ddot(r2, r4)) / r44);
    let bbox = match centre {
        Some(b0) if r44 < 0.0 && mc.w > 0.0 => {
            let n1 = r1 - b0.x * r4;
            let n2 = r2 - b0.y * r4;
            let h = (DVec2::new(ddot(n1, n1), ddot(n2, n2)) / -r44)
                .max(DVec2::ZERO)
                .to_array()
                .map(f64::sqrt);
            let h = DVec2::from(h);
            Some(NdcBox {
                lo: b0 - h,
                hi: b0 + h,
            })
        }
        _ => None,
    };
    QuadricBox {
        r4dr4: r44,
        centre,
        w_centre: mc.w,
        depth: mc.z / mc.w,
        bbox,
        reach,
    }
}

/// What the vertex stage draws for the ellipsoid of radii `r` in `geo`'s frame about its
/// centre (a glyph's own, or a bound of it): its box, the viewport when the camera plane cuts
/// it, nothing when it lies behind the camera or outside the frustum.
pub fn ellipsoid_proxy(view_proj: &DMat4, geo: &GlyphGeometry, r: DVec3) -> Proxy {
    let f = geo.frame;
    let b = quadric_box(
        view_proj,
        f.x_axis * r.x,
        f.y_axis * r.y,
        f.z_axis * r.z,
        geo.centre,
    );
    if b.outside_frustum() {
        return Proxy::Culled;
    }
    match b.bbox {
        Some(bbox) => Proxy::Box(bbox),
        None if b.r4dr4 < 0.0 => Proxy::Culled,
        None => Proxy::Viewport,
    }
}

/// The two end discs (at `c − w` and `c + w`) of a cylinder with axis half-vector `w` and
/// cross-section semi-axes `u`, `v`, and the exact box of the cylinder (their union) when both
/// discs lie in front of the camera plane.
pub fn cylinder_boxes(
    view_proj: &DMat4,
    u: DVec3,
    v: DVec3,
    w: DVec3,
    c: DVec3,
) -> ([QuadricBox; 2], Option<NdcBox>) {
    let caps = [
        quadric_box(view_proj, u, v, DVec3::ZERO, c - w),
        quadric_box(view_proj, u, v, DVec3::ZERO, c + w),
    ];
    let union = match (caps[0].bbox, caps[1].bbox) {
        (Some(a), Some(b)) => Some(a.union(b)),
        _ => None,
    };
    (caps, union)
}

/// What the vertex stage draws for a glyph.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Proxy {
    /// Eye inside (perspective), the glyph wholly behind the camera plane, or wholly outside
    /// one plane of the view frustum.
    Culled,
    /// The glyph crosses the camera plane: the whole viewport.
    Viewport,
    Box(NdcBox),
}

impl Proxy {
    /// Pixels whose fragments the proxy shades on a `width` x `height` target (the box is
    /// clipped to the viewport).
    pub fn pixels(self, width: u32, height: u32) -> u64 {
        match self {
            Proxy::Culled => 0,
            Proxy::Viewport => u64::from(width) * u64::from(height),
            Proxy::Box(b) => b.pixels(width, height),
        }
    }

    /// [`NdcBox::strip_tile_invocations`] of the proxy (the viewport proxy is a box too).
    pub fn strip_tile_invocations(self, width: u32, height: u32, block: u32) -> u64 {
        let full = NdcBox {
            lo: DVec2::NEG_ONE,
            hi: DVec2::ONE,
        };
        match self {
            Proxy::Culled => 0,
            Proxy::Viewport => full.strip_tile_invocations(width, height, block),
            Proxy::Box(b) => b.strip_tile_invocations(width, height, block),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_vectors::{cases, m4, v3};
    use serde_json::Value;

    fn f(v: &Value) -> f64 {
        v.as_f64().unwrap()
    }

    fn close_box(got: Option<NdcBox>, want: &Value, what: &str) {
        if want.is_null() {
            assert!(got.is_none(), "{what}: box {got:?} where none is defined");
            return;
        }
        let got = got
            .unwrap_or_else(|| panic!("{what}: no box, want {want}"))
            .to_array();
        for k in 0..4 {
            assert!(
                (got[k] - f(&want[k])).abs() <= 1e-9,
                "{what}: box {got:?} vs {want}"
            );
        }
    }

    /// Every ellipsoid and cylinder case: box, centre, r4ᵀDr4, cylinder cap boxes (1e-9).
    #[test]
    fn boxes_match_the_test_vectors() {
        let mut checked = 0;
        for case in &cases() {
            let id = case["id"].as_str().unwrap();
            let e = &case["expected"];
            let s = &e["sigg"];
            if s.is_null() {
                continue;
            }
            let vp = m4(&e["proj_cols"]) * m4(&e["view_cols"]);
            let g = &case["glyph"];
            match case["kind"].as_str().unwrap() {
                "ellipsoid" => {
                    // T's columns (the symmetric glyph matrix) give the same Q as r_i e_i.
                    let t = &g["T"];
                    let col = |j: usize| DVec3::new(f(&t[0][j]), f(&t[1][j]), f(&t[2][j]));
                    let q = quadric_box(&vp, col(0), col(1), col(2), v3(&g["c"]));
                    close_box(q.bbox, &s["bbox_ndc"], id);
                    let r44 = f(&s["r4Dr4"]);
                    assert!(
                        (q.r4dr4 - r44).abs() <= 1e-9 * r44.abs().max(1.0),
                        "{id}: r4Dr4 {} vs {r44}",
                        q.r4dr4
                    );
                    if let Some(want) = s.get("centre_ndc") {
                        let c = q.centre.unwrap();
                        assert!(
                            (c - DVec2::new(f(&want[0]), f(&want[1]))).length() <= 1e-9,
                            "{id}: centre {c} vs {want}"
                        );
                    }
                }
                "cylinder" => {
                    let (caps, union) =
                        cylinder_boxes(&vp, v3(&g["u"]), v3(&g["v"]), v3(&g["w"]), v3(&g["c"]));
                    close_box(union, &s["bbox_ndc"], id);
                    // The vectors list the disc at c + w first.
                    close_box(caps[1].bbox, &s["cap_bboxes_ndc"][0], id);
                    close_box(caps[0].bbox, &s["cap_bboxes_ndc"][1], id);
                }
                other => panic!("{id}: Sigg data for an unexpected kind {other}"),
            }
            checked += 1;
        }
        assert_eq!(checked, 12, "every ellipsoid and cylinder case");
    }

    #[test]
    fn box_pixels_count_pixel_centres() {
        // 8 x 4 target: pixel centres at x = −7/8, −5/8, ..., 7/8 and y = ±1/4, ±3/4.
        let b = NdcBox {
            lo: DVec2::new(-0.7, -0.3),
            hi: DVec2::new(0.2, 0.8),
        };
        // x: −5/8, −3/8, −1/8, 1/8 (4); y: −1/4, 1/4, 3/4 (3).
        assert_eq!(b.pixels(8, 4), 12);
        let off = NdcBox {
            lo: DVec2::new(1.5, 0.0),
            hi: DVec2::new(2.0, 1.0),
        };
        assert_eq!(off.pixels(8, 4), 0);
        assert_eq!(Proxy::Viewport.pixels(8, 4), 32);
    }

    #[test]
    fn tile_model_counts_diagonal_tiles_twice() {
        // 8x8 viewport, 4x4 tiles: the diagonal (bottom-right to top-left) crosses two tiles,
        // which both triangles touch: 4 + 2 tiles.
        assert_eq!(Proxy::Viewport.strip_tile_invocations(8, 8, 4), 6 * 16);
        // A box inside one tile: one tile per triangle.
        let b = NdcBox {
            lo: DVec2::new(-0.95, 0.3),
            hi: DVec2::new(-0.3, 0.95),
        };
        assert_eq!(b.strip_tile_invocations(8, 8, 4), 2 * 16);
    }
}
