//! The formats crate's integration tests, one module per subject, linked
//! into one test executable (as ripgrep does): a test binary per file
//! would link the crate and its dependencies once each.

mod course_and_recovery;
mod fuzz_regressions;
mod malformed;
mod p3f;
mod parallel_parse;
mod properties;
mod spd_fixtures;
