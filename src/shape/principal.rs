//! Principal-stress glyphs: per tensor a bar along each eigenvector e_i, through the centre,
//! of half-length ∝ |σ_i| (the style's radii, without their minimum), coloured by the sign of
//! σ_i by default (tension red, compression blue, white near zero); with `--arrows` a cone head
//! at each end, pointing outward for tension and inward for compression. The stress analysts'
//! glyph (OPM/ResInsight, underworld3, FerriteViz), drawn exactly.
//!
//! Each bar and each head is an instance of its own ([`Shape::parts`]), so every instance is a
//! convex solid one ray cast decides: a bar is the capped circular cylinder of the cylinder kind
//! (axis the frame's first column, half-length radii.x, radius radii.y = radii.z), a head a
//! finite circular cone (axis the frame's first column towards the apex, half-length radii.x,
//! base radius radii.y). In parameter space, the local frame scaled by the radii, a bar is
//! |x| ≤ 1, y² + z² ≤ 1 and a head x ∈ [−1, 1], √(y² + z²) ≤ (1 − x)/2: base at x = −1,
//! apex at x = 1. Both lie in the cylinder |x| ≤ 1, y² + z² ≤ 1, whose bounds, screen boxes
//! and Gumhold quad they share. Every instance of a glyph carries the glyph's index, so
//! picking finds the tensor.

use glam::{DMat3, DVec3};

use super::cylinder::Cylinder;
use super::mesh::{Mesh, prism_sides};
use super::{
    Capabilities, Exact, GlyphGeometry, GlyphInstance, GlyphKind, Part, RayHit, Shape, stable_roots,
};
use crate::glyph::{ColorScheme, Glyph, ResolvedStyle};

pub const WGSL: &str = include_str!("../../shaders/shape/principal.wgsl");

/// A head's base radius, in bar radii.
pub const HEAD_RADIUS: f64 = 2.2;
/// A head's length, in bar radii, at most [`HEAD_MAX`] of the bar's half-length.
pub const HEAD_LENGTH: f64 = 4.0;
pub const HEAD_MAX: f64 = 0.4;

/// `shape` word 0 of a head (a bar's is 0).
pub const HEAD: u32 = 1;

/// The principal-stress kind.
pub struct Kind;

impl Shape for Kind {
    fn kind(&self) -> GlyphKind {
        GlyphKind::Principal
    }

    fn caps(&self) -> Capabilities {
        Capabilities {
            arrows: true,
            ..Capabilities::NONE
        }
    }

    fn default_color(&self) -> Option<ColorScheme> {
        Some(ColorScheme::Sign)
    }

    /// Three bars, then their heads (two per bar).
    fn parts(&self) -> usize {
        9
    }

    fn place(&self, g: &Glyph, part: usize, style: &ResolvedStyle) -> Option<Part> {
        let (i, head) = if part < 3 {
            (part, None)
        } else {
            (
                (part - 3) / 2,
                Some(if part.is_multiple_of(2) { -1.0 } else { 1.0 }),
            )
        };
        if head.is_some() && !style.arrows {
            return None;
        }
        let sigma = f64::from(g.eigenvalues[i]);
        let length = f64::from(style.lengths(g)[i]);
        if sigma == 0.0 || sigma.abs() < style.min_stress || length.is_nan() || length <= 0.0 {
            return None;
        }
        let w = style.bar_width;
        let head_length = (HEAD_LENGTH * w).min(HEAD_MAX * length);
        let shaft = if style.arrows {
            length - head_length
        } else {
            length
        };
        let frame = crate::tensor::eigen::quat_to_frame(g.rotation).map(DVec3::from);
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let color = if style.color == ColorScheme::Sign {
            let largest = g
                .eigenvalues
                .iter()
                .fold(0.0f64, |m, x| m.max(f64::from(*x).abs()));
            ResolvedStyle::sign_color(sigma, largest)
        } else {
            style.color(g)
        };
        let (cols, radii, offset, params) = match head {
            None => (
                [frame[i], frame[j], frame[k]],
                [shaft, w, w],
                DVec3::ZERO,
                [0, 0],
            ),
            Some(end) => {
                // The apex points outward for tension, inward for compression.
                let outward = sigma > 0.0;
                let apex = frame[i] * if outward { end } else { -end };
                // Swapping the other two columns keeps a reversed axis right-handed.
                let cols = if apex.dot(frame[i]) > 0.0 {
                    [apex, frame[j], frame[k]]
                } else {
                    [apex, frame[k], frame[j]]
                };
                (
                    cols,
                    [0.5 * head_length, HEAD_RADIUS * w, HEAD_RADIUS * w],
                    frame[i] * (end * (length - 0.5 * head_length)),
                    [HEAD, 0],
                )
            }
        };
        let q = glam::DQuat::from_mat3(&DMat3::from_cols(cols[0], cols[1], cols[2])).normalize();
        Some(Part {
            offset: offset.to_array(),
            rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
            radii: radii.map(|r| r as f32),
            params,
            color,
        })
    }

    /// A plain instance (a synthetic scene's) as a bar, or as a head for odd glyph indices, so
    /// that a scene of several exercises both solids. (A one-glyph scene stays a bar: the
    /// stability suite's probes place their eye and near plane for the glyph's ellipsoid, and a
    /// head well inside it, seen through a near plane of 1e-7, sends the meshes' far fragments
    /// to depth 1.0, where the depth test drops them.)
    fn adopt(&self, g: &GlyphInstance) -> GlyphInstance {
        GlyphInstance {
            shape: if g.glyph % 2 == 1 { [HEAD, 0] } else { [0, 0] },
            ..*g
        }
    }

    /// Bars and heads lie in their cylinder.
    fn bounds(&self, geo: &GlyphGeometry) -> DVec3 {
        geo.glyph_half_extents()
    }

    fn exact(&self, geo: &GlyphGeometry) -> Box<dyn Exact> {
        if geo.params[0] == HEAD {
            Box::new(Cone::of(geo))
        } else {
            Box::new(Cylinder::of(geo))
        }
    }

    /// The cylinder's prism: a head narrows it to its apex in the vertex shader.
    fn unit_mesh(&self, level: u8) -> Mesh {
        super::cylinder::prism(level)
    }

    fn mesh_stats(&self, level: u8) -> (usize, usize) {
        let s = prism_sides(level) as usize;
        (4 * s + 2, 4 * s)
    }

    fn wgsl(&self) -> &'static [&'static str] {
        &[super::cylinder::SLAB_WGSL, WGSL]
    }
}

/// A finite circular cone as the reference casts it: in parameter space (the frame scaled by
/// the radii) x ∈ [−1, 1], √(y² + z²) ≤ (1 − x)/2, the apex at x = 1.
#[derive(Debug, Clone, Copy)]
pub struct Cone {
    pub c: DVec3,
    pub frame: DMat3,
    pub radii: DVec3,
}

impl Cone {
    pub fn of(geo: &GlyphGeometry) -> Self {
        Self {
            c: geo.centre,
            frame: geo.frame,
            radii: geo.radii,
        }
    }

    fn param(&self, v: DVec3) -> DVec3 {
        (self.frame.transpose() * v) / self.radii
    }

    pub fn contains(&self, p: DVec3) -> bool {
        let q = self.param(p - self.c);
        let r = 0.5 * (1.0 - q.x);
        q.x.abs() <= 1.0 && q.y * q.y + q.z * q.z <= r * r
    }

    /// The interval of `o + t v` (parameter space) inside the solid, and whether each end lies
    /// on the base: (t_in, base_in, t_out, base_out), or `None` for a miss.
    pub fn span(o: DVec3, v: DVec3) -> Option<(f64, bool, f64, bool)> {
        // The nappe √(y² + z²) ≤ q, q = (1 − x)/2 ≥ 0: F = y² + z² − q² ≤ 0.
        let (qa, qb) = (0.5 * (1.0 - o.x), -0.5 * v.x);
        let a = v.y * v.y + v.z * v.z - qb * qb;
        let b = o.y * v.y + o.z * v.z - qa * qb;
        let c = o.y * o.y + o.z * o.z - qa * qa;
        // Where q ≥ 0 along the ray.
        let (q_lo, q_hi) = half_line(qa, qb);
        let (f_lo, f_hi) = if a == 0.0 {
            // F linear in t (a ray parallel to a generator).
            if b == 0.0 {
                if c > 0.0 {
                    return None;
                }
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                let t = -c / (2.0 * b);
                if b > 0.0 {
                    (f64::NEG_INFINITY, t)
                } else {
                    (t, f64::INFINITY)
                }
            }
        } else {
            let disc = b * b - a * c;
            if disc.is_nan() || disc < 0.0 {
                // F keeps the sign of a: no inside for a > 0; everywhere for a < 0, where the
                // ray is inside the double cone throughout (q ≥ 0 picks the nappe).
                if a > 0.0 {
                    return None;
                }
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                let (t1, t2) = stable_roots(a, b, c, disc);
                if a > 0.0 {
                    (t1, t2)
                } else if qb < 0.0 {
                    // Inside beyond the roots, one half-line per nappe: q grows towards
                    // t → −∞, so this nappe's is the first.
                    (f64::NEG_INFINITY, t1)
                } else {
                    (t2, f64::INFINITY)
                }
            }
        };
        let (side_in, side_out) = (f_lo.max(q_lo), f_hi.min(q_hi));
        let (mut base_in, mut base_out) = (f64::NEG_INFINITY, f64::INFINITY);
        if v.x != 0.0 {
            let t = (-1.0 - o.x) / v.x;
            if v.x > 0.0 {
                base_in = t;
            } else {
                base_out = t;
            }
        } else if o.x < -1.0 {
            return None;
        }
        let t_in = side_in.max(base_in);
        let t_out = side_out.min(base_out);
        if t_in.is_nan() || t_out.is_nan() || t_in > t_out {
            return None;
        }
        Some((t_in, base_in >= side_in, t_out, base_out <= side_out))
    }

    /// The outward normal (parameter space) at `p` on the side, or on the base.
    pub fn normal(p: DVec3, base: bool) -> DVec3 {
        if base {
            DVec3::new(-1.0, 0.0, 0.0)
        } else {
            DVec3::new(0.5 * (1.0 - p.x), 2.0 * p.y, 2.0 * p.z)
        }
    }
}

/// The `t` where `qa + qb t ≥ 0`.
fn half_line(qa: f64, qb: f64) -> (f64, f64) {
    if qb > 0.0 {
        (-qa / qb, f64::INFINITY)
    } else if qb < 0.0 {
        (f64::NEG_INFINITY, -qa / qb)
    } else if qa >= 0.0 {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        (f64::INFINITY, f64::NEG_INFINITY)
    }
}

impl Exact for Cone {
    fn centre(&self) -> DVec3 {
        self.c
    }

    /// The box of its cylinder.
    fn half_extents(&self) -> DVec3 {
        let a = self.frame.x_axis * self.radii.x;
        let u = self.frame.y_axis * self.radii.y;
        let v = self.frame.z_axis * self.radii.z;
        a.abs() + DVec3::new(u.x.hypot(v.x), u.y.hypot(v.y), u.z.hypot(v.z))
    }

    fn contains(&self, p: DVec3) -> bool {
        Cone::contains(self, p)
    }

    /// The first forward crossing from the ray point nearest the centre in parameter space (no
    /// cancellation for distant glyphs, nor for thin ones); from inside, the exit.
    fn intersect(&self, o: DVec3, d: DVec3) -> Option<RayHit> {
        let t0 = (self.c - o).dot(d);
        let v_t = self.param(d);
        // The world-nearest point lies up to k radii from the centre along a thin axis (k the
        // radii's ratio): the span's b² − a c then cancelled ~k² of itself, and heads of
        // k = 1e7 discs were hit up to 0.03 radii beside their edge. The parameter-space
        // nearest point is O(1), as the GPU's thin rays start (thin_pixel_ray).
        let w = self.param((o - self.c) + d * t0);
        let slide = -w.dot(v_t) / v_t.length_squared();
        let (t0, o_t) = if slide.is_finite() {
            (t0 + slide, w + v_t * slide)
        } else {
            (t0, w)
        };
        let (t_in, base_in, t_out, base_out) = Cone::span(o_t, v_t)?;
        if t0 + t_out <= 0.0 {
            return None;
        }
        let (t, base) = if t0 + t_in > 0.0 {
            (t_in, base_in)
        } else {
            (t_out, base_out)
        };
        let n_t = Cone::normal(o_t + v_t * t, base);
        let normal = (self.frame * (n_t / self.radii)).normalize();
        Some(RayHit { t: t0 + t, normal })
    }
}

#[cfg(test)]
mod tests;
