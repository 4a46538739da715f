//! Every input the `render_nff` fuzzer ever failed on, replayed through
//! its body (`nffkit_tracer::fuzzing`), so that a failure once fixed stays
//! fixed. The inputs live in `tests/fuzz-regressions/render_nff/`.

use nffkit_formats::fuzzing::replay;
use nffkit_tracer::fuzzing::TARGETS;
use std::path::Path;

#[test]
fn every_input_the_fuzzer_failed_on_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    let (failed, replayed) = replay(&root, &TARGETS);
    assert!(failed.is_empty(), "still failing (or not a target): {failed:?}");
    assert!(replayed > 0, "no inputs under {}", root.display());
}
