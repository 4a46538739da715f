//! The tracer's integration tests, one module per subject, linked into one
//! test executable (as ripgrep does): a test binary per file would link the
//! crate and its dependencies once each.

mod determinism;
mod fidelity;
mod fuzz_regressions;
mod packets;
mod shading;
