//! `nffbench`'s comparison with POV-Ray 3.7: the same SPD scene written by
//! nffconvert's POV-Ray writer (so both trace the same geometry, lights,
//! finishes and depth), each renderer timed as a whole process, side by
//! side: the two run in turn, and the speedup is the median of the rounds'
//! ratios ([`super::paired`]). How each setting maps:
//!
//! | row | render | POV-Ray |
//! |---|---|---|
//! | 1 spp | pixel centres | `-A` (one ray a pixel) |
//! | 16 spp | `--spp 16` (multi-jittered) | `+AM1 +A0.0 +R4 -J`: every pixel supersampled 4x4 plus its centre, 17 rays |
//! | 16 spp, pruned | the same, `--min-weight 0.0039` | the same, `adc_bailout 1/255` (POV-Ray's default) |
//! | soft shadows | `--spp 16 --light-size S` (a square facing the point, one light sample a ray) | the 16 spp row, each light an `area_light` of side S, 4x4 `jitter orient adaptive 0` (16 shadow rays a hit) |
//! | depth of field | `--spp 16 --aperture A` (focus on `at`) | `focal_blur`: `aperture 2A` (its aperture is a diameter), `blur_samples 16 confidence 1 variance 0`, `-A` |

use super::paired::{alternate, Paired};
use super::wall_seconds;
use crate::convert::{pov, ExportOptions};
use anyhow::{Context, Result};
use nffkit_formats::Scene;
use std::path::{Path, PathBuf};

/// One comparison: its label, `render`'s extra flags, the export's
/// settings and POV-Ray's extra flags.
pub struct Setting {
    /// The row's label.
    pub label: &'static str,
    /// `render` flags beyond the scene, output and size.
    pub ours: Vec<String>,
    /// How the scene is written for POV-Ray.
    pub export: ExportOptions,
    /// POV-Ray flags beyond input, output, size and threads.
    pub pov: Vec<&'static str>,
}

/// POV-Ray's 16-sample antialiasing: every pixel 4x4 plus its centre.
const POV_AA: [&str; 4] = ["+AM1", "+A0.0", "+R4", "-J"];

/// The settings of the module doc for a scene with lights of area side
/// `light` and a lens of radius `aperture`.
pub fn settings(light: f64, aperture: f64) -> Vec<Setting> {
    let base = ExportOptions::default();
    let spp16 = || vec!["--spp".to_string(), "16".to_string()];
    let with = |extra: &[String]| [spp16(), extra.to_vec()].concat();
    vec![
        Setting { label: "1 spp", ours: vec![], export: base, pov: vec!["-A"] },
        Setting { label: "16 spp", ours: spp16(), export: base, pov: POV_AA.to_vec() },
        Setting {
            label: "16 spp, --min-weight 0.0039 / adc_bailout 1/255",
            ours: with(&["--min-weight".into(), "0.0039".into()]),
            export: ExportOptions { min_weight: 1.0 / 255.0, ..base },
            pov: POV_AA.to_vec(),
        },
        Setting {
            label: "soft shadows, 16 spp",
            ours: with(&["--light-size".into(), light.to_string()]),
            export: ExportOptions { area_light: Some(light), ..base },
            pov: POV_AA.to_vec(),
        },
        Setting {
            label: "depth of field, 16 spp",
            ours: with(&["--aperture".into(), aperture.to_string()]),
            export: ExportOptions { aperture: Some(aperture), ..base },
            pov: vec!["-A"],
        },
    ]
}

/// Where the comparison runs: the two programs, the image size, the runs
/// of each timing, and a folder for its files.
pub struct Runner {
    /// POV-Ray.
    pub povray: PathBuf,
    /// `render`.
    pub render: PathBuf,
    /// Image side, pixels.
    pub size: u32,
    /// Runs of each program, in alternation ([`alternate`]).
    pub runs: u32,
    /// Where the scene and images are written.
    pub dir: PathBuf,
}

impl Runner {
    /// Whole-process seconds of POV-Ray (`a`) and of `render` (`b`) for
    /// `setting` on `scene` (read from `nff`), the two run in
    /// alternation: the ratio is POV-Ray's time over ours, our speedup.
    pub fn compare(&self, nff: &Path, scene: &Scene, setting: &Setting) -> Result<Paired> {
        let pov_file = self.dir.join("scene.pov");
        let mut text = Vec::new();
        pov::write(scene, &setting.export, &mut text)?;
        std::fs::write(&pov_file, text).with_context(|| format!("writing {}", pov_file.display()))?;
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let pov_in = format!("+I{}", pov_file.display());
        let pov_out = format!("+O{}", self.dir.join("pov.png").display());
        let (w, h, wt) = (format!("+W{}", self.size), format!("+H{}", self.size), format!("+WT{threads}"));
        let mut pov_args = vec![pov_in.as_str(), pov_out.as_str(), &w, &h, &wt, "-D", "+FN", "-GA"];
        pov_args.extend(&setting.pov);
        let size = self.size.to_string();
        let out = self.dir.join("ours.png");
        let mut ours: Vec<&str> = vec![nff.to_str().context("the scene's path is not UTF-8")?];
        ours.extend([
            "-o",
            out.to_str().context("temporary path is not UTF-8")?,
            "--width",
            &size,
            "--height",
            &size,
        ]);
        ours.extend(["--depth", "6", "-q"]);
        ours.extend(setting.ours.iter().map(String::as_str));
        let rounds = alternate(
            self.runs,
            || wall_seconds(&self.povray, &pov_args),
            || wall_seconds(&self.render, &ours),
        )?;
        Paired::of(&rounds).context("no rounds")
    }
}
