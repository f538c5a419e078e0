//! A cohort: the book's Slurm recipe (examples/cohort/report_array.sbatch) run as Slurm would
//! run its array, tasks at once, without Slurm; its pages byte for byte a serial run's with
//! `--reproducible`; the broken participant failing alone; and the group level over them: one
//! row per map with FA and MD medians equal to numpy's (tests/data/bids/expected.json), robust
//! z-scores and flags computed here from those, the broken participant listed with its error, a
//! missing or malformed summary a row saying so.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::cli::{stderr, tg};

fn bids() -> String {
    crate::data::path("bids/derivatives")
        .to_string_lossy()
        .into_owned()
}

/// Every file under `dir`, by its path relative to `dir`, with its bytes.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    crate::data::files_below(dir)
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
            (rel, std::fs::read(&p).unwrap())
        })
        .collect()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// Iglewicz and Hoaglin's modified z-scores, as the book states them.
fn modified_z(v: &[f64]) -> Vec<f64> {
    let med = median(&mut v.to_vec());
    let mad = median(&mut v.iter().map(|x| (x - med).abs()).collect::<Vec<_>>());
    v.iter().map(|x| 0.6745 * (x - med) / mad).collect()
}

#[test]
fn the_slurm_recipe_matches_a_serial_run_and_the_group_page_lists_everyone() {
    let root = tempfile::tempdir().unwrap();
    let (serial, array) = (root.path().join("serial"), root.path().join("array"));
    let o = tg(&[
        "report",
        &bids(),
        serial.to_str().unwrap(),
        "participant",
        "--reproducible",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));

    // The array's five tasks at once, as Slurm would start them.
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cohort/report_array.sbatch");
    let tasks: Vec<_> = (1..=5)
        .map(|task| {
            Command::new("bash")
                .arg(&script)
                .arg(bids())
                .arg(&array)
                .env("SLURM_ARRAY_TASK_ID", task.to_string())
                .env("TG", env!("CARGO_BIN_EXE_tensorglyph"))
                .env("XDG_RUNTIME_DIR", std::env::temp_dir())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let done: Vec<_> = tasks
        .into_iter()
        .map(|t| t.wait_with_output().unwrap())
        .collect();
    let status: Vec<Option<i32>> = done.iter().map(|o| o.status.code()).collect();
    // Task 4 is sub-04, whose map is broken: it fails alone, in one line.
    assert_eq!(status, [Some(0), Some(0), Some(0), Some(1), Some(0)]);
    let err = stderr(&done[3]);
    assert!(
        err.starts_with("error: sub-04: ") && err.lines().count() == 1,
        "{err}"
    );
    let (a, s) = (files(&array), files(&serial));
    assert_eq!(a.keys().collect::<Vec<_>>(), s.keys().collect::<Vec<_>>());
    for (name, bytes) in &s {
        assert!(
            a[name] == *bytes,
            "{name} differs between the array and the serial run"
        );
    }
    assert!(s.contains_key("sub-04.json") && !s.contains_key("sub-04.html"));
    // The pages hold no time: nothing that would differ between runs.
    assert!(!String::from_utf8_lossy(&s["sub-01.html"]).contains("Time for this page"));

    let o = tg(&["report", &bids(), array.to_str().unwrap(), "group"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let line = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        line.ends_with("group.html: 5 participants, 5 maps; 1 without a report, 2 maps flagged\n"),
        "{line}"
    );
    let tsv = std::fs::read_to_string(array.join("group.tsv")).unwrap();
    let rows: Vec<Vec<&str>> = tsv.lines().map(|l| l.split('\t').collect()).collect();
    assert_eq!(
        rows[0][..4],
        ["participant_id", "session_id", "map", "kind"]
    );
    let col = |name: &str| rows[0].iter().position(|h| *h == name).unwrap();
    let who: Vec<&str> = rows[1..].iter().map(|r| r[0]).collect();
    assert_eq!(
        who,
        ["sub-01", "sub-02", "sub-03", "sub-03", "sub-04", "sub-05"]
    );
    assert!(
        rows[5][col("problem")].contains("gzip data is corrupt"),
        "{tsv}"
    );

    // numpy's FA and MD of every good map, their medians and z-scores.
    let text = std::fs::read_to_string(crate::data::path("bids/expected.json")).unwrap();
    let truth: BTreeMap<String, serde_json::Value> = serde_json::from_str(&text).unwrap();
    let values = |m: &serde_json::Value, key: &str| -> Vec<f64> {
        m[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let good: Vec<&Vec<&str>> = rows[1..].iter().filter(|r| r[3] == "tensor").collect();
    assert_eq!(good.len(), truth.len());
    let fa: Vec<f64> = truth
        .values()
        .map(|m| median(&mut values(m, "fa")))
        .collect();
    let md: Vec<f64> = truth
        .values()
        .map(|m| median(&mut values(m, "md")))
        .collect();
    let (zfa, zmd) = (modified_z(&fa), modified_z(&md));
    for (k, ((path, _), row)) in truth.iter().zip(&good).enumerate() {
        assert!(path.ends_with(row[2]), "{path} vs {}", row[2]);
        let num = |name: &str| {
            let v = row[col(name)];
            v.parse::<f64>()
                .unwrap_or_else(|_| panic!("{name} is {v}: {row:?}"))
        };
        assert!(
            (num("fa_median") - fa[k]).abs() < 1e-4,
            "FA {row:?} vs {}",
            fa[k]
        );
        assert!(
            (num("md_median") / md[k] - 1.0).abs() < 1e-3,
            "MD {} vs {}",
            row[7],
            md[k]
        );
        assert!(
            (num("z_fa_median") - zfa[k]).abs() < 1e-2 * zfa[k].abs().max(1.0),
            "{tsv}"
        );
        assert!(
            (num("z_md_median") - zmd[k]).abs() < 1e-2 * zmd[k].abs().max(1.0),
            "{tsv}"
        );
        let flagged = zfa[k].abs() > 3.5 || zmd[k].abs() > 3.5;
        assert_eq!(
            row[col("flagged")],
            if flagged { "1" } else { "0" },
            "{tsv}"
        );
    }
    let html = std::fs::read_to_string(array.join("group.html")).unwrap();
    for p in ["sub-01", "sub-02", "sub-03", "sub-05"] {
        assert!(
            html.contains(&format!("<a href=\"{p}.html\">{p}</a>")),
            "{p}"
        );
    }
    assert!(html.contains("the report failed: ") && html.contains("gzip data is corrupt"));
    for img in html.split("<img src=\"").skip(1) {
        let path = &img[..img.find('"').unwrap()];
        assert!(array.join(path).is_file(), "{path}");
    }

    // A participant without a summary, and one whose summary is not one: rows saying so.
    std::fs::remove_file(array.join("sub-05.json")).unwrap();
    std::fs::write(array.join("sub-02.json"), "{\"name\": \"sub-02\", ").unwrap();
    let o = tg(&["report", &bids(), array.to_str().unwrap(), "group"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let tsv = std::fs::read_to_string(array.join("group.tsv")).unwrap();
    let problem = |who: &str| {
        tsv.lines()
            .find(|l| l.starts_with(who))
            .unwrap()
            .rsplit('\t')
            .next()
            .unwrap()
            .to_string()
    };
    assert!(
        problem("sub-05").starts_with("no participant report ("),
        "{tsv}"
    );
    let bad = problem("sub-02");
    assert!(
        bad.contains("sub-02.json: not a participant summary: "),
        "{bad}"
    );
}
