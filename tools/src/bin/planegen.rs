//! `planegen`: write a checkerboard plane as NFF (P3D report §4.3).

use anyhow::{bail, Context, Result};
use clap::Parser;
use glam::{DVec2, DVec3};
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tools::gen::planegen::Board;
use nffkit_tools::{cli_util, input};
use std::path::PathBuf;
use std::process::ExitCode;

/// Write a checkerboard plane as an NFF scene, or add one to a scene.
///
/// Write an XY-aligned checkerboard of `p 4` squares as an NFF scene (with a
/// view, a light and a background), or add it to an existing scene.
#[derive(Parser, Debug)]
#[command(name = "planegen", version)]
struct Args {
    /// Squares along x.
    #[arg(long, default_value_t = 16)]
    nx: u32,
    /// Squares along y.
    #[arg(long, default_value_t = 16)]
    ny: u32,
    /// Total size of the board along x.
    #[arg(long, default_value_t = 8.0)]
    sx: f64,
    /// Total size of the board along y.
    #[arg(long, default_value_t = 8.0)]
    sy: f64,
    /// First colour, R,G,B in [0,1] (the square at the -x,-y corner).
    #[arg(long, value_parser = cli_util::parse_triple, default_value = "0.95,0.95,0.95")]
    c1: DVec3,
    /// Second colour, R,G,B in [0,1].
    #[arg(long, value_parser = cli_util::parse_triple, default_value = "0.1,0.1,0.12")]
    c2: DVec3,
    /// Height of the plane (z).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    z: f64,
    /// Centre of the board, X,Y.
    #[arg(long, value_parser = cli_util::parse_pair, default_value = "0,0", allow_negative_numbers = true)]
    center: DVec2,
    /// Diffuse weight of the squares.
    #[arg(long, default_value_t = 1.0)]
    kd: f64,
    /// Specular weight of the squares.
    #[arg(long, default_value_t = 0.0)]
    ks: f64,
    /// Phong exponent of the squares.
    #[arg(long, default_value_t = 1.0)]
    shine: f64,
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
    let board = Board {
        nx: a.nx,
        ny: a.ny,
        sx: a.sx,
        sy: a.sy,
        c1: a.c1,
        c2: a.c2,
        z: a.z,
        center: a.center,
        kd: a.kd,
        ks: a.ks,
        shine: a.shine,
    };
    board.validate()?;
    let scene = match &a.append_to {
        Some(path) => {
            let mut scene = input::load_scene(path, &ParseOptions::default(), false)
                .with_context(|| format!("cannot append to {}", path.display()))?
                .scene;
            board.add_to(&mut scene);
            scene
        }
        None => board.scene(),
    };
    let out = match (&a.output, a.in_place, &a.append_to) {
        (Some(_), true, _) => bail!("--in-place and -o both name an output; give one"),
        (_, true, Some(p)) => Some(p.clone()),
        (o, _, _) => o.clone(),
    };
    cli_util::write_output(out.as_deref(), |w| nff::write(&scene, w).map(|_| ()))
}

fn main() -> ExitCode {
    cli_util::exit(run(&Args::parse()), "planegen")
}
