//! Any bytes through the parser and the checkers (materials and scenes): diagnostics or a
//! model, never a panic, and every diagnostic's span inside the text.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    glazec_lab::fuzzing::parse_and_check(text);
});
