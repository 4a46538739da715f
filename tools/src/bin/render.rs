//! `render`: validate (`--check`) NFF scenes.

use anyhow::Result;
use clap::Parser;
use nffkit_formats::nff::ParseOptions;
use nffkit_tools::{check, input};
use std::path::PathBuf;
use std::process::ExitCode;

/// Validate NFF scene files.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Args {
    /// Scene files (`-` for standard input).
    files: Vec<PathBuf>,
    /// Parse and validate the files, print diagnostics and a summary per file.
    #[arg(long)]
    check: bool,
    /// The file is a fragment to append to another scene: no `v` block needed.
    #[arg(long)]
    fragment: bool,
    /// Unknown entities become warnings and are skipped.
    #[arg(long)]
    lenient: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("render: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<ExitCode> {
    let opts = ParseOptions { lenient: args.lenient, fragment: args.fragment };
    let mut failed = 0;
    for path in &args.files {
        let name = input::display_name(path);
        let report = match input::read_source(path) {
            Ok(src) => check::check_source(&name, &src, &opts),
            Err(e) => {
                eprintln!("error: {e:#}");
                failed += 1;
                continue;
            }
        };
        eprint!("{}", report.diagnostics);
        println!("{}", report.summary);
        failed += (report.errors > 0) as usize;
    }
    Ok(if failed == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE })
}
