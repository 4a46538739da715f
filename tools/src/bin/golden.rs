//! `golden`: check or regenerate the golden images of `scenes/`.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use nffkit_formats::image_io;
use nffkit_tools::cli_util;
use nffkit_tools::golden::{
    check_case, compare, find_scenes_dir, html_report, load_catalogue, read_png, render_case,
};
use std::path::PathBuf;
use std::process::ExitCode;

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
    #[arg(long, value_name = "DIR")]
    scenes: Option<PathBuf>,
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
        /// Where the report goes.
        #[arg(long, default_value = "target/golden/report")]
        report: PathBuf,
    },
}

fn run(a: &Args) -> Result<bool> {
    let scenes = match &a.scenes {
        Some(dir) => dir.clone(),
        None => find_scenes_dir(&std::env::current_dir().context("reading the current directory")?)?,
    };
    let catalogue = load_catalogue(&scenes)?;
    match &a.command {
        Command::Update { names } => {
            for n in names {
                if !catalogue.case.iter().any(|c| &c.name == n) {
                    bail!("no case named {n} in the catalogue");
                }
            }
            // Render everything first: a case that fails to render writes nothing.
            let mut rendered = Vec::new();
            for case in catalogue.case.iter().filter(|c| names.is_empty() || names.contains(&c.name)) {
                rendered.push((case, render_case(case, &scenes, 2)?));
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
                println!("{:<28} {status}", case.name);
            }
            Ok(true)
        }
        Command::Check { report } => {
            let mut all = Vec::new();
            for case in &catalogue.case {
                let c = check_case(case, &scenes)?;
                println!("{:<28} {}", case.name, c.failure.as_deref().unwrap_or("pass"));
                all.push(c);
            }
            let ok = all.iter().all(|c| c.failure.is_none());
            println!("report: {}", html_report(&all, report)?.display());
            Ok(ok)
        }
    }
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => cli_util::exit(Err(e), "golden"),
    }
}
