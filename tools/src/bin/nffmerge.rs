//! `nffmerge`: join the parts of a farmed render. See `nffmerge --help`.

use anyhow::{Context, Result};
use clap::Parser;
use nffkit_formats::image_io::{self, ImageKind};
use nffkit_tools::cli_util;
use nffkit_tools::outputs::Outputs;
use nffkit_tools::render::{part, report};
use std::path::PathBuf;
use std::process::ExitCode;

/// Merge the EXR parts of a render into the full image.
///
/// Each part comes from `render --crop`, `--pixel-bounds` or `--tile K/N`
/// written to .exr. The parts must come from the same scene (by the digest of
/// the parsed scene) and the same settings, and cover the image exactly once;
/// otherwise nffmerge names the part, pixel or setting at fault and writes
/// nothing. The result is byte-identical to a single full render written to
/// the same format.
#[derive(Parser, Debug)]
#[command(name = "nffmerge", version)]
struct Args {
    /// The parts (.exr), in any order.
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The merged image; the extension picks the format (.png, .ppm, .exr,
    /// .hdr), as for `render -o`.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Apply the sRGB curve to 8-bit output (as `render --srgb`).
    #[arg(long)]
    srgb: bool,
    /// Print the parts' ray counters, summed.
    #[arg(long)]
    stats: bool,
    /// Print nothing but errors.
    #[arg(short, long)]
    quiet: bool,
}

fn run(a: &Args) -> Result<()> {
    let kind = ImageKind::from_path(&a.output)?;
    Outputs::new().inputs(a.parts.iter().map(|p| p.as_path())).file("-o", &a.output)?;
    let parts = a.parts.iter().map(|p| part::read_part(p)).collect::<Result<Vec<_>>>()?;
    let merged = part::merge(&parts)?;
    let bytes = image_io::encode(&merged.image, kind, a.srgb)?;
    nffkit_formats::atomic::write_bytes(&a.output, &bytes)?;
    if a.stats {
        cli_util::print(report::counters(&merged.counters))?;
    }
    if !a.quiet {
        let (w, h) = (merged.image.width, merged.image.height);
        nffkit_tools::eprintln_safe!("merged {} parts into {} ({w}x{h})", parts.len(), a.output.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("nffmerge", || run(&args).context("nothing written").map(|_| ExitCode::SUCCESS))
}
