//! `raybench`: primary-ray throughput of an accelerator on one thread, the
//! figure compared with Embree's `rtcIntersect1` (pixel-centre eye rays,
//! nearest hit only, no shading); with `--all`, shadow rays and packets
//! too, the kernels a render spends its time in, without the rest of a
//! render around them.

use anyhow::{Context, Result};
use clap::Parser;
use nffkit_formats::nff::ParseOptions;
use nffkit_tools::{cli_util, input};
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::bench::{eye_rays, ray_rates};
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Primary-ray throughput of one accelerator on one thread.
///
/// Shoot one pixel-centre eye ray per pixel on one thread and report the
/// nearest-hit rate (best of --runs), without shading. With --all, also
/// the shadow rays of those hits (one per light facing the point), one by
/// one, and both kinds as 16-ray packets (4x4 pixels).
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
    /// Also shadow rays, and eye and shadow rays as packets of 16.
    #[arg(long)]
    all: bool,
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
    let name = input::display_name(&a.scene);
    if a.all {
        let r = one.install(|| ray_rates(&prepared, a.runs));
        return cli_util::print(format_args!(
            "{name}: Mrays/s on one thread, best of {}: eye {:.2} ({} hit), shadow {:.2} ({} rays), \
             eye packets {:.2} ({} hit), shadow packets {:.2}\n",
            a.runs,
            r.eye,
            r.eye_hits,
            r.shadow,
            r.shadow_rays,
            r.eye_packet,
            r.eye_packet_hits,
            r.shadow_packet
        ));
    }
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
        "{name}: {rays} eye rays ({hits} hit) in {:.4} s on one thread: {:.2} Mrays/s\n",
        best,
        rays as f64 / best / 1e6
    ))?;
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("raybench", || run(&args).map(|_| ExitCode::SUCCESS))
}
