//! The group level of the BIDS form (`report BIDS_DIR OUT_DIR group`), as a BIDS App's: one
//! page over the participants the participant level reported on, for finding the ones that are
//! off, as MRIQC's group reports are used.
//!
//! The participant level leaves beside each page a summary (`sub-<label>.json`: each map's
//! size, valid share, FA and MD medians or an ODF map's crossing share, its axial figure; or
//! the error that stopped it). The group level reads no image: it lists the BIDS folder's
//! participants (those of `--participant-label` when given), reads their summaries and writes
//! `group.html` (a row per map: thumbnail, measures, robust z-scores, a link to the
//! participant's page) and `group.tsv` (the same numbers, `n/a` where none). A participant
//! whose report failed, or that has no summary, is a row saying so; it does not stop the page.
//!
//! **Outliers** are flagged by the modified z-score of Iglewicz and Hoaglin (1993),
//! z = 0.6745 (x − median) / MAD over the maps of one kind (tensor maps: FA median, MD median,
//! valid share; ODF maps: the share with a series, the crossing share), |z| > 3.5: the median
//! and the median absolute deviation are not pulled by the outliers they look for, as a mean
//! and a standard deviation are in a small cohort. Where MAD is 0 (most maps equal) any map
//! that differs is flagged (z = ±∞). Fewer than three maps of a kind get no z-scores.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::page::esc;
use super::{ReportError, Section};
use crate::bids;
use crate::error::escape_path;
use crate::image_out::write_atomic;

/// The threshold on |z| (Iglewicz and Hoaglin's).
pub const Z_LIMIT: f64 = 3.5;

/// A summary larger than this is not read (a summary is a few hundred bytes a map).
const SUMMARY_BYTES: u64 = 1 << 20;

/// What the participant level leaves beside a page for the group level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParticipantSummary {
    /// `sub-<label>`.
    pub name: String,
    /// The page, relative to the output folder; `None` where the report failed.
    pub page: Option<String>,
    /// Why the report failed (the command line's error text).
    pub error: Option<String>,
    pub maps: Vec<MapSummary>,
}

/// One map of a participant's report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapSummary {
    /// The file's name without its extensions.
    pub name: String,
    pub session: Option<String>,
    /// `tensor` or `odf`.
    pub kind: String,
    pub dims: [usize; 3],
    /// Voxels holding a valid tensor (tensor maps) or a series not all zero (ODF maps).
    pub valid: usize,
    pub fa_median: Option<f64>,
    pub md_median: Option<f64>,
    /// An ODF map's share of sampled voxels with two peaks or more
    /// ([`super::PeakStats::crossing_share`]).
    #[serde(default)]
    pub crossing_share: Option<f64>,
    /// The axial figure, relative to the output folder.
    pub thumbnail: Option<String>,
}

impl MapSummary {
    fn voxels(&self) -> usize {
        self.dims.iter().product()
    }

    /// The share of the lattice's voxels that hold something to draw.
    pub fn valid_share(&self) -> f64 {
        self.valid as f64 / self.voxels().max(1) as f64
    }
}

/// The summary of the report `name` made of `maps`.
pub(crate) fn summary(name: &str, maps: &[Section]) -> ParticipantSummary {
    let thumbnail = |figures: &[super::FigureReport]| {
        figures
            .iter()
            .find(|f| f.orientation == "axial")
            .or(figures.first())
            .map(|f| format!("{name}/figures/{}", f.file))
    };
    let maps = maps
        .iter()
        .map(|m| match m {
            Section::Tensor(t) => MapSummary {
                name: t.name.clone(),
                session: t.session.clone(),
                kind: "tensor".into(),
                dims: t.dims,
                valid: t.valid,
                fa_median: t.fa.map(|s| s.median),
                md_median: t.md.map(|s| s.median),
                crossing_share: None,
                thumbnail: thumbnail(&t.figures),
            },
            Section::Odf(o) => MapSummary {
                name: o.name.clone(),
                session: o.session.clone(),
                kind: "odf".into(),
                dims: o.dims,
                valid: o.held,
                fa_median: None,
                md_median: None,
                crossing_share: o.peaks.map(|p| p.crossing_share()),
                thumbnail: thumbnail(&o.figures),
            },
            Section::Peaks(p) => MapSummary {
                name: p.name.clone(),
                session: p.session.clone(),
                kind: "peaks".into(),
                dims: p.dims,
                valid: p.counts.held,
                fa_median: None,
                md_median: None,
                crossing_share: Some(p.counts.crossing_share()),
                thumbnail: thumbnail(&p.figures),
            },
        })
        .collect();
    ParticipantSummary {
        name: name.into(),
        page: Some(format!("{name}.html")),
        error: None,
        maps,
    }
}

/// Where the summary of report `name` goes in `out`.
pub fn summary_path(out: &Path, name: &str) -> PathBuf {
    out.join(format!("{name}.json"))
}

/// Write `s` to its place in `out` (atomically; never over one of `inputs`).
pub(crate) fn write_summary(
    out: &Path,
    s: &ParticipantSummary,
    inputs: &[&Path],
) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(s).expect("a summary serialises");
    write_atomic(&summary_path(out, &s.name), inputs, |w| {
        use std::io::Write as _;
        writeln!(w, "{text}")
    })
}

/// A measure of the group page, for maps of one kind.
struct Measure {
    title: &'static str,
    kind: &'static str,
    of: fn(&MapSummary) -> Option<f64>,
}

const MEASURES: [Measure; 5] = [
    Measure {
        title: "FA median",
        kind: "tensor",
        of: |m| m.fa_median,
    },
    Measure {
        title: "MD median",
        kind: "tensor",
        of: |m| m.md_median,
    },
    Measure {
        title: "valid share",
        kind: "tensor",
        of: |m| Some(m.valid_share()),
    },
    Measure {
        title: "share with an ODF",
        kind: "odf",
        of: |m| Some(m.valid_share()),
    },
    Measure {
        title: "crossing share",
        kind: "odf",
        of: |m| m.crossing_share,
    },
];

/// The median of `v` (not empty).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// The modified z-scores of `values` ([module doc](self)); `None` for fewer than three.
pub fn robust_z(values: &[f64]) -> Option<Vec<f64>> {
    if values.len() < 3 {
        return None;
    }
    let med = median(&mut values.to_vec());
    let mad = median(&mut values.iter().map(|x| (x - med).abs()).collect::<Vec<_>>());
    Some(
        values
            .iter()
            .map(|&x| {
                if x == med {
                    0.0
                } else if mad > 0.0 {
                    0.6745 * (x - med) / mad
                } else {
                    f64::INFINITY.copysign(x - med)
                }
            })
            .collect(),
    )
}

/// One row of the group page: a map, or a participant without one.
struct Row {
    participant: String,
    page: Option<String>,
    map: Option<MapSummary>,
    /// Why there is no map: the report failed, or there is no summary.
    problem: Option<String>,
    /// z per measure (`MEASURES`' order), where the measure applies and there are enough maps.
    z: [Option<f64>; 5],
}

impl Row {
    fn flagged(&self) -> Vec<String> {
        MEASURES
            .iter()
            .zip(&self.z)
            .filter_map(|(m, z)| z.filter(|z| z.abs() > Z_LIMIT).map(|z| (m, z)))
            .map(|(m, z)| format!("{} z = {}", m.title, z_text(z)))
            .collect()
    }
}

fn z_text(z: f64) -> String {
    if z.is_infinite() {
        if z > 0.0 { "+∞" } else { "−∞" }.into()
    } else {
        format!("{z:+.1}")
    }
}

/// What the group level wrote.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupOutcome {
    pub page: PathBuf,
    pub table: PathBuf,
    pub participants: usize,
    pub maps: usize,
    /// Participants whose report failed or is missing.
    pub without_report: Vec<String>,
    /// `sub-<label>` and its map's name, for every flagged map.
    pub flagged: Vec<(String, String)>,
}

/// Read participant `name`'s summary in `out`: `Err` says why there is none to show.
fn read_summary(out: &Path, name: &str) -> Result<ParticipantSummary, String> {
    let path = summary_path(out, name);
    let file = std::fs::File::open(&path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            format!(
                "no participant report ({} is missing: run the participant level for it)",
                escape_path(&path)
            )
        } else {
            format!("{}: {e}", escape_path(&path))
        }
    })?;
    let mut text = String::new();
    use std::io::Read as _;
    file.take(SUMMARY_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| format!("{}: {e}", escape_path(&path)))?;
    if text.len() as u64 > SUMMARY_BYTES {
        return Err(format!(
            "{}: over {SUMMARY_BYTES} bytes, not a participant summary",
            escape_path(&path)
        ));
    }
    let s: ParticipantSummary = serde_json::from_str(&text).map_err(|e| {
        format!(
            "{}: not a participant summary: {}",
            escape_path(&path),
            crate::error::escape_for_error(e.to_string())
        )
    })?;
    if s.name != name {
        return Err(format!(
            "{}: the summary of {}, not of {name}",
            escape_path(&path),
            crate::error::escape_for_error(s.name)
        ));
    }
    Ok(s)
}

/// The group level: the participants of the BIDS folder `dir` (those of `labels` when it names
/// some), their summaries read from `out`, and `group.html` and `group.tsv` written there.
pub fn run(dir: &Path, out: &Path, labels: &[String]) -> Result<GroupOutcome, ReportError> {
    if let (Ok(a), Ok(b)) = (dir.canonicalize(), out.canonicalize())
        && a == b
    {
        return Err(ReportError::OutputIsInput(out.to_path_buf()));
    }
    let participants = bids::participants(dir, labels)?;
    let mut rows = Vec::new();
    let mut without_report = Vec::new();
    for p in &participants {
        let name = format!("sub-{}", p.label);
        let summary = read_summary(out, &name).and_then(|s| match s.error {
            Some(e) => Err(format!("the report failed: {e}")),
            None if s.maps.is_empty() => Err("the report holds no map".into()),
            None => Ok(s),
        });
        match summary {
            Ok(s) => rows.extend(s.maps.into_iter().map(|m| Row {
                participant: name.clone(),
                page: s.page.clone(),
                map: Some(m),
                problem: None,
                z: [None; 5],
            })),
            Err(problem) => {
                without_report.push(name.clone());
                rows.push(Row {
                    participant: name,
                    page: None,
                    map: None,
                    problem: Some(problem),
                    z: [None; 5],
                });
            }
        }
    }
    for (k, m) in MEASURES.iter().enumerate() {
        let at: Vec<(usize, f64)> = rows
            .iter()
            .enumerate()
            .filter_map(|(i, r)| {
                let map = r.map.as_ref().filter(|map| map.kind == m.kind)?;
                (m.of)(map).filter(|v| v.is_finite()).map(|v| (i, v))
            })
            .collect();
        let values: Vec<f64> = at.iter().map(|&(_, v)| v).collect();
        if let Some(z) = robust_z(&values) {
            for (&(i, _), z) in at.iter().zip(z) {
                rows[i].z[k] = Some(z);
            }
        }
    }
    let flagged: Vec<(String, String)> = rows
        .iter()
        .filter(|r| !r.flagged().is_empty())
        .filter_map(|r| Some((r.participant.clone(), r.map.as_ref()?.name.clone())))
        .collect();
    let maps = rows.iter().filter(|r| r.map.is_some()).count();
    let outcome = GroupOutcome {
        page: out.join("group.html"),
        table: out.join("group.tsv"),
        participants: participants.len(),
        maps,
        without_report,
        flagged,
    };
    std::fs::create_dir_all(out).map_err(|source| ReportError::Write {
        path: out.to_path_buf(),
        source,
    })?;
    let write = |path: &Path, text: String| {
        write_atomic(path, &[], |w| {
            use std::io::Write as _;
            w.write_all(text.as_bytes())
        })
        .map_err(|source| ReportError::Write {
            path: path.to_path_buf(),
            source,
        })
    };
    write(&outcome.table, tsv(&rows))?;
    write(&outcome.page, html(&rows, &outcome))?;
    Ok(outcome)
}

fn number(v: Option<f64>, digits: usize) -> String {
    v.map_or("n/a".into(), |v| format!("{v:.digits$}"))
}

/// The table: one line per row, `n/a` where a value does not apply (BIDS' convention).
fn tsv(rows: &[Row]) -> String {
    let mut t = String::from(
        "participant_id\tsession_id\tmap\tkind\tvoxels\tvalid_share\tfa_median\tmd_median\t\
         crossing_share\tz_fa_median\tz_md_median\tz_valid_share\tz_odf_share\t\
         z_crossing_share\tflagged\tproblem\n",
    );
    // Tabs and line ends in file-derived text would break the table's columns.
    let cell = |s: &str| s.replace(['\t', '\n', '\r'], " ");
    for r in rows {
        let z: Vec<String> =
            r.z.iter()
                .map(|z| z.map_or("n/a".into(), |z| format!("{z:.3}")))
                .collect();
        let m = r.map.as_ref();
        let _ = writeln!(
            t,
            "{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}",
            cell(&r.participant),
            m.and_then(|m| m.session.as_deref())
                .map_or("n/a".into(), |s| format!("ses-{}", cell(s))),
            m.map_or("n/a".into(), |m| cell(&m.name)),
            m.map_or("n/a", |m| m.kind.as_str()),
            m.map_or("n/a".into(), |m| m.voxels().to_string()),
            number(m.map(MapSummary::valid_share), 4),
            number(m.and_then(|m| m.fa_median), 4),
            m.and_then(|m| m.md_median)
                .map_or("n/a".into(), |v| format!("{v:.4e}")),
            number(m.and_then(|m| m.crossing_share), 4),
            z.join("\t"),
            format_args!(
                "{}\t{}",
                u8::from(!r.flagged().is_empty()),
                r.problem.as_deref().map_or("n/a".into(), cell)
            ),
        );
    }
    t
}

fn html(rows: &[Row], o: &GroupOutcome) -> String {
    let mut body = String::new();
    for r in rows {
        let flags = r.flagged();
        let style = if r.problem.is_some() || !flags.is_empty() {
            " style=\"background:#fdd\""
        } else {
            ""
        };
        let who = match &r.page {
            Some(p) => format!("<a href=\"{}\">{}</a>", esc(p), esc(&r.participant)),
            None => esc(&r.participant),
        };
        let Some(m) = &r.map else {
            let _ = writeln!(
                body,
                "<tr{style}><td>{who}</td><td colspan=\"7\"></td><td>{}</td></tr>",
                esc(r.problem.as_deref().unwrap_or_default())
            );
            continue;
        };
        let thumb = m.thumbnail.as_ref().map_or(String::new(), |t| {
            format!(
                "<img src=\"{}\" alt=\"axial\" style=\"height:96px;background:#000\">",
                esc(t)
            )
        });
        let session = m
            .session
            .as_ref()
            .map_or(String::new(), |s| format!("<br>ses-{}", esc(s)));
        let measure = |k: usize, v: Option<f64>, sci: bool| {
            let v = v.map(|v| {
                if sci {
                    format!("{v:.3e}")
                } else {
                    format!("{v:.3}")
                }
            });
            match (v, r.z[k]) {
                (None, _) => "–".to_string(),
                (Some(v), Some(z)) => format!("{v} (z {})", z_text(z)),
                (Some(v), None) => v,
            }
        };
        let (fa, md, share, crossing) = if m.kind == "odf" {
            (
                "–".into(),
                "–".into(),
                measure(3, Some(m.valid_share()), false),
                measure(4, m.crossing_share, false),
            )
        } else {
            (
                measure(0, m.fa_median, false),
                measure(1, m.md_median, true),
                measure(2, Some(m.valid_share()), false),
                "–".into(),
            )
        };
        let _ = writeln!(
            body,
            "<tr{style}><td>{who}{session}</td><td>{thumb}</td><td>{}<br>{}</td><td>{fa}</td>\
             <td>{md}</td><td>{share}</td><td>{crossing}</td><td>{}</td><td>{}</td></tr>",
            esc(&m.name),
            if m.kind == "odf" {
                "ODF map"
            } else {
                "tensor map"
            },
            m.dims.map(|d| d.to_string()).join("×"),
            esc(&flags.join("; ")),
        );
    }
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>group: tensorglyph report</title>\n<style>body{{font-family:sans-serif;\
         margin:2em}}td,th{{text-align:left;padding:0.3em 1em 0.3em 0;vertical-align:top}}\
         </style></head><body>\n<h1>Group</h1>\n<p>tensorglyph {version}. {n} participants, \
         {maps} maps; {failed} without a report, {flagged} maps flagged. A map is flagged \
         where a measure's modified z-score (0.6745 (x − median) / MAD over the maps of its \
         kind; Iglewicz and Hoaglin) is beyond ±{Z_LIMIT}; with MAD 0 any map that differs \
         from the median is. MD is in the file's units. The valid share is the share of the \
         lattice's voxels holding a valid tensor (tensor maps) or a series (ODF maps); the \
         crossing share an ODF map's share of sampled voxels with two peaks or more. Each \
         participant links to its page.</p>\n<table>\n<tr><th>participant</th><th>axial</th>\
         <th>map</th><th>FA median</th><th>MD median</th><th>valid share</th>\
         <th>crossing share</th><th>size</th><th>flags</th></tr>\n{body}</table>\n</body></html>\n",
        version = env!("CARGO_PKG_VERSION"),
        n = o.participants,
        maps = o.maps,
        failed = o.without_report.len(),
        flagged = o.flagged.len(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Worked by hand: median 1.0, deviations 0, 0, 0.1, 0.1, 9 → MAD 0.1.
    #[test]
    fn robust_z_is_iglewicz_and_hoaglins() {
        let z = robust_z(&[1.0, 1.0, 0.9, 1.1, 10.0]).unwrap();
        let want = [0.0, 0.0, -0.6745, 0.6745, 0.6745 * 9.0 / 0.1];
        for (a, b) in z.iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "{z:?}");
        }
        // MAD 0: the one that differs is infinitely far.
        assert_eq!(
            robust_z(&[1.0, 1.0, 1.0, 0.5]).unwrap(),
            [0.0, 0.0, 0.0, f64::NEG_INFINITY]
        );
        assert_eq!(robust_z(&[1.0, 2.0]), None);
    }
}
