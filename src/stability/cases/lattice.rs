//! Case 15: random lattices of thin glyphs, drawn through every preset. 4³ glyphs of random
//! orientations 1.5 apart (largest radius 1), so that neighbours pass through each other:
//! needles (1, 1/k, 1/k), discs (1, 1, 1/k) and a mixed field (1, 10⁻ᵘ, 10⁻ᵛ with u and v
//! uniform in [0, log₁₀ k]), for k = 10³ … 10⁷, each in three views: perspective from near
//! (glyphs about 60 pixels across, most rasterised), from far (about 16 pixels: the default
//! preset's splats) and orthographic. The other cases draw one or two thin glyphs with the
//! baseline: there the splats' choice of *which* glyph a pixel shows, and *whether* a glyph
//! shows at all, was never tested. [`Probe::presets`] runs every preset a method takes, and the
//! rows are held to [`crate::stability::Bounds::LATTICE`].

use glam::DVec3;

use super::probe::{Probe, look, ortho, probe, spec};
use crate::scene::Scene;
use crate::stability::rng::Rng;

/// The lattice's glyphs per side and their spacing (largest radius 1).
const SIDE: usize = 4;
const SPACING: f64 = 1.5;

/// The fields: (case, radii of glyph k of the lattice from anisotropy k and the generator).
type Radii = fn(f64, &mut Rng) -> DVec3;
const FIELDS: [(&str, Radii); 3] = [
    ("15-lattice-needles", |k, _| {
        DVec3::new(1.0, 1.0 / k, 1.0 / k)
    }),
    ("15-lattice-discs", |k, _| DVec3::new(1.0, 1.0, 1.0 / k)),
    ("15-lattice-mixed", |k, rng| {
        let top = k.log10();
        DVec3::new(
            1.0,
            10f64.powf(-top * rng.uniform()),
            10f64.powf(-top * rng.uniform()),
        )
    }),
];

/// The three views: (label, camera of the scene).
const VIEWS: [&str; 3] = ["near", "far", "ortho"];

/// The quick subset: (case, k, view) of one probe where each fault this case found showed (the
/// splats' dropped needles and discs, the reference's arrowheads, the triangle proxy's capsule
/// rays). Every field at every k in every view draws each of 64 glyphs through every preset of
/// every method, mesh:6 included: three minutes of a release build, too long for a subset.
const QUICK: [(&str, f64, &str); 3] = [
    ("15-lattice-needles", 1e3, "far"),
    ("15-lattice-discs", 1e7, "far"),
    ("15-lattice-mixed", 1e3, "far"),
];

/// Case 15's scenes: every field at every k in every view (three probes, far, when `quick`).
pub fn lattice(quick: bool) -> Vec<Probe> {
    let mut out = Vec::new();
    for (case, radii) in FIELDS {
        for k in [1e3, 1e5, 1e7] {
            if quick && !QUICK.iter().any(|q| q.0 == case && q.1 == k) {
                continue;
            }
            // The same orientations at every k: only the thinness changes along a sweep.
            let mut rng = Rng(0x5DEE_CE66_D1CE_4E5B);
            let mut specs = Vec::new();
            for n in 0..SIDE * SIDE * SIDE {
                let (i, j, l) = (n % SIDE, (n / SIDE) % SIDE, n / (SIDE * SIDE));
                let centre = DVec3::new(i as f64, j as f64, l as f64) * SPACING;
                let rotation = rng.quat();
                let r = radii(k, &mut rng);
                let hue = [
                    (60 + 50 * i) as u8,
                    (60 + 50 * j) as u8,
                    (60 + 50 * l) as u8,
                    255,
                ];
                specs.push(spec(centre, rotation, r, hue));
            }
            let scene = Scene::from_specs(&specs);
            let dir = DVec3::new(-0.55, 0.8, -0.45).normalize();
            for view in VIEWS {
                if quick && !QUICK.contains(&(case, k, view)) {
                    continue;
                }
                let cam = match view {
                    "near" => look(&scene, scene.centre - dir * 9.0, scene.centre, 40.0),
                    "far" => look(&scene, scene.centre - dir * 90.0, scene.centre, 9.0),
                    _ => ortho(&scene, dir, DVec3::Z, 14.0),
                };
                let mut p = probe(case, "anisotropy k", k, scene.clone(), cam);
                p.label = format!("{k:e} {view}");
                p.presets = true;
                out.push(p);
            }
        }
    }
    out
}
