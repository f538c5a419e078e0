//! Options that choose how much work a frame does (issue 7), shared by `render`, `demo` and
//! `bench`: the proxy shape, conservative depth, culling and draw order, and `--baseline` for the
//! path before them, for comparison.

use clap::Args;

use tensorglyph::render::{FrameRequest, Proxy, ProxyShape};

#[derive(Args, Debug, Clone)]
pub struct PathArgs {
    /// The path before issue 7: quads at the silhouette plane, no culling (overrides the
    /// options below).
    #[arg(long)]
    pub baseline: bool,
    /// Proxy polygon of Gumhold's ray casters: quad, octagon (fewer pixels, more triangles) or
    /// triangle (one triangle, more pixels).
    #[arg(long, value_enum, default_value_t = ProxyShape::Quad)]
    pub proxy: ProxyShape,
    /// Move Gumhold ellipsoid proxies to the glyph's nearest plane (conservative depth), and
    /// declare it for early depth tests where the adapter supports that.
    #[arg(long)]
    pub conservative_depth: bool,
    /// Draw glyphs outside the view frustum too (they are culled in the vertex stage otherwise).
    #[arg(long)]
    pub no_cull: bool,
    /// Skip glyphs whose projected bounding sphere is smaller than this radius in pixels
    /// (0: draw all; glyphs under ~0.3 px rarely cover a pixel centre).
    #[arg(long, default_value_t = 0.0, value_name = "PX")]
    pub min_pixel_radius: f32,
    /// Draw front to back (sorted by view depth) instead of in file order: pays where early
    /// depth tests reject hidden fragments; on lavapipe it measured slower (see the README).
    #[arg(long)]
    pub sort: bool,
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
        let req = FrameRequest {
            proxy: Proxy {
                shape: self.proxy,
                conservative: self.conservative_depth,
                early_depth: false,
            },
            cull: !self.no_cull,
            min_pixel_radius: self.min_pixel_radius,
            ..req
        };
        if self.baseline { req.baseline() } else { req }
    }

    /// Whether to sort the instances front to back before upload.
    pub fn sort(&self) -> bool {
        !self.baseline && self.sort
    }
}
