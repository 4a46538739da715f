//! The tools' integration tests, mostly end to end through the binaries a
//! user runs, one module per subject, linked into one test executable (as
//! ripgrep does): a test binary per file would link the crate and its
//! dependencies once each.

mod aademo;
mod bench;
mod cli;
mod common;
mod convert;
mod farm;
mod files;
mod generators;
mod gpu;
mod mesh2nff;
mod mesh_looks;
mod p3f;
mod playground;
mod spd;
