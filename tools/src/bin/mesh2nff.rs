//! `mesh2nff`: convert OBJ and glTF 2.0 meshes to NFF. See `mesh2nff --help`.

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};
use nffkit_formats::mesh::ImportOptions;
use nffkit_tools::cli_util;
use nffkit_tools::mesh2nff::{convert, Lights, Options, Up};
use nffkit_tools::outputs::Outputs;
use std::path::PathBuf;
use std::process::ExitCode;

/// Convert OBJ and glTF meshes into NFF scenes that render as they are.
///
/// Convert an OBJ (with MTL) or glTF 2.0 (.gltf, .glb) mesh into an NFF scene
/// that renders as it is: polygons or smooth patches, materials as `f`
/// lines, and (unless --no-view) a view, lights and background framing the
/// model. Coordinates stay the source's world coordinates unless --center,
/// --fit or --scale is given.
///
/// Looks: textures (glTF base colour, OBJ map_Kd) and vertex colours are
/// averaged per face into `f` colours; emitting faces (glTF emissive, OBJ Ke)
/// become up to 64 point lights just off their fronts and render in their
/// emission colour (clamped to 1). glTF materials map as
/// documented in the README (rough → diffuse, smooth metal → mirror).
///
/// View: the model's glTF camera (--camera N, or the only one), else a
/// framing view; when the model lights itself, the framing direction that
/// shows its lit side. Lights: see --lights.
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
    /// Image size of the view, W,H [default: 512,512, or 512 wide at a glTF
    /// camera's aspect ratio].
    #[arg(long, value_parser = cli_util::parse_resolution)]
    resolution: Option<[u32; 2]>,
    /// Lights added to the model's emission: `auto` frames the model with
    /// two lights unless its emitting faces give what the camera sees more
    /// than a tenth of its light (then, weighed by that, beside them), and
    /// adds one at the eye when the eye is inside the model's box or test
    /// renders find what it sees unlit;
    /// `eye` puts one light at the eye; `none` adds nothing.
    #[arg(long, value_enum, default_value_t = LightsArg::Auto)]
    lights: LightsArg,
    /// Use the model's N-th perspective camera (glTF, numbered from 0 in
    /// scene order) for the view.
    #[arg(long, value_name = "N")]
    camera: Option<usize>,
    /// Ignore textures: faces take their material's colour.
    #[arg(long)]
    no_textures: bool,
    /// Read buffers, images and material libraries that lie outside the
    /// model's folder (absolute paths, `..`); refused by default.
    #[arg(long)]
    allow_outside_paths: bool,
    /// The most triangles a model may expand to (instances included),
    /// checked before anything is read; any one accessor may hold three
    /// times as many elements.
    #[arg(long, value_name = "N", default_value_t = nffkit_formats::mesh::resource::MAX_TRIANGLES,
          value_parser = clap::value_parser!(u64).range(1..))]
    max_triangles: u64,
    /// The most memory the decoded textures may take in all, in MB; a
    /// texture past it keeps its material's factor, with a warning. Each
    /// image is decoded once, however many textures use it.
    #[arg(long, value_name = "MB", default_value_t = nffkit_formats::mesh::resource::MAX_TEXTURE_BYTES >> 20,
          value_parser = clap::value_parser!(u64).range(1..=1 << 24))]
    max_texture_mb: u64,
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
enum LightsArg {
    Auto,
    Eye,
    None,
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
        Outputs::new().inputs([a.model.as_path()]).file("-o", out)?;
    }
    let import = ImportOptions {
        textures: !a.no_textures,
        allow_outside_paths: a.allow_outside_paths,
        max_triangles: a.max_triangles,
        max_texture_bytes: a.max_texture_mb << 20,
    };
    let mesh = if a.model.as_os_str() == "-" {
        let bytes = nffkit_tools::input::read_stream(
            &mut std::io::stdin().lock(),
            "standard input",
            nffkit_tools::input::stream_cap(),
        )?;
        if bytes.starts_with(b"glTF") || bytes.trim_ascii_start().starts_with(b"{") || bytes.contains(&0) {
            anyhow::bail!(
                "standard input is read as OBJ text, and this is not (a GLB, glTF JSON or other binary); \
                 give a glTF or GLB file by name"
            );
        }
        nffkit_formats::mesh::load_obj_bytes(
            &bytes,
            std::path::Path::new("<stdin>"),
            std::path::Path::new("."),
            &import,
        )
    } else {
        cli_util::without_panics(&name, || nffkit_formats::mesh::load_with(&a.model, &import))?
    }
    .context("cannot convert")?;
    if !a.quiet {
        for w in &mesh.warnings {
            nffkit_tools::eprintln_safe!("mesh2nff: warning: {name}: {w}");
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
        lights: match a.lights {
            LightsArg::Auto => Lights::Auto,
            LightsArg::Eye => Lights::Eye,
            LightsArg::None => Lights::None,
        },
        camera: a.camera,
    };
    if let Some(i) = a.camera.filter(|&i| i >= mesh.cameras.len()) {
        anyhow::bail!(
            "--camera {i}: {name} has {} perspective camera{} (numbered from 0)",
            mesh.cameras.len(),
            if mesh.cameras.len() == 1 { "" } else { "s" }
        );
    }
    // Everything but writing first: a conversion error is not a write error.
    let converted = convert(&mesh, &opts).with_context(|| format!("cannot convert {name}"))?;
    cli_util::write_output(a.output.as_deref(), |w| converted.write_to(w))?;
    if !a.quiet {
        let s = &converted.summary;
        for note in &s.notes {
            nffkit_tools::eprintln_safe!("mesh2nff: {note}");
        }
        nffkit_tools::eprintln_safe!(
            "mesh2nff: {} polygons, {} patches, {} materials ({} faces triangulated, {} degenerate dropped)",
            s.polygons,
            s.patches,
            s.materials,
            s.triangulated,
            s.degenerate + mesh.dropped_degenerate
        );
        if s.repeated > 0 {
            nffkit_tools::eprintln_safe!(
                "mesh2nff: warning: {name}: {} triangle{} of faces whose outlines run over themselves \
                 repeated others of the same face and were left out",
                s.repeated,
                if s.repeated == 1 { "" } else { "s" }
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("mesh2nff", || run(&args).map(|_| ExitCode::SUCCESS))
}
