//! Any bytes: the reader must return a scene or diagnostics, never panic,
//! and a scene it accepts must survive the writer.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nffkit_formats::nff::{self, ParseOptions};

fuzz_target!(|data: &[u8]| {
    for opts in [ParseOptions::default(), ParseOptions { lenient: true, fragment: true, ..Default::default() }] {
        if let Ok(parsed) = nff::parse(data, &opts) {
            let text = nff::write(&parsed.scene, Vec::new()).expect("writing to memory");
            let again = nff::parse(&text, &ParseOptions { fragment: true, ..opts }).expect("written text parses");
            assert_eq!(again.scene, parsed.scene);
        }
        if let Err(e) = nff::parse(data, &opts) {
            for d in &e.diagnostics {
                let _ = d.render("fuzz.nff", data);
            }
        }
    }
});
