//! Options that choose how much work a frame does (issue 7), shared by `render` and `demo`: the
//! proxy shape, conservative depth, culling, the compute prepass and draw order. The defaults are the path before
//! them (quads, no culling, file order): on lavapipe none of the others pays for itself in every
//! view (README, "Doing less work"), so each is a flag to measure with.

use clap::Args;

use tensorglyph::render::{FrameRequest, Proxy, ProxyShape};

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
    /// Cull glyphs outside the view frustum in the vertex stage (on lavapipe a culled glyph
    /// still costs its vertex invocations: see the README).
    #[arg(long)]
    pub cull: bool,
    /// Skip glyphs whose projected bounding sphere is smaller than this radius in pixels
    /// (0: draw all; glyphs under ~0.3 px rarely cover a pixel centre).
    #[arg(long, default_value_t = 0.0, value_name = "PX")]
    pub min_pixel_radius: f32,
    /// Draw front to back (sorted by view depth) instead of in file order: pays where early
    /// depth tests reject hidden fragments; on lavapipe it measured slower (see the README).
    #[arg(long)]
    pub sort: bool,
    /// Gumhold ellipsoids: build each glyph's proxy once in a compute pass (not once per
    /// vertex) and draw only the glyphs it keeps, so culled glyphs cost nothing in the draw.
    #[arg(long)]
    pub prepass: bool,
    /// Gumhold ellipsoids: ray cast glyphs whose proxy spans at most PX pixels across per pixel
    /// in a compute pass instead of drawing them (implies --prepass; needs depth correction;
    /// 0: off).
    #[arg(long, default_value_t = 0, value_name = "PX")]
    pub splat: u32,
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
        FrameRequest {
            proxy: Proxy {
                shape: self.proxy,
                conservative: self.conservative_depth,
                early_depth: false,
            },
            cull: self.cull,
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
