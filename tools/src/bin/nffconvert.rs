//! `nffconvert`: a scene into another language. See `nffconvert --help`.

use anyhow::{bail, Context, Result};
use clap::Parser;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{dialect, Dialect, Scene};
use nffkit_tools::convert::{gltf, mitsuba, obj, pov, ExportOptions, Format};
use nffkit_tools::outputs::Outputs;
use nffkit_tools::{cli_util, eprintln_safe, input};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Convert an NFF or P3F scene for another renderer or viewer.
///
/// The output's extension picks the language, or --to does (needed for
/// standard output): .nff and .p3f (each other's closest scene), .pov
/// (POV-Ray 3.7, rendering as `render` does: the same camera, lights,
/// Phong finishes, depth; --area-light and --aperture for soft shadows and
/// depth of field), .obj (Wavefront OBJ, with its .mtl beside it), .gltf
/// (glTF 2.0, with its .bin beside it), .glb (one binary glTF) and .xml
/// (Mitsuba 3, with a PLY file per material beside it). OBJ and glTF hold
/// triangles only: spheres and cones are tessellated (--tessellate), as
/// Mitsuba's cones are. One note a line says what the output cannot hold. Files
/// are written whole or not at all; the input is never overwritten.
#[derive(Parser, Debug)]
#[command(name = "nffconvert", version)]
struct Args {
    /// The scene to convert; `-` reads standard input.
    input: PathBuf,
    /// Where to write it; its extension picks the language. Default:
    /// standard output (then --to is needed; not for obj and gltf, which
    /// write a second file beside the first).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// The output language (default: the output's extension).
    #[arg(long, value_enum)]
    to: Option<Format>,
    /// The input language: nff or p3f (default: the input's extension, else
    /// its content).
    #[arg(long, value_name = "nff|p3f", value_parser = cli_util::parse_dialect)]
    dialect: Option<Dialect>,
    /// POV-Ray: recursion limit (max_trace_level), counting the eye ray as
    /// 1, as `render --depth`.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(1..=64))]
    depth: u32,
    /// POV-Ray: give each point light a square area of this side, 4x4
    /// jittered and facing each shaded point, as `render --light-size`.
    #[arg(long, value_name = "SIZE", value_parser = positive)]
    area_light: Option<f64>,
    /// POV-Ray: lens radius for depth of field (`focal_blur`, 16 samples),
    /// as `render --aperture`.
    #[arg(long, value_parser = positive)]
    aperture: Option<f64>,
    /// POV-Ray: distance in focus, as `render --focus` (default: the
    /// from-at distance).
    #[arg(long, value_parser = positive)]
    focus: Option<f64>,
    /// POV-Ray: skip rays whose weight falls below this (`adc_bailout`),
    /// as `render --min-weight`; 0 traces every ray.
    #[arg(long, default_value_t = 0.0, value_parser = weight)]
    min_weight: f64,
    /// OBJ and glTF: spheres as six faces of N x N quadrilaterals, cones as
    /// 4N sides.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    tessellate: u32,
    /// Print nothing but errors (not what the output cannot hold).
    #[arg(short, long)]
    quiet: bool,
}

fn weight(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (0.0..1.0).contains(&v) => Ok(v),
        _ => Err(format!("expected a number in [0, 1), found `{s}`")),
    }
}

fn positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("expected a number greater than 0, found `{s}`")),
    }
}

/// The file beside `path` with extension `ext`.
fn beside(path: &Path, ext: &str) -> PathBuf {
    path.with_extension(ext)
}

/// The file name of `path`, for references from one output to another.
fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

fn run(a: &Args) -> Result<()> {
    let format = match (a.to, &a.output) {
        (Some(f), _) => f,
        (None, Some(out)) => match Format::from_path(out) {
            Some(f) => f,
            None => bail!(
                "{}: the extension names no language (.nff .p3f .pov .obj .gltf .glb .xml); --to names one",
                out.display()
            ),
        },
        (None, None) => bail!("writing to standard output needs --to (nff, p3f, pov, glb)"),
    };
    // OBJ and glTF write one file beside their own, Mitsuba one per
    // material (checked once the materials are known).
    let sidecar = match format {
        Format::Obj => Some("mtl"),
        Format::Gltf => Some("bin"),
        _ => None,
    };
    match &a.output {
        Some(out) => {
            let outputs = Outputs::new().inputs([a.input.as_path()]).file("-o", out)?;
            if let Some(ext) = sidecar {
                outputs.file("-o", &beside(out, ext))?;
            }
        }
        None if sidecar.is_some() || format == Format::Mitsuba => {
            bail!("--to {format:?} writes files beside its own: give -o FILE")
        }
        None => {}
    }
    let warnings = if a.quiet { input::Warnings::Hide } else { input::Warnings::Summarise };
    let scene = input::load_scene(&a.input, &ParseOptions::default(), a.dialect, warnings)?.scene;
    let opts = ExportOptions {
        depth: a.depth,
        area_light: a.area_light,
        aperture: a.aperture,
        focus: a.focus,
        tessellate: a.tessellate,
        min_weight: a.min_weight,
    };
    let lost = write(&scene, format, &a.input, a.output.as_deref(), &opts)?;
    if !a.quiet {
        let to = format!("{format:?}").to_uppercase();
        for l in &lost {
            eprintln_safe!("note: {to} does not hold {l}");
        }
        if let Some(out) = &a.output {
            eprintln_safe!("wrote {} ({} primitives)", out.display(), scene.primitives.len());
        }
    }
    Ok(())
}

/// Write `scene` (read from `input`) as `format` to `out` (standard output
/// when `None`), and say what was lost.
fn write(
    scene: &Scene,
    format: Format,
    input: &Path,
    out: Option<&Path>,
    opts: &ExportOptions,
) -> Result<Vec<String>> {
    let stdout_or = |bytes: &[u8]| cli_util::write_output(out, |w| w.write_all(bytes));
    match format {
        Format::Nff | Format::P3f => {
            let (converted, lost) =
                if format == Format::P3f { dialect::to_p3f(scene) } else { dialect::to_nff(scene) };
            cli_util::write_output(out, |w| nff::write(&converted, w).map(|_| ()))?;
            Ok(lost)
        }
        Format::Pov => {
            let mut text = Vec::new();
            let lost = pov::write(scene, opts, &mut text)?;
            stdout_or(&text)?;
            Ok(lost)
        }
        Format::Obj => {
            let out = out.context("OBJ needs -o")?;
            let mtl = beside(out, "mtl");
            let (obj_text, mtl_text, lost) = obj::write(scene, opts, &file_name(&mtl));
            nffkit_formats::atomic::write_bytes(&mtl, mtl_text.as_bytes())?;
            nffkit_formats::atomic::write_bytes(out, obj_text.as_bytes())?;
            Ok(lost)
        }
        Format::Gltf => {
            let out = out.context("glTF needs -o")?;
            let bin = beside(out, "bin");
            let doc = gltf::build(scene, opts, Some(&file_name(&bin)));
            nffkit_formats::atomic::write_bytes(&bin, &doc.bin)?;
            let text = serde_json::to_vec_pretty(&doc.json).context("writing the glTF JSON")?;
            nffkit_formats::atomic::write_bytes(out, &text)?;
            Ok(doc.lost)
        }
        Format::Mitsuba => {
            let out = out.context("Mitsuba needs -o")?;
            let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            let mitsuba::MitsubaScene { xml, plys, lost } =
                mitsuba::write(scene, opts, |m| format!("{stem}-m{m}.ply"));
            let dir = out.parent().unwrap_or(Path::new(""));
            let mut check = Outputs::new().inputs([input]).file("-o", out)?;
            for (name, _) in &plys {
                check = check.file("-o", &dir.join(name))?;
            }
            drop(check);
            for (name, bytes) in &plys {
                nffkit_formats::atomic::write_bytes(&dir.join(name), bytes)?;
            }
            nffkit_formats::atomic::write_bytes(out, xml.as_bytes())?;
            Ok(lost)
        }
        Format::Glb => {
            let doc = gltf::build(scene, opts, None);
            stdout_or(&doc.glb())?;
            Ok(doc.lost)
        }
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("nffconvert", || run(&args).context("nothing written").map(|_| ExitCode::SUCCESS))
}
