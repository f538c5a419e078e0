//! What the figure effects cost, measured as Sigg et al. (2006) did in their Table 1: the same
//! frames shaded directly and deferred, then with outlines, hard shadows (one shadow map texel),
//! soft shadows, both, both without the adaptive PCF test, ambient occlusion, and all three;
//! each stage's share is the difference it makes to the frame time. The
//! accuracy of the effects (outline and shadow mismatch against the exact reference) is
//! measured once per view with both on.

use std::fmt::Write as _;

use crate::bench::View;
use crate::effects::ao::AmbientOcclusion;
use crate::effects::{Effects, Outlines, Shading, Shadows};
use crate::error::RenderError;
use crate::metrics::compare;
use crate::reference::ReferenceScene;
use crate::render::GpuRenderer;
use crate::request::{FrameRequest, Method, Preset};

/// One configuration on one view.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EffectsRow {
    pub view: String,
    pub config: &'static str,
    /// Median frame time, submit to completion.
    pub median_ms: f64,
    /// `median_ms` over the direct frame's of the same view.
    pub vs_direct: f64,
    pub outline_mismatch: Option<f64>,
    pub shadow_mismatch: Option<f64>,
    /// Mean |open fraction − the exact one| ([`crate::metrics::Accuracy::ao_error_mean`]).
    pub ao_error_mean: Option<f64>,
}

/// The configurations of the table, in its order, for an image of `size` samples.
pub fn configs(size: (u32, u32)) -> Vec<(&'static str, Effects)> {
    let shadows = Shadows {
        map_size: Shadows::map_for(size.0, size.1),
        ..Shadows::default()
    };
    let outlines = Some(Outlines::default());
    let deferred = Effects {
        shading: Shading::Deferred,
        ..Effects::default()
    };
    vec![
        ("direct", Effects::default()),
        ("deferred", deferred),
        (
            "+outlines",
            Effects {
                outlines,
                ..deferred
            },
        ),
        (
            "+shadows, hard",
            Effects {
                shadows: Some(Shadows {
                    pcf_radius: 0,
                    ..shadows
                }),
                ..deferred
            },
        ),
        (
            "+shadows",
            Effects {
                shadows: Some(shadows),
                ..deferred
            },
        ),
        (
            "+both",
            Effects {
                outlines,
                shadows: Some(shadows),
                ..deferred
            },
        ),
        (
            "+both, full PCF",
            Effects {
                outlines,
                shadows: Some(Shadows {
                    adaptive: false,
                    ..shadows
                }),
                ..deferred
            },
        ),
        (
            "+ao",
            Effects {
                ao: Some(AmbientOcclusion::default()),
                ..deferred
            },
        ),
        (
            "all effects",
            Effects {
                outlines,
                shadows: Some(shadows),
                ao: Some(AmbientOcclusion::default()),
                ..deferred
            },
        ),
    ]
}

/// Time every configuration on every view (`frames` repetitions, configurations interleaved),
/// drawing Gumhold ellipsoids as `render` does by default.
pub fn run(gpu: &GpuRenderer, views: &[View], frames: u32) -> Result<Vec<EffectsRow>, RenderError> {
    let mut rows = Vec::new();
    for view in views {
        let camera = &view.camera;
        let configs = configs((camera.width, camera.height));
        let base = FrameRequest::preset(Method::Gumhold, true, Preset::DEFAULT);
        let buffers = gpu.upload(&view.scene)?;
        let mut times = vec![Vec::new(); configs.len()];
        for _ in 0..frames.max(1) {
            for (k, (_, effects)) in configs.iter().enumerate() {
                // Two frames, the second timed, as `run` in bench/mod.rs times frames below
                // WARM_UP_BELOW_MS.
                let req = FrameRequest {
                    effects: *effects,
                    frames: 2,
                    ..base
                };
                let frame = gpu.render_uploaded(&buffers, camera, &req)?;
                times[k].extend(super::steady_ms(&frame));
            }
        }
        let medians: Vec<f64> = times
            .iter_mut()
            .map(|t| {
                t.sort_by(f64::total_cmp);
                t[t.len() / 2]
            })
            .collect();
        // Every effect against the exact reference.
        let both_at = configs
            .iter()
            .position(|(n, _)| *n == "all effects")
            .expect("the configuration of all effects");
        let both = configs[both_at].1;
        let req = FrameRequest {
            effects: both,
            aux: true,
            ..base
        };
        let frame = gpu.render_uploaded(&buffers, camera, &req)?;
        let reference = ReferenceScene::new(&view.scene, camera).render(&req);
        let accuracy =
            compare(&frame, &reference, &view.scene).with_effects(&frame, &reference, &both);
        for (k, (name, _)) in configs.iter().enumerate() {
            let measured = k == both_at;
            rows.push(EffectsRow {
                view: view.name.clone(),
                config: name,
                median_ms: medians[k],
                vs_direct: medians[k] / medians[0],
                outline_mismatch: accuracy.outline_mismatch.filter(|_| measured),
                shadow_mismatch: accuracy.shadow_mismatch.filter(|_| measured),
                ao_error_mean: accuracy.ao_error_mean.filter(|_| measured),
            });
        }
    }
    Ok(rows)
}

/// The stage shares of one view's rows: (stage, ms) from the differences between
/// configurations.
pub fn stage_shares(rows: &[EffectsRow]) -> Vec<(&'static str, f64)> {
    let ms = |c: &str| {
        rows.iter()
            .find(|r| r.config == c)
            .map_or(0.0, |r| r.median_ms)
    };
    vec![
        ("deferred shading pass", ms("deferred") - ms("direct")),
        ("outlines", ms("+outlines") - ms("deferred")),
        ("shadow map", ms("+shadows, hard") - ms("deferred")),
        ("PCF", ms("+shadows") - ms("+shadows, hard")),
        ("adaptive PCF saves", ms("+both, full PCF") - ms("+both")),
        ("ambient occlusion", ms("+ao") - ms("deferred")),
    ]
}

pub fn csv(rows: &[EffectsRow]) -> String {
    let mut s = String::from(
        "view,config,median_ms,vs_direct,outline_mismatch,shadow_mismatch,ao_error_mean\n",
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.5}"));
    for r in rows {
        let _ = writeln!(
            s,
            "{},\"{}\",{:.3},{:.3},{},{},{}",
            r.view,
            r.config,
            r.median_ms,
            r.vs_direct,
            opt(r.outline_mismatch),
            opt(r.shadow_mismatch),
            opt(r.ao_error_mean)
        );
    }
    s
}

pub fn markdown(rows: &[EffectsRow]) -> String {
    let mut md = String::from(
        "| view | configuration | ms/frame | × direct | outline mismatch | shadow mismatch | AO error (mean) |\n\
         |---|---|---:|---:|---:|---:|---:|\n",
    );
    let pct = |v: Option<f64>| v.map_or(String::new(), |v| format!("{:.2} %", v * 100.0));
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {:.1} | {:.2} | {} | {} | {} |",
            r.view,
            r.config,
            r.median_ms,
            r.vs_direct,
            pct(r.outline_mismatch),
            pct(r.shadow_mismatch),
            r.ao_error_mean.map_or(String::new(), |v| format!("{v:.3}"))
        );
    }
    let mut views: Vec<&str> = rows.iter().map(|r| r.view.as_str()).collect();
    views.dedup();
    for v in views {
        let these: Vec<EffectsRow> = rows.iter().filter(|r| r.view == v).cloned().collect();
        let shares: Vec<String> = stage_shares(&these)
            .into_iter()
            .map(|(s, ms)| format!("{s} {ms:.1} ms"))
            .collect();
        let _ = writeln!(md, "\nStages ({v}): {}.", shares.join(", "));
    }
    md
}
