//! libFuzzer target: [`raceway_fuzzing::input_files`]; a finding is a panic with its description.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = raceway_fuzzing::input_files(data) {
        panic!("{e}");
    }
});
