//! The short runs of the fuzz harnesses in the test command (a few seconds each, seeded, so a
//! finding is reproducible): `FUZZ_CASES` scales every target, `FUZZ_SEED` moves the seed.
//! The long runs are libFuzzer's (`scripts/fuzz_long.sh`).

use raceway_fuzzing::{drive, fmi_calls, input_files, state_blob};

fn cases(default: u64) -> u64 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn seed() -> u64 {
    std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5eed)
}

#[test]
fn fmi_call_sequences_follow_the_standard() {
    let n = drive(fmi_calls, seed(), cases(300), 160).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("fmi_calls: {n} cases, no finding");
}

#[test]
fn mutated_input_files_are_read_or_refused_naming_the_field() {
    let n = drive(input_files, seed(), cases(5000), 24).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("input_files: {n} cases, no finding");
}

#[test]
fn mutated_state_blobs_are_rejected_with_a_message_or_run() {
    let n = drive(state_blob, seed(), cases(2000), 40).unwrap_or_else(|e| panic!("{e}"));
    eprintln!("state_blob: {n} cases, no finding");
}
