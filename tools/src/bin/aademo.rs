//! `aademo`: the anti-aliasing demonstration. See `aademo --help`.

use anyhow::{Context, Result};
use clap::Parser;
use nffkit_formats::{atomic, image_io};
use nffkit_tools::aademo::{contact_sheet, convergence_svg, run, table, DemoConfig};
use nffkit_tools::cli_util;
use std::path::PathBuf;
use std::process::ExitCode;

/// Anti-aliasing demonstration: every sampler at several sample counts, compared with a reference.
///
/// Render the checkerboard plane with every sampler at several sample
/// counts; write a labelled contact sheet (contact-sheet.png), the error
/// table against a high-sample reference (errors.md, also printed) and a
/// log-log convergence plot (convergence.svg) into the output folder.
#[derive(Parser, Debug)]
#[command(name = "aademo", version)]
struct Args {
    /// Output folder (created if missing).
    #[arg(short, long, default_value = "aademo")]
    out: PathBuf,
    /// Tile size in pixels.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(16..=1024))]
    size: u32,
    /// Sample counts, comma-separated.
    #[arg(long, default_value = "1,4,16,64", value_delimiter = ',')]
    spp: Vec<u32>,
    /// Samples per pixel of the reference.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=65536))]
    reference_spp: u32,
    /// Seed of the random patterns.
    #[arg(long, default_value_t = 1)]
    seed: u32,
}

fn main_inner(a: &Args) -> Result<()> {
    if a.spp.is_empty() || a.spp.iter().any(|&s| s == 0 || s > 65536) {
        anyhow::bail!("--spp takes counts from 1 to 65536");
    }
    let cfg = DemoConfig {
        size: a.size,
        spps: a.spp.clone(),
        reference_spp: a.reference_spp,
        seed: a.seed,
        ..Default::default()
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
    let result = run(&cfg, &|what| eprintln!("rendering {what}"))?;
    let sheet = a.out.join("contact-sheet.png");
    image_io::save(&contact_sheet(&result, &cfg), &sheet, false)?;
    let t = table(&result, &cfg);
    atomic::write_bytes(&a.out.join("errors.md"), t.as_bytes())?;
    atomic::write_bytes(&a.out.join("convergence.svg"), convergence_svg(&result, &cfg).as_bytes())?;
    print!("{t}");
    eprintln!("wrote {}, errors.md and convergence.svg", sheet.display());
    Ok(())
}

fn main() -> ExitCode {
    cli_util::exit(main_inner(&Args::parse()), "aademo")
}
