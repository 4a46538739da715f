//! The library behind nffkit's command-line tools. Binaries in `src/bin/` are
//! thin shells of argument parsing over these functions, so tests and other
//! tools call exactly the same code.
#![forbid(unsafe_code)]

pub mod aademo;
pub mod bench;
pub mod check;
pub mod cli_util;
pub mod default_scene;
pub mod golden;
pub mod input;
pub mod lighting;
pub mod mesh2nff;
pub mod metrics;
pub mod part;
pub mod planegen;
pub mod render_args;
pub mod render_cli;
pub mod report;
pub mod spd_published;
pub mod sphereflake;
pub mod table1;
pub mod text;
