//! Legacy `.vtk` (ASCII and binary): inputs that do not start with the header get it, so
//! libFuzzer spends its time past the format check.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("fuzz.vtk");
    if data.starts_with(b"# vtk DataFile") {
        common::check(path, data);
    } else {
        let mut b = b"# vtk DataFile Version 4.2\n".to_vec();
        b.extend_from_slice(data);
        common::check(path, &b);
    }
});
