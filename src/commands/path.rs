//! Options that choose how much work a frame does (issue 7), shared by `render` and `demo`: the
//! proxy shape, conservative depth, culling, the compute prepass, splats and draw order. The
//! defaults are what measured fastest on lavapipe with the reference's accuracy (README,
//! "Doing less work"): Gumhold ellipsoids of up to 32 pixels across are splats, larger ones
//! are drawn from the prepass, and glyphs outside the view are culled. `--baseline` runs the
//! path before issue 7 (a quad drawn for every glyph) for comparison.

use clap::Args;

use tensorglyph::render::{DEFAULT_SPLAT, FrameRequest, Proxy, ProxyShape};

#[derive(Args, Debug, Clone)]
pub struct PathArgs {
    /// Proxy polygon of Gumhold's ray casters: quad, octagon (fewer pixels, more triangles) or
    /// triangle (one triangle, more pixels).
    #[arg(long, value_enum, default_value_t = ProxyShape::Quad)]
    pub proxy: ProxyShape,
    /// Move Gumhold ellipsoid proxies to the glyph's nearest plane (conservative depth), and
    /// declare it for early depth tests where the adapter supports that.
    #[arg(long)]
    pub conservative_depth: bool,
    /// Draw glyphs outside the view frustum too (by default they are culled).
    #[arg(long)]
    pub no_cull: bool,
    /// Skip glyphs whose projected bounding sphere is smaller than this radius in pixels
    /// (0: draw all; glyphs under ~0.3 px rarely cover a pixel centre).
    #[arg(long, default_value_t = 0.0, value_name = "PX")]
    pub min_pixel_radius: f32,
    /// Draw front to back (sorted by view depth) instead of in file order: pays where early
    /// depth tests reject hidden fragments; on lavapipe it measured slower (see the README).
    /// The prepass draws in no fixed order: sorting applies to `--splat 0` without --prepass.
    #[arg(long)]
    pub sort: bool,
    /// Gumhold ellipsoids: build each glyph's proxy once in a compute pass (not once per
    /// vertex) and draw only the glyphs it keeps, so culled glyphs cost nothing in the draw
    /// (on whenever --splat is above 0).
    #[arg(long)]
    pub prepass: bool,
    /// Gumhold ellipsoids: ray cast glyphs whose proxy spans at most PX pixels across per pixel
    /// in a compute pass instead of drawing them (needs depth correction; 0: draw every glyph).
    #[arg(long, default_value_t = DEFAULT_SPLAT, value_name = "PX")]
    pub splat: u32,
    /// The path before issue 7, for comparison: a quad drawn for every glyph, no culling, no
    /// prepass, no splats (the same as --splat 0 --no-cull).
    #[arg(long, conflicts_with_all = ["prepass", "conservative_depth", "sort", "proxy", "splat", "no_cull"])]
    pub baseline: bool,
}

impl PathArgs {
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.min_pixel_radius.is_finite() && self.min_pixel_radius >= 0.0,
            "--min-pixel-radius must be a number of pixels ≥ 0, got {}",
            self.min_pixel_radius
        );
        Ok(())
    }

    /// `req` with these options (early depth is left off: it depends on the scene and adapter).
    pub fn apply(&self, req: FrameRequest) -> FrameRequest {
        if self.baseline {
            return FrameRequest {
                proxy: Proxy::BASELINE,
                cull: false,
                prepass: false,
                splat: 0,
                min_pixel_radius: self.min_pixel_radius,
                ..req
            };
        }
        FrameRequest {
            proxy: Proxy {
                shape: self.proxy,
                conservative: self.conservative_depth,
                early_depth: false,
            },
            cull: !self.no_cull,
            min_pixel_radius: self.min_pixel_radius,
            prepass: self.prepass,
            splat: self.splat,
            ..req
        }
    }

    /// Whether to sort the instances front to back before upload.
    pub fn sort(&self) -> bool {
        self.sort
    }
}
