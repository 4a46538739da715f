//! `raybench`: primary-ray throughput of an accelerator on one thread, the
//! figure compared with Embree's `rtcIntersect1` (pixel-centre eye rays,
//! nearest hit only, no shading).

use anyhow::{Context, Result};
use clap::Parser;
use nffkit_formats::nff::ParseOptions;
use nffkit_tools::{cli_util, input};
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::bench::eye_rays;
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Primary-ray throughput of one accelerator on one thread.
///
/// Shoot one pixel-centre eye ray per pixel on one thread and report the
/// nearest-hit rate (best of --runs), without shading.
#[derive(Parser, Debug)]
#[command(name = "raybench", version)]
struct Args {
    /// Scene file.
    scene: PathBuf,
    /// Image size.
    #[arg(long, default_value_t = 512)]
    size: u32,
    /// Accelerator.
    #[arg(long, value_enum, default_value_t = AccelKind::Bvh)]
    accel: AccelKind,
    /// Repetitions; the best is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,
}

fn run(a: &Args) -> Result<()> {
    let scene = input::load_scene(&a.scene, &ParseOptions::default(), None, input::Warnings::Hide)?.scene;
    let opts = PrepareOptions {
        width: Some(a.size),
        height: Some(a.size),
        accel: AccelOptions { kind: a.accel, ..Default::default() },
        ..Default::default()
    };
    let prepared = prepare(&scene, &opts).context("preparing the scene")?;
    // On a worker thread of its own, as nffbench and the renderer trace.
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let (best, rays, hits) = one.install(|| {
        let mut best = f64::INFINITY;
        let (mut rays, mut hits) = (0, 0);
        for _ in 0..a.runs.max(1) {
            let t0 = Instant::now();
            (rays, hits) = eye_rays(&prepared);
            best = best.min(t0.elapsed().as_secs_f64());
        }
        (best, rays, hits)
    });
    cli_util::print(format_args!(
        "{}: {rays} eye rays ({hits} hit) in {:.4} s on one thread: {:.2} Mrays/s\n",
        input::display_name(&a.scene),
        best,
        rays as f64 / best / 1e6
    ))?;
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("raybench", || run(&args).map(|_| ExitCode::SUCCESS))
}
