//! `render`: render or validate NFF scenes. See `render --help`.

use clap::Parser;
use nffkit_tools::render_cli::{main_with, Args};
use std::process::ExitCode;

fn main() -> ExitCode {
    main_with(Args::parse())
}
