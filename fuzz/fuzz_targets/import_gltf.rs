//! Any bytes: the glTF/GLB importer returns a consistent mesh or an error.
//! The body is nffkit_formats::fuzzing::import_gltf, which the regression test replays.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| nffkit_formats::fuzzing::import_gltf(data));
