//! `nffconvert`: a scene from one language into another. See
//! `nffconvert --help`.

use anyhow::{bail, Context, Result};
use clap::Parser;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{dialect, Dialect};
use nffkit_tools::outputs::Outputs;
use nffkit_tools::{cli_util, eprintln_safe, input};
use std::path::PathBuf;
use std::process::ExitCode;

/// Convert a scene between NFF and P3F (the P3D course's language).
///
/// The output's extension picks the language (.nff, .p3f), or --to does
/// (needed when writing to standard output). Going to NFF writes the
/// closest NFF and says, one note a line, what NFF cannot hold: specular
/// colours (each Ks scaled by its colour's mean), the cube map, area lights
/// (points at their centres), Fresnel-weighted glass, the lens and the
/// directives, with the `render` flags that give each back where there are
/// some. Going to P3F converts the view angle to the course's convention
/// and gives uncoloured lights NFF's 1/sqrt(n). Nothing is written on an
/// error; the input is never overwritten.
#[derive(Parser, Debug)]
#[command(name = "nffconvert", version)]
struct Args {
    /// The scene to convert; `-` reads standard input.
    input: PathBuf,
    /// Where to write it; its extension picks the language. Default:
    /// standard output (then --to is needed).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// The output language: nff or p3f (default: the output's extension).
    #[arg(long, value_name = "nff|p3f", value_parser = language)]
    to: Option<Dialect>,
    /// The input language: nff or p3f (default: the input's extension, else
    /// its content).
    #[arg(long, value_name = "nff|p3f", value_parser = language)]
    dialect: Option<Dialect>,
    /// Print nothing but errors (not what the output cannot hold).
    #[arg(short, long)]
    quiet: bool,
}

fn language(s: &str) -> Result<Dialect, String> {
    s.to_ascii_lowercase().parse().map_err(|_| format!("`{s}` is no scene language; expected nff or p3f"))
}

fn run(a: &Args) -> Result<()> {
    let to = match (a.to, &a.output) {
        (Some(to), _) => to,
        (None, Some(out)) => match dialect::from_extension(out) {
            Some(d) => d,
            None => bail!("{}: the extension says no language (.nff or .p3f); --to names one", out.display()),
        },
        (None, None) => bail!("writing to standard output needs --to nff or --to p3f"),
    };
    if let Some(out) = &a.output {
        Outputs::new().inputs([a.input.as_path()]).file("-o", out)?;
    }
    let warnings = if a.quiet { input::Warnings::Hide } else { input::Warnings::Summarise };
    let scene = input::load_scene(&a.input, &ParseOptions::default(), a.dialect, warnings)?.scene;
    let (converted, lost) = match to {
        Dialect::Nff => dialect::to_nff(&scene),
        Dialect::P3f => dialect::to_p3f(&scene),
    };
    cli_util::write_output(a.output.as_deref(), |w| nff::write(&converted, w).map(|_| ()))?;
    if !a.quiet {
        let from = scene.dialect.to_string().to_uppercase();
        let to = to.to_string().to_uppercase();
        for l in &lost {
            eprintln_safe!("note: {to} cannot hold {l}");
        }
        if let Some(out) = &a.output {
            eprintln_safe!(
                "wrote {} ({from} to {to}, {} primitives)",
                out.display(),
                converted.primitives.len()
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("nffconvert", || run(&args).context("nothing written").map(|_| ExitCode::SUCCESS))
}
