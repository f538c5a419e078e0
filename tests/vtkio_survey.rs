//! Why the reader does not use vtkio: run vtkio 0.7.0-rc2 on every test file and report what
//! it does with the tensor array VTK reads. Ignored by default (it documents, not tests):
//! `cargo test --test vtkio_survey -- --ignored --nocapture`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use vtkio::Vtk;
use vtkio::model::{Attribute, Attributes, DataSet, Piece};

fn attrs_of(ds: &DataSet, out: &mut Vec<Attributes>) {
    macro_rules! pieces {
        ($pieces:expr) => {
            for p in $pieces {
                match p {
                    Piece::Inline(p) => out.push(p.data.clone()),
                    Piece::Loaded(d) => attrs_of(d, out),
                    Piece::Source(..) => {}
                }
            }
        };
    }
    match ds {
        DataSet::ImageData { pieces, .. } => pieces!(pieces),
        DataSet::StructuredGrid { pieces, .. } => pieces!(pieces),
        DataSet::RectilinearGrid { pieces, .. } => pieces!(pieces),
        DataSet::UnstructuredGrid { pieces, .. } => pieces!(pieces),
        DataSet::PolyData { pieces, .. } => pieces!(pieces),
        _ => {}
    }
}

/// Values of the named array over all pieces (`None`: not present).
fn values_of(attrs: &[Attributes], name: &str) -> Option<usize> {
    let mut found = None;
    for a in attrs {
        for at in a.point.iter().chain(&a.cell) {
            match at {
                Attribute::DataArray(d) if d.name == name => {
                    *found.get_or_insert(0) += d.data.len();
                }
                Attribute::Field { data_array, .. } => {
                    for f in data_array.iter().filter(|f| f.name == name) {
                        *found.get_or_insert(0) += f.data.len();
                    }
                }
                _ => {}
            }
        }
    }
    found
}

#[test]
#[ignore]
fn vtkio_on_vtk_written_files() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let exp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    std::panic::set_hook(Box::new(|_| {}));
    let mut tally = std::collections::BTreeMap::<String, Vec<String>>::new();
    for (file, e) in exp.as_object().unwrap() {
        let path = dir.join(file);
        let outcome = match catch_unwind(AssertUnwindSafe(|| {
            let mut vtk = Vtk::import(&path)?;
            vtk.load_all_pieces()?;
            Ok::<_, vtkio::Error>(vtk)
        })) {
            Err(_) => "panic".to_string(),
            Ok(Err(err)) => format!(
                "error: {}",
                format!("{err:?}").chars().take(90).collect::<String>()
            ),
            Ok(Ok(vtk)) => {
                let mut attrs = Vec::new();
                attrs_of(&vtk.data, &mut attrs);
                let mut problems = Vec::new();
                for arr in e["arrays"].as_array().unwrap() {
                    let name = arr["name"].as_str().unwrap();
                    let want = (arr["tuples"].as_u64().unwrap()
                        * arr["components"].as_u64().unwrap())
                        as usize;
                    match values_of(&attrs, name) {
                        None => problems.push(format!("'{name}' missing")),
                        Some(n) if n != want => {
                            problems.push(format!("'{name}' has {n} values, not {want}"))
                        }
                        Some(_) => {}
                    }
                }
                if problems.is_empty() {
                    "ok (all tensor arrays present with the right length)".to_string()
                } else {
                    format!("Ok but {}", problems.join(", "))
                }
            }
        };
        tally.entry(outcome).or_default().push(file.clone());
    }
    let _ = std::panic::take_hook();
    for (outcome, files) in &tally {
        println!("{outcome}: {} files", files.len());
        for f in files {
            println!("    {f}");
        }
    }
}
