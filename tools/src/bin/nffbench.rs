//! `nffbench`: the project's benchmark. See `nffbench --help` and the
//! module doc of `nffkit_tools::bench`.

use anyhow::{bail, Context, Result};
use clap::Parser;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Scene;
use nffkit_tools::bench::paired::{alternate, median, Paired};
use nffkit_tools::bench::{self, capture, embree_mrays, render_timing, write_flake, FlakeProcess};
use nffkit_tools::cli_util;
use nffkit_tools::qa::golden::find_scenes_dir;
use nffkit_tools::spd::Database;
use nffkit_tracer::bench::{best_of, eye_rays, ray_rates, RayRates};
use nffkit_tracer::prepare::{prepare, PrepareOptions, RenderScene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Benchmark: ray throughput, Whitted renders and big-scene loading, as markdown tables.
///
/// Measures, on balls_s4 and mount_s7 (the project's scenes/spd): eye and
/// shadow rays per second on one thread, and whole Whitted renders (depth 6)
/// at 1 and 16 spp on every thread; `render --check` of mount_s7 as a whole
/// process; then the sphereflake at levels 2 and 6, each read, built and
/// rendered in a fresh process, with its peak memory, BVH build time and
/// the tree's SAH cost; and single eye rays on one thread on teapot_s12,
/// gears_s4 (both written by our SPD generator) and the big sphereflake.
/// With --povray,
/// POV-Ray 3.7 renders the same scenes as nffconvert writes them, whole
/// processes side by side: 1 and 16 spp, 16 spp pruned, soft shadows
/// (area lights) and depth of field (focal blur). With --shared DIR (the
/// project's ../shared), Intel Embree (bench/embree-rays: rtcIntersect1
/// and 8/16-wide packets) is run on the same scenes and shown beside these
/// figures, its single rays beside ours on the other three scenes, and its
/// BVH build of the big sphereflake beside ours.
///
/// POV-Ray and Embree run in alternation with us, round by round (--runs
/// rounds), so that a shared machine's drift between processes falls on
/// both sides; each ratio is the median of the rounds' ratios, with their
/// range.
#[derive(Parser, Debug)]
#[command(name = "nffbench", version)]
struct Args {
    /// Image size (square).
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=4096))]
    size: u32,
    /// Repetitions of each timing (in process, and the sphereflake's fresh
    /// processes; the best is reported), and rounds of each side-by-side
    /// comparison with POV-Ray or Embree (the median is reported).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// The shared folder with bench/embree-rays: run Embree beside us.
    #[arg(long, value_name = "DIR")]
    shared: Option<PathBuf>,
    /// Run POV-Ray (`povray` on PATH) on nffconvert's export of each scene,
    /// beside us (slow: minutes).
    #[arg(long)]
    povray: bool,
    /// Sphereflake level of the big-scene test (compared with level 2).
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(2..=7))]
    flake_level: u32,
    /// The SPD scenes (balls_s4.nff, mount_s7.nff). Default: `scenes/spd`
    /// of the current directory or the nearest folder above it.
    #[arg(long, value_name = "DIR")]
    spd_dir: Option<PathBuf>,
    /// Also trace on a GPU (wgpu; lavapipe where there is no GPU): eye
    /// rays and the 16 spp Whitted render of each scene, beside the CPU's.
    #[arg(long, value_enum, default_value = "cpu")]
    device: nffkit_tools::render::args::Device,
    /// Internal: measure one sphereflake file in this process.
    #[arg(long, hide = true, value_name = "FILE")]
    flake_child: Option<PathBuf>,
}

const SCENES: [&str; 2] = ["balls_s4", "mount_s7"];

/// The scenes of the single-ray table that our SPD generator writes (the
/// big sphereflake joins them there).
const SINGLE_SCENES: [(Database, u32); 2] = [(Database::Teapot, 12), (Database::Gears, 4)];

/// One scene's column.
struct Column {
    rates: RayRates,
    eye: f64,
    eye_hits: u64,
    shadow: f64,
    spp1: bench::RenderTiming,
    spp16: bench::RenderTiming,
    /// POV-Ray against us, whole-process seconds, per setting of
    /// `bench::povray::settings`.
    pov: Vec<(&'static str, Paired)>,
    embree: Option<EmbreeSide>,
    gpu: Option<bench::GpuTiming>,
}

/// Embree's rays beside ours, round by round: each ratio is ours over
/// Embree's (eye rays, one thread).
struct EmbreeSide {
    /// Our single rays against `rtcIntersect1`.
    single: Paired,
    /// Our packets against `rtcIntersect1`.
    packets_vs_single: Paired,
    /// Our packets against the faster of `rtcIntersect8` and `16`.
    packets_vs_best: Paired,
    /// Medians of `rtcIntersect8` and `rtcIntersect16`, Mrays/s.
    packet8: f64,
    packet16: f64,
    /// Eye and shadow rays, single (one run).
    shadow: Option<f64>,
}

/// `embree-rays` on `scene` (a name from the shared folder's SPD scenes,
/// or a file) at `size` on one thread, with `extra` options: its output.
/// The progress line names it by its file stem.
fn embree_rays(shared: &Path, scene: &str, size: &str, extra: &[&str]) -> Result<String> {
    let name = Path::new(scene).file_stem().map_or(scene.into(), |s| s.to_string_lossy());
    nffkit_tools::eprintln_safe!("{name}: Embree {}", extra.join(" "));
    let args = [scene, "--width", size, "--height", size, "--threads", "1"];
    capture(&shared.join("bench/embree-rays"), &[&args[..], extra].concat())
}

/// Embree's eye rays on `scene` in one timing (`packet`: none for
/// `rtcIntersect1`, or `--packet K`): Mrays/s on one thread, and its
/// primary hits where it printed them.
fn embree_eye(shared: &Path, scene: &str, size: &str, packet: &[&str]) -> Result<(f64, Option<u64>)> {
    let out =
        embree_rays(shared, scene, size, &[&["--seconds", "1", "--repeats", "3"][..], packet].concat())?;
    let rate =
        embree_mrays(&out).with_context(|| format!("embree-rays printed no rate for {scene}:\n{out}"))?;
    Ok((rate, bench::number_after(&out, "primary hits").map(|h| h as u64)))
}

/// Embree's eye rays on `name` in one round: `rtcIntersect1`, then 8- and
/// 16-ray packets, Mrays/s on one thread.
fn embree_round(shared: &Path, name: &str, size: &str) -> Result<[f64; 3]> {
    let em = |packet: &[&str]| embree_eye(shared, name, size, packet).map(|(rate, _)| rate);
    Ok([em(&[])?, em(&["--packet", "8"])?, em(&["--packet", "16"])?])
}

/// The scene in `file` (called `label` in errors), prepared at `size`
/// square, and a one-thread pool to time its rays on.
fn load_for_rays(label: &str, file: &Path, size: u32) -> Result<(Scene, RenderScene, rayon::ThreadPool)> {
    let src = std::fs::read(file).with_context(|| format!("reading {}", file.display()))?;
    let scene =
        nff::parse(&src, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{label}: {e}"))?.scene;
    let opts = PrepareOptions { width: Some(size), height: Some(size), ..Default::default() };
    let prepared = prepare(&scene, &opts)?;
    Ok((scene, prepared, rayon::ThreadPoolBuilder::new().num_threads(1).build()?))
}

/// Single eye rays on one of the other scenes: ours, and Embree's beside
/// them.
struct SingleRow {
    label: String,
    primitives: usize,
    /// Our rate, Mrays/s (with Embree: the median of the rounds, each the
    /// best of --runs), and our hits.
    ours: f64,
    hits: u64,
    /// Ours against `rtcIntersect1`, round by round, and Embree's hits.
    embree: Option<(Paired, Option<u64>)>,
}

/// [`SingleRow`] for the scene in `file`, at the benchmark's size.
fn single_row(label: String, file: &Path, a: &Args) -> Result<SingleRow> {
    nffkit_tools::eprintln_safe!("{label}: single eye rays on one thread");
    let (scene, prepared, one) = load_for_rays(&label, file, a.size)?;
    let mut hits = 0;
    let mut ours = || -> Result<f64> {
        let mut rays = 0;
        let seconds = one.install(|| best_of(a.runs, || (rays, hits) = eye_rays(&prepared)));
        Ok(rays as f64 / seconds / 1e6)
    };
    let (rate, embree) = match &a.shared {
        None => (ours()?, None),
        Some(shared) => {
            let path = file.to_str().context("temporary path is not UTF-8")?;
            let size = a.size.to_string();
            let rounds = alternate(a.runs, &mut ours, || embree_eye(shared, path, &size, &[]))?;
            let rates: Vec<(f64, f64)> = rounds.iter().map(|&(o, (e, _))| (o, e)).collect();
            let paired = Paired::of(&rates).context("no rounds")?;
            (paired.a, Some((paired, rounds[0].1 .1)))
        }
    };
    Ok(SingleRow { label, primitives: scene.primitives.len(), ours: rate, hits, embree })
}

/// The table of [`SingleRow`]s.
fn single_table(t: &mut String, rows: &[SingleRow], size: u32) {
    let _ = writeln!(t, "\n## Single eye rays on the other scenes ({size}x{size}, one thread)\n");
    let _ =
        writeln!(t, "| scene | primitives | ours, Mrays/s | Embree rtcIntersect1, Mrays/s | ours / Embree |");
    let _ = writeln!(t, "|---|---:|---:|---:|---:|");
    for r in rows {
        let (theirs, ratio) = match &r.embree {
            Some((p, hits)) => {
                let hits = hits.map_or(String::new(), |h| format!(" ({h} hit)"));
                (format!("{:.2}{hits}", p.b), p.ratio_text())
            }
            None => ("-".into(), "-".into()),
        };
        let _ = writeln!(
            t,
            "| {} | {} | {:.2} ({} hit) | {theirs} | {ratio} |",
            r.label, r.primitives, r.ours, r.hits
        );
    }
}

/// Where the sphereflake at `level` is written in `dir`.
fn flake_file(dir: &Path, level: u32) -> PathBuf {
    dir.join(format!("flake{level}.nff"))
}

/// Each rate's median over rounds (the hit counts are the same in all).
fn median_rates(rounds: &[RayRates]) -> RayRates {
    let m = |f: fn(&RayRates) -> f64| median(rounds.iter().map(f));
    RayRates {
        eye: m(|r| r.eye),
        shadow: m(|r| r.shadow),
        eye_packet: m(|r| r.eye_packet),
        shadow_packet: m(|r| r.shadow_packet),
        ..rounds[0]
    }
}

fn measure(
    name: &str,
    spd: &Path,
    a: &Args,
    threads: usize,
    gpu: Option<&nffkit_tracer::gpu::Gpu>,
) -> Result<Column> {
    let path = spd.join(format!("{name}.nff"));
    nffkit_tools::eprintln_safe!("{name}: rays on one thread");
    let (scene, prepared, one) = load_for_rays(name, &path, a.size)?;
    let size = a.size.to_string();
    let ours = || one.install(|| ray_rates(&prepared, a.runs));
    let (rates, embree) = match &a.shared {
        None => (ours(), None),
        Some(shared) => {
            let rounds = alternate(a.runs, || Ok(ours()), || embree_round(shared, name, &size))?;
            let (mine, theirs): (Vec<RayRates>, Vec<[f64; 3]>) = rounds.into_iter().unzip();
            let pairs = |of_ours: fn(&RayRates) -> f64, of_theirs: fn(&[f64; 3]) -> f64| {
                let rounds: Vec<(f64, f64)> =
                    mine.iter().zip(&theirs).map(|(m, t)| (of_ours(m), of_theirs(t))).collect();
                Paired::of(&rounds).context("no rounds")
            };
            let shadow = embree_mrays(&embree_rays(shared, name, &size, &["--shadow"])?);
            let side = EmbreeSide {
                single: pairs(|m| m.eye, |t| t[0])?,
                packets_vs_single: pairs(|m| m.eye_packet, |t| t[0])?,
                packets_vs_best: pairs(|m| m.eye_packet, |t| t[1].max(t[2]))?,
                packet8: median(theirs.iter().map(|t| t[1])),
                packet16: median(theirs.iter().map(|t| t[2])),
                shadow,
            };
            (median_rates(&mine), Some(side))
        }
    };
    let base = ["--width", &size, "--height", &size, "--depth", "6"];
    nffkit_tools::eprintln_safe!("{name}: Whitted renders on {threads} threads");
    let spp1 = render_timing(&scene, &base, a.runs)?;
    let spp16 = render_timing(&scene, &[&base[..], &["--spp", "16"]].concat(), a.runs)?;
    let gpu = match gpu {
        Some(g) => {
            nffkit_tools::eprintln_safe!("{name}: eye rays and the 16 spp render on the GPU");
            Some(bench::gpu_timing(g, &scene, &[&base[..], &["--spp", "16"]].concat(), a.runs)?)
        }
        None => None,
    };
    let mut pov = Vec::new();
    if a.povray {
        let dir = tempfile::tempdir()?;
        let runner = bench::povray::Runner {
            povray: povray_path()?,
            render: std::env::current_exe()?.with_file_name("render"),
            size: a.size,
            runs: a.runs,
            dir: dir.path().to_path_buf(),
        };
        // Soft lights a tenth of their distance wide; a lens whose blur
        // shows (balls_s4: the eye 2.95 from `at`; mount_s7: 2.9).
        let (light, aperture) = if name.starts_with("mount") { (17.0, 0.05) } else { (0.5, 0.05) };
        for setting in bench::povray::settings(light, aperture) {
            nffkit_tools::eprintln_safe!("{name}: POV-Ray and render, {}", setting.label);
            let t = runner.compare(&path, &scene, &setting)?;
            pov.push((setting.label, t));
        }
    }
    Ok(Column {
        rates,
        eye: rates.eye,
        eye_hits: rates.eye_hits,
        shadow: rates.shadow,
        spp1,
        spp16,
        pov,
        embree,
        gpu,
    })
}

/// One fresh process's figures, and its whole-process seconds.
type FlakeRun = (FlakeProcess, f64);

/// What is measured beside each sphereflake process, given its file.
type Beside<'a, T> = &'a mut dyn FnMut(&Path) -> Result<T>;

/// The sphereflake at `level`, written to `dir` and loaded in `runs` fresh
/// processes: each run's figures, and the figures of `beside` (given the
/// file), run in turn with each (before or after it, alternately).
fn flake_runs<T>(
    level: u32,
    dir: &Path,
    runs: u32,
    beside: Option<Beside<'_, T>>,
) -> Result<(Vec<FlakeRun>, Vec<T>)> {
    let file = flake_file(dir, level);
    nffkit_tools::eprintln_safe!("sphereflake level {level}: writing and loading in {runs} fresh processes");
    write_flake(level, &file)?;
    let exe = std::env::current_exe()?;
    let ours = || -> Result<FlakeRun> {
        let t0 = Instant::now();
        let out = capture(&exe, &["--flake-child", file.to_str().context("temporary path is not UTF-8")?])?;
        let whole = t0.elapsed().as_secs_f64();
        Ok((out.lines().find_map(FlakeProcess::from_line).context("the child printed no figures")?, whole))
    };
    match beside {
        None => Ok(((0..runs.max(1)).map(|_| ours()).collect::<Result<_>>()?, Vec::new())),
        Some(f) => Ok(alternate(runs, ours, || f(&file))?.into_iter().unzip()),
    }
}

/// Each step's best time over runs, the best whole-process time, and the
/// highest peak.
fn best_flake(runs: &[FlakeRun]) -> Result<FlakeRun> {
    let (first, rest) = runs.split_first().context("no sphereflake run")?;
    Ok(rest.iter().fold(*first, |(b, w), &(f, whole)| (b.best(f), w.min(whole))))
}

/// Millions of rays per second, to three significant figures or so
/// (lavapipe's fractions to an H100's thousands).
fn rate(mrays: f64) -> String {
    match mrays {
        m if m >= 100.0 => format!("{m:.0}"),
        m if m >= 1.0 => format!("{m:.2}"),
        m => format!("{m:.4}"),
    }
}

fn report(a: &Args) -> Result<String> {
    let spd = spd_dir(a)?;
    let threads = rayon::current_num_threads();
    let gpu = match a.device {
        nffkit_tools::render::args::Device::Gpu => Some(nffkit_tracer::gpu::Gpu::new()?),
        nffkit_tools::render::args::Device::Cpu => None,
    };
    let cols =
        SCENES.iter().map(|s| measure(s, &spd, a, threads, gpu.as_ref())).collect::<Result<Vec<_>>>()?;
    let mut t = format!("## Rays and renders ({0}x{0}, depth 6; {threads} threads for renders)\n\n", a.size);
    let _ = writeln!(t, "| measure | {} |", SCENES.join(" | "));
    let _ = writeln!(t, "|---|{}", "---:|".repeat(SCENES.len()));
    let mut row = |label: &str, f: &dyn Fn(&Column) -> String| {
        let cells: Vec<String> = cols.iter().map(f).collect();
        let _ = writeln!(t, "| {label} | {} |", cells.join(" | "));
    };
    row("eye rays, single, Mrays/s per thread", &|c| format!("{:.2} ({} hit)", c.eye, c.eye_hits));
    row(&format!("eye rays, packets of 4x4 ({}), Mrays/s per thread", nffkit_tracer::simd::isa()), &|c| {
        format!("{:.2} ({} hit)", c.rates.eye_packet, c.rates.eye_packet_hits)
    });
    row("shadow rays, single, Mrays/s per thread", &|c| format!("{:.2}", c.shadow));
    row("shadow rays, packets of 16, Mrays/s per thread", &|c| format!("{:.2}", c.rates.shadow_packet));
    for (label, pick) in [("Whitted 1 spp", 0), ("Whitted 16 spp", 1)] {
        row(&format!("{label}, s (Mrays/s per thread)"), &|c| {
            let r = if pick == 0 { c.spp1 } else { c.spp16 };
            format!("{:.3} ({:.2})", r.seconds, r.rays as f64 / r.seconds / threads as f64 / 1e6)
        });
    }
    if let Some(g) = &gpu {
        let adapter = g.description();
        row(&format!("GPU eye rays, Mrays/s ({adapter})"), &|c| {
            c.gpu.map_or("-".into(), |g| rate(g.eye_mrays))
        });
        row("GPU Whitted 16 spp, s (Mrays/s)", &|c| {
            c.gpu.map_or("-".into(), |g| {
                format!("{:.3} ({})", g.render_seconds, rate(g.rays as f64 / g.render_seconds / 1e6))
            })
        });
        row(&format!("GPU 16 spp against the CPU's {threads} threads: CPU s / GPU s"), &|c| {
            c.gpu.map_or("-".into(), |g| format!("{:.2}x", c.spp16.seconds / g.render_seconds))
        });
    }
    let mrays = |v: f64| format!("{v:.2}");
    let embree_row = |c: &Column, f: &dyn Fn(&EmbreeSide) -> String| c.embree.as_ref().map_or("-".into(), f);
    if a.shared.is_some() {
        row("Embree rtcIntersect1, Mrays/s", &|c| embree_row(c, &|e| mrays(e.single.b)));
        row("Embree rtcIntersect8", &|c| embree_row(c, &|e| mrays(e.packet8)));
        row("Embree rtcIntersect16", &|c| embree_row(c, &|e| mrays(e.packet16)));
        row("Embree eye+shadow (single)", &|c| embree_row(c, &|e| e.shadow.map_or("-".into(), mrays)));
        row("eye rays: our single / Embree single", &|c| embree_row(c, &|e| e.single.ratio_text()));
        row("eye rays: our packets / Embree single", &|c| {
            embree_row(c, &|e| e.packets_vs_single.ratio_text())
        });
        row("eye rays: our packets / Embree's best packets", &|c| {
            embree_row(c, &|e| e.packets_vs_best.ratio_text())
        });
    }
    if a.povray {
        for k in 0..cols[0].pov.len() {
            let label = cols[0].pov[k].0;
            row(&format!("POV-Ray {label}, whole process: POV-Ray s / ours s = speedup"), &|c| {
                let p = c.pov[k].1;
                format!("{:.3} / {:.3} = {}", p.a, p.b, p.ratio_text())
            });
        }
    }
    if a.shared.is_some() || a.povray {
        let _ = writeln!(
            t,
            "\nBeside POV-Ray and Embree: medians of {} rounds, each side run in turn; a ratio is the median of the rounds' ratios (their range in brackets).",
            a.runs
        );
    }
    check_section(&mut t, &spd, 10 * a.runs)?;
    let dir = tempfile::tempdir()?;
    let (small, small_whole) = best_flake(&flake_runs::<()>(2, dir.path(), a.runs, None)?.0)?;
    let mut embree = a.shared.as_deref().map(|shared| move |file: &Path| embree_build(shared, file, threads));
    let beside = embree.as_mut().map(|f| f as Beside<'_, (f64, f64)>);
    let (big_runs, embree_builds) = flake_runs(a.flake_level, dir.path(), a.runs, beside)?;
    let (big, big_whole) = best_flake(&big_runs)?;
    let _ =
        writeln!(t, "\n## Sphereflake, each level in fresh processes (512x512, 1 spp, {threads} threads; best of {} runs, highest peak)\n", a.runs);
    let _ = writeln!(
        t,
        "| level | NFF MB | parse s (MB/s) | prepare ms | of which BVH build ms | BVH SAH cost | render ms | whole process s | peak MB |"
    );
    let _ = writeln!(t, "|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (level, f, whole) in [(2, small, small_whole), (a.flake_level, big, big_whole)] {
        let mb = f.bytes as f64 / 1e6;
        let _ = writeln!(
            t,
            "| {level} | {mb:.1} | {:.3} ({:.0}) | {:.1} | {:.1} | {:.2} | {:.1} | {whole:.3} | {:.0} |",
            f.parse,
            mb / f.parse,
            f.build * 1e3,
            f.bvh * 1e3,
            f.sah,
            f.render * 1e3,
            f.peak as f64 / 1e6
        );
    }
    let _ = writeln!(
        t,
        "\nLevel {} against level 2: whole process {:.1}x, render {:.1}x.",
        a.flake_level,
        big_whole / small_whole,
        big.render / small.render
    );
    if a.shared.is_some() {
        build_table(&mut t, &big, &big_runs, &embree_builds, threads)?;
    }
    let mut rows = Vec::new();
    for (db, size) in SINGLE_SCENES {
        let label = format!("{}_s{size}", db.name());
        let file = dir.path().join(format!("{label}.nff"));
        bench::write_spd(db, size, &file)?;
        rows.push(single_row(label, &file, a)?);
    }
    let level = a.flake_level;
    rows.push(single_row(format!("sphereflake level {level}"), &flake_file(dir.path(), level), a)?);
    single_table(&mut t, &rows, a.size);
    Ok(t)
}

/// Embree's build of the sphereflake in `file` on `threads` threads: its
/// first build (with start-up) and the median of its rebuilds, ms.
fn embree_build(shared: &Path, file: &Path, threads: usize) -> Result<(f64, f64)> {
    nffkit_tools::eprintln_safe!("sphereflake: Embree's build on {threads} threads");
    let file = file.to_str().context("temporary path is not UTF-8")?;
    let n = threads.to_string();
    let args =
        [file, "--width", "16", "--height", "16", "--threads", &n, "--seconds", "0.01", "--repeats", "1"];
    let out = capture(&shared.join("bench/embree-rays"), &[&args[..], &["--verbose"]].concat())?;
    bench::embree_build_ms(&out).context("embree-rays printed no build times")
}

/// Our sphereflake builds beside Embree's, run by run; `best` is the best
/// of our runs ([`best_flake`]).
fn build_table(
    t: &mut String,
    best: &FlakeProcess,
    ours: &[FlakeRun],
    embree: &[(f64, f64)],
    threads: usize,
) -> Result<()> {
    let rounds: Vec<(f64, f64)> = ours.iter().zip(embree).map(|((f, _), e)| (f.bvh * 1e3, e.1)).collect();
    let paired = Paired::of(&rounds).context("no Embree builds")?;
    let first = median(embree.iter().map(|e| e.0));
    let _ = writeln!(t, "\n| BVH build, {threads} threads | ms | SAH cost |");
    let _ = writeln!(t, "|---|---:|---:|");
    let _ = writeln!(t, "| ours (fresh process, best) | {:.1} | {:.2} |", best.bvh * 1e3, best.sah);
    let _ = writeln!(t, "| ours (fresh process, median) | {:.1} | |", paired.a);
    let _ = writeln!(t, "| Embree, first build (with start-up), median | {first:.1} | - |");
    let _ = writeln!(t, "| Embree, median of 5 rebuilds, median | {:.1} | - |", paired.b);
    let _ = writeln!(t, "| our time / Embree's rebuild time, run by run | {} | |", paired.ratio_text());
    Ok(())
}

/// `render --check` of mount_s7 as a whole process, beside `render
/// --version` (starting the process and nothing else), each run `runs`
/// times: short processes need many runs for the best to be the
/// machine's, not its noise.
fn check_section(t: &mut String, spd: &Path, runs: u32) -> Result<()> {
    nffkit_tools::eprintln_safe!("render --check mount_s7: {runs} fresh processes");
    let render = std::env::current_exe()?.with_file_name("render");
    let file = spd.join("mount_s7.nff");
    let file = file.to_str().context("the scene's path is not UTF-8")?;
    let mb = std::fs::metadata(file).with_context(|| format!("reading {file}"))?.len() as f64 / 1e6;
    let check = bench::process_times(&render, &["--check", file], runs)?;
    let floor = bench::process_times(&render, &["--version"], runs)?;
    let _ = writeln!(t, "\n## Checking a file, whole process ({runs} runs)\n");
    let _ = writeln!(t, "| command | best ms | median ms |");
    let _ = writeln!(t, "|---|---:|---:|");
    for (label, (best, median)) in
        [(format!("render --check mount_s7 ({mb:.1} MB)"), check), ("render --version".to_string(), floor)]
    {
        let _ = writeln!(t, "| {label} | {:.1} | {:.1} |", best * 1e3, median * 1e3);
    }
    Ok(())
}

/// The folder of the SPD scenes, checked.
fn spd_dir(a: &Args) -> Result<PathBuf> {
    let dir = match &a.spd_dir {
        Some(d) => d.clone(),
        None => find_scenes_dir(&std::env::current_dir()?, "pass --spd-dir DIR")?.join("spd"),
    };
    for scene in SCENES {
        let file = dir.join(format!("{scene}.nff"));
        if !file.is_file() {
            bail!(
                "{} not found; --spd-dir names the folder holding {}",
                file.display(),
                SCENES.join(".nff, ")
            );
        }
    }
    Ok(dir)
}

/// The comparison script of `--shared DIR`, there before anything is timed.
fn check_shared(shared: &Path) -> Result<()> {
    let path = shared.join("bench/embree-rays");
    if !path.is_file() {
        bail!(
            "--shared {}: {} not found (the folder must hold bench/embree-rays)",
            shared.display(),
            path.display()
        );
    }
    Ok(())
}

/// POV-Ray on PATH, for --povray.
fn povray_path() -> Result<PathBuf> {
    let paths = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&paths)
        .map(|d| d.join("povray"))
        .find(|p| p.is_file())
        .context("--povray: no `povray` on PATH (Debian: apt-get install povray)")
}

fn run(a: &Args) -> Result<()> {
    if let Some(file) = &a.flake_child {
        return cli_util::print(format_args!("{}\n", bench::flake_process(file)?.to_line()));
    }
    if let Some(shared) = &a.shared {
        check_shared(shared)?;
    }
    if a.povray {
        povray_path()?;
    }
    cli_util::print(report(a)?)
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("nffbench", || run(&args).map(|_| ExitCode::SUCCESS))
}
