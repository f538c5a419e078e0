//! Parallel `.pvti`: the fuzzed file is placed (by name only, it is not written) in
//! `tests/data/vtk`, so its `Source`s reach the real piece files there, and anything else.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/vtk/fuzz.pvti"));
    common::check(path, data);
});
