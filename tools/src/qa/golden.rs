//! Golden-image regression: the scene catalogue (`scenes/catalogue.toml`),
//! rendering each case with the same library code as the binaries, and the
//! comparison with its golden PNG.
//!
//! The comparison counts pixels that differ by more than 8/255 in some
//! channel (catches a one-pixel shift of an edge) and takes NVIDIA's FLIP
//! (see [`crate::qa::metrics`]), whose mean catches a small colour change spread
//! over an object and whose error map shows a person where images differ.
//! Tolerances are per case.

use super::metrics;
use crate::cli_util::parse_args;
use crate::gen::default_scene::default_scene;
use crate::gen::planegen::Board;
use crate::gen::sphereflake::Sphereflake;
use crate::render::args::render_config_from;
use crate::{input, memory};
use anyhow::{bail, Context, Result};
use nffkit_formats::atomic;
use nffkit_formats::image_io::{self, RgbImage};
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Scene;
use nffkit_tracer::film::inferno;
use nffkit_tracer::prepare::prepare;
use nffkit_tracer::render::render;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Default per-case tolerances: the fraction of pixels off by more than
/// 8/255 (catches an edge moved by a pixel) and the mean FLIP error
/// (catches a small colour change spread over an object).
const MAX_BAD: f64 = 0.002;
const MAX_FLIP: f64 = 0.004;
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
    pub source: Source,
    /// `render` arguments.
    #[serde(default)]
    pub render: Vec<String>,
    /// Fraction of pixels allowed to differ by more than 8/255.
    pub max_bad: Option<f64>,
    /// Allowed mean FLIP error.
    pub max_flip: Option<f64>,
}

/// Where a case's scene comes from: exactly one of these (serde refuses a
/// source naming none or two). A generator's options are its command line
/// (`planegen = ["--nx", "16"]`), parsed by the options struct its binary
/// uses.
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Source {
    /// The built-in default scene (`source = "default"`).
    Default,
    /// planegen's board, with `planegen` arguments.
    Planegen(Vec<String>),
    /// sphereflake, with `sphereflake` arguments.
    Sphereflake(Vec<String>),
    /// An SPD database, with `spd` arguments.
    Spd(Vec<String>),
    /// A file under `scenes/`.
    File(String),
    /// A mesh under `scenes/`, converted by mesh2nff (default options).
    Mesh(String),
}

impl Case {
    /// The golden image's name.
    pub fn golden_name(&self) -> &str {
        self.golden.as_deref().unwrap_or(&self.name)
    }
}

/// The `scenes/` folder holding `catalogue.toml`, looked for in `start`
/// and each folder above it (so `golden` works from anywhere inside a
/// checkout, and no path of the build machine is compiled in). `hint`
/// says how the command takes the folder instead ("pass --scenes DIR").
pub fn find_scenes_dir(start: &Path, hint: &str) -> Result<PathBuf> {
    start
        .ancestors()
        .map(|a| if a.file_name().is_some_and(|n| n == "scenes") { a.to_path_buf() } else { a.join("scenes") })
        .find(|s| s.join("catalogue.toml").is_file())
        .with_context(|| {
            format!(
                "no scenes/catalogue.toml in {} or any folder above it; run inside an nffkit checkout or {hint}",
                start.display()
            )
        })
}

/// Read the catalogue, checked: every name (and golden name) a plain file
/// name, since it names files under `golden/` and the report; no name
/// twice.
pub fn load_catalogue(scenes: &Path) -> Result<Catalogue> {
    let path = scenes.join("catalogue.toml");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let catalogue: Catalogue = toml::from_str(&text).with_context(|| format!("{}", path.display()))?;
    let mut seen = std::collections::HashSet::new();
    for case in &catalogue.case {
        for (what, name) in [("name", Some(&case.name)), ("golden", case.golden.as_ref())] {
            let Some(name) = name else { continue };
            let plain = !name.is_empty()
                && !name.starts_with('.')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
            if !plain {
                bail!(
                    "{}: case `{}`: {what} `{name}` must be a plain file name (letters, digits, `_`, `-`, `.`; not starting with `.`)",
                    path.display(),
                    case.name
                );
            }
        }
        if !seen.insert(&case.name) {
            bail!("{}: two cases are named `{}`", path.display(), case.name);
        }
    }
    Ok(catalogue)
}

/// Make a case's scene with the generators' library code.
pub fn scene_of(case: &Case, scenes: &Path) -> Result<Scene> {
    Ok(match &case.source {
        Source::Default => default_scene(),
        Source::Planegen(args) => {
            let board: Board =
                parse_args(args).with_context(|| format!("case {}: planegen options", case.name))?;
            board.validate()?;
            // The binary streams its squares; here they are held (a polygon
            // and its vertices, then the renderer's triangles: ~700 bytes).
            let squares = board.nx as u64 * board.ny as u64;
            memory::check(&format!("case {}: a board of {squares} squares", case.name), squares * 700)?;
            board.scene()
        }
        Source::Sphereflake(args) => {
            let flake: Sphereflake =
                parse_args(args).with_context(|| format!("case {}: sphereflake options", case.name))?;
            flake.validate()?;
            // Held in memory, unlike the binary's stream: a sphere is
            // ~96 bytes read, ~200 more rendered.
            let spheres = crate::gen::sphereflake::sphere_count(flake.level);
            memory::check(&format!("case {}: sphereflake level {}", case.name, flake.level), spheres * 300)?;
            flake.scene()
        }
        Source::Spd(args) => {
            let g: crate::spd::Generate =
                parse_args(args).with_context(|| format!("case {}: spd options", case.name))?;
            let (db, size) = g.checked().with_context(|| format!("case {}", case.name))?;
            // Held in memory, unlike the binary's stream: ~300 bytes a
            // primitive read and prepared.
            memory::check(
                &format!("case {}: spd {} --size {size}", case.name, db.name()),
                db.primitives(size) * 300,
            )?;
            let text = g.write(Vec::new())?;
            nff::parse(&text, &ParseOptions::default())
                .map_err(|e| anyhow::anyhow!("spd {}: {e}", db.name()))?
                .scene
        }
        Source::Mesh(m) => {
            let mesh = nffkit_formats::mesh::load(&scenes.join(m))?;
            let (text, _) = crate::mesh2nff::write(&mesh, &crate::mesh2nff::Options::default(), Vec::new())?;
            nff::parse(&text, &ParseOptions::default())
                .map_err(|e| anyhow::anyhow!("{m} converted: {e}"))?
                .scene
        }
        Source::File(f) => {
            input::load_scene(&scenes.join(f), &ParseOptions::default(), None, input::Warnings::Hide)?.scene
        }
    })
}

/// Render a case on `threads` threads, as 8-bit RGB.
pub fn render_case(case: &Case, scenes: &Path, threads: usize) -> Result<RgbImage> {
    let config = render_config_from(&case.render)
        .with_context(|| format!("case {}: bad render arguments", case.name))?;
    let scene = scene_of(case, scenes)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| {
        let prepared = prepare(&scene, &config.prepare)?;
        let out = render(&prepared, &config.settings, &|_, _| {});
        let img = out.film.to_image();
        let bytes = img.to_rgb8(config.srgb);
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
    /// Mean FLIP error.
    pub flip: f64,
}

/// Compare two images of the same size: the bad-pixel fraction and mean
/// FLIP, and FLIP's error map.
pub fn compare(actual: &RgbImage, expected: &RgbImage) -> (Difference, RgbImage) {
    let n = actual.pixels.len().max(1);
    let bad = actual
        .pixels
        .iter()
        .zip(&expected.pixels)
        .filter(|(p, q)| (0..3).any(|i| (p[i] - q[i]).abs() as f64 > BAD_DIFF + 1e-6))
        .count();
    let f = metrics::flip(expected, actual);
    (Difference { bad: bad as f64 / n as f64, flip: f.mean }, f.error_map)
}

impl Difference {
    /// Why it fails `case`'s tolerances, if it does.
    pub fn failure(&self, case: &Case) -> Option<String> {
        let (max_bad, max_flip) = (case.max_bad.unwrap_or(MAX_BAD), case.max_flip.unwrap_or(MAX_FLIP));
        (self.bad > max_bad || self.flip > max_flip).then(|| {
            format!(
                "{:.3}% of pixels differ by more than 8/255 (allowed {:.3}%), mean FLIP {:.5} (allowed {:.5})",
                self.bad * 100.0,
                max_bad * 100.0,
                self.flip,
                max_flip
            )
        })
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
    /// FLIP's error map, when sizes match.
    pub flip_map: Option<RgbImage>,
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
pub fn check_case(case: &Case, scenes: &Path, threads: usize) -> Result<Checked> {
    let actual = render_case(case, scenes, threads)?;
    let golden = scenes.join("golden").join(format!("{}.png", case.golden_name()));
    // An unreadable golden is this case's failure, not the check's end.
    let (expected, unreadable) = match golden.exists().then(|| read_png(&golden)) {
        None => (None, None),
        Some(Ok(img)) => (Some(img), None),
        Some(Err(e)) => (None, Some(format!("{e:#}"))),
    };
    let (diff, flip_map, failure) = match &expected {
        None if unreadable.is_some() => (None, None, unreadable),
        None => (None, None, Some(format!("no golden image {}", golden.display()))),
        Some(e) if (e.width, e.height) != (actual.width, actual.height) => (
            None,
            None,
            Some(format!(
                "size {}x{} differs from the golden {}x{}",
                actual.width, actual.height, e.width, e.height
            )),
        ),
        Some(e) => {
            let (d, map) = compare(&actual, e);
            (Some(d), Some(map), d.failure(case))
        }
    };
    Ok(Checked { case: case.clone(), actual, expected, diff, flip_map, failure })
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

/// The images written for one case; `None` where there was nothing to
/// write (no golden, or a golden of another size).
pub struct CaseImages {
    /// What the renderer made now.
    pub actual: PathBuf,
    /// The golden image.
    pub expected: Option<PathBuf>,
    /// |actual − expected| ×4, inferno scale.
    pub diff: Option<PathBuf>,
    /// FLIP's per-pixel error, magma scale.
    pub flip: Option<PathBuf>,
}

/// Write actual, expected, difference and FLIP error images of a case into
/// `dir` (the last two when a golden of the same size exists).
pub fn write_failure_images(c: &Checked, dir: &Path) -> Result<CaseImages> {
    std::fs::create_dir_all(dir)?;
    let name = &c.case.name;
    let save = |kind: &str, img: &RgbImage| -> Result<PathBuf> {
        let path = dir.join(format!("{name}.{kind}.png"));
        image_io::save(img, &path, false)?;
        Ok(path)
    };
    let actual = save("actual", &c.actual)?;
    let expected = c.expected.as_ref().map(|e| save("expected", e)).transpose()?;
    // The FLIP map exists exactly when the golden has the actual's size.
    let (diff, flip) = match (&c.expected, &c.flip_map) {
        (Some(e), Some(map)) => (Some(save("diff", &diff_image(&c.actual, e))?), Some(save("flip", map)?)),
        _ => (None, None),
    };
    Ok(CaseImages { actual, expected, diff, flip })
}

/// The HTML review page: a summary, then every case with expected, actual
/// and difference, the failures first.
pub fn html_report(checked: &[Checked], dir: &Path) -> Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let mut rows = String::new();
    let failed: Vec<&Checked> = checked.iter().filter(|c| c.failure.is_some()).collect();
    let passed = checked.iter().filter(|c| c.failure.is_none());
    for c in failed.iter().copied().chain(passed) {
        let images = write_failure_images(c, dir)?;
        let status = match &c.failure {
            None => "<td class=ok>pass</td>".to_string(),
            Some(f) => format!("<td class=bad>FAIL: {}</td>", escape_html(f)),
        };
        let figures =
            c.diff.map_or("-".into(), |d| format!("bad {:.3}%, mean FLIP {:.5}", d.bad * 100.0, d.flip));
        let img = |p: Option<&PathBuf>| match p.and_then(|p| p.file_name()) {
            Some(f) => format!("<td><img src=\"{}\"></td>", f.to_string_lossy()),
            None => "<td>-</td>".into(),
        };
        rows += &format!(
            "<tr><td>{}</td>{status}<td>{figures}</td>{}{}{}{}</tr>\n",
            escape_html(&c.case.name),
            img(images.expected.as_ref()),
            img(Some(&images.actual)),
            img(images.diff.as_ref()),
            img(images.flip.as_ref())
        );
    }
    let summary = summary_line(checked.len(), failed.len());
    let summary_class = if failed.is_empty() { "ok" } else { "bad" };
    let html = format!(
        "<!doctype html><meta charset=utf-8><title>nffkit golden images</title>\
         <style>body{{font-family:sans-serif}}td{{padding:4px;vertical-align:top}}img{{image-rendering:pixelated;width:192px}}\
         .ok{{color:green}}.bad{{color:#b00}}</style>\
         <h1>Golden images</h1><p class={summary_class}>{summary}</p><table><tr><th>case</th><th>status</th><th>metrics</th><th>expected</th><th>actual</th><th>difference (x4)</th><th>FLIP error</th></tr>\n{rows}</table>\n"
    );
    let path = dir.join("index.html");
    atomic::write_bytes(&path, html.as_bytes())?;
    Ok(path)
}

/// "31 cases: 30 passed, 1 failed".
pub fn summary_line(cases: usize, failed: usize) -> String {
    format!("{cases} cases: {} passed, {failed} failed", cases - failed)
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(source: &str) -> Result<Catalogue, toml::de::Error> {
        toml::from_str(&format!("[[case]]\nname = \"x\"\nsource = {source}\n"))
    }

    #[test]
    fn a_source_names_exactly_one_way_to_make_the_scene() {
        assert!(matches!(parse("\"default\"").unwrap().case[0].source, Source::Default));
        assert!(matches!(parse("{ file = \"a.nff\" }").unwrap().case[0].source, Source::File(_)));
        assert!(matches!(
            &parse("{ planegen = [\"--nx\", \"2\", \"--ny\", \"3\"] }").unwrap().case[0].source,
            Source::Planegen(args) if args == &["--nx", "2", "--ny", "3"]
        ));
        for bad in ["{ file = \"a.nff\", mesh = \"b.obj\" }", "{}", "{ movie = \"x\" }", "\"file\""] {
            assert!(parse(bad).is_err(), "accepted {bad}");
        }
    }

    #[test]
    fn generator_options_are_checked_as_their_binaries_check_them() {
        let scene = |source: &str| {
            scene_of(&parse(source).unwrap().case[0], Path::new(".")).map(|s| s.primitives.len())
        };
        assert_eq!(scene("{ planegen = [\"--nx\", \"2\", \"--ny\", \"3\"] }").unwrap(), 6);
        assert_eq!(scene("{ sphereflake = [\"--level\", \"1\", \"--no-floor\"] }").unwrap(), 10);
        assert_eq!(scene("{ spd = [\"tetra\", \"--size\", \"2\"] }").unwrap(), 16);
        assert_eq!(
            scene("{ spd = [\"mount\", \"-s\", \"1\", \"--tessellate\", \"1\"] }").unwrap(),
            8 + 4 * 12
        );
        for (bad, says) in [
            ("{ spd = [\"tetra\", \"--size\", \"99\"] }", "--size 99: tetra takes sizes 1 to"),
            ("{ spd = [\"teapots\"] }", "invalid value 'teapots'"),
            ("{ planegen = [\"--nx\", \"0\"] }", "--nx and --ny must be at least 1"),
            ("{ planegen = [\"--squares\", \"2\"] }", "--squares"),
            ("{ sphereflake = [\"--level\", \"10\"] }", "the highest level is 9"),
        ] {
            let e = format!("{:#}", scene(bad).unwrap_err());
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}
