//! The promises every fuzz target checks, the same as `tests/campaign/main.rs`: a consistent field
//! that survives glyph derivation and the `info` report, or an error that is one clean line
//! naming the file. (Time and memory are libFuzzer's `-timeout` and `-rss_limit_mb`.)

use std::path::Path;

use tensorglyph::field::Location;
use tensorglyph::field::vtk::{ReadOptions, read_field_bytes};

pub fn check(path: &Path, bytes: &[u8]) {
    match read_field_bytes(path, bytes, &ReadOptions::default()) {
        Ok(f) => {
            let n = f.tensors.len();
            let want = match f.array.location {
                Location::Point => f.points,
                Location::Cell => f.cells,
            };
            assert_eq!(f.positions.len(), n);
            assert_eq!(want, n);
            assert!(matches!(f.array.components, 6 | 9));
            if let Some(d) = f.dims {
                assert_eq!(d[0].checked_mul(d[1]).and_then(|v| v.checked_mul(d[2])), Some(f.points));
            }
            let set = tensorglyph::glyph::derive_glyphs(&f, &tensorglyph::progress::Silent);
            let samples: Vec<usize> = if n == 0 { vec![] } else { vec![0, n - 1] };
            tensorglyph::info::info_report(&f, &set, &samples).expect("info report");
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.chars().any(char::is_control), "{msg:?}");
            assert!(msg.contains(&*path.file_name().unwrap().to_string_lossy()), "{msg}");
        }
    }
}
