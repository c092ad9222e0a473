//! Any text through the whole pipeline: parse → check → lower → validate → emit every target.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    glazec_lab::fuzzing::whole_pipeline(text);
});
