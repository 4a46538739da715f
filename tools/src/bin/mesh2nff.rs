//! `mesh2nff`: convert OBJ and glTF 2.0 meshes to NFF. See `mesh2nff --help`.

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};
use nffkit_tools::cli_util;
use nffkit_tools::mesh2nff::{write, Options, Up};
use std::path::PathBuf;
use std::process::ExitCode;

/// Convert OBJ and glTF meshes into NFF scenes that render as they are.
///
/// Convert an OBJ (with MTL) or glTF 2.0 (.gltf, .glb) mesh into an NFF scene
/// that renders as it is: polygons or smooth patches, materials as `f`
/// lines, and (unless --no-view) a view, lights and background framing the
/// model. Coordinates stay the source's world coordinates unless --center,
/// --fit or --scale is given.
#[derive(Parser, Debug)]
#[command(name = "mesh2nff", version)]
struct Args {
    /// The model (.obj, .gltf, .glb); `-` reads OBJ from standard input
    /// (material libraries are then looked for in the current folder).
    model: PathBuf,
    /// Output file (default: standard output). Written atomically.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Geometry and materials only, for appending to another scene.
    #[arg(long)]
    no_view: bool,
    /// Image size of the view, W,H.
    #[arg(long, value_parser = cli_util::parse_resolution, default_value = "512,512")]
    resolution: [u32; 2],
    /// The source's up axis (only the view uses it).
    #[arg(long, value_enum, default_value_t = UpArg::Y)]
    up: UpArg,
    /// Scale positions by this factor.
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Move the bounding box centre to the origin.
    #[arg(long)]
    center: bool,
    /// Scale (about the box centre, which moves to the origin) so the box's
    /// largest side is 1.
    #[arg(long)]
    fit: bool,
    /// Write flat `p` polygons, dropping normals.
    #[arg(long, conflicts_with = "smooth")]
    flat: bool,
    /// Compute area-weighted vertex normals for faces without normals.
    #[arg(long)]
    smooth: bool,
    /// Print nothing but errors.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum UpArg {
    Y,
    Z,
}

fn run(a: &Args) -> Result<()> {
    if !(a.scale.is_finite() && a.scale != 0.0) {
        anyhow::bail!("--scale must be a finite, non-zero number");
    }
    let name = if a.model.as_os_str() == "-" { "<stdin>".into() } else { a.model.display().to_string() };
    if let Some(out) = &a.output {
        let existing = std::fs::canonicalize(out).ok();
        if a.model.as_os_str() != "-"
            && existing.is_some()
            && existing == std::fs::canonicalize(&a.model).ok()
        {
            anyhow::bail!("-o {} is the input model; refusing to overwrite it", out.display());
        }
    }
    let mesh = if a.model.as_os_str() == "-" {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut bytes).context("reading standard input")?;
        nffkit_formats::mesh::load_obj_bytes(
            &bytes,
            std::path::Path::new("<stdin>"),
            std::path::Path::new("."),
        )
    } else {
        nffkit_formats::mesh::load(&a.model)
    }
    .context("cannot convert")?;
    if !a.quiet {
        for w in &mesh.warnings {
            eprintln!("mesh2nff: warning: {name}: {w}");
        }
    }
    let opts = Options {
        view: !a.no_view,
        resolution: a.resolution,
        up: if matches!(a.up, UpArg::Z) { Up::Z } else { Up::Y },
        scale: a.scale,
        center: a.center,
        fit: a.fit,
        flat: a.flat,
        smooth: a.smooth,
    };
    nffkit_tools::mesh2nff::check(&mesh).with_context(|| format!("cannot convert {name}"))?;
    let mut summary = None;
    cli_util::write_output(a.output.as_deref(), |w| {
        let (_, s) = write(&mesh, &opts, w).map_err(std::io::Error::other)?;
        summary = Some(s);
        Ok(())
    })?;
    if let (false, Some(s)) = (a.quiet, summary) {
        eprintln!(
            "mesh2nff: {} polygons, {} patches ({} faces triangulated, {} degenerate dropped)",
            s.polygons, s.patches, s.triangulated, s.degenerate
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    cli_util::exit(run(&Args::parse()), "mesh2nff")
}
