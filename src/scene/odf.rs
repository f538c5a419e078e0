//! A scene of ODF glyphs from a field of SH series ([`ShField`]): one glyph per voxel whose
//! series is not all zero (a CSD fit writes zeros outside its mask), at the voxel's centre,
//! turned from the series' axes into world axes, sized to the voxel and normalised as DIPY's
//! `odf_slicer` and mrview do. Each glyph's series goes to the scene's [`Payload`] in the plain
//! basis, scaled to parameter space with its bounds ([`crate::shape::odf`]).
//!
//! **Normalisation** ([`OdfNormalize`]): `max` (the default, DIPY's `norm=True`) scales each
//! voxel's ODF to its own largest value; `minmax` maps each voxel's [min, max] to [0, 1] (DIPY's
//! `minmax_norm`, mrview's "normalise"); `none` keeps the amplitudes comparable across voxels,
//! scaled by the field's largest. Negative values are not drawn (r = max(f, 0)). The largest
//! value is the largest on a geodesic sphere of 2562 or 10242 directions (a glyph's size, not its bound: the bound R is
//! rigorous).

use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};
use nalgebra::Matrix3;
use rayon::prelude::*;

use super::{GlyphInstance, GlyphKind, Scene};
use crate::field::ShField;
use crate::field::frame::tensor_rotation;
use crate::select::Plane;
use crate::shape::Payload;
use crate::shape::odf::{
    Ellipsoid, OdfColoring, bounding_ellipsoid, plain_of, range_of, rigorous_bounds,
    sampled_values_many,
};

/// How each voxel's ODF is scaled ([module doc](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OdfNormalize {
    #[default]
    Max,
    MinMax,
    None,
}

crate::names::named_values!(OdfNormalize {
    Max => "max",
    MinMax => "minmax",
    None => "none",
});

/// What an ODF scene is made with.
#[derive(Debug, Clone, PartialEq)]
pub struct OdfOptions {
    pub normalize: OdfNormalize,
    /// The largest radius of a normalised glyph, in units of the voxel's smallest spacing
    /// (0.5: a glyph fills its voxel).
    pub scale: f64,
    /// Keep only voxels on these lattice planes (`--slice`); `None`: every voxel.
    pub planes: Option<Vec<Plane>>,
    /// How each pixel is coloured: by its direction from the glyph's centre (DEC, the default),
    /// by the amplitude there, or `color`.
    pub coloring: OdfColoring,
    pub color: [u8; 4],
}

impl Default for OdfOptions {
    fn default() -> Self {
        Self {
            normalize: OdfNormalize::Max,
            scale: 0.5,
            planes: None,
            coloring: OdfColoring::Direction,
            color: [200, 200, 200, 255],
        }
    }
}

/// The world directions of the series' axes (columns): the affine's rotation, or a reflection
/// taken as the rotation −Q (an even function does not tell u from −u).
pub fn series_frame(field: &ShField) -> DMat3 {
    let m = field.frame.voxel_to_world.unwrap_or([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    let linear = Matrix3::from_fn(|r, c| m[r][c]);
    let q = tensor_rotation(field.frame.tensor_frame, &linear).unwrap_or_else(Matrix3::identity);
    let q = if q.determinant() < 0.0 { -q } else { q };
    DMat3::from_cols_array(&[
        q[(0, 0)],
        q[(1, 0)],
        q[(2, 0)],
        q[(0, 1)],
        q[(1, 1)],
        q[(2, 1)],
        q[(0, 2)],
        q[(1, 2)],
        q[(2, 2)],
    ])
}

/// One glyph's series before it is normalised: its index (the instance's `glyph`), its world
/// centre and the plain coefficients of f ([`plain_of`], unscaled).
#[derive(Debug, Clone)]
pub struct Series {
    pub index: usize,
    pub centre: DVec3,
    pub plain: Vec<f64>,
}

/// One glyph after normalising: plain coefficients of r (world units), its gradient bound and
/// its bounding ellipsoid (world units; the ball of its bound R where none is tighter).
struct Made {
    index: usize,
    centre: DVec3,
    plain: Vec<f64>,
    g: f64,
    ellipsoid: Ellipsoid,
}

/// The scene of `field`'s ODFs ([module doc](self)); its kind is [`GlyphKind::Odf`].
pub fn odf_scene(field: &ShField, opts: &OdfOptions) -> Scene {
    let frame = series_frame(field);
    let spacing = field.spacing();
    let series = series_on(field, opts.planes.as_deref());
    series_scene(series, field.layout.lmax, frame, opts.scale * spacing, opts)
}

/// The largest value of the ODFs on `planes` (every voxel without), sampled as [`odf_scene`]
/// samples them: what `--odf-normalize none` scales to a full radius (0 for none).
pub fn sampled_largest(field: &ShField, planes: Option<&[Plane]>) -> f64 {
    let lmax = field.layout.lmax;
    series_on(field, planes)
        .par_chunks(SAMPLED_BLOCK)
        .map(|block| {
            let plains: Vec<&[f64]> = block.iter().map(|s| s.plain.as_slice()).collect();
            let values = sampled_values_many(&plains, lmax);
            values.iter().copied().fold(0.0f64, f64::max)
        })
        .reduce(|| 0.0, f64::max)
}

/// Series sampled together: each block's values one matrix product.
const SAMPLED_BLOCK: usize = 64;

/// The series of the voxels on `planes` (every voxel without) that are not all zero.
fn series_on(field: &ShField, planes: Option<&[Plane]>) -> Vec<Series> {
    let count = field.layout.count;
    let d = field.dims;
    let keep = |v: usize| {
        planes.is_none_or(|planes| {
            let ijk = [v % d[0], v / d[0] % d[1], v / d[0] / d[1]];
            planes.iter().any(|p| ijk[p.axis.min(2)] == p.index)
        })
    };
    (0..field.voxels())
        .into_par_iter()
        .filter(|&v| keep(v))
        .filter_map(|v| {
            let mut c = vec![0.0; count];
            field.coefficients_of(v, &mut c);
            if c.iter().all(|&x| x == 0.0) {
                return None;
            }
            Some(Series {
                index: v,
                centre: DVec3::from(field.position(v)),
                plain: plain_of(&c, field.layout.basis, 1.0).ok()?,
            })
        })
        .collect()
}

/// The scene of `series` (each of order `lmax`, in the axes whose world directions are the
/// columns of `frame`), normalised by `opts.normalize` to a largest radius of `size` (world);
/// glyphs whose r is nowhere positive are left out.
pub fn series_scene(
    series: Vec<Series>,
    lmax: u32,
    frame: DMat3,
    size: f64,
    opts: &OdfOptions,
) -> Scene {
    let rotation = DQuat::from_mat3(&frame).normalize();
    // Each series' sampled range, and the ellipsoid of the values as they will be drawn up to
    // their scale (r = k f for max and none, k (f − min) for minmax).
    let sampled: Vec<(f64, f64, Option<Ellipsoid>)> = series
        .par_chunks(SAMPLED_BLOCK)
        .flat_map_iter(|block| {
            let plains: Vec<&[f64]> = block.iter().map(|s| s.plain.as_slice()).collect();
            let values = sampled_values_many(&plains, lmax);
            let n = values.nrows();
            values
                .as_slice()
                .chunks_exact(n.max(1))
                .map(|column| {
                    let (min, max) = range_of(column);
                    let ellipsoid = if opts.normalize == OdfNormalize::MinMax {
                        let shifted: Vec<f64> = column.iter().map(|v| v - min).collect();
                        bounding_ellipsoid(&shifted, lmax)
                    } else {
                        bounding_ellipsoid(column, lmax)
                    };
                    (max, min, ellipsoid)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let raw: Vec<(Series, f64, f64, Option<Ellipsoid>)> = series
        .into_iter()
        .zip(sampled)
        .map(|(s, (max, min, e))| (s, max, min, e))
        .collect();
    let global = raw.iter().map(|r| r.1).fold(0.0f64, f64::max);
    let y00 = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
    let made: Vec<Made> = raw
        .into_par_iter()
        .filter_map(|(s, max, min, ellipsoid)| {
            // r = k f + b: b goes to the constant term (Y₀⁰ is constant).
            let (k, b) = match opts.normalize {
                OdfNormalize::Max => (size / max, 0.0),
                OdfNormalize::MinMax => (size / (max - min), -size * min / (max - min)),
                OdfNormalize::None => (size / global, 0.0),
            };
            if !k.is_finite() || k <= 0.0 || !b.is_finite() {
                return None;
            }
            let mut plain: Vec<f64> = s.plain.iter().map(|x| x * k).collect();
            plain[0] += b / y00;
            let (g, r) = rigorous_bounds(&plain, lmax, (k * min + b, k * max + b));
            if r.is_nan() || r <= 0.0 || r.is_infinite() {
                return None;
            }
            let ball = Ellipsoid {
                axes: DMat3::IDENTITY,
                semi: DVec3::splat(r),
            };
            // The ellipsoid where it is smaller than the ball.
            let ellipsoid = ellipsoid
                .map(|e| Ellipsoid {
                    semi: e.semi * k,
                    ..e
                })
                .filter(|e| {
                    e.semi.is_finite()
                        && e.semi.min_element() > 0.0
                        && e.semi.element_product() < r * r * r
                })
                .unwrap_or(ball);
            Some(Made {
                index: s.index,
                centre: s.centre,
                plain,
                g,
                ellipsoid,
            })
        })
        .collect();
    let (lo, hi) = made.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), g| (lo.min(g.centre), hi.max(g.centre)),
    );
    let origin = if made.is_empty() {
        DVec3::ZERO
    } else {
        (lo + hi) / 2.0
    };
    let mut payload = Payload::new(lmax).expect("a field's lmax is checked when read");
    payload.values.reserve(made.len() * payload.stride());
    let flags = opts.coloring.flags() | (lmax << 8);
    let instances = made
        .iter()
        .map(|g| {
            // Parameter space is the glyph's own axes scaled by its ellipsoid's largest
            // semi-axis, which bounds r as the ellipsoid holds the glyph.
            let e = &g.ellipsoid;
            let big = e.semi.max_element();
            let plain: Vec<f64> = g.plain.iter().map(|x| x / big).collect();
            let axes = DQuat::from_mat3(&e.axes).normalize();
            // The amplitude colouring's 1 is the normalised 1 (`size`), not the bound.
            let k = payload.push(&plain, g.g / big, big / size, axes, e.semi / big);
            let q = (rotation * axes).normalize();
            let c = g.centre - origin;
            GlyphInstance {
                centre: [c.x as f32, c.y as f32, c.z as f32],
                color: GlyphInstance::pack_color(opts.color),
                rotation: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                radii: e.semi.to_array().map(|v| v as f32),
                glyph: g.index as u32,
                shape: [k as u32 + 1, flags],
            }
        })
        .collect();
    let mut scene = Scene::from_instances_as(origin, instances, GlyphKind::Odf);
    scene.payload = Some(Arc::new(payload));
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::frame::{FrameInfo, TensorFrame};
    use crate::field::sh_field::Coefficients;
    use crate::field::{ShLayout, frame::Why};
    use crate::sh::{ShBasis, ShEval};
    use crate::shape::odf::{Odf, Profile};
    use crate::shape::{Exact, GlyphGeometry};

    fn field(
        dims: [usize; 3],
        series: &[Vec<f64>],
        frame: TensorFrame,
        m: [[f64; 4]; 4],
    ) -> ShField {
        let count = series[0].len();
        let n = dims.iter().product::<usize>();
        let mut c = vec![0.0; count * n];
        for (v, s) in series.iter().enumerate() {
            for (j, &x) in s.iter().enumerate() {
                c[j * n + v] = x;
            }
        }
        ShField {
            format: "nifti".into(),
            dims,
            layout: ShLayout {
                lmax: crate::sh::lmax_of_count(count).unwrap(),
                count,
                basis: ShBasis::Descoteaux07Legacy,
                why: Why::Default,
                reason: String::new(),
                recognised: String::new(),
            },
            coefficients: Coefficients::F64(c),
            frame: FrameInfo {
                tensor_frame: frame,
                world: "RAS".into(),
                voxel_to_world: Some(m),
                source: "sform".into(),
            },
        }
    }

    /// Each glyph's surface lies where the voxel's series, normalised, puts it: the distance
    /// from the centre along a world direction w is scale·f(Qᵀw)/max f, with the series read by
    /// ShEval in its own basis (DIPY's), the voxel axes turned into world by a reflecting affine.
    #[test]
    fn glyph_radius_is_the_normalised_series_in_world() {
        let mut s1 = vec![0.0; 15];
        s1[0] = 2.5;
        s1[3] = 0.6;
        s1[5] = 0.2;
        s1[12] = 0.3;
        let mut s2 = s1.clone();
        s2[1] = -0.25;
        let zero = vec![0.0; 15];
        // x flipped, 2 mm voxels: voxel axis x is world −x.
        let m = [
            [-2.0, 0.0, 0.0, 10.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.5, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let f = field(
            [3, 1, 1],
            &[s1.clone(), zero, s2.clone()],
            TensorFrame::Voxel,
            m,
        );
        let scene = odf_scene(&f, &OdfOptions::default());
        assert_eq!(scene.instances.len(), 2, "the all-zero voxel has no glyph");
        let mut ev = ShEval::new(4, ShBasis::Descoteaux07Legacy).unwrap();
        for (inst, series) in scene.instances.iter().zip([&s1, &s2]) {
            let geo = GlyphGeometry::of(inst);
            let odf = Odf::of(&geo, scene.payload.as_ref());
            assert!(matches!(odf.profile, Profile::Series { .. }));
            let max = (0..20000)
                .map(|i| {
                    let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / 20000.0;
                    let phi = f64::from(i) * 2.399963;
                    let s = (1.0 - z * z).sqrt();
                    ev.value(series, [s * phi.cos(), s * phi.sin(), z])
                })
                .fold(f64::NEG_INFINITY, f64::max);
            for w in [
                DVec3::X,
                DVec3::new(0.3, -0.5, 0.8).normalize(),
                DVec3::new(-0.9, 0.1, 0.2).normalize(),
            ] {
                let voxel_dir = DVec3::new(-w.x, w.y, w.z);
                let want = 0.5 * 2.0 * ev.value(series, voxel_dir.to_array()).max(0.0) / max;
                assert!(want > 0.1, "the series is positive along {w}");
                let o = geo.centre + w * 10.0;
                let hit = odf.intersect(o, -w).expect("a ray through the centre hits");
                let got = 10.0 - hit.t;
                // The scale uses the sampled maximum: within 0.5 % of the dense one.
                assert!((got - want).abs() <= 5e-3 * want + 1e-9, "{got} {want}");
            }
        }
    }

    /// `minmax` maps each voxel's [min, max] to [0, scale] (mrview's normalise), `none` scales
    /// every voxel by the field's largest value: the radius along w is scale·(f − min)/(max −
    /// min) and scale·f/max over the field, with min and max found densely here.
    #[test]
    fn minmax_and_none_scale_as_documented() {
        let mut s1 = vec![0.0; 15];
        s1[0] = 2.5;
        s1[3] = 0.6;
        s1[5] = 0.2;
        s1[12] = 0.3;
        // A weaker voxel: half the first's amplitude.
        let s2: Vec<f64> = s1.iter().map(|c| 0.5 * c).collect();
        let m = [
            [2.0, 0.0, 0.0, 0.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let f = field([2, 1, 1], &[s1.clone(), s2.clone()], TensorFrame::Voxel, m);
        let mut ev = ShEval::new(4, ShBasis::Descoteaux07Legacy).unwrap();
        let dirs: Vec<[f64; 3]> = (0..20000)
            .map(|i| {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / 20000.0;
                let phi = f64::from(i) * 2.399963;
                let s = (1.0 - z * z).sqrt();
                [s * phi.cos(), s * phi.sin(), z]
            })
            .collect();
        let range = |ev: &mut ShEval, c: &[f64]| {
            dirs.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| {
                    let v = ev.value(c, d);
                    (lo.min(v), hi.max(v))
                })
        };
        let (min1, max1) = range(&mut ev, &s1);
        let (min2, max2) = range(&mut ev, &s2);
        assert!(min1 > 0.0, "a positive ODF, so minmax differs from max");
        for normalize in [OdfNormalize::MinMax, OdfNormalize::None] {
            let opts = OdfOptions {
                normalize,
                coloring: OdfColoring::Amplitude,
                ..OdfOptions::default()
            };
            let scene = odf_scene(&f, &opts);
            assert_eq!(scene.instances.len(), 2);
            for (inst, (series, min, max)) in scene
                .instances
                .iter()
                .zip([(&s1, min1, max1), (&s2, min2, max2)])
            {
                let geo = GlyphGeometry::of(inst);
                let odf = Odf::of(&geo, scene.payload.as_ref());
                for w in [DVec3::X, DVec3::new(0.3, -0.5, 0.8).normalize()] {
                    let v = ev.value(series, w.to_array());
                    // 0.5 of the 2 mm voxel.
                    let want = match normalize {
                        OdfNormalize::MinMax => 1.0 * (v - min) / (max - min),
                        _ => 1.0 * v / max1,
                    };
                    let o = geo.centre + w * 10.0;
                    let got = match odf.intersect(o, -w) {
                        Some(hit) => 10.0 - hit.t,
                        None => 0.0,
                    };
                    assert!(
                        (got - want).abs() <= 5e-3 * want.abs().max(0.1),
                        "{normalize:?} along {w}: {got} {want}"
                    );
                    // Coloured by amplitude: the normalised value (the full radius is 1 here)
                    // through viridis, whatever the series' bound R.
                    let colour = odf.tint(geo.centre + w, DVec3::ZERO);
                    let [r, g, b] = crate::glyph::colormap::viridis(want);
                    assert!(
                        (colour - DVec3::new(r, g, b)).abs().max_element() <= 1e-2,
                        "{normalize:?} along {w}: colour {colour} for amplitude {want}"
                    );
                }
            }
        }
    }

    /// The glyphs of fits up to lmax 12 draw with odf.wgsl's monomial-only pipeline
    /// (`ODF_GENERAL` false); lmax 14 and 16, held as plain series, and a tensor's profile need
    /// the general one.
    #[test]
    fn only_monomial_series_leave_the_general_paths_out() {
        use crate::shape::Shape;
        let identity = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        for lmax in [2u32, 8, 12, 14, 16] {
            let count = crate::sh::count_of_lmax(lmax).unwrap();
            let mut c = vec![0.0; count];
            c[0] = 1.0;
            c[3] = 0.4;
            let f = field([1, 1, 1], &[c], TensorFrame::Voxel, identity);
            let scene = odf_scene(&f, &OdfOptions::default());
            assert_eq!(scene.instances.len(), 1);
            let general = crate::shape::odf::Kind.is_general(&scene.instances[0]);
            assert_eq!(general, lmax > 12, "lmax {lmax}");
        }
        // A tensor's profile: no series named.
        let profile = GlyphInstance {
            centre: [0.0; 3],
            color: 0,
            rotation: [0.0, 0.0, 0.0, 1.0],
            radii: [1.0, 0.5, 0.25],
            glyph: 0,
            shape: [0, 0],
        };
        assert!(crate::shape::odf::Kind.is_general(&profile));
    }
}
