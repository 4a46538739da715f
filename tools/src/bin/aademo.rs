//! `aademo`: the anti-aliasing demonstration. See `aademo --help`.

use anyhow::{Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use nffkit_formats::{atomic, image_io};
use nffkit_tools::cli_util;
use nffkit_tools::demo::page::{self, FiguresSection};
use nffkit_tools::demo::{contact_sheet, figures, playground, run, serve, table, DemoConfig};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

/// Anti-aliasing demonstration: a web page comparing every sampler and filter on the checkerboard.
///
/// Renders the checkerboard plane with every sampler at several sample
/// counts and with every filter, and writes OUT/index.html: each pattern's
/// samples in the unit square with its strata (16 and 64 samples), the
/// render, 8x magnified crops of the horizon with RMSE and FLIP against a
/// high-sample reference, the same board turned (where a regular grid
/// loses), a filter row with each filter's profile measured against a
/// reference through the same filter, the error table and log-log
/// convergence plots with fitted slopes, each section saying what to look
/// for. With --figures it also rebuilds the P3D report's figures 4-8 and its
/// Table 1 (`table1`, which needs the project's scenes/spd). Also written:
/// contact-sheet.png, errors.md (printed too) and convergence.svg. Renders
/// run in parallel on every core.
///
/// With --playground it also writes OUT/playground/: nffkit's tracer as
/// WebAssembly behind a page where a student turns the knobs (scene,
/// sampler, count, filter, light size, aperture) and watches the image
/// refine. Browsers run it from a web server, not from disk: `aademo --out
/// OUT --serve` serves the folder on 127.0.0.1.
#[derive(Parser, Debug)]
#[command(name = "aademo", version)]
struct Args {
    /// Output folder (created if missing).
    #[arg(short, long, default_value = "aademo")]
    out: PathBuf,
    /// Image size in pixels (square).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(16..=1024))]
    size: u32,
    /// Sample counts, comma-separated.
    #[arg(long, default_value = "1,4,16,64", value_delimiter = ',')]
    spp: Vec<u32>,
    /// Samples per pixel of the reference.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=65536))]
    reference_spp: u32,
    /// Seed of the random patterns.
    #[arg(long, default_value_t = 1)]
    seed: u32,
    /// The turn of the second board, in degrees (see the page's section on
    /// why regular wins).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    rotation: f64,
    /// Squares per side of the board.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..=512))]
    squares: u32,
    /// Also rebuild the P3D report's figures 4-8 and Table 1 on the page.
    #[arg(long)]
    figures: bool,
    /// Image side of Table 1 with --figures (the report's is 512; brute
    /// force is estimated from every 64th row past 2 s a cell).
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=4096), requires = "figures")]
    table1_size: u32,
    /// Worker threads (default: all cores). The page does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Also write the playground (OUT/playground/) with the tracer's
    /// WebAssembly module, built by `cargo playground`.
    #[arg(long)]
    playground: bool,
    /// The playground's WebAssembly module (default: where `cargo
    /// playground` leaves it, beside this program's target folder).
    #[arg(long, value_name = "FILE", requires = "playground")]
    wasm: Option<PathBuf>,
    /// Render nothing: serve the folder OUT on http://127.0.0.1:PORT/ until
    /// stopped (Ctrl-C).
    #[arg(long, conflicts_with_all = ["playground", "figures"])]
    serve: bool,
    /// The port for --serve (0: any free port, printed).
    #[arg(long, default_value_t = 8000, requires = "serve")]
    port: u16,
    /// Print nothing but errors and the error table.
    #[arg(short, long)]
    quiet: bool,
}

fn bar(quiet: bool, what: &str) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let b = ProgressBar::new(1);
    let style = ProgressStyle::with_template(&format!(
        "{{spinner}} {what} [{{bar:40}}] {{pos}}/{{len}} ({{elapsed}})"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    b.set_style(style);
    Some(b)
}

fn main_inner(a: &Args) -> Result<()> {
    if a.spp.is_empty() || a.spp.iter().any(|&s| s == 0 || s > 65536) {
        anyhow::bail!("--spp takes counts from 1 to 65536");
    }
    nffkit_tools::outputs::Outputs::new().folder("--out", &a.out)?;
    let wasm = match a.playground {
        true => {
            let wasm = a
                .wasm
                .clone()
                .or_else(playground::built_wasm)
                .context("cannot find this program's folder")?;
            Some(playground::read_wasm(&wasm)?)
        }
        false => None,
    };
    let cfg = DemoConfig {
        size: a.size,
        spps: a.spp.clone(),
        reference_spp: a.reference_spp,
        seed: a.seed,
        rotation: a.rotation,
        squares: a.squares,
        ..Default::default()
    };
    if !a.rotation.is_finite() {
        anyhow::bail!("--rotation must be a finite number of degrees");
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(a.threads.unwrap_or(0) as usize).build()?;
    let t0 = std::time::Instant::now();
    let (result, figures) = pool.install(|| -> Result<_> {
        let b = bar(a.quiet, "rendering");
        let result = run(&cfg, &|done, total| {
            if let Some(b) = &b {
                b.set_length(total as u64);
                b.set_position(done as u64);
            }
        })?;
        if let Some(b) = b {
            b.finish_and_clear();
        }
        let figures = match a.figures {
            false => None,
            true => {
                let b = bar(a.quiet, "figures");
                if let Some(b) = &b {
                    b.set_length(figures::FIGURES.len() as u64);
                }
                let images = figures::render_all(&|| {
                    if let Some(b) = &b {
                        b.inc(1);
                    }
                })?;
                if let Some(b) = b {
                    b.finish_and_clear();
                }
                let quiet = a.quiet;
                let table1 = nffkit_tools::bench::table1::table(a.table1_size, 2.0, 1, &|what| {
                    if !quiet {
                        nffkit_tools::eprintln_safe!("table1: timing {what}");
                    }
                })?;
                Some(FiguresSection { images, table1, table1_size: a.table1_size })
            }
        };
        Ok((result, figures))
    })?;
    std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
    // The command as the user would type it, without the binary's folder.
    let command =
        std::iter::once("aademo".to_string()).chain(std::env::args().skip(1)).collect::<Vec<_>>().join(" ");
    let index = page::write(&a.out, &cfg, &result, figures.as_ref(), &command, wasm.is_some())?;
    image_io::save(&contact_sheet(&result, &cfg), &a.out.join("contact-sheet.png"), false)?;
    let t = table(&result, &cfg);
    atomic::write_bytes(&a.out.join("errors.md"), t.as_bytes())?;
    cli_util::print(&t)?;
    if let Some(wasm) = wasm {
        let page = playground::write(&a.out, &wasm)?;
        if !a.quiet {
            nffkit_tools::eprintln_safe!(
                "wrote {}; to open it: aademo --out {} --serve",
                page.display(),
                a.out.display()
            );
        }
    }
    if !a.quiet {
        nffkit_tools::eprintln_safe!("wrote {} in {:.1} s", index.display(), t0.elapsed().as_secs_f64());
    }
    Ok(())
}

/// `--serve`: the folder on 127.0.0.1 until stopped.
fn serve(a: &Args) -> Result<()> {
    if !a.out.join("index.html").is_file() && !a.out.join("playground/index.html").is_file() {
        anyhow::bail!(
            "nothing to serve in {0}: make it first with `aademo --out {0} --playground`",
            a.out.display()
        );
    }
    let listener = serve::bind(a.port)?;
    let port = listener.local_addr()?.port();
    let page = if a.out.join("playground/index.html").is_file() { "playground/" } else { "" };
    cli_util::print(format!(
        "serving {} on http://127.0.0.1:{port}/{page} (Ctrl-C to stop)\n",
        a.out.display()
    ))?;
    serve::serve(listener, &a.out)
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("aademo", || {
        if args.serve { serve(&args) } else { main_inner(&args) }.map(|_| ExitCode::SUCCESS)
    })
}
