//! Structure-aware: a shipped material, mutated where it matters (numbers swapped for extreme
//! or non-finite values, layers duplicated or dropped, tokens deleted, nesting deepened), then
//! the whole pipeline.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = glazec_lab::fuzzing::mutate_shipped(data);
    glazec_lab::fuzzing::whole_pipeline(&text);
});
