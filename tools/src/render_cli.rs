//! The `render` command: argument parsing, loading, rendering, writing and
//! reporting. The work itself is done by `nffkit_tracer`.

use crate::{check, default_scene, input};
use anyhow::{bail, Context, Result};
use clap::{Parser, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use nffkit_formats::image_io::{self, ImageKind};
use nffkit_formats::nff::ParseOptions;
use nffkit_formats::Scene;
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::film::cost_heatmap;
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::integrator::LightShape;
use nffkit_tracer::prepare::{prepare, PrepareOptions, RenderScene};
use nffkit_tracer::render::{render, RenderOutput, RenderSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Render NFF scenes with a Whitted ray tracer, or validate them (--check).
///
/// With no FILE, renders the built-in default scene (a level-3 sphereflake
/// over a checkerboard). The camera's `angle` is the spec's: measured between
/// the centres of the outer pixel rows/columns of the smaller image side.
#[derive(Parser, Debug)]
#[command(version, about, long_about)]
pub struct Args {
    /// Scene file(s); `-` reads standard input. Rendering takes one file;
    /// --check takes any number.
    pub files: Vec<PathBuf>,

    /// Output image; the extension picks the format: .png (8-bit, default),
    /// .ppm, .exr or .hdr (linear floating point). Default: the scene's
    /// file name with .png, in the current directory.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Image width in pixels (overrides the file's; keeps the field of view).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the file's).
    #[arg(long)]
    pub height: Option<u32>,
    /// Recursion limit, counting the eye ray as depth 1.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub depth: u32,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
    /// Print ray and traversal statistics to standard output.
    #[arg(long)]
    pub stats: bool,
    /// SPD test procedure: one eye ray through each pixel corner ((w+1)x(h+1)
    /// rays, each pixel the mean of its four corners), depth 5, with
    /// statistics, so counts compare with those the SPD publishes.
    #[arg(long)]
    pub spd_stats: bool,
    /// Adaptive depth control: skip reflected and refracted rays whose
    /// weight (product of Ks and T along the path) is below this; 0 (the
    /// default) traces every ray, as classic NFF renderers do. POV-Ray's
    /// default is 1/255 = 0.0039.
    #[arg(long, default_value_t = 0.0)]
    pub min_weight: f32,
    /// Seed of every random pattern.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Apply the sRGB transfer curve when writing 8-bit images (off by
    /// default, so images match classic NFF renderers).
    #[arg(long)]
    pub srgb: bool,

    /// Validate the files: print every diagnostic and a summary per file.
    #[arg(long)]
    pub check: bool,
    /// Accept a file without a `v` block (a fragment to append to a scene).
    #[arg(long)]
    pub fragment: bool,
    /// Unknown entities become warnings and are skipped.
    #[arg(long)]
    pub lenient: bool,

    /// The spec's one-sided rule: opaque objects are invisible from behind.
    /// Default is two-sided shading; transmitters are always two-sided.
    #[arg(long)]
    pub one_sided: bool,

    /// Samples per pixel (anti-aliasing).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: u32,
    /// Sample pattern. With 1 sample per pixel and no --sampler, the pixel
    /// centre is used (classic NFF).
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerArg>,
    /// Reconstruction filter.
    #[arg(long, value_enum, default_value_t = FilterArg::Box)]
    pub filter: FilterArg,

    /// Give each point light an area of this size (soft shadows): one light
    /// sample per light per eye sample.
    #[arg(long, default_value_t = 0.0)]
    pub light_size: f32,
    /// Shape of the light area: side of a square or diameter of a disc.
    #[arg(long, value_enum, default_value_t = LightShapeArg::Square)]
    pub light_shape: LightShapeArg,

    /// Lens radius for depth of field (0: pinhole).
    #[arg(long, default_value_t = 0.0)]
    pub aperture: f32,
    /// Distance in focus (default: the from-at distance).
    #[arg(long)]
    pub focus: Option<f32>,

    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = AccelArg::Bvh)]
    pub accel: AccelArg,
    /// Uniform grid density multiplier M (cells per axis from the seed's
    /// formula (1)); 0 gives one cell.
    #[arg(long, default_value_t = 2.0)]
    pub grid_m: f32,
    /// Turn the grid's mailboxes off (to measure what they save).
    #[arg(long)]
    pub no_mailbox: bool,
    /// Also write a heat map of the traversal work per pixel (primitive
    /// tests plus nodes or cells visited) to this PNG, with a colour bar.
    #[arg(long, value_name = "FILE")]
    pub aov_cost: Option<PathBuf>,
}

/// Sampler names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
#[allow(missing_docs)]
pub enum SamplerArg {
    Random,
    Regular,
    Jittered,
    NRooks,
    MultiJittered,
    Cmj,
    Hammersley,
    Sobol,
}

impl SamplerArg {
    fn kind(self) -> SamplerKind {
        match self {
            SamplerArg::Random => SamplerKind::Random,
            SamplerArg::Regular => SamplerKind::Regular,
            SamplerArg::Jittered => SamplerKind::Jittered,
            SamplerArg::NRooks => SamplerKind::NRooks,
            SamplerArg::MultiJittered => SamplerKind::MultiJittered,
            SamplerArg::Cmj => SamplerKind::CorrelatedMultiJittered,
            SamplerArg::Hammersley => SamplerKind::Hammersley,
            SamplerArg::Sobol => SamplerKind::Sobol,
        }
    }
}

/// Filter names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
#[allow(missing_docs)]
pub enum FilterArg {
    Box,
    Tent,
    Gaussian,
    Mitchell,
}

/// Light shapes on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
#[allow(missing_docs)]
pub enum LightShapeArg {
    Square,
    Disk,
}

/// Accelerators on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
#[allow(missing_docs)]
pub enum AccelArg {
    None,
    Grid,
    Bvh,
}

/// Run the command; the exit code reflects errors.
pub fn run(args: &Args) -> Result<ExitCode> {
    let parse_opts = ParseOptions { lenient: args.lenient, fragment: args.fragment };
    if args.check {
        if args.files.is_empty() {
            bail!("--check needs at least one file");
        }
        return Ok(check_files(&args.files, &parse_opts));
    }
    if args.files.len() > 1 {
        bail!("render takes one scene file (got {}); --check takes many", args.files.len());
    }
    let threads = args.threads.unwrap_or(0);
    let pool =
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().context("starting worker threads")?;
    pool.install(|| render_command(args, &parse_opts))?;
    Ok(ExitCode::SUCCESS)
}

fn check_files(files: &[PathBuf], opts: &ParseOptions) -> ExitCode {
    let mut failed = 0;
    for path in files {
        let name = input::display_name(path);
        match input::read_source(path) {
            Ok(src) => {
                let report = check::check_source(&name, &src, opts);
                eprint!("{}", report.diagnostics);
                println!("{}", report.summary);
                failed += (report.errors > 0) as usize;
            }
            Err(e) => {
                eprintln!("error: {e:#}");
                failed += 1;
            }
        }
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn output_path(args: &Args) -> PathBuf {
    if let Some(o) = &args.output {
        return o.clone();
    }
    match args.files.first() {
        Some(f) if f.as_os_str() != "-" => {
            PathBuf::from(f.file_stem().unwrap_or_default()).with_extension("png")
        }
        Some(_) => PathBuf::from("render.png"),
        None => PathBuf::from("nffkit-default.png"),
    }
}

/// Build the render settings from the arguments, telling the user about
/// any adjustment (a sample count rounded up for a grid pattern).
pub fn settings(args: &Args) -> Result<RenderSettings> {
    if !(args.light_size >= 0.0 && args.light_size.is_finite()) {
        bail!("--light-size must be a non-negative number (got {})", args.light_size);
    }
    if !(0.0..1.0).contains(&args.min_weight) {
        bail!("--min-weight must be in [0, 1) (got {})", args.min_weight);
    }
    if !(args.aperture >= 0.0 && args.aperture.is_finite()) {
        bail!("--aperture must be a non-negative number (got {})", args.aperture);
    }
    if args.focus.is_some_and(|f| !(f > 0.0 && f.is_finite())) {
        bail!("--focus must be a positive distance");
    }
    let kind = args.sampler.map(SamplerArg::kind).unwrap_or(SamplerKind::MultiJittered);
    let (sampler, message) = Sampler::new(kind, args.spp, args.seed);
    if let Some(m) = message {
        if !args.quiet {
            eprintln!("note: {m}");
        }
    }
    Ok(RenderSettings {
        sampler,
        centre_single_sample: args.sampler.is_none(),
        filter: match args.filter {
            FilterArg::Box => FilterKind::Box,
            FilterArg::Tent => FilterKind::Tent,
            FilterArg::Gaussian => FilterKind::Gaussian,
            FilterArg::Mitchell => FilterKind::Mitchell,
        },
        max_depth: if args.spd_stats { 5 } else { args.depth },
        light_size: args.light_size,
        min_weight: if args.spd_stats { 0.0 } else { args.min_weight },
        light_shape: match args.light_shape {
            LightShapeArg::Square => LightShape::Square,
            LightShapeArg::Disk => LightShape::Disk,
        },
        spd_corners: args.spd_stats,
        cost: args.aov_cost.is_some(),
        row_stride: 1,
    })
}

/// Preparation options from the arguments.
pub fn prepare_options(args: &Args) -> PrepareOptions {
    PrepareOptions {
        width: args.width,
        height: args.height,
        one_sided: args.one_sided,
        aperture: args.aperture,
        focus: args.focus,
        accel: AccelOptions {
            kind: match args.accel {
                AccelArg::None => AccelKind::None,
                AccelArg::Grid => AccelKind::Grid,
                AccelArg::Bvh => AccelKind::Bvh,
            },
            grid_m: args.grid_m,
            mailbox: !args.no_mailbox,
        },
    }
}

fn render_command(args: &Args, parse_opts: &ParseOptions) -> Result<()> {
    let t_start = Instant::now();
    let out_path = output_path(args);
    if ImageKind::from_path(&out_path).is_none() {
        bail!("{}: unknown image extension (use .png, .ppm, .exr or .hdr)", out_path.display());
    }
    if !(args.grid_m >= 0.0 && args.grid_m.is_finite()) {
        bail!("--grid-m must be a non-negative number (got {})", args.grid_m);
    }
    let settings = settings(args)?;
    let (scene, name) = match args.files.first() {
        Some(path) => (input::load_scene(path, parse_opts, args.quiet)?.scene, input::display_name(path)),
        None => (default_scene::default_scene(), "built-in default scene".to_string()),
    };
    let t_parse = t_start.elapsed().as_secs_f64();
    let prepared = prepare(&scene, &prepare_options(args)).with_context(|| name.clone())?;
    let (w, h) = prepared.camera.resolution();
    let bar = progress_bar(args, w, h);
    let tick = |done: usize, total: usize| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    };
    let out = render(&prepared, &settings, &tick);
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    image_io::save(&out.film.to_image(), &out_path, args.srgb)
        .with_context(|| format!("writing {}", out_path.display()))?;
    if let (Some(path), Some(cost)) = (&args.aov_cost, &out.cost) {
        let (img, max) = cost_heatmap(cost, w, h);
        image_io::save(&img, path, false).with_context(|| format!("writing {}", path.display()))?;
        if !args.quiet {
            eprintln!("cost image: {} (black = 0, white = {max} tests and visits per pixel)", path.display());
        }
    }
    if args.stats || args.spd_stats {
        print!(
            "{}",
            report(&name, &scene, &prepared, &settings, &out, t_parse, t_start.elapsed().as_secs_f64())
        );
    }
    if !args.quiet {
        eprintln!("wrote {} ({w}x{h}) in {:.3} s", out_path.display(), t_start.elapsed().as_secs_f64());
    }
    Ok(())
}

fn progress_bar(args: &Args, w: u32, h: u32) -> Option<ProgressBar> {
    if args.quiet || !std::io::stderr().is_terminal() || (w as u64 * h as u64) < 64 * 64 {
        return None;
    }
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}% tiles, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    Some(bar)
}

fn per(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// The statistics block printed by --stats.
pub fn report(
    name: &str,
    scene: &Scene,
    prepared: &RenderScene,
    settings: &RenderSettings,
    out: &RenderOutput,
    parse_seconds: f64,
    total_seconds: f64,
) -> String {
    let g = &prepared.geometry;
    let c = &out.counters;
    let info = prepared.accel.info();
    let (w, h) = prepared.camera.resolution();
    let rays = c.rays();
    let mode = if settings.spd_corners {
        "SPD test procedure (pixel corners, depth 5)".to_string()
    } else {
        format!("{} spp {}, filter {}", settings.sampler.spp, settings.sampler.kind, settings.filter)
    };
    let mut s = String::new();
    s += &format!(
        "scene        {name}: {} primitives in the file -> {} spheres, {} triangles, {} cones\n",
        scene.primitives.len(),
        g.spheres.len(),
        g.triangles.len(),
        g.cones.len()
    );
    s += &format!("image        {w}x{h}, {mode}, depth {}\n", settings.max_depth);
    s += &format!(
        "accelerator  {}: {} {}, {:.2} MB, built in {:.1} ms\n",
        info.summary,
        info.nodes,
        if info.summary.starts_with("uniform") { "cells" } else { "nodes" },
        info.bytes as f64 / 1e6,
        info.build_seconds * 1e3
    );
    s += &format!(
        "rays         {rays} total: eye {}, reflected {}, refracted {}, shadow {}\n",
        c.eye, c.reflected, c.refracted, c.shadow
    );
    s += &format!(
        "tests        {} total ({:.2} per ray): spheres {}, triangles {}, cones {}\n",
        c.total_tests(),
        per(c.total_tests(), rays),
        c.tests[0],
        c.tests[1],
        c.tests[2]
    );
    s += &format!(
        "traversal    {} nodes/cells visited ({:.2} per ray), {} mailbox hits\n",
        c.visits,
        per(c.visits, rays),
        c.mailbox_hits
    );
    s += &format!(
        "time         parse {:.3} s, render {:.3} s ({:.2} Mrays/s), total {:.3} s\n",
        parse_seconds,
        out.seconds,
        rays as f64 / out.seconds.max(1e-9) / 1e6,
        total_seconds
    );
    s
}

/// Entry point shared by the binary.
pub fn main_with(args: Args) -> ExitCode {
    match run(&args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("render: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
