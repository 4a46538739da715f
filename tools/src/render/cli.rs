//! The `render` command: runs a validated [`Command`] (see
//! [`crate::render::args`]): loading, the thread pool, the progress bar,
//! writing the image and printing statistics. The work itself is done by
//! `nffkit_tracer`; validation is done before anything here runs.

use super::scene_warnings::{file_warnings, prepared_warnings};
use super::{check, environment, part, report, spd_published};
use crate::gen::default_scene;
use crate::outputs::Outputs;
use crate::render::args::{Command, Device, RenderArgs, RenderConfig};
use crate::{cli_util, eprint_safe, eprintln_safe, input, memory};
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use nffkit_formats::image_io::{self, ImageKind};
use nffkit_formats::nff::ParseOptions;
use nffkit_formats::Dialect;
use nffkit_tracer::film::cost_heatmap;
use nffkit_tracer::gpu::{Gpu, GpuScene};
use nffkit_tracer::prepare::prepare_freeing;
use nffkit_tracer::render::{render, PixelWindow};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Run the command; the exit code reflects errors.
pub fn run(args: &RenderArgs) -> Result<ExitCode> {
    if let Some(mb) = args.stream_limit {
        input::set_stream_limit(mb << 20);
    }
    match args.command()? {
        Command::Check { files, parse, dialect, warnings } => check_files(&files, &parse, dialect, warnings),
        Command::Render(config) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(config.threads)
                .build()
                .context("starting worker threads")?;
            let mut config = *config;
            pool.install(|| render_command(&mut config))?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn check_files(
    files: &[PathBuf],
    opts: &ParseOptions,
    dialect: Option<Dialect>,
    warnings: input::Warnings,
) -> Result<ExitCode> {
    let mut failed = 0;
    for (k, path) in files.iter().enumerate() {
        let name = input::display_name(path);
        match input::read_source(path) {
            Ok(src) => {
                let opts =
                    ParseOptions { dialect: nffkit_formats::dialect::detect(path, &src, dialect), ..*opts };
                let report = check::check_source(&name, &src, &opts, warnings);
                eprint_safe!("{}", report.diagnostics);
                cli_util::print(format_args!("{}\n", report.summary))?;
                failed += (report.errors > 0) as usize;
                if k + 1 == files.len() {
                    // The process ends next, and the system takes the
                    // memory back at once, faster than freeing the scene
                    // piece by piece (one list per polygon).
                    std::mem::forget(report.scene);
                }
            }
            Err(e) => {
                eprintln_safe!("error: {}", cli_util::chain_once(&e));
                failed += 1;
            }
        }
    }
    Ok(if failed == 0 { ExitCode::SUCCESS } else { ExitCode::FAILURE })
}

fn render_command(cfg: &mut RenderConfig) -> Result<()> {
    let t_start = Instant::now();
    let outputs = Outputs::new().inputs(cfg.input.as_deref()).file("-o", &cfg.output)?;
    if let Some(cost) = &cfg.aov_cost {
        outputs.file("--aov-cost", cost)?;
    }
    let (mut scene, name) = match &cfg.input {
        Some(path) => {
            (input::load_scene(path, &cfg.parse, cfg.dialect, cfg.warnings)?.scene, input::display_name(path))
        }
        None => (default_scene::default_scene(), "built-in default scene".to_string()),
    };
    cfg.apply_directives(&scene.directives);
    if !cfg.quiet {
        for note in &cfg.notes {
            eprintln_safe!("note: {note}");
        }
    }
    let environment = match (&cfg.env, &scene.environment) {
        (Some(dir), _) => Some(environment::load_given(dir)?),
        (None, Some(dir)) => Some(environment::load(cfg.input.as_deref(), dir, cfg.allow_outside_paths)?),
        (None, None) => None,
    };
    let t_parse = t_start.elapsed().as_secs_f64();
    // What is read from the file's primitives, before preparing frees them.
    let mut warnings =
        if cfg.quiet { Vec::new() } else { file_warnings(&scene, cfg.prepare.ambient.lights(), true) };
    let in_file = scene.primitives.len();
    let published = spd_published::recognise(&scene);
    let digest = cfg.part.map(|_| part::scene_digest(&scene));
    let mut prepared = prepare_freeing(&mut scene, &cfg.prepare).with_context(|| name.clone())?;
    prepared.environment = environment.map(std::sync::Arc::new);
    if !cfg.quiet {
        warnings.extend(prepared_warnings(&prepared));
        for w in warnings {
            eprint_safe!("{}", w.render(&name));
        }
    }
    if let Some(w) = prepared.accel_info().warning.filter(|_| !cfg.quiet) {
        eprintln_safe!("warning: {name}: {w}");
    }
    let full = prepared.camera.resolution();
    let mut settings = cfg.settings.clone();
    settings.window = cfg.part.map(|p| p.window(full.0, full.1)).transpose()?;
    let window = settings.window.unwrap_or(PixelWindow::full(full.0, full.1));
    let (w, h) = (window.width(), window.height());
    memory::check(&format!("a {w}x{h} image"), image_bytes(w, h, cfg))?;
    let bar = progress_bar(cfg.quiet, w, h);
    let tick = |done: usize, total: usize| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    };
    let out = match cfg.device {
        Device::Cpu => render(&prepared, &settings, &tick),
        Device::Gpu => {
            let gpu = Gpu::new()?;
            if !cfg.quiet {
                eprintln_safe!("note: rendering on {}", gpu.description());
            }
            GpuScene::new(&gpu, &prepared, &settings)?.render(&tick)?
        }
    };
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let bytes = match (&digest, cfg.output_kind) {
        // A part in EXR carries its window and what merging needs to check.
        (Some(digest), ImageKind::Exr) => part::encode_part(
            &out.film.to_image(),
            full,
            window,
            digest,
            &part::settings_signature(&settings, &cfg.prepare, &prepared.camera),
            &out.counters,
        )?,
        (_, kind) if kind.is_8bit() => image_io::encode_rgb8(w, h, out.film.to_rgb8(cfg.srgb), kind)?,
        (_, kind) => image_io::encode(&out.film.to_image(), kind, cfg.srgb)?,
    };
    nffkit_formats::atomic::write_bytes(&cfg.output, &bytes)?;
    if let (Some(path), Some(cost)) = (&cfg.aov_cost, &out.cost) {
        let (img, max) = cost_heatmap(cost, w, h);
        image_io::save(&img, path, false)?;
        if !cfg.quiet {
            eprintln_safe!(
                "cost image: {} (black = 0, white = {max} tests and visits per pixel)",
                path.display()
            );
        }
    }
    if cfg.stats {
        let times = report::Times { parse: t_parse, total: t_start.elapsed().as_secs_f64() };
        cli_util::print(report::statistics(&name, in_file, &prepared, &settings, &out, times))?;
        if let Some(published) = published.filter(|_| settings.shade.spd) {
            cli_util::print(spd_published::comparison(published, &out.counters, full.0, full.1))?;
        }
    }
    if !cfg.quiet {
        let what = if settings.window.is_some() {
            format!(
                "pixels {}..{} x {}..{} of {}x{}",
                window.x0, window.x1, window.y0, window.y1, full.0, full.1
            )
        } else {
            format!("{w}x{h}")
        };
        eprintln_safe!("wrote {} ({what}) in {:.3} s", cfg.output.display(), t_start.elapsed().as_secs_f64());
    }
    Ok(())
}

/// The memory a `w` x `h` render takes at its peak, as measured (4096x4096
/// of balls_s1: 37 bytes a pixel to PNG, 54 to EXR, 29 more for the cost
/// image): the film, the image, its encoding and the cost counts.
fn image_bytes(w: u32, h: u32, cfg: &RenderConfig) -> u64 {
    let exr = if cfg.output_kind == ImageKind::Exr { 18 } else { 0 };
    let cost = if cfg.aov_cost.is_some() { 30 } else { 0 };
    w as u64 * h as u64 * (38 + exr + cost)
}

fn progress_bar(quiet: bool, w: u32, h: u32) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() || (w as u64 * h as u64) < 64 * 64 {
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

/// Entry point shared by the binary.
pub fn main_with(args: RenderArgs) -> ExitCode {
    cli_util::run_main("render", || run(&args))
}
