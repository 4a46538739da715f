//! `render`: render or validate NFF scenes. See `render --help`.

use clap::Parser;
use nffkit_tools::render::args::RenderArgs;
use nffkit_tools::render::cli::main_with;
use std::process::ExitCode;

fn main() -> ExitCode {
    main_with(RenderArgs::parse())
}
