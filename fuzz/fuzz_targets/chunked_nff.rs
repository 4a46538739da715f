//! Any bytes: read in pieces, an NFF file gives exactly what it gives read in one (or goes back to the sequential reader).
//! The body is nffkit_formats::fuzzing::chunked_nff, which the regression test replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| nffkit_formats::fuzzing::chunked_nff(data));
