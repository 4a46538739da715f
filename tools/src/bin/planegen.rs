//! `planegen`: write a checkerboard plane as NFF (P3D report §4.3).

use anyhow::{bail, Context, Result};
use clap::Parser;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tools::gen::planegen::Board;
use nffkit_tools::outputs::Outputs;
use nffkit_tools::{cli_util, input};
use std::path::PathBuf;
use std::process::ExitCode;

/// Write a checkerboard plane as an NFF scene, or add one to a scene.
///
/// Write an XY-aligned checkerboard of `p 4` squares as an NFF scene (with a
/// view, a light and a background), or add it to an existing scene.
#[derive(Parser, Debug)]
#[command(name = "planegen", version, allow_negative_numbers = true)]
struct Args {
    #[command(flatten)]
    board: Board,
    /// Add the board to this scene (keeping its view and lights) instead of
    /// writing a new scene.
    #[arg(long, value_name = "SCENE.nff")]
    append_to: Option<PathBuf>,
    /// With --append-to: overwrite that file (atomically) instead of writing
    /// to -o or standard output.
    #[arg(long, requires = "append_to")]
    in_place: bool,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn run(a: &Args) -> Result<()> {
    let board = &a.board;
    board.validate()?;
    let out = match (&a.output, a.in_place, &a.append_to) {
        (Some(_), true, _) => bail!("--in-place and -o both name an output; give one"),
        (_, true, Some(p)) => Some(p.clone()),
        (o, _, _) => o.clone(),
    };
    if let Some(o) = &out {
        // --in-place means overwriting the scene read; nothing else may.
        let reads = a.append_to.as_deref().filter(|_| !a.in_place);
        Outputs::new().inputs(reads).file(if a.in_place { "--in-place" } else { "-o" }, o)?;
    }
    let scene = match &a.append_to {
        Some(path) => {
            let mut scene =
                input::load_scene(path, &ParseOptions::default(), None, input::Warnings::Summarise)
                    .with_context(|| format!("cannot append to {}", path.display()))?
                    .scene;
            board.add_to(&mut scene);
            scene
        }
        None => board.scene(),
    };
    cli_util::write_output(out.as_deref(), |w| nff::write(&scene, w).map(|_| ()))
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("planegen", || run(&args).map(|_| ExitCode::SUCCESS))
}
