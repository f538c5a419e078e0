use super::*;
use crate::glyph::{GlyphSet, GlyphStyle, Scale};
use crate::shape::GlyphInstance;

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }

    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

fn cone(rng: &mut Lcg) -> Cone {
    let x = rng.unit();
    let y = x.any_orthonormal_vector();
    let z = x.cross(y);
    Cone {
        c: DVec3::new(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
        ),
        frame: DMat3::from_cols(x, y, z),
        radii: DVec3::new(rng.range(0.2, 2.0), rng.range(0.1, 1.0), 0.0),
    }
    .round()
}

impl Cone {
    /// A circular cone: the cross-section's radii equal.
    fn round(mut self) -> Self {
        self.radii.z = self.radii.y;
        self
    }
}

/// The first t ≥ 0 at which `contains` holds along the ray, by fine sampling and bisection:
/// the truth the closed form is held to (it never calls `span`).
fn sampled_entry(c: &Cone, o: DVec3, d: DVec3, reach: f64) -> Option<f64> {
    let n = 20_000;
    let mut prev = 0.0;
    if c.contains(o) {
        return None;
    }
    for k in 1..=n {
        let t = reach * f64::from(k) / f64::from(n);
        if c.contains(o + d * t) {
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if c.contains(o + d * mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = t;
    }
    None
}

/// Rays from outside at random cones: the closed form's entry is where sampling `contains`
/// finds the solid (up to the sampling's blind spots: rays that clip the solid over less than a
/// sample step are counted, not compared), and the normal is the gradient of the surface there.
#[test]
fn cone_entries_are_where_the_solid_begins() {
    let mut rng = Lcg(7);
    let (mut hits, mut misses, mut clips) = (0, 0, 0);
    for _ in 0..400 {
        let c = cone(&mut rng);
        let size = c.radii.max_element();
        let aim = c.c + rng.unit() * rng.range(0.0, 1.2) * size;
        let o = c.c + rng.unit() * (4.0 * size);
        let d = (aim - o).normalize();
        let reach = 10.0 * size;
        let want = sampled_entry(&c, o, d, reach);
        let got = Exact::intersect(&c, o, d);
        match (got, want) {
            (Some(h), Some(t)) => {
                assert!((h.t - t).abs() <= 1e-3 * size, "t {} vs sampled {t}", h.t);
                // The normal faces the ray and is perpendicular to the surface: points a hair
                // along the tangent plane stay on the boundary to second order.
                assert!(h.normal.dot(d) < 0.0, "normal {} against {d}", h.normal);
                hits += 1;
            }
            (None, None) => misses += 1,
            (Some(h), None) => {
                // A grazing clip thinner than a sample step.
                let p = o + d * h.t;
                assert!(c.contains(p + d * 1e-9 * size) || c.contains(p - d * 1e-9 * size));
                clips += 1;
            }
            (None, Some(t)) => panic!("missed a solid sampled at t = {t}"),
        }
    }
    assert!(
        hits > 100 && misses > 50,
        "{hits} hits, {misses} misses, {clips} clips"
    );
}

/// The closed-form normal against the numerical gradient of the cone's inside test measured
/// along the surface, on side points.
#[test]
fn cone_normals_are_the_surface_gradient() {
    for &(x, a) in &[(-0.5, 0.3), (0.2, 2.0), (0.9, 4.0), (-0.99, 1.0)] {
        let r = 0.5 * (1.0 - x);
        let p = DVec3::new(x, r * f64::cos(a), r * f64::sin(a));
        let n = Cone::normal(p, false).normalize();
        // Along the generator (towards the apex) and around: both tangent.
        let along = DVec3::new(1.0, 0.0, 0.0) - DVec3::new(0.0, p.y, p.z) / r * 0.5;
        let around = DVec3::new(0.0, -p.z, p.y);
        assert!(n.dot(along).abs() < 1e-12 && n.dot(around).abs() < 1e-12);
        assert!(n.dot(DVec3::new(0.0, p.y, p.z)) > 0.0, "outward");
    }
}

/// From inside (the base centre nudged in), the only forward crossing is the exit.
#[test]
fn from_inside_the_exit() {
    let c = Cone {
        c: DVec3::ZERO,
        frame: DMat3::IDENTITY,
        radii: DVec3::new(1.0, 0.5, 0.5),
    };
    let o = DVec3::new(-0.9, 0.0, 0.0);
    assert!(c.contains(o));
    let h = Exact::intersect(&c, o, DVec3::X).unwrap();
    assert!((h.t - 1.9).abs() < 1e-12, "apex at 1: {}", h.t);
    let h = Exact::intersect(&c, o, DVec3::Y).unwrap();
    // r(x = −0.9) = 0.95 in parameter units, 0.475 in world.
    assert!((h.t - 0.475).abs() < 1e-12, "{}", h.t);
}

/// Heads of k = 1e7 discs (radii 1, 1, 1e-7: a flat triangle) at random orientations, hit by
/// rays from 5 to 9 radii away in every direction: a ray meets the plate where it crosses the
/// midplane, so it hits iff that point lies in the triangle |y| ≤ (1 − x)/2, x ∈ [−1, 1] (rays
/// within 1e-4 of an edge are not judged), and the hit lies within the plate's thickness of the
/// crossing. Solved from the world-nearest point, the span's b² − a c cancelled ~k² of itself
/// and missed or invented heads up to 0.03 radii beside their edges.
#[test]
fn thin_heads_are_hit_where_their_plane_is_inside() {
    let mut rng = Lcg(11);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..4000 {
        let x = rng.unit();
        let y = x.any_orthonormal_vector();
        let c = Cone {
            c: DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 0.0),
            frame: DMat3::from_cols(x, y, x.cross(y)),
            radii: DVec3::new(1.0, 1.0, 1e-7),
        };
        let aim = c.c + c.frame * DVec3::new(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), 0.0);
        let o = aim + rng.unit() * rng.range(5.0, 9.0);
        let d = (aim - o).normalize();
        // The midplane crossing, in the head's parameter space.
        let (po, pd) = (c.param(o - c.c), c.frame.transpose() * d);
        if pd.z.abs() < 1e-3 {
            continue;
        }
        let t_plane = -(c.frame.transpose() * (o - c.c)).z / pd.z;
        let q = po + c.param(d) * t_plane;
        let margin = (0.5 * (1.0 - q.x) - q.y.abs()).min(1.0 - q.x.abs());
        if margin.abs() < 1e-4 {
            continue;
        }
        match Exact::intersect(&c, o, d) {
            Some(h) if margin > 0.0 => {
                let slack = 1e-7 / pd.z.abs() + 1e-9;
                assert!(
                    (h.t - t_plane).abs() <= slack,
                    "t {} vs the plane's {t_plane}",
                    h.t
                );
                hits += 1;
            }
            None if margin < 0.0 => misses += 1,
            got => panic!("{got:?} where the midplane point is {margin} inside: {q}"),
        }
    }
    assert!(hits > 500 && misses > 500, "{hits} hits, {misses} misses");
}

fn glyph(ev: [f32; 3]) -> Glyph {
    Glyph {
        centre: [1.0, 2.0, 3.0],
        eigenvalues: ev,
        rotation: [0.1, 0.2, 0.3, 0.927_361_8],
        index: 0,
    }
}

fn style(glyphs: &[Glyph], arrows: bool, min_stress: f64) -> ResolvedStyle {
    let mut set = GlyphSet {
        glyphs: glyphs.to_vec(),
        ..GlyphSet::default()
    };
    set.stats.valid = glyphs.len();
    GlyphStyle {
        scale: Scale::Factor(1.0),
        color: ColorScheme::Sign,
        arrows,
        min_stress,
        ..GlyphStyle::default()
    }
    .resolve(&set, 1.0)
}

/// A bar per principal stress, along its eigenvector, as long as the stress (scale 1),
/// coloured by its sign, hidden below the threshold; heads at the bar's ends pointing out for
/// tension and in for compression, inside the bar's length.
#[test]
fn bars_and_heads_follow_the_principal_stresses() {
    let g = glyph([3.0, -1.0, 0.01]);
    let frame = crate::tensor::eigen::quat_to_frame(g.rotation).map(DVec3::from);
    let plain = style(&[g], false, 0.0);
    let bars: Vec<Part> = (0..9).filter_map(|p| Kind.place(&g, p, &plain)).collect();
    assert_eq!(bars.len(), 3, "no heads without arrows");
    for (i, bar) in bars.iter().enumerate() {
        let geo = GlyphGeometry::of(&instance(bar));
        assert!((geo.frame.x_axis.dot(frame[i]).abs() - 1.0).abs() < 1e-6);
        assert!(geo.frame.determinant() > 0.0);
        assert!((geo.radii.x - f64::from(g.eigenvalues[i]).abs()).abs() < 1e-6);
        assert_eq!(geo.radii.y, plain.bar_width as f32 as f64);
        assert_eq!(bar.offset, [0.0; 3]);
    }
    let red = ResolvedStyle::sign_color(1.0, 1.0);
    let blue = ResolvedStyle::sign_color(-1.0, 1.0);
    assert_eq!(bars[0].color, red);
    assert_eq!(bars[1].color, blue);
    assert_eq!(bars[2].color, [255, 255, 255, 255], "0.01 of 3 is neutral");
    // Hidden below the threshold.
    let thresholded = style(&[g], false, 0.5);
    assert_eq!(
        (0..9)
            .filter_map(|p| Kind.place(&g, p, &thresholded))
            .count(),
        2
    );
    // Heads: apex outward for tension (bar 0), inward for compression (bar 1).
    let arrows = style(&[g], true, 0.5);
    let parts: Vec<Part> = (0..9).filter_map(|p| Kind.place(&g, p, &arrows)).collect();
    assert_eq!(parts.len(), 6);
    for (bar, sigma, heads) in [(0, 3.0, &parts[2..4]), (1, -1.0, &parts[4..6])] {
        let axis = frame[bar];
        for head in heads {
            let geo = GlyphGeometry::of(&instance(head));
            assert_eq!(head.params, [HEAD, 0]);
            let centre = DVec3::from(head.offset);
            let end = centre.dot(axis).signum();
            let apex = geo.frame.x_axis.normalize();
            // Outward: the apex points away from the centre along the bar.
            let outward = apex.dot(axis) * end > 0.0;
            assert_eq!(outward, sigma > 0.0, "bar {bar}");
            assert!(geo.frame.determinant() > 0.0);
            // The head ends at the bar's length.
            let reach = centre.dot(axis).abs() + geo.radii.x;
            assert!((reach - f64::abs(sigma)).abs() < 1e-6, "{reach}");
        }
        // The shaft stops where the heads begin.
        let shaft = GlyphGeometry::of(&instance(&parts[bar]));
        let head = GlyphGeometry::of(&instance(&heads[0]));
        assert!((shaft.radii.x + 2.0 * head.radii.x - f64::abs(sigma)).abs() < 1e-6);
    }
}

fn instance(p: &Part) -> GlyphInstance {
    GlyphInstance {
        centre: p.offset.map(|x| x as f32),
        color: GlyphInstance::pack_color(p.color),
        rotation: p.rotation,
        radii: p.radii,
        glyph: 0,
        shape: p.params,
    }
}
