//! `nffbench`: the project's one benchmark. It measures where the rays are
//! spent and prints markdown tables:
//!
//! - per-thread eye-ray and shadow-ray throughput (one thread, pixel-centre
//!   eye rays, the same rays `embree-rays` traces), one by one and as 16-ray
//!   packets (4x4 pixels; shadow rays per block and light, as the renderer
//!   packs them), and whole Whitted renders
//!   at 1 and 16 spp on all threads, on balls_s4 and mount_s7 (the scenes of
//!   the SPD and of the P3D report's Table 1);
//! - reading, building and rendering the sphereflake at level 6 (597,871
//!   spheres) against level 2, each in a fresh process, with its peak memory;
//! - single eye rays on one thread on three more scenes: teapot_s12
//!   and gears_s4 (from our SPD generator) and that sphereflake.
//!
//! With `--povray` it also runs POV-Ray on nffconvert's export of the same
//! scenes ([`povray`]: anti-aliasing, soft shadows, depth of field), and
//! with `--shared DIR` (the project's `../shared`) Intel Embree
//! (`bench/embree-rays`, single rays and 8/16-wide packets), and prints
//! their figures beside ours, run in turn with ours ([`paired`]). Figures
//! are noisy on shared machines: compare columns of one run.

pub mod paired;
pub mod povray;
pub mod table1;

use crate::gen::sphereflake::{Floor, Sphereflake};
use crate::render::args::render_config_from;
use crate::spd::{Database, Precision};
use anyhow::{bail, Context, Result};
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Scene;
use nffkit_tracer::bench::best_of;
use nffkit_tracer::prepare::{prepare, prepare_freeing, PrepareOptions};
use nffkit_tracer::render::render;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

/// A whole Whitted render: seconds from parsed scene to image, on every
/// thread of the current pool, and its rays.
#[derive(Debug, Clone, Copy)]
pub struct RenderTiming {
    /// Wall seconds (prepare and render), best of the runs.
    pub seconds: f64,
    /// Rays traced.
    pub rays: u64,
}

/// Time `render` with `args` (render's own options) on `scene`.
pub fn render_timing(scene: &Scene, args: &[&str], runs: u32) -> Result<RenderTiming> {
    let config = render_config_from(args.iter().copied())?;
    let mut rays = 0;
    let mut err = None;
    let seconds = best_of(runs, || match prepare(scene, &config.prepare) {
        Ok(p) => rays = render(&p, &config.settings, &|_, _| {}).counters.rays(),
        Err(e) => err = Some(e),
    });
    if let Some(e) = err {
        return Err(e.into());
    }
    Ok(RenderTiming { seconds, rays })
}

/// What the GPU measured on one scene: eye rays (one per pixel centre, to
/// the nearest hit, no shading) and a whole Whitted render.
#[derive(Debug, Clone, Copy)]
pub struct GpuTiming {
    /// Eye rays per second, in millions (best of the runs).
    pub eye_mrays: f64,
    /// The render's seconds on the GPU, dispatch to completion (scene
    /// upload and shader compilation before), best of the runs.
    pub render_seconds: f64,
    /// The render's rays.
    pub rays: u64,
}

/// Time the GPU on `scene` with `args` (render's own options) for the
/// render, at the same image size for the eye rays.
pub fn gpu_timing(
    gpu: &nffkit_tracer::gpu::Gpu,
    scene: &Scene,
    args: &[&str],
    runs: u32,
) -> Result<GpuTiming> {
    use nffkit_tracer::gpu::GpuScene;
    let config = render_config_from(args.iter().copied())?;
    let prepared = prepare(scene, &config.prepare)?;
    let eye = GpuScene::new(gpu, &prepared, &nffkit_tracer::render::RenderSettings::default())?;
    let mut eye_mrays = 0.0f64;
    let whitted = GpuScene::new(gpu, &prepared, &config.settings)?;
    let (mut render_seconds, mut rays) = (f64::INFINITY, 0);
    for _ in 0..runs.max(1) {
        let e = eye.eye_rays()?;
        eye_mrays = eye_mrays.max(e.rays as f64 / e.seconds / 1e6);
        let r = whitted.render(&|_, _| {})?;
        if r.seconds < render_seconds {
            (render_seconds, rays) = (r.seconds, r.counters.rays());
        }
    }
    Ok(GpuTiming { eye_mrays, render_seconds, rays })
}

/// What loading the sphereflake costs in one fresh process.
#[derive(Debug, Clone, Copy, Default)]
pub struct FlakeProcess {
    /// Bytes of NFF.
    pub bytes: usize,
    /// Reading and parsing, seconds.
    pub parse: f64,
    /// Preparing the scene (primitives, camera, accelerator), seconds.
    pub build: f64,
    /// Of which building the BVH, seconds.
    pub bvh: f64,
    /// The BVH's SAH cost (the same every run: the build is deterministic).
    pub sah: f64,
    /// Rendering 512x512 at 1 spp, seconds.
    pub render: f64,
    /// Peak resident memory of the process, bytes (Linux; 0 elsewhere).
    pub peak: u64,
}

impl FlakeProcess {
    /// The child's line for the parent.
    pub fn to_line(&self) -> String {
        format!(
            "flake bytes={} parse={} build={} bvh={} sah={} render={} peak={}",
            self.bytes, self.parse, self.build, self.bvh, self.sah, self.render, self.peak
        )
    }

    /// Read the child's line back.
    pub fn from_line(line: &str) -> Option<FlakeProcess> {
        let mut f = FlakeProcess::default();
        for field in line.strip_prefix("flake ")?.split_whitespace() {
            let (k, v) = field.split_once('=')?;
            match k {
                "bytes" => f.bytes = v.parse().ok()?,
                "parse" => f.parse = v.parse().ok()?,
                "build" => f.build = v.parse().ok()?,
                "bvh" => f.bvh = v.parse().ok()?,
                "sah" => f.sah = v.parse().ok()?,
                "render" => f.render = v.parse().ok()?,
                "peak" => f.peak = v.parse().ok()?,
                _ => return None,
            }
        }
        Some(f)
    }

    /// The best of two runs: each time's minimum, the highest peak.
    pub fn best(self, o: FlakeProcess) -> FlakeProcess {
        FlakeProcess {
            parse: self.parse.min(o.parse),
            build: self.build.min(o.build),
            bvh: self.bvh.min(o.bvh),
            render: self.render.min(o.render),
            peak: self.peak.max(o.peak),
            ..o
        }
    }
}

/// Inside the child process: read `path`, prepare and render it, and
/// measure each step.
pub fn flake_process(path: &Path) -> Result<FlakeProcess> {
    let t0 = Instant::now();
    // As `render` reads it (memory-mapped).
    let bytes = crate::input::read_source(path)?;
    let mut scene = nff::parse(&bytes, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?.scene;
    let parse = t0.elapsed().as_secs_f64();
    // As `render` does: the file's bytes are not kept past reading.
    let len = bytes.len();
    drop(bytes);
    let t1 = Instant::now();
    // As `render` does: the file's primitives are freed before the build.
    let prepared = prepare_freeing(&mut scene, &PrepareOptions::default())?;
    let build = t1.elapsed().as_secs_f64();
    let config = render_config_from(["--depth", "6"])?;
    let t2 = Instant::now();
    render(&prepared, &config.settings, &|_, _| {});
    let render = t2.elapsed().as_secs_f64();
    let info = prepared.accel_info();
    Ok(FlakeProcess {
        bytes: len,
        parse,
        build,
        bvh: info.build_seconds,
        sah: info.sah_cost.unwrap_or(0.0),
        render,
        peak: peak_memory(),
    })
}

/// Peak resident set of this process (VmHWM), bytes.
pub fn peak_memory() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

/// Write the sphereflake at `level` (SPD's balls, 512x512) to `path`.
pub fn write_flake(level: u32, path: &Path) -> Result<()> {
    write_scene(path, |w| Ok(Sphereflake::at(level, Floor::Square).write(w)?))
}

/// Write SPD database `db` at `size`, numbers at full precision, to `path`.
pub fn write_spd(db: Database, size: u32, path: &Path) -> Result<()> {
    write_scene(path, |w| Ok(db.write(size, Precision::Full, None, w)?))
}

/// Create `path` and fill it through `write`, buffered.
fn write_scene(path: &Path, write: impl FnOnce(BufWriter<File>) -> Result<BufWriter<File>>) -> Result<()> {
    let file = File::create(path).with_context(|| format!("creating {}", path.display()))?;
    write(BufWriter::new(file))?.flush()?;
    Ok(())
}

/// Run `program args`, returning its standard output; fails with its
/// standard error.
pub fn capture(program: &Path, args: &[&str]) -> Result<String> {
    let o = std::process::Command::new(program)
        .args(args)
        .output()
        .with_context(|| format!("running {}", program.display()))?;
    if !o.status.success() {
        bail!("{} {} failed:\n{}", program.display(), args.join(" "), String::from_utf8_lossy(&o.stderr));
    }
    Ok(String::from_utf8_lossy(&o.stdout).into_owned())
}

/// Whole-process wall times of `program args` over `runs` runs (output
/// discarded), seconds: the best and the median. Fails if a run fails.
pub fn process_times(program: &Path, args: &[&str], runs: u32) -> Result<(f64, f64)> {
    let mut times = (0..runs.max(1)).map(|_| wall_seconds(program, args)).collect::<Result<Vec<_>>>()?;
    times.sort_by(f64::total_cmp);
    Ok((times[0], times[times.len() / 2]))
}

/// One whole-process wall time of `program args` (output discarded),
/// seconds. Fails if the run fails.
pub fn wall_seconds(program: &Path, args: &[&str]) -> Result<f64> {
    let t = Instant::now();
    let status = std::process::Command::new(program)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .with_context(|| format!("running {}", program.display()))?;
    let seconds = t.elapsed().as_secs_f64();
    if !status.success() {
        bail!("{} {} failed", program.display(), args.join(" "));
    }
    Ok(seconds)
}

/// The first number after `key` in `text` (`"speedup (povray / ours): 3.10x"`).
pub fn number_after(text: &str, key: &str) -> Option<f64> {
    let rest = &text[text.find(key)? + key.len()..];
    let start = rest.find(|c: char| c.is_ascii_digit())?;
    let num: String = rest[start..].chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
    num.parse().ok()
}

/// The Mrays/s of an `embree-rays` run: the number before " Mrays/s" on its
/// RESULT line.
pub fn embree_mrays(text: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with("RESULT"))?;
    let before = &line[..line.find(" Mrays/s")?];
    before.rsplit([' ', ':']).next()?.parse().ok()
}

/// Embree's build times from `embree-rays --verbose`: its first build
/// (with one-off start-up) and the median of its rebuilds, milliseconds.
pub fn embree_build_ms(text: &str) -> Option<(f64, f64)> {
    let line = text.lines().find(|l| l.starts_with("build: first "))?;
    let first = number_after(line, "build: first")?;
    let median = number_after(line, "median")?;
    Some((first, median))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_out_of_tool_output() {
        let pov = "povray  median 2.550 s  (min 2.5, max 2.6)\nours    median 0.812 s\nspeedup (povray / ours): 3.25x";
        assert_eq!(number_after(pov, "povray  median"), Some(2.55));
        assert_eq!(number_after(pov, "speedup"), Some(3.25));
        let embree = "RESULT balls_s4: single, 1 spp, 1 thread, 512x512, quality medium: 6.123 Mrays/s median [5.9-6.2] of 5";
        assert_eq!(number_after(embree, "quality medium:"), Some(6.123));
        assert_eq!(number_after("nothing", "RESULT"), None);
        assert_eq!(embree_mrays(embree), Some(6.123));
        let build =
            "build: first 130.05 ms (includes one-off start-up); 5 rebuilds: median 96.13 ms [90.21-144.55]";
        assert_eq!(embree_build_ms(build), Some((130.05, 96.13)));
        assert_eq!(embree_build_ms("RESULT x"), None);
    }

    #[test]
    fn flake_lines_round_trip() {
        let f = FlakeProcess {
            bytes: 10,
            parse: 0.5,
            build: 0.25,
            bvh: 0.0625,
            sah: 3.5,
            render: 0.125,
            peak: 4096,
        };
        let g = FlakeProcess::from_line(&f.to_line()).unwrap();
        assert_eq!(
            (g.bytes, g.parse, g.build, g.bvh, g.sah, g.render, g.peak),
            (10, 0.5, 0.25, 0.0625, 3.5, 0.125, 4096)
        );
        let best = f.best(FlakeProcess { parse: 0.25, bvh: 0.125, peak: 8192, ..f });
        assert_eq!((best.parse, best.bvh, best.peak), (0.25, 0.0625, 8192));
    }
}
