//! `table1`: reproduce Table 1 of the P3D report. See `table1 --help`.

use anyhow::Result;
use clap::Parser;
use nffkit_tools::cli_util;
use std::process::ExitCode;

/// Reproduce Table 1 of the P3D report: brute force, uniform grid and BVH timed on six SPD scenes.
///
/// The SPD's balls (sizes 1, 2, 4) and mount (sizes 1, 5, 7), generated
/// as `spd` writes them (no files needed), at 512x512, depth 6, 1 spp, with no acceleration, the uniform grid
/// and the BVH; prints a markdown table with speedups and Mrays/s.
#[derive(Parser, Debug)]
#[command(name = "table1", version)]
struct Args {
    /// Image size.
    #[arg(long, default_value_t = 512)]
    size: u32,
    /// Time cap per brute-force cell in seconds; beyond it the time is
    /// estimated from a subset of rows.
    #[arg(long, default_value_t = 30.0)]
    cap: f64,
    /// Time this many cells at once, each on one thread, to use every core
    /// (default 1: one cell at a time on all cores, the figures to quote).
    /// The images rendered do not depend on it.
    #[arg(long, short, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    jobs: u32,
    /// A quick table: 128x128 and a 1 s brute-force cap (what `aademo
    /// --figures` shows), overriding --size and --cap.
    #[arg(long)]
    quick: bool,
}

fn run(a: &Args) -> Result<()> {
    let (size, cap) = if a.quick { nffkit_tools::bench::table1::QUICK } else { (a.size, a.cap) };
    let t = nffkit_tools::bench::table1::table(size, cap, a.jobs as usize, &|what| {
        nffkit_tools::eprintln_safe!("timing {what}")
    })?;
    cli_util::print(&t)?;
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("table1", || run(&args).map(|_| ExitCode::SUCCESS))
}
