//! XML `.vti/.vtr/.vts/.vtu/.vtp`: the tokenizer, every encoding and compressor.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("fuzz.vtu");
    if data.first() == Some(&b'<') {
        common::check(path, data);
    } else {
        let mut b = b"<".to_vec();
        b.extend_from_slice(data);
        common::check(path, &b);
    }
});
