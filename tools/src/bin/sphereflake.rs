//! `sphereflake`: write the SPD "balls" database at any level.

use anyhow::Result;
use clap::Parser;
use nffkit_tools::cli_util;
use nffkit_tools::gen::sphereflake::Sphereflake;
use nffkit_tools::outputs::Outputs;
use std::path::PathBuf;
use std::process::ExitCode;

/// Write the SPD sphereflake ("balls") database at any level.
///
/// Write the SPD sphereflake ("balls") at a level, sphere for sphere as the
/// SPD's own program does (level N has 1 + 9 + ... + 9^N spheres). The
/// output streams, so level 7 (5.4 million spheres) needs no memory to speak
/// of.
#[derive(Parser, Debug)]
#[command(name = "sphereflake", version, allow_negative_numbers = true)]
struct Args {
    #[command(flatten)]
    flake: Sphereflake,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn run(a: &Args) -> Result<()> {
    a.flake.validate()?;
    if let Some(o) = &a.output {
        Outputs::new().file("-o", o)?;
    }
    cli_util::write_output(a.output.as_deref(), |w| a.flake.write(w).map(|_| ()))
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("sphereflake", || run(&args).map(|_| ExitCode::SUCCESS))
}
