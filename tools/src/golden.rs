//! Golden-image regression: the scene catalogue (`scenes/catalogue.toml`),
//! rendering each case with the same library code as the binaries, and the
//! comparison with its golden PNG.
//!
//! The comparison counts pixels that differ by more than 8/255 in some
//! channel (catches a one-pixel shift of an edge) and the mean absolute
//! difference (catches a small colour change spread over an object), and
//! reports the mean SSIM as a perceptual summary. Tolerances are per case.

use crate::default_scene::default_scene;
use crate::planegen::Board;
use crate::render_cli::{prepare_options, settings, Args};
use crate::sphereflake::{Floor, Sphereflake};
use anyhow::{bail, Context, Result};
use clap::Parser;
use nffkit_formats::image_io::{self, RgbImage};
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Scene;
use nffkit_tracer::film::inferno;
use nffkit_tracer::prepare::prepare;
use nffkit_tracer::render::render;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Default per-case tolerances.
const MAX_BAD: f64 = 0.002;
const MAX_MEAN: f64 = 0.002;
/// A channel difference counted as a bad pixel.
const BAD_DIFF: f64 = 8.0 / 255.0;

/// The catalogue file.
#[derive(Debug, Deserialize)]
pub struct Catalogue {
    /// The cases.
    pub case: Vec<Case>,
}

/// One case.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Name, used in messages and (unless `golden` is set) as the image name.
    pub name: String,
    /// Golden image name when several cases share one (grid, BVH, none).
    pub golden: Option<String>,
    /// How the scene is made.
    pub source: SourceSpec,
    /// `render` arguments.
    #[serde(default)]
    pub render: Vec<String>,
    /// Fraction of pixels allowed to differ by more than 8/255.
    pub max_bad: Option<f64>,
    /// Allowed mean absolute difference.
    pub max_mean: Option<f64>,
}

/// Where a case's scene comes from.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SourceSpec {
    /// The built-in default scene.
    #[serde(default)]
    pub default: bool,
    /// planegen's board.
    pub planegen: Option<PlanegenSpec>,
    /// sphereflake.
    pub sphereflake: Option<SphereflakeSpec>,
    /// A file under `scenes/`.
    pub file: Option<String>,
    /// A mesh under `scenes/`, converted by mesh2nff (default options).
    pub mesh: Option<String>,
}

/// planegen options.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct PlanegenSpec {
    /// Squares along x.
    pub nx: u32,
    /// Squares along y.
    pub ny: u32,
}

/// sphereflake options.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SphereflakeSpec {
    /// Level.
    pub level: u32,
    /// Checkerboard floor.
    pub checker: Option<[u32; 2]>,
}

impl Case {
    /// The golden image's name.
    pub fn golden_name(&self) -> &str {
        self.golden.as_deref().unwrap_or(&self.name)
    }
}

/// The `scenes/` folder of this checkout.
pub fn scenes_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes"))
}

/// Read the catalogue.
pub fn load_catalogue(scenes: &Path) -> Result<Catalogue> {
    let path = scenes.join("catalogue.toml");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
    toml::from_str(&text).with_context(|| format!("{}", path.display()))
}

/// Make a case's scene with the generators' library code.
pub fn scene_of(case: &Case, scenes: &Path) -> Result<Scene> {
    let s = &case.source;
    let chosen = s.default as u8
        + s.planegen.is_some() as u8
        + s.sphereflake.is_some() as u8
        + s.file.is_some() as u8
        + s.mesh.is_some() as u8;
    if chosen != 1 {
        bail!(
            "case {}: the source must name exactly one of default, planegen, sphereflake, file, mesh",
            case.name
        );
    }
    Ok(if s.default {
        default_scene()
    } else if let Some(p) = &s.planegen {
        Board { nx: p.nx, ny: p.ny, ..Default::default() }.scene()
    } else if let Some(f) = &s.sphereflake {
        let floor = f.checker.map_or(Floor::Square, |[x, y]| Floor::Checker(x, y));
        Sphereflake { level: f.level, resolution: [512, 512], floor }.scene()
    } else if let Some(m) = &s.mesh {
        let mesh = nffkit_formats::mesh::load(&scenes.join(m))?;
        let (text, _) = crate::mesh2nff::write(&mesh, &crate::mesh2nff::Options::default(), Vec::new())?;
        nff::parse(&text, &ParseOptions::default()).map_err(|e| anyhow::anyhow!("{m} converted: {e}"))?.scene
    } else {
        let path = scenes.join(s.file.as_ref().expect("one source is set"));
        let src = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        nff::parse(&src, &ParseOptions::default())
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
            .scene
    })
}

/// Render a case on `threads` threads, as 8-bit RGB.
pub fn render_case(case: &Case, scenes: &Path, threads: usize) -> Result<RgbImage> {
    let args = Args::try_parse_from(std::iter::once("render".to_string()).chain(case.render.iter().cloned()))
        .with_context(|| format!("case {}: bad render arguments", case.name))?;
    let scene = scene_of(case, scenes)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| {
        let prepared = prepare(&scene, &prepare_options(&args))?;
        let out = render(&prepared, &settings(&args)?, &|_, _| {});
        let img = out.film.to_image();
        let bytes = img.to_rgb8(args.srgb);
        Ok(RgbImage {
            width: img.width,
            height: img.height,
            pixels: bytes
                .chunks(3)
                .map(|c| [c[0] as f32 / 255.0, c[1] as f32 / 255.0, c[2] as f32 / 255.0])
                .collect(),
        })
    })
}

/// How two images differ.
#[derive(Debug, Clone, Copy, Default)]
pub struct Difference {
    /// Fraction of pixels with a channel differing by more than 8/255.
    pub bad: f64,
    /// Mean absolute difference over all channels.
    pub mean: f64,
    /// Mean SSIM of luminance over 8x8 windows.
    pub ssim: f64,
}

/// Compare two images of the same size.
pub fn compare(a: &RgbImage, b: &RgbImage) -> Difference {
    let n = a.pixels.len().max(1);
    let (mut bad, mut sum) = (0usize, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (0..3).map(|i| (p[i] - q[i]).abs() as f64).fold(0.0, f64::max);
        bad += (d > BAD_DIFF + 1e-6) as usize;
        sum += (0..3).map(|i| (p[i] - q[i]).abs() as f64).sum::<f64>();
    }
    let film = |img: &RgbImage| nffkit_tracer::film::Film {
        width: img.width,
        height: img.height,
        pixels: img.pixels.iter().map(|p| glam::Vec3A::from_array(*p)).collect(),
    };
    Difference {
        bad: bad as f64 / n as f64,
        mean: sum / (3 * n) as f64,
        ssim: crate::aademo::mean_ssim(&film(a), &film(b)),
    }
}

/// The outcome of checking one case.
pub struct Checked {
    /// The case.
    pub case: Case,
    /// The rendered image.
    pub actual: RgbImage,
    /// The golden image, if it exists.
    pub expected: Option<RgbImage>,
    /// The difference, when sizes match.
    pub diff: Option<Difference>,
    /// Why it failed, if it did.
    pub failure: Option<String>,
}

/// Read a golden PNG as linear [0, 1] values of its 8-bit codes.
pub fn read_png(path: &Path) -> Result<RgbImage> {
    let img = image::open(path).with_context(|| format!("cannot read {}", path.display()))?.to_rgb8();
    Ok(RgbImage {
        width: img.width(),
        height: img.height(),
        pixels: img
            .pixels()
            .map(|p| [p[0] as f32 / 255.0, p[1] as f32 / 255.0, p[2] as f32 / 255.0])
            .collect(),
    })
}

/// Render a case and compare it with its golden image.
pub fn check_case(case: &Case, scenes: &Path) -> Result<Checked> {
    let actual = render_case(case, scenes, 2)?;
    let golden = scenes.join("golden").join(format!("{}.png", case.golden_name()));
    let expected = if golden.exists() { Some(read_png(&golden)?) } else { None };
    let (diff, failure) = match &expected {
        None => (None, Some(format!("no golden image {}", golden.display()))),
        Some(e) if (e.width, e.height) != (actual.width, actual.height) => (
            None,
            Some(format!(
                "size {}x{} differs from the golden {}x{}",
                actual.width, actual.height, e.width, e.height
            )),
        ),
        Some(e) => {
            let d = compare(&actual, e);
            let (max_bad, max_mean) = (case.max_bad.unwrap_or(MAX_BAD), case.max_mean.unwrap_or(MAX_MEAN));
            let fail = (d.bad > max_bad || d.mean > max_mean).then(|| {
                format!(
                    "{:.3}% of pixels differ by more than 8/255 (allowed {:.3}%), mean difference {:.5} (allowed {:.5}), SSIM {:.4}",
                    d.bad * 100.0,
                    max_bad * 100.0,
                    d.mean,
                    max_mean,
                    d.ssim
                )
            });
            (Some(d), fail)
        }
    };
    Ok(Checked { case: case.clone(), actual, expected, diff, failure })
}

/// The difference heat map: |a − b| (max over channels, ×4) on the inferno
/// scale.
pub fn diff_image(a: &RgbImage, b: &RgbImage) -> RgbImage {
    let pixels = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| inferno((0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f32::max) * 4.0))
        .collect();
    RgbImage { width: a.width, height: a.height, pixels }
}

/// Write actual, expected and difference images of a failed case into
/// `dir`; returns their paths.
pub fn write_failure_images(c: &Checked, dir: &Path) -> Result<[PathBuf; 3]> {
    std::fs::create_dir_all(dir)?;
    let name = &c.case.name;
    let paths = [
        dir.join(format!("{name}.actual.png")),
        dir.join(format!("{name}.expected.png")),
        dir.join(format!("{name}.diff.png")),
    ];
    image_io::save(&c.actual, &paths[0], false)?;
    if let Some(e) = &c.expected {
        image_io::save(e, &paths[1], false)?;
        if (e.width, e.height) == (c.actual.width, c.actual.height) {
            image_io::save(&diff_image(&c.actual, e), &paths[2], false)?;
        }
    }
    Ok(paths)
}

/// The HTML review page: every case with expected, actual and difference.
pub fn html_report(checked: &[Checked], dir: &Path) -> Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let mut rows = String::new();
    for c in checked {
        let [a, e, d] = write_failure_images(c, dir)?;
        let file = |p: &Path| p.file_name().unwrap().to_string_lossy().into_owned();
        let status = match &c.failure {
            None => "<td class=ok>pass</td>".to_string(),
            Some(f) => format!("<td class=bad>FAIL: {f}</td>"),
        };
        let metrics = c.diff.map_or("-".into(), |d| {
            format!("bad {:.3}%, mean {:.5}, SSIM {:.4}", d.bad * 100.0, d.mean, d.ssim)
        });
        rows += &format!(
            "<tr><td>{}</td>{status}<td>{metrics}</td><td><img src=\"{}\"></td><td><img src=\"{}\"></td><td><img src=\"{}\"></td></tr>\n",
            c.case.name,
            file(&e),
            file(&a),
            file(&d)
        );
    }
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>nffkit golden images</title>\
         <style>body{{font-family:sans-serif}}td{{padding:4px;vertical-align:top}}img{{image-rendering:pixelated;width:192px}}\
         .ok{{color:green}}.bad{{color:#b00}}</style>\
         <h1>Golden images</h1><table><tr><th>case</th><th>status</th><th>metrics</th><th>expected</th><th>actual</th><th>difference (x4)</th></tr>\n{rows}</table>\n"
    );
    let path = dir.join("index.html");
    image_io::write_atomically(&path, html.as_bytes())?;
    Ok(path)
}
