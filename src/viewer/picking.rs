//! What is under the pointer: the id target's pixel (instance + 1, 0 for background), mapped
//! back through the selection to the glyph and its tensor.

use crate::error::RenderError;
use crate::field::ShField;
use crate::render::GpuContext;
use crate::render::targets::Readback;
#[cfg(not(target_arch = "wasm32"))]
use crate::render::targets::Targets;
use crate::scene::Scene;
use crate::scene::odf::series_frame;
use crate::sh::{Peak, PeakFinder, PeakOptions};
use crate::tensor::shape;
use crate::viewer::loader::Loaded;
use glam::DVec3;

/// A glyph's details, as the hover tooltip shows them.
#[derive(Debug, Clone, PartialEq)]
pub struct PickInfo {
    /// Index of the tensor (or the voxel of an ODF or of peaks) in file order.
    pub index: usize,
    pub position: [f64; 3],
    pub detail: Detail,
}

/// What a picked glyph shows of its data.
#[derive(Debug, Clone, PartialEq)]
pub enum Detail {
    Tensor {
        /// World-space tensor as stored (before symmetrisation), row-major.
        tensor: [f64; 9],
        eigenvalues: [f64; 3],
        fa: f64,
        class: shape::ShapeClass,
    },
    /// A stick of a file of peaks: its voxel's peaks as the file holds them, in world axes
    /// (direction scaled by amplitude).
    Peaks { peaks: Vec<[f64; 3]> },
    /// An ODF glyph: its voxel's series and its peaks, as DIPY's `peaks_from_model` finds them
    /// ([`PeakOptions::default`]), directions in world axes.
    Odf {
        lmax: u32,
        basis: crate::sh::ShBasis,
        coefficients: Vec<f64>,
        peaks: Vec<Peak>,
    },
}

impl PickInfo {
    /// The glyph behind id `id` (0 = background) when `scene` holds `selected` glyphs of
    /// `data.set` (an instance's `glyph` is its place in `selected`; a glyph may be several
    /// instances), or, for a file of SH series, the voxel an instance names.
    pub fn of(
        id: u32,
        scene: &Scene,
        selected: &[usize],
        data: &Loaded,
        class_threshold: f64,
    ) -> Option<Self> {
        let instance = scene.instances.get((id as usize).checked_sub(1)?)?;
        if let Some(sh) = &data.odf {
            return Self::of_voxel(sh, instance.glyph as usize);
        }
        if let Some(p) = &data.peaks {
            // A peaks scene's instances name their voxel.
            let v = instance.glyph as usize;
            return (v < p.voxels()).then(|| Self {
                index: v,
                position: p.position(v),
                detail: Detail::Peaks {
                    peaks: p.peaks_of(v).map(|x| x.map(f64::from)).collect(),
                },
            });
        }
        let g = data
            .set
            .glyphs
            .get(*selected.get(instance.glyph as usize)?)?;
        let ev = g.eigenvalues.map(f64::from);
        let index = g.index as usize;
        Some(Self {
            index,
            position: g.centre,
            detail: Detail::Tensor {
                tensor: data.field.world_tensor(index),
                eigenvalues: ev,
                fa: shape::fa(ev),
                class: shape::classify(ev, class_threshold),
            },
        })
    }

    /// Voxel `v` of `sh`: its series and peaks.
    pub fn of_voxel(sh: &ShField, v: usize) -> Option<Self> {
        if v >= sh.voxels() {
            return None;
        }
        let mut c = vec![0.0; sh.layout.count];
        sh.coefficients_of(v, &mut c);
        let frame = series_frame(sh);
        let peaks = PeakFinder::new(sh.layout.lmax, sh.layout.basis)
            .ok()?
            .peaks(&c, &PeakOptions::default())
            .into_iter()
            .map(|p| Peak {
                direction: (frame * DVec3::from(p.direction)).to_array(),
                value: p.value,
            })
            .collect();
        Some(Self {
            index: v,
            position: sh.position(v),
            detail: Detail::Odf {
                lmax: sh.layout.lmax,
                basis: sh.layout.basis,
                coefficients: c,
                peaks,
            },
        })
    }

    /// Multi-line text for the tooltip.
    pub fn text(&self) -> String {
        let [x, y, z] = self.position;
        match &self.detail {
            Detail::Tensor {
                tensor: t,
                eigenvalues: [l1, l2, l3],
                fa,
                class,
            } => format!(
                "glyph #{}\nposition ({x:.4}, {y:.4}, {z:.4})\ntensor\n  {:>11.4e} {:>11.4e} {:>11.4e}\n  {:>11.4e} {:>11.4e} {:>11.4e}\n  {:>11.4e} {:>11.4e} {:>11.4e}\nλ = {l1:.4e}, {l2:.4e}, {l3:.4e}\nFA {fa:.4}   class {}",
                self.index,
                t[0],
                t[1],
                t[2],
                t[3],
                t[4],
                t[5],
                t[6],
                t[7],
                t[8],
                class.glyph_name()
            ),
            Detail::Peaks { peaks } => {
                let mut s = format!(
                    "voxel #{}\nposition ({x:.4}, {y:.4}, {z:.4})\npeaks ({})",
                    self.index,
                    peaks.len()
                );
                for (k, p) in peaks.iter().enumerate() {
                    let a = DVec3::from(*p).length();
                    let [dx, dy, dz] = (DVec3::from(*p) / a).to_array();
                    s += &format!(
                        "\n  {}: ({dx:+.3}, {dy:+.3}, {dz:+.3})  amplitude {a:.4e}",
                        k + 1
                    );
                }
                s
            }
            Detail::Odf {
                lmax,
                basis,
                coefficients,
                peaks,
            } => {
                let mut s = format!(
                    "voxel #{}\nposition ({x:.4}, {y:.4}, {z:.4})\nSH lmax {lmax}, {basis}, {} coefficients",
                    self.index,
                    coefficients.len()
                );
                // Order by order, as the files store them (l = 0, 2, 4, …; m from −l to l).
                let mut at = 0;
                for l in (0..=*lmax).step_by(2) {
                    let n = 2 * l as usize + 1;
                    let row: Vec<String> = coefficients[at..at + n]
                        .iter()
                        .map(|c| format!("{c:.3e}"))
                        .collect();
                    s += &format!("\n  l={l}: {}", row.join(" "));
                    at += n;
                }
                s += &format!("\npeaks ({})", peaks.len());
                for (k, p) in peaks.iter().enumerate() {
                    let [dx, dy, dz] = p.direction;
                    s += &format!(
                        "\n  {}: ({dx:+.3}, {dy:+.3}, {dz:+.3})  f = {:.4e}",
                        k + 1,
                        p.value
                    );
                }
                s
            }
        }
    }
}

/// Read the id target at pixel (x, y): one pixel copied and mapped, nothing else.
#[cfg(not(target_arch = "wasm32"))]
pub fn read_id(ctx: &GpuContext, targets: &Targets, x: u32, y: u32) -> Result<u32, RenderError> {
    pollster::block_on(read_id_async(ctx, &targets.id, x, y))
}

/// [`read_id`] of the id texture `id`, without blocking (the browser's way).
pub async fn read_id_async(
    ctx: &GpuContext,
    id: &wgpu::Texture,
    x: u32,
    y: u32,
) -> Result<u32, RenderError> {
    if x >= id.width() || y >= id.height() {
        return Ok(0);
    }
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let rb = Readback::record_region(ctx, &mut encoder, id, 4, [x, y], [1, 1]);
    ctx.queue.submit([encoder.finish()]);
    let bytes = rb.read_async(ctx).await?;
    Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::ReadOptions;
    use crate::staging::{Demo, Source};
    use crate::viewer::loader::load_now;

    /// A stick picked in the viewer shows its voxel's place and peaks as the file holds them
    /// (the reader's, which tests/readers holds to sh2peaks' own read back).
    #[test]
    fn peak_picks_show_the_voxel_and_its_peaks() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/sh/sh2peaks_lmax8.mif");
        let silent = &crate::progress::Silent;
        let data = load_now(&Source::File(path), &ReadOptions::default(), &None, silent).unwrap();
        let peaks = data.peaks.as_ref().unwrap();
        let recipe = crate::staging::Recipe {
            style: crate::glyph::GlyphStyle {
                color: crate::glyph::ColorScheme::Dec,
                ..Default::default()
            },
            ..Default::default()
        };
        let built = crate::staging::build_peaks(peaks, "peaks", &recipe).unwrap();
        for (k, inst) in built.scene.instances.iter().enumerate().step_by(7) {
            let pick = PickInfo::of(k as u32 + 1, &built.scene, &built.selected, &data, 0.2)
                .expect("a stick is picked");
            let v = inst.glyph as usize;
            assert_eq!((pick.index, pick.position), (v, peaks.position(v)));
            let want: Vec<[f64; 3]> = peaks.peaks_of(v).map(|x| x.map(f64::from)).collect();
            assert_eq!(pick.detail, Detail::Peaks { peaks: want });
            let text = pick.text();
            assert!(
                text.starts_with(&format!("voxel #{v}\n")) && text.contains("peaks (3)"),
                "{text}"
            );
        }
        assert!(PickInfo::of(0, &built.scene, &built.selected, &data, 0.2).is_none());
    }

    #[test]
    fn ids_map_through_the_selection() {
        let data = load_now(
            &Source::Demo(Demo { n: 3 }),
            &ReadOptions::default(),
            &None,
            &crate::progress::Silent,
        )
        .unwrap();
        let selected = vec![4, 7];
        // Two instances of glyph 0 of the selection, one of glyph 1.
        let instance = |glyph| crate::scene::GlyphInstance {
            centre: [0.0; 3],
            color: 0,
            rotation: [0.0, 0.0, 0.0, 1.0],
            radii: [1.0; 3],
            glyph,
            shape: [0; 2],
        };
        let scene = Scene::from_instances(
            glam::DVec3::ZERO,
            vec![instance(0), instance(0), instance(1)],
        );
        assert_eq!(
            PickInfo::of(0, &scene, &selected, &data, 0.5),
            None,
            "background"
        );
        assert_eq!(
            PickInfo::of(4, &scene, &selected, &data, 0.5),
            None,
            "no such instance"
        );
        assert_eq!(
            PickInfo::of(2, &scene, &selected, &data, 0.5)
                .unwrap()
                .index,
            data.set.glyphs[4].index as usize
        );
        let p = PickInfo::of(3, &scene, &selected, &data, 0.5).unwrap();
        let g = data.set.glyphs[7];
        assert_eq!(p.index, g.index as usize);
        assert_eq!(p.position, g.centre);
        let Detail::Tensor { fa, .. } = p.detail else {
            panic!("a tensor's pick")
        };
        assert!((0.0..=1.0).contains(&fa));
        let text = p.text();
        assert!(text.contains(&format!("glyph #{}", g.index)) && text.contains("FA"));
    }

    /// An ODF glyph picked in the viewer shows its voxel's place, series and peaks: the peaks
    /// where DIPY's `peak_directions_nl` finds them (tests/data/sh/expected.json, voxel axes),
    /// turned to world by the affine DIPY's voxel positions span (a rotation times 2 mm).
    #[test]
    fn odf_picks_show_the_voxel_its_series_and_dipys_peaks_in_world() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/sh");
        let name = "dipy_lmax8_descoteaux07_legacy.nii.gz";
        let data = load_now(
            &Source::File(dir.join(name)),
            &ReadOptions::default(),
            &None,
            &crate::progress::Silent,
        )
        .unwrap();
        assert!(data.odf.is_some() && data.set.glyphs.is_empty());
        assert_eq!(data.field.lattice_dims(), Some([4, 4, 4]));
        let built = crate::staging::build_sh(
            data.odf.as_ref().unwrap(),
            name,
            &crate::staging::Recipe {
                style: crate::glyph::GlyphStyle {
                    color: crate::glyph::ColorScheme::Dec,
                    ..Default::default()
                },
                ..Default::default()
            },
            &crate::progress::Silent,
        )
        .unwrap();
        let text = std::fs::read_to_string(dir.join("expected.json")).unwrap();
        let exp: serde_json::Value = serde_json::from_str(&text).unwrap();
        let t = &exp["files"][name];
        let v3 = |v: &serde_json::Value| {
            DVec3::from_slice(
                &v.as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect::<Vec<_>>(),
            )
        };
        let pos: Vec<DVec3> = t["positions"].as_array().unwrap().iter().map(v3).collect();
        // The affine's columns from neighbouring voxels (x fastest).
        let a = glam::DMat3::from_cols(pos[1] - pos[0], pos[4] - pos[0], pos[16] - pos[0]);
        let mut compared = 0;
        for (id, inst) in built.scene.instances.iter().enumerate() {
            let v = inst.glyph as usize;
            let p = PickInfo::of(id as u32 + 1, &built.scene, &built.selected, &data, 0.5).unwrap();
            assert_eq!(p.index, v);
            assert!(
                (DVec3::from(p.position) - pos[v]).length() < 1e-4,
                "voxel {v}"
            );
            let Detail::Odf {
                lmax,
                coefficients,
                peaks,
                ..
            } = &p.detail
            else {
                panic!("an ODF's pick")
            };
            assert_eq!((*lmax, coefficients.len()), (8, 45));
            let Some(truth) = t["peaks"].get(v.to_string()) else {
                continue;
            };
            let dirs = truth["directions"].as_array().unwrap();
            assert_eq!(peaks.len(), dirs.len(), "voxel {v}: {peaks:?}");
            for (d, q) in dirs.iter().zip(peaks) {
                let want = (a * v3(d)).normalize();
                let cos = want.dot(DVec3::from(q.direction)).abs().min(1.0);
                assert!(cos.acos().to_degrees() < 1.0, "voxel {v}: {want} vs {q:?}");
                compared += 1;
            }
            let text = p.text();
            assert!(text.contains(&format!("voxel #{v}")) && text.contains("l=8:"));
        }
        assert!(compared >= 16, "{compared} peaks compared");
    }
}
