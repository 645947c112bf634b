//! Hostile bytes as a trace, through `replay` (text and JSON output) and `validate`. Neither
//! may panic; any failure must be a typed error.
#![no_main]

use cooperation_trace::{replay, validate, Options};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let options = Options::default();
    let _ = replay(data, std::io::sink(), &options, false);
    let _ = replay(data, std::io::sink(), &options, true);
    let _ = validate(data, &options);
});
