//! `spd`: the Standard Procedural Databases as NFF. See `spd --help`.

use anyhow::Result;
use clap::Parser;
use nffkit_tools::cli_util;
use nffkit_tools::outputs::Outputs;
use nffkit_tools::spd::{Database, Generate};
use std::path::PathBuf;
use std::process::ExitCode;
use strum::VariantArray;

/// Generate the Standard Procedural Databases as NFF.
///
/// Eric Haines' Standard Procedural Databases (1987, CC0) are the scenes
/// ray tracers are compared on: each program writes one kind of scene at a
/// chosen size. This writes them as the SPD's C programs do, streamed
/// (any size in bounded memory), to standard output unless -o:
///
///     spd mount --size 7 | render - --spd-stats
///
/// With --precision spd every number is written as the C programs write
/// it (`%g`, six significant digits): the output is theirs byte for byte.
/// The default writes every digit.
///
/// Every database of the SPD's but sample and nurbtst (which test the
/// library's primitives, not a tracer), as the SPD's default curved output
/// (-c: spheres, cylinders and cones as themselves) or tessellated
/// (--tessellate, the SPD's -t).
#[derive(Parser, Debug)]
#[command(name = "spd", version)]
struct Args {
    #[command(flatten)]
    generate: Generate,
    /// Output file (default: standard output). Written atomically.
    #[arg(short, long, conflicts_with = "list")]
    output: Option<PathBuf>,
}

/// The databases, their default and largest sizes and their counts.
fn list(w: &mut dyn std::io::Write) -> std::io::Result<()> {
    writeln!(
        w,
        "{:<10} {:>7} {:>7}  primitives at size 1, 2, 3, ... (the default marked *)",
        "database", "default", "largest"
    )?;
    for &db in Database::VARIANTS {
        let counts: Vec<String> = (1..=db.max_size().min(db.default_size().max(6)))
            .map(|s| format!("{}{}", db.primitives(s), if s == db.default_size() { "*" } else { "" }))
            .collect();
        writeln!(
            w,
            "{:<10} {:>7} {:>7}  {}",
            db.name(),
            db.default_size(),
            db.max_size(),
            counts.join(", ")
        )?;
    }
    Ok(())
}

fn run(a: &Args) -> Result<()> {
    let g = &a.generate;
    if g.list {
        return cli_util::write_output(None, list);
    }
    let (db, size) = g.checked()?;
    if let Some(o) = &a.output {
        Outputs::new().file("-o", o)?;
    }
    cli_util::write_output(a.output.as_deref(), |w| {
        db.write(size, g.precision, g.resolution(), w).map(|_| ())
    })
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("spd", || run(&args).map(|_| ExitCode::SUCCESS))
}
