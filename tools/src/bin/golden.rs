//! `golden`: check or regenerate the golden images of `scenes/`.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use nffkit_formats::image_io;
use nffkit_tools::cli_util;
use nffkit_tools::qa::golden::Case;
use nffkit_tools::qa::golden::{
    check_case, compare, find_scenes_dir, html_report, load_catalogue, read_png, render_case, summary_line,
};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Check or regenerate the golden images of the scene catalogue.
///
/// Golden-image regression: render every case of the scene catalogue
/// (scenes/catalogue.toml) and compare it with its golden image (pixels off
/// by more than 8/255, and NVIDIA's FLIP), or regenerate the goldens.
#[derive(Parser, Debug)]
#[command(name = "golden", version)]
struct Args {
    /// The scenes folder holding catalogue.toml and golden/. Default: the
    /// `scenes/` folder of the current directory or the nearest folder
    /// above it that has one.
    #[arg(long, global = true, value_name = "DIR")]
    scenes: Option<PathBuf>,
    /// Cases rendered at once, each on one thread (default: all cores).
    /// Images do not depend on it.
    #[arg(long, short, global = true, value_parser = clap::value_parser!(u32).range(1..=1024))]
    jobs: Option<u32>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render the named cases (all when none) and rewrite their goldens,
    /// printing which changed and by how much.
    Update { names: Vec<String> },
    /// Render every case, compare with its golden and write an HTML report
    /// (expected, actual and difference side by side) for review.
    Check {
        /// Where the report goes (default: target/golden/report in the
        /// checkout, beside the scenes folder).
        #[arg(long, value_name = "DIR")]
        report: Option<PathBuf>,
    },
}

fn run(a: &Args) -> Result<bool> {
    let scenes = match &a.scenes {
        Some(dir) => dir.clone(),
        None => find_scenes_dir(
            &std::env::current_dir().context("reading the current directory")?,
            "pass --scenes DIR",
        )?,
    };
    let catalogue = load_catalogue(&scenes)?;
    let jobs =
        a.jobs.map_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()), |j| j as usize);
    let pool =
        rayon::ThreadPoolBuilder::new().num_threads(jobs).build().context("starting worker threads")?;
    match &a.command {
        Command::Update { names } => {
            for n in names {
                if !catalogue.case.iter().any(|c| &c.name == n) {
                    bail!("no case named {n} in the catalogue");
                }
            }
            // Render everything first: a case that fails to render writes nothing.
            let cases: Vec<&Case> =
                catalogue.case.iter().filter(|c| names.is_empty() || names.contains(&c.name)).collect();
            let images = in_parallel(&pool, &cases, |case| render_case(case, &scenes, 1), |_| "rendered");
            let mut rendered = Vec::new();
            for (case, img) in cases.iter().zip(images) {
                rendered.push((case, img?));
            }
            for (case, img) in rendered {
                let path = scenes.join("golden").join(format!("{}.png", case.golden_name()));
                let status = match read_png(&path) {
                    Ok(old) if (old.width, old.height) == (img.width, img.height) => {
                        if img == old {
                            "unchanged".to_string()
                        } else {
                            let (d, _) = compare(&img, &old);
                            format!("changed: {:.3}% pixels, mean FLIP {:.5}", d.bad * 100.0, d.flip)
                        }
                    }
                    Ok(_) => "changed size".to_string(),
                    Err(_) => "new".to_string(),
                };
                std::fs::create_dir_all(path.parent().unwrap())?;
                image_io::save(&img, &path, false)?;
                cli_util::print(format_args!("{:<28} {status}\n", case.name))?;
            }
            Ok(true)
        }
        Command::Check { report } => {
            let cases: Vec<&Case> = catalogue.case.iter().collect();
            let checked = in_parallel(
                &pool,
                &cases,
                |case| check_case(case, &scenes, 1),
                |c| {
                    if c.failure.is_some() {
                        "FAIL"
                    } else {
                        "pass"
                    }
                },
            );
            let mut all = Vec::new();
            for c in checked {
                let c = c?;
                cli_util::print(format_args!(
                    "{:<28} {}\n",
                    c.case.name,
                    c.failure.as_deref().unwrap_or("pass")
                ))?;
                all.push(c);
            }
            let failed: Vec<&str> =
                all.iter().filter(|c| c.failure.is_some()).map(|c| c.case.name.as_str()).collect();
            let report = match report {
                Some(r) => r.clone(),
                None => scenes.parent().unwrap_or(Path::new(".")).join("target/golden/report"),
            };
            cli_util::print(format_args!(
                "{}\nreport: {}\n",
                summary_line(all.len(), failed.len()),
                html_report(&all, &report)?.display()
            ))?;
            if !failed.is_empty() {
                cli_util::print(format_args!(
                    "if the change is intended: golden update {}\n",
                    failed.join(" ")
                ))?;
            }
            Ok(failed.is_empty())
        }
    }
}

/// Run `f` on every case on `pool`, printing a progress line to stderr as
/// each finishes; results come back in the cases' order.
fn in_parallel<T: Send>(
    pool: &rayon::ThreadPool,
    cases: &[&Case],
    f: impl Fn(&Case) -> Result<T> + Sync,
    status: impl Fn(&T) -> &'static str + Sync,
) -> Vec<Result<T>> {
    let done = AtomicUsize::new(0);
    pool.install(|| {
        cases
            .par_iter()
            .map(|case| {
                let r = f(case);
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                let s = r.as_ref().map_or("error", &status);
                nffkit_tools::eprintln_safe!("[{n:>3}/{}] {:<28} {s}", cases.len(), case.name);
                r
            })
            .collect()
    })
}

fn main() -> ExitCode {
    let args = Args::parse();
    cli_util::run_main("golden", || {
        run(&args).map(|ok| if ok { ExitCode::SUCCESS } else { ExitCode::FAILURE })
    })
}
