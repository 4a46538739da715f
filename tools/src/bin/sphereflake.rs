//! `sphereflake`: write the SPD "balls" database at any level.

use anyhow::{bail, Result};
use clap::Parser;
use nffkit_tools::cli_util;
use nffkit_tools::gen::sphereflake::{sphere_count, Floor, Sphereflake};
use std::path::PathBuf;
use std::process::ExitCode;

/// Write the SPD sphereflake ("balls") database at any level.
///
/// Write the SPD sphereflake ("balls") at a level, sphere for sphere as the
/// SPD's own program does (level N has 1 + 9 + ... + 9^N spheres). The
/// output streams, so level 7 (5.4 million spheres) needs no memory to speak
/// of.
#[derive(Parser, Debug)]
#[command(name = "sphereflake", version)]
struct Args {
    /// Recursion level (the SPD's size factor; its balls_s1..s4 are 1..4).
    #[arg(long, default_value_t = 4)]
    level: u32,
    /// Image size in the view, W,H.
    #[arg(long, value_parser = cli_util::parse_resolution, default_value = "512,512")]
    resolution: [u32; 2],
    /// Leave out the floor.
    #[arg(long, conflicts_with = "checker")]
    no_floor: bool,
    /// Put a checkerboard of NX,NY squares under the flake instead of the
    /// single floor square.
    #[arg(long, value_parser = cli_util::parse_resolution, value_name = "NX,NY")]
    checker: Option<[u32; 2]>,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn run(a: &Args) -> Result<()> {
    if a.level > 9 {
        bail!("--level {} would write {} spheres; the limit is 9", a.level, sphere_count(a.level));
    }
    let floor = match (a.no_floor, a.checker) {
        (true, _) => Floor::None,
        (_, Some([nx, ny])) => Floor::Checker(nx, ny),
        _ => Floor::Square,
    };
    let flake = Sphereflake { level: a.level, resolution: a.resolution, floor };
    cli_util::write_output(a.output.as_deref(), |w| flake.write(w).map(|_| ()))
}

fn main() -> ExitCode {
    cli_util::exit(run(&Args::parse()), "sphereflake")
}
