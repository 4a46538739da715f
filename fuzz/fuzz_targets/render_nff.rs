//! Any bytes: a small scene the reader accepts renders without panicking,
//! to the same bits with every accelerator, with packets or without.
//! The body is nffkit_tracer::fuzzing::render_nff, which the regression test replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| nffkit_tracer::fuzzing::render_nff(data));
