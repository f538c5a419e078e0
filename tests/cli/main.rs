//! The `tensorglyph` binary as a user runs it: outputs, JSON reports, exit status and one-line
//! errors, `report` on tensor and ODF maps, the selection flags, scaling on real fields, stress fields against VTK's yield criteria, `bench --large`, the viewer under Xvfb,
//! `render --glyph superquadric` against Teem's `tend glyph`, and `report`/`render` in a bare
//! container (no driver, display or writable HOME) against the same run on lavapipe. tests/README.md is the map.

#[path = "../common/cli.rs"]
mod cli;
#[path = "../common/data.rs"]
mod data;
#[path = "../common/xvfb.rs"]
mod xvfb;

mod bench_large;
mod brain_report;
mod cohort;
mod commands;
mod container;
mod report;
mod report_odf;
mod scaling;
mod selection;
mod stress_fields;
mod teem;
mod viewer;
