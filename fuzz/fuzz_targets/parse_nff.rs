//! Any bytes: the NFF reader returns a scene or diagnostics, and a scene it accepts survives the writer.
//! The body is nffkit_formats::fuzzing::parse_nff, which the regression test replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| nffkit_formats::fuzzing::parse_nff(data));
