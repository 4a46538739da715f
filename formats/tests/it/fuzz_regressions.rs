//! Every input a fuzzer ever failed on, replayed through the target's own
//! body (`nffkit_formats::fuzzing`), so that a crash once fixed stays
//! fixed. The inputs live in `tests/fuzz-regressions/<target>/`, one file
//! each (see the README there).

use nffkit_formats::fuzzing::{replay, TARGETS};
use std::path::Path;

#[test]
fn every_input_a_fuzzer_failed_on_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    let (failed, replayed) = replay(&root, &TARGETS);
    assert!(failed.is_empty(), "still failing (or not a target): {failed:?}");
    assert!(replayed > 0, "no inputs under {}", root.display());
}
