//! `bench --startup`: time to the first image as a pipeline meets it, one subject per process.
//! Each case is the `tensorglyph` binary run as a new process, timed from its start to its exit
//! (the PNG or the report written), cold (an empty cache folder: neither Mesa's shader cache nor
//! the pipeline cache hold anything) and warm (a cache folder an untimed run filled), with the
//! cases and both states interleaved across repetitions so that machine drift hits all alike.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde::Serialize;
use web_time::Instant;

use crate::percentile::percentiles;

/// One way of starting.
pub struct Case {
    pub name: &'static str,
    /// The arguments after the binary; `{out}` is replaced by a fresh output path.
    pub args: Vec<String>,
}

/// The cases: grid40 (the default, with the prepass and splats), grid:2 (the pipelines with
/// next to nothing to draw), grid40 with the baseline preset (one pipeline), and, when a BIDS
/// derivatives folder is given, a report of its participant `01`.
pub fn cases(bids: Option<&Path>) -> Vec<Case> {
    let render = |name, extra: &[&str]| {
        let mut args: Vec<String> = ["render", "--demo"].map(String::from).to_vec();
        args.extend(extra.iter().map(|s| s.to_string()));
        args.extend(["-o", "{out}.png", "-q"].map(String::from));
        Case { name, args }
    };
    let mut cases = vec![
        render("render --demo grid40", &["grid40"]),
        render("render --demo grid:2", &["grid:2"]),
        render(
            "render --demo grid40 --preset baseline",
            &["grid40", "--preset", "baseline"],
        ),
    ];
    if let Some(bids) = bids {
        cases.push(Case {
            name: "report, one participant",
            args: vec![
                "report".into(),
                bids.display().to_string(),
                "{out}".into(),
                "participant".into(),
                "--participant-label".into(),
                "01".into(),
            ],
        });
    }
    cases
}

/// What one case measured.
#[derive(Debug, Clone, Serialize)]
pub struct StartupRow {
    pub case: String,
    pub cold_s_median: f64,
    pub warm_s_median: f64,
    pub cold_s_min: f64,
    pub warm_s_min: f64,
    /// Empty when every run succeeded; else the first failure.
    pub error: String,
}

/// Run every case `repetitions` times cold and warm with `exe`, in `work` (a folder for the
/// outputs and the cache folders, emptied by the caller).
pub fn run(exe: &Path, work: &Path, cases: &[Case], repetitions: u32) -> Vec<StartupRow> {
    let warm_cache = work.join("warm-cache");
    let mut times: Vec<[Vec<f64>; 2]> = cases.iter().map(|_| Default::default()).collect();
    let mut errors: Vec<String> = vec![String::new(); cases.len()];
    let mut n = 0;
    let mut once = |case: &Case, cache: &Path| -> Result<f64, String> {
        n += 1;
        let out = work.join(format!("out-{n}"));
        let args: Vec<String> = case
            .args
            .iter()
            .map(|a| a.replace("{out}", &out.display().to_string()))
            .collect();
        let t = Instant::now();
        let o = Command::new(exe)
            .args(&args)
            .env("XDG_CACHE_HOME", cache)
            .env_remove("TENSORGLYPH_PIPELINE_CACHE")
            .env_remove("MESA_SHADER_CACHE_DIR")
            .env_remove("MESA_SHADER_CACHE_DISABLE")
            .output()
            .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
        let s = t.elapsed().as_secs_f64();
        if !o.status.success() {
            let err = String::from_utf8_lossy(&o.stderr);
            return Err(err.lines().next().unwrap_or("failed").to_string());
        }
        Ok(s)
    };
    // Fill the warm cache, untimed.
    for (i, case) in cases.iter().enumerate() {
        if let Err(e) = once(case, &warm_cache) {
            errors[i] = e;
        }
    }
    for r in 0..repetitions {
        for (i, case) in cases.iter().enumerate() {
            if !errors[i].is_empty() {
                continue;
            }
            let cold_cache = work.join(format!("cold-cache-{r}-{i}"));
            for (k, cache) in [cold_cache.as_path(), warm_cache.as_path()]
                .into_iter()
                .enumerate()
            {
                match once(case, cache) {
                    Ok(s) => times[i][k].push(s),
                    Err(e) => errors[i] = e,
                }
            }
            let _ = std::fs::remove_dir_all(&cold_cache);
        }
    }
    cases
        .iter()
        .zip(times)
        .zip(errors)
        .map(|((case, [cold, warm]), error)| {
            let min = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::min);
            let median = |v: &[f64]| {
                percentiles(v.to_vec(), [0.5, 0.5], f64::total_cmp).map_or(f64::NAN, |p| p[0])
            };
            StartupRow {
                case: case.name.to_string(),
                cold_s_median: median(&cold),
                warm_s_median: median(&warm),
                cold_s_min: min(&cold),
                warm_s_min: min(&warm),
                error,
            }
        })
        .collect()
}

/// The rows as CSV.
pub fn csv(rows: &[StartupRow]) -> String {
    let mut s = String::from("case,cold_s_median,warm_s_median,cold_s_min,warm_s_min,error\n");
    for r in rows {
        s.push_str(&format!(
            "{},{:.4},{:.4},{:.4},{:.4},{}\n",
            r.case,
            r.cold_s_median,
            r.warm_s_median,
            r.cold_s_min,
            r.warm_s_min,
            r.error.replace(',', ";")
        ));
    }
    s
}

/// The rows as a markdown section of report.md, with warm to cold and each case's warm start
/// as a ratio to grid:2's (the start with next to nothing to draw).
pub fn markdown(rows: &[StartupRow], repetitions: u32, adapter: &str) -> String {
    let base = rows
        .iter()
        .find(|r| r.case.ends_with("grid:2"))
        .map_or(f64::NAN, |r| r.warm_s_median);
    let mut s = format!(
        "## Start-up: time to the first image\n\n\
         Each case a new process, timed from its start to its exit (the PNG or the report \
         written), {repetitions} runs each, cases and cache states interleaved; medians. Cold: an \
         empty cache folder (`XDG_CACHE_HOME`: Mesa's shader cache and the pipeline cache); \
         warm: one an earlier run filled. Adapter: {adapter}.\n\n\
         | case | cold (s) | warm (s) | warm / cold | warm / grid:2 warm |\n\
         |---|---|---|---|---|\n"
    );
    for r in rows {
        if !r.error.is_empty() {
            s.push_str(&format!("| {} | failed: {} | | | |\n", r.case, r.error));
            continue;
        }
        s.push_str(&format!(
            "| {} | {:.3} | {:.3} | {:.2} | {:.2} |\n",
            r.case,
            r.cold_s_median,
            r.warm_s_median,
            r.warm_s_median / r.cold_s_median,
            r.warm_s_median / base
        ));
    }
    s
}

/// A BIDS derivatives folder in `dir` with one participant (`sub-01`): the whole-brain volume
/// of `bench --brain` as its BEP016 tensor map, in image axes.
pub fn write_bids(dir: &Path) -> std::io::Result<PathBuf> {
    let root = dir.join("derivatives");
    let dwi = root.join("sub-01").join("dwi");
    std::fs::create_dir_all(&dwi)?;
    std::fs::write(
        root.join("dataset_description.json"),
        r#"{"Name": "tensorglyph start-up bench", "BIDSVersion": "1.10.0", "DatasetType": "derivative"}"#,
    )?;
    super::brain::write(&dwi.join("sub-01_model-DTI_param-tensor_dwimap.nii.gz"))?;
    std::fs::write(
        dwi.join("sub-01_model-DTI_dwimap.json"),
        r#"{"OrientationRepresentation": "param", "ReferenceAxes": "ijk"}"#,
    )?;
    Ok(root)
}
