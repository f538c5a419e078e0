//! A large scene's glyphs in bricks of nearby ones, for occlusion culling (Grottel et al. 2010:
//! cost follows what is seen, not the glyph count). The glyphs are sorted once, at upload, into
//! cells of their box in Morton order, each cell cut into runs of [`BRICK`]; each brick keeps a
//! ball bounding its glyphs. Each frame drops the bricks outside the camera's frustum and orders
//! the rest ([`Bricks::frame_order`]): those in front first, nearest first, so that the prepass
//! draws them first and culls the rest against what they left
//! (`src/render/gumhold/occlusion.rs`).
//!
//! The order only decides how much is culled, never what is drawn: the GPU tests each brick
//! against the depth actually drawn.

use glam::DVec3;

use crate::camera::Camera;
use crate::scene::GlyphInstance;

/// Glyphs per brick (`BRICK` in shaders/method/prepass.wgsl), a multiple of the prepass's
/// workgroup.
pub const BRICK: u32 = 256;

/// Scenes of at least this many glyphs get bricks. Below it one slice holds the scene and the
/// culling pays for neither its second pass nor its depth tiles (measured in the book's Speed
/// page).
pub const MIN_GLYPHS: usize = 1 << 17;

/// The share of the bricks a frame may see at most for it to be drawn by bricks. Drawing by
/// bricks costs an indirection per glyph, a slice more and the depth tiles between slices, and
/// on a porous field (grid:100 whole: 198,000 glyphs seen) even the frame's own final depth
/// hides only 12 % of the bricks, so a frame that sees the whole field is drawn in file order
/// (the book's Speed page has the measurements).
pub const BRICKS_PAY_SHARE: f64 = 0.5;

/// An unused position of the last brick.
pub const NO_GLYPH: u32 = u32::MAX;

/// Cells across the image of the estimate of what is in front ([`Bricks::frame_order`]).
const COVER_CELLS: (usize, usize) = (64, 48);
/// Bricks a cell takes before the bricks behind count as hidden by the estimate.
const COVER_LAYERS: u8 = 2;

/// A scene's bricks: the glyphs (chunk-local indices) in brick order, and each brick's ball.
pub struct Bricks {
    /// Glyph index per position, [`BRICK`] positions a brick, the last padded with
    /// [`NO_GLYPH`].
    pub glyphs: Vec<u32>,
    /// Per brick: the centre (relative to the scene origin) and radius of a ball holding its
    /// glyphs.
    balls: Vec<(DVec3, f64)>,
}

/// One frame's order of the bricks: `order` (brick indices), of which the first `front` are
/// those the coarse estimate found in front.
pub struct FrameOrder {
    pub order: Vec<u32>,
    pub front: usize,
}

/// Spreads the low 10 bits of `v` to every third bit.
fn spread(v: u32) -> u64 {
    let mut x = u64::from(v & 0x3ff);
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    x = (x | (x << 2)) & 0x0924_9249;
    x
}

impl Bricks {
    /// The bricks of `instances` (centres relative to the scene origin).
    pub fn new(instances: &[GlyphInstance]) -> Self {
        let centre = |g: &GlyphInstance| DVec3::from(g.centre.map(f64::from));
        let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for g in instances {
            lo = lo.min(centre(g));
            hi = hi.max(centre(g));
        }
        // Cells of about BRICK glyphs each (were the glyphs spread evenly over their box), in
        // Morton order; a brick never spans two cells (a run of the curve alone can straddle
        // half the field where the curve jumps).
        let extent = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        let cells_per_axis =
            ((instances.len() as f64 / f64::from(BRICK)).cbrt().ceil()).clamp(1.0, 1023.0);
        let scale = cells_per_axis / extent.max_element();
        let cell_of = |g: &GlyphInstance| {
            let q = ((centre(g) - lo) * scale)
                .min(DVec3::splat(1023.0))
                .as_uvec3();
            spread(q.x) | (spread(q.y) << 1) | (spread(q.z) << 2)
        };
        let mut keyed: Vec<(u64, u32)> = instances
            .iter()
            .enumerate()
            .map(|(i, g)| (cell_of(g), i as u32))
            .collect();
        keyed.sort_unstable();
        let mut glyphs = Vec::with_capacity(keyed.len() + keyed.len() / 2);
        let mut balls = Vec::new();
        for cell in keyed.chunk_by(|a, b| a.0 == b.0) {
            for run in cell.chunks(BRICK as usize) {
                let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
                let mut reach = 0.0f64;
                for &(_, i) in run {
                    let g = &instances[i as usize];
                    lo = lo.min(centre(g));
                    hi = hi.max(centre(g));
                    // The box of its radii holds every kind of glyph.
                    reach = reach.max(DVec3::from(g.radii.map(f64::from)).length());
                    glyphs.push(i);
                }
                balls.push(((lo + hi) * 0.5, (hi - lo).length() * 0.5 + reach));
                glyphs.resize(glyphs.len().next_multiple_of(BRICK as usize), NO_GLYPH);
            }
        }
        Self { glyphs, balls }
    }

    /// Whether a scene of `count` glyphs gets bricks.
    pub fn pays(count: usize) -> bool {
        count >= MIN_GLYPHS
    }

    pub fn count(&self) -> usize {
        self.balls.len()
    }

    /// The balls as the GPU reads them (`brick_balls` in shaders/method/occlusion.wgsl):
    /// centre and radius, the radius rounded up past the centre's f32 rounding.
    pub fn balls_f32(&self) -> Vec<[f32; 4]> {
        self.balls
            .iter()
            .map(|&(c, r)| {
                let c32 = c.as_vec3();
                let moved = (c - c32.as_dvec3()).length();
                [c32.x, c32.y, c32.z, ((r + moved) * (1.0 + 1e-6)) as f32]
            })
            .collect()
    }

    /// The bricks `camera` (whose scene origin is `origin`) may see, in the order it draws
    /// them: those wholly outside its frustum are left out; first come those a coarse estimate
    /// finds in front (per cell of a grid over the image, the first `COVER_LAYERS` (2) bricks
    /// whose projected ball covers it, nearest first), then the rest, nearest first.
    pub fn frame_order(&self, camera: &Camera, origin: DVec3) -> FrameOrder {
        let eye = camera.eye - origin;
        let forward = camera.forward();
        let view = camera.view(origin);
        let proj = camera.projection_matrix();
        let planes = camera.frustum_planes(origin);
        let (cells_x, cells_y) = COVER_CELLS;
        // Per brick in the frustum: its nearest view distance.
        let mut near: Vec<(f64, u32)> = self
            .balls
            .iter()
            .enumerate()
            .filter(|(_, (c, r))| {
                // A little slack: the GPU tests the same balls in f32 and decides.
                planes
                    .iter()
                    .all(|p| p.truncate().dot(*c) + p.w >= -r * (1.0 + 1e-6) - 1e-9 * r.max(1.0))
            })
            .map(|(i, &(c, r))| ((c - eye).dot(forward) - r, i as u32))
            .collect();
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut cover = vec![0u8; cells_x * cells_y];
        let mut front = Vec::new();
        let mut rest = Vec::new();
        for &(d, i) in &near {
            let (c, r) = self.balls[i as usize];
            // Reaching in front of the near plane: counted as in front.
            if d <= camera.near {
                front.push(i);
                continue;
            }
            // The ball's square at its nearest distance bounds its projection well enough for
            // an estimate.
            let v = view.transform_point3(c);
            let clip = proj * v.extend(1.0);
            let (x, y) = (clip.x / clip.w, clip.y / clip.w);
            let half = if camera.is_ortho() {
                r * proj.x_axis.x
            } else {
                r * proj.x_axis.x / d
            };
            let half_y = half * proj.y_axis.y / proj.x_axis.x;
            let cell = |ndc: f64, n: usize| ((ndc * 0.5 + 0.5) * n as f64).floor();
            let x0 = cell(x - half, cells_x).max(0.0);
            let x1 = cell(x + half, cells_x).min(cells_x as f64 - 1.0);
            let y0 = cell(y - half_y, cells_y).max(0.0);
            let y1 = cell(y + half_y, cells_y).min(cells_y as f64 - 1.0);
            if !(x0 <= x1 && y0 <= y1) {
                rest.push(i);
                continue;
            }
            let mut seen = false;
            for cy in y0 as usize..=y1 as usize {
                for cx in x0 as usize..=x1 as usize {
                    let n = &mut cover[cy * cells_x + cx];
                    seen |= *n < COVER_LAYERS;
                    *n = n.saturating_add(1);
                }
            }
            if seen { front.push(i) } else { rest.push(i) }
        }
        let count = front.len();
        front.extend(rest);
        FrameOrder {
            order: front,
            front: count,
        }
    }

    /// Whether a frame that sees `seen` of the bricks draws faster by bricks than in file
    /// order: only where the frustum leaves out a good share of them ([`BRICKS_PAY_SHARE`]).
    pub fn pay_for(&self, seen: usize) -> bool {
        (seen as f64) <= BRICKS_PAY_SHARE * self.balls.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glyph(centre: [f32; 3]) -> GlyphInstance {
        GlyphInstance {
            centre,
            color: 0,
            rotation: [0.0, 0.0, 0.0, 1.0],
            radii: [0.4; 3],
            glyph: 0,
            shape: [0, 0],
        }
    }

    #[test]
    fn every_glyph_is_in_one_brick_and_each_ball_holds_its_glyphs() {
        let n = 20;
        let instances: Vec<_> = (0..n * n * n)
            .map(|i| glyph([(i % n) as f32, (i / n % n) as f32, (i / n / n) as f32]))
            .collect();
        let b = Bricks::new(&instances);
        assert_eq!(b.glyphs.len() % BRICK as usize, 0);
        let mut seen = vec![0; instances.len()];
        for (p, &i) in b.glyphs.iter().enumerate() {
            if i == NO_GLYPH {
                continue;
            }
            seen[i as usize] += 1;
            let (c, r) = b.balls[p / BRICK as usize];
            let g = DVec3::from(instances[i as usize].centre.map(f64::from));
            assert!((g - c).length() + 0.4 * 3f64.sqrt() <= r + 1e-9);
        }
        assert!(seen.iter().all(|&s| s == 1));
        // Morton runs are compact: a brick of 256 grid points spans a few cells, not a row.
        let widest = b.balls.iter().map(|&(_, r)| r).fold(0.0, f64::max);
        assert!(widest < 8.0, "{widest}");
    }
}
