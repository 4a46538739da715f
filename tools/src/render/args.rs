//! What the user typed to `render`, and the one step that turns it into
//! validated, typed settings (ripgrep's low and high arguments).
//!
//! [`RenderArgs`] is the clap schema: flag names, help texts and value
//! parsers live here and nowhere else. [`RenderArgs::command`] checks every
//! value and combination once and yields a [`Command`] holding the tracer's
//! own types ([`PrepareOptions`], [`RenderSettings`]); nothing downstream
//! validates again. Library errors describe the problem; the messages here
//! add the flag that caused it.

use crate::input::Warnings;
use anyhow::{bail, Result};
use clap::Parser;
use nffkit_formats::image_io::ImageKind;
use nffkit_formats::nff::ParseOptions;
use nffkit_formats::{Dialect, Directives};
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::light::LightShape;
use nffkit_tracer::prepare::{Ambient, PrepareOptions};
use nffkit_tracer::render::{PixelWindow, RenderSettings, ShadeSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::path::PathBuf;

/// Render NFF and P3F scenes with a Whitted ray tracer, or validate them
/// (--check).
///
/// With no FILE, renders the built-in default scene (a level-3 sphereflake
/// over a checkerboard). An NFF camera's `angle` is the spec's: measured
/// between the centres of the outer pixel rows/columns of the smaller image
/// side; a P3F camera's is the P3D course's: the image height, edge to edge.
/// P3F files (a .p3f name, --dialect p3f, or recognised on standard input)
/// render as the course meant: specular colours, Fresnel-weighted glass,
/// area lights, the lens, the cube map, and their `spp` and `accel` as
/// defaults the flags override (docs/p3f.md).
#[derive(Parser, Debug, Clone)]
#[command(name = "render", version, allow_negative_numbers = true)]
pub struct RenderArgs {
    /// Scene file(s); `-` reads standard input. Rendering takes one file;
    /// --check takes any number.
    pub files: Vec<PathBuf>,

    /// Output image; the extension picks the format: .png (8-bit, default),
    /// .ppm, .exr or .hdr (linear floating point). Default: the scene's
    /// file name with .png, in the current directory.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Image width in pixels (overrides the file's; keeps the field of view).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the file's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub height: Option<u32>,
    /// Recursion limit, counting the eye ray as depth 1.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub depth: u32,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Print nothing but errors (and, with --check, each file's summary).
    #[arg(short, long)]
    pub quiet: bool,
    /// Print every warning and note. By default the first few of each kind
    /// are printed and the rest counted ("... and 24518 more like ...").
    #[arg(long, conflicts_with = "quiet")]
    pub all_warnings: bool,
    /// The most a scene read from a stream (standard input, a pipe, a
    /// device) may bring, in MB, before render gives up on it (default
    /// 2048; never more than a third of the memory available). Files are
    /// mapped, without a limit.
    #[arg(long, value_name = "MB", value_parser = clap::value_parser!(u64).range(1..=1 << 30))]
    pub stream_limit: Option<u64>,
    /// Print ray and traversal statistics to standard output.
    #[arg(long)]
    pub stats: bool,
    /// SPD test procedure: one eye ray through each pixel corner ((w+1)x(h+1)
    /// rays, each pixel the mean of its four corners), depth 5, with
    /// statistics, so counts compare with those the SPD publishes.
    #[arg(long = "spd-stats")]
    pub spd: bool,
    /// Adaptive depth control: skip reflected and refracted rays whose
    /// weight (product of Ks and T along the path) is below this; 0 (the
    /// default) traces every ray, as classic NFF renderers do. POV-Ray's
    /// default is 1/255 = 0.0039.
    #[arg(long, default_value_t = 0.0, value_parser = unit_interval)]
    pub min_weight: f32,
    /// Ambient light: `ambient × colour × Kd` at every hit. A number, or
    /// `spd` for the SPD Readme's lighting (the ambient and each light
    /// without a colour at 1/(2 sqrt(n)) for n lights). Default: none, the
    /// classic image.
    #[arg(long, value_name = "VALUE|spd", value_parser = ambient)]
    pub ambient: Option<Ambient>,
    /// Seed of every random pattern.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Apply the sRGB transfer curve when writing 8-bit images (off by
    /// default, so images match classic NFF renderers).
    #[arg(long)]
    pub srgb: bool,

    /// Validate the files: print every diagnostic and a summary per file.
    #[arg(long)]
    pub check: bool,
    /// Accept a file without a `v` block (a fragment to append to a scene).
    #[arg(long)]
    pub fragment: bool,
    /// Unknown entities become warnings and are skipped.
    #[arg(long)]
    pub lenient: bool,
    /// Read the plain language: in NFF the 2017 course extensions `pl`
    /// (infinite plane through three points) and `aabb` (axis-aligned box),
    /// read by default, become errors; in P3F, what the course's description
    /// does not hold (extra `f` values, unknown directives), warned about
    /// and skipped by default, becomes an error.
    #[arg(long, conflicts_with = "lenient")]
    pub strict: bool,
    /// The scene language: nff, or p3f (the P3D course's). Default: from
    /// the file name (.p3f, .nff), else recognised from the content.
    #[arg(long, value_name = "nff|p3f", value_parser = crate::cli_util::parse_dialect)]
    pub dialect: Option<Dialect>,
    /// Let a P3F scene's `env` folder lie outside the scene's folder (or be
    /// reached through a link that leads out of it). Off by default: a
    /// downloaded scene reads nothing outside its folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// The cube map (six images: right, left, top, bottom, front, back,
    /// .jpg or .png) that rays leaving the scene see, in place of a P3F
    /// scene's `env` or an NFF scene's background.
    #[arg(long, value_name = "DIR")]
    pub env: Option<PathBuf>,

    /// The spec's one-sided rule: opaque objects are invisible from behind.
    /// Default is two-sided shading; transmitters are always two-sided.
    #[arg(long)]
    pub one_sided: bool,

    /// Samples per pixel (anti-aliasing). Default: a P3F file's `spp`,
    /// else 1.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: Option<u32>,
    /// Sample pattern. With 1 sample per pixel and no --sampler, the pixel
    /// centre is used (classic NFF); otherwise the default is multi-jittered.
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerKind>,
    /// Reconstruction filter.
    #[arg(long, value_enum, default_value_t = FilterKind::Box)]
    pub filter: FilterKind,

    /// Give each point light an area of this size (soft shadows): one light
    /// sample per light per eye sample.
    #[arg(long, default_value_t = 0.0, value_parser = non_negative)]
    pub light_size: f32,
    /// Shape of the light area: side of a square or diameter of a disc.
    #[arg(long, value_enum, default_value_t = LightShape::Square)]
    pub light_shape: LightShape,

    /// Lens radius for depth of field (0: pinhole). Default: a P3F view's
    /// lens (`aperture` pixels), else a pinhole.
    #[arg(long, value_parser = non_negative)]
    pub aperture: Option<f32>,
    /// Distance in focus. Default: a P3F view's `focal` ratio of the
    /// from-at distance, else the from-at distance.
    #[arg(long, value_parser = positive)]
    pub focus: Option<f32>,
    /// Weigh transmitters' reflection and transmission by Fresnel's
    /// equations (reflection Kr, transmission T(1 - Kr)), as P3F scenes
    /// always are, instead of NFF's fixed Ks and T.
    #[arg(long)]
    pub fresnel: bool,

    /// Acceleration structure. Default: a P3F file's `accel` (1 grid, 2
    /// BVH; its 0, "none", keeps the BVH), else the BVH. Every one gives
    /// the same image.
    #[arg(long, value_enum)]
    pub accel: Option<AccelKind>,
    /// Uniform grid density multiplier M (cells per axis from formula (1)
    /// of the P3D report); 0 gives one cell.
    #[arg(long, default_value_t = 2.0, value_parser = non_negative)]
    pub grid_m: f32,
    /// Turn the grid's mailboxes off (to measure what they save).
    #[arg(long)]
    pub no_mailbox: bool,
    /// Turn the shadow cache off (each light's last occluder tested first;
    /// to measure what it saves). The image does not change.
    #[arg(long)]
    pub no_shadow_cache: bool,
    /// Trace eye rays and their shadow rays one by one instead of as SIMD
    /// packets (a pixel's samples, or 4x4 pixel centres, together; to
    /// measure what packets save). The image does not change.
    #[arg(long)]
    pub no_packets: bool,
    /// Where to trace: `cpu` (every core, SIMD packets) or `gpu` (compute
    /// shaders through wgpu on Vulkan, Metal or DX12; `WGPU_ADAPTER_NAME`
    /// picks an adapter by name, `WGPU_BACKEND` a backend). The same
    /// samples, so the GPU's image matches the CPU's within floating-point
    /// differences; the GPU always walks a BVH.
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Also write a heat map of the traversal work per pixel (primitive
    /// tests plus nodes or cells visited) to this PNG, with a colour bar.
    #[arg(long, value_name = "FILE")]
    pub aov_cost: Option<PathBuf>,

    /// Render only a crop window, as fractions of the image (pbrt's
    /// convention): columns ceil(x0*w)..ceil(x1*w), rows likewise. Written
    /// to .exr, the part carries its window and can be merged by nffmerge.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = crop_window, group = "part")]
    pub crop: Option<[f64; 4]>,
    /// Render only these pixels: columns X0..X1, rows Y0..Y1, ends exclusive.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = pixel_bounds, group = "part")]
    pub pixel_bounds: Option<[u32; 4]>,
    /// Render the K-th of N parts (0-based): horizontal bands of whole
    /// 16-row render tiles, as equal as the tiles allow. For render farms:
    /// write each part to .exr and join them with nffmerge.
    #[arg(long, value_name = "K/N", value_parser = tile_of, group = "part")]
    pub tile: Option<[u32; 2]>,
}

/// The processor that traces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    /// The CPU's cores.
    Cpu,
    /// A GPU, through wgpu.
    Gpu,
}

/// Which part of the image to render, as the user gave it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PartSpec {
    /// Fractions of the image: x0, x1, y0, y1.
    Crop([f64; 4]),
    /// Pixels: x0, x1, y0, y1, ends exclusive.
    Pixels([u32; 4]),
    /// The K-th of N bands.
    Tile {
        /// Which band, from 0.
        k: u32,
        /// How many bands.
        n: u32,
    },
}

impl PartSpec {
    /// The pixels of a `width` x `height` image this part covers.
    pub fn window(&self, width: u32, height: u32) -> Result<PixelWindow> {
        let win = match *self {
            PartSpec::Crop([x0, x1, y0, y1]) => {
                let at = |f: f64, n: u32| (f * n as f64).ceil() as u32;
                PixelWindow { x0: at(x0, width), x1: at(x1, width), y0: at(y0, height), y1: at(y1, height) }
            }
            PartSpec::Pixels([x0, x1, y0, y1]) => {
                if x1 > width || y1 > height {
                    bail!("--pixel-bounds {x0},{x1},{y0},{y1} reaches past the {width}x{height} image");
                }
                PixelWindow { x0, x1, y0, y1 }
            }
            PartSpec::Tile { k, n } => {
                let rows = height.div_ceil(TILE_ROWS);
                if n > rows {
                    bail!(
                        "--tile {k}/{n}: the {width}x{height} image has only {rows} bands of {TILE_ROWS} rows; use at most {rows} parts"
                    );
                }
                let band = |i: u32| ((i as u64 * rows as u64 / n as u64) as u32 * TILE_ROWS).min(height);
                PixelWindow { x0: 0, x1: width, y0: band(k), y1: band(k + 1) }
            }
        };
        if win.width() == 0 || win.height() == 0 {
            let flag = match *self {
                PartSpec::Crop([x0, x1, y0, y1]) => format!("--crop {x0},{x1},{y0},{y1}"),
                PartSpec::Pixels([x0, x1, y0, y1]) => format!("--pixel-bounds {x0},{x1},{y0},{y1}"),
                PartSpec::Tile { k, n } => format!("--tile {k}/{n}"),
            };
            bail!("{flag} covers no whole pixel of the {width}x{height} image");
        }
        Ok(win)
    }
}

/// Rows of one band of render tiles (the renderer's tile side).
const TILE_ROWS: u32 = nffkit_tracer::render::TILE;

/// What `render` is asked to do, validated.
#[derive(Debug, Clone)]
pub enum Command {
    /// Validate files and print their diagnostics.
    Check {
        /// The files (`-` is standard input).
        files: Vec<PathBuf>,
        /// How to parse them.
        parse: ParseOptions,
        /// Their language, when the user said.
        dialect: Option<Dialect>,
        /// Which warnings and notes to print.
        warnings: Warnings,
    },
    /// Render one scene.
    Render(Box<RenderConfig>),
}

/// A render, ready to run: every value checked, in the tracer's types.
#[derive(Debug, Clone)]
pub struct RenderConfig {
    /// The scene file (`-` is standard input); `None` is the default scene.
    pub input: Option<PathBuf>,
    /// Where the image goes, and its format.
    pub output: PathBuf,
    /// The output's format, from its extension.
    pub output_kind: ImageKind,
    /// How to parse the scene.
    pub parse: ParseOptions,
    /// The scene's language, when the user said (else from its name or
    /// content).
    pub dialect: Option<Dialect>,
    /// May the scene's cube map lie outside its folder.
    pub allow_outside_paths: bool,
    /// The cube map the user named, in place of the scene's.
    pub env: Option<PathBuf>,
    /// What the command line set of what a P3F file's directives also
    /// set: those the file may not change.
    pub given: Given,
    /// How to turn the scene into a renderable one.
    pub prepare: PrepareOptions,
    /// How to render it.
    pub settings: RenderSettings,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// sRGB curve on 8-bit output.
    pub srgb: bool,
    /// Where the cost heat map goes, if asked for.
    pub aov_cost: Option<PathBuf>,
    /// Print statistics.
    pub stats: bool,
    /// Print nothing but errors.
    pub quiet: bool,
    /// Which of the scene's warnings to print.
    pub warnings: Warnings,
    /// Adjustments to tell the user about (a sample count rounded up).
    pub notes: Vec<String>,
    /// Only a part of the image, for render farms.
    pub part: Option<PartSpec>,
    /// Where to trace.
    pub device: Device,
}

impl RenderArgs {
    /// Validate everything and say what to do.
    pub fn command(&self) -> Result<Command> {
        if self.check {
            if self.files.is_empty() {
                bail!("--check needs at least one file");
            }
            return Ok(Command::Check {
                files: self.files.clone(),
                parse: self.parse_options(),
                dialect: self.dialect,
                warnings: self.warnings(),
            });
        }
        Ok(Command::Render(Box::new(self.render_config()?)))
    }

    /// The render configuration (whatever --check says).
    pub fn render_config(&self) -> Result<RenderConfig> {
        if self.files.len() > 1 {
            bail!("render takes one scene file (got {}); --check takes many", self.files.len());
        }
        let output = self.output_path();
        let output_kind = ImageKind::from_path(&output)?;
        if self.spd && self.part().is_some() {
            bail!("--spd-stats traces pixel corners over the whole image; it takes no --crop, --pixel-bounds or --tile");
        }
        if self.device == Device::Gpu {
            if self.spd {
                bail!("--spd-stats counts the SPD procedure's rays on the CPU; it takes no --device gpu");
            }
            if self.aov_cost.is_some() {
                bail!("--aov-cost counts the CPU's traversal work; it takes no --device gpu");
            }
        }
        if let Some(cost) = &self.aov_cost {
            if ImageKind::from_path(cost)? != ImageKind::Png {
                bail!("--aov-cost writes a PNG heat map; {} is not a .png", cost.display());
            }
        }
        let kind = self.sampler.unwrap_or(SamplerKind::MultiJittered);
        let (sampler, note) = Sampler::new(kind, self.spp.unwrap_or(1), self.seed);
        let settings = RenderSettings {
            sampler,
            centre_single_sample: self.sampler.is_none(),
            filter: self.filter,
            shade: ShadeSettings {
                max_depth: if self.spd { 5 } else { self.depth },
                light_size: self.light_size,
                light_shape: self.light_shape,
                min_weight: if self.spd { 0.0 } else { self.min_weight },
                spd: self.spd,
            },
            cost: self.aov_cost.is_some(),
            shadow_cache: !self.no_shadow_cache,
            packets: !self.no_packets,
            row_stride: 1,
            window: None,
        };
        let prepare = PrepareOptions {
            width: self.width,
            height: self.height,
            one_sided: self.one_sided,
            aperture: self.aperture,
            focus: self.focus,
            fresnel: self.fresnel,
            accel: AccelOptions {
                kind: self.accel.unwrap_or(AccelKind::Bvh),
                grid_m: self.grid_m,
                mailbox: !self.no_mailbox,
            },
            ambient: self.ambient.unwrap_or_default(),
        };
        Ok(RenderConfig {
            input: self.files.first().cloned(),
            output,
            output_kind,
            parse: self.parse_options(),
            dialect: self.dialect,
            allow_outside_paths: self.allow_outside_paths,
            env: self.env.clone(),
            given: Given { spp: self.spp.is_some(), accel: self.accel.is_some() },
            prepare,
            settings,
            threads: self.threads.unwrap_or(0) as usize,
            srgb: self.srgb,
            aov_cost: self.aov_cost.clone(),
            stats: self.stats || self.spd,
            quiet: self.quiet,
            warnings: self.warnings(),
            notes: note.into_iter().map(|m| format!("--spp: {m}")).collect(),
            part: self.part(),
            device: self.device,
        })
    }

    fn warnings(&self) -> Warnings {
        if self.quiet {
            Warnings::Hide
        } else if self.all_warnings {
            Warnings::All
        } else {
            Warnings::Summarise
        }
    }

    fn parse_options(&self) -> ParseOptions {
        ParseOptions {
            dialect: Default::default(),
            lenient: self.lenient,
            fragment: self.fragment,
            strict: self.strict,
        }
    }

    fn part(&self) -> Option<PartSpec> {
        self.crop
            .map(PartSpec::Crop)
            .or(self.pixel_bounds.map(PartSpec::Pixels))
            .or(self.tile.map(|[k, n]| PartSpec::Tile { k, n }))
    }

    fn output_path(&self) -> PathBuf {
        if let Some(o) = &self.output {
            return o.clone();
        }
        match self.files.first() {
            Some(f) if f.as_os_str() != "-" => {
                PathBuf::from(f.file_stem().unwrap_or_default()).with_extension("png")
            }
            Some(_) => PathBuf::from("render.png"),
            None => PathBuf::from("nffkit-default.png"),
        }
    }
}

/// Which settings the command line gave, of those a P3F file's directives
/// also give.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Given {
    /// `--spp`.
    pub spp: bool,
    /// `--accel`.
    pub accel: bool,
}

impl RenderConfig {
    /// Take a P3F scene's `spp` and `accel` where the command line gave
    /// none (the course's `accel` numbers: 1 uniform grid, 2 BVH; 0, "none",
    /// keeps the BVH, with a note).
    pub fn apply_directives(&mut self, d: &Directives) {
        if let (Some(spp), false) = (d.spp, self.given.spp) {
            let s = &self.settings.sampler;
            // 0: one sample, at the pixel centre unless --sampler says.
            let (sampler, note) = Sampler::new(s.kind, spp.max(1), s.seed);
            self.settings.sampler = sampler;
            self.notes.extend(note.map(|m| format!("the scene's `spp {spp}`: {m}")));
        }
        match (d.accel, self.given.accel) {
            // The course's template starts every file at `accel 0`, its
            // students' tracers before they have a structure; every
            // accelerator here gives the same image, so 0 asks for nothing.
            (Some(0), false) => self.notes.push(
                "the scene's `accel 0` (the course's \"none\") is taken as no preference: the BVH, \
                 which gives the same image; --accel none traces without one"
                    .into(),
            ),
            (Some(n), false) => {
                self.prepare.accel.kind = if n == 1 { AccelKind::Grid } else { AccelKind::Bvh }
            }
            _ => {}
        }
    }
}

/// The render configuration for `render` arguments given as strings (the
/// golden catalogue's `render = [...]`), without the program name.
pub fn render_config_from<I, S>(args: I) -> Result<RenderConfig>
where
    I: IntoIterator<Item = S>,
    S: Into<std::ffi::OsString> + Clone,
{
    let args = RenderArgs::try_parse_from(
        std::iter::once(std::ffi::OsString::from("render")).chain(args.into_iter().map(Into::into)),
    )?;
    args.render_config()
}

fn four<T: std::str::FromStr + Copy>(s: &str) -> Result<[T; 4], String> {
    let parts: Vec<Option<T>> = s.split(',').map(|p| p.trim().parse().ok()).collect();
    match parts[..] {
        [Some(a), Some(b), Some(c), Some(d)] => Ok([a, b, c, d]),
        _ => Err(format!("expected four comma-separated numbers X0,X1,Y0,Y1, found `{s}`")),
    }
}

fn crop_window(s: &str) -> Result<[f64; 4], String> {
    let [x0, x1, y0, y1] = four::<f64>(s)?;
    let unit = |v: f64| (0.0..=1.0).contains(&v);
    if !([x0, x1, y0, y1].into_iter().all(unit) && x0 < x1 && y0 < y1) {
        return Err(format!("needs fractions 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1, found `{s}`"));
    }
    Ok([x0, x1, y0, y1])
}

fn pixel_bounds(s: &str) -> Result<[u32; 4], String> {
    let [x0, x1, y0, y1] = four::<u32>(s)?;
    if !(x0 < x1 && y0 < y1) {
        return Err(format!("needs x0 < x1 and y0 < y1 (ends exclusive), found `{s}`"));
    }
    Ok([x0, x1, y0, y1])
}

fn tile_of(s: &str) -> Result<[u32; 2], String> {
    let parsed = s
        .split_once('/')
        .and_then(|(k, n)| Some((k.trim().parse::<u32>().ok()?, n.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((k, n)) if n >= 1 && k < n => Ok([k, n]),
        Some((k, n)) => Err(format!("part {k} of {n} does not exist: K counts from 0 to N-1")),
        None => Err(format!("expected K/N (the K-th of N parts, from 0), found `{s}`")),
    }
}

fn number(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("`{s}` is not a finite number")),
    }
}

fn non_negative(s: &str) -> Result<f32, String> {
    number(s).and_then(|v| if v >= 0.0 { Ok(v) } else { Err(format!("must not be negative (got {v})")) })
}

fn ambient(s: &str) -> Result<Ambient, String> {
    if s.eq_ignore_ascii_case("spd") {
        return Ok(Ambient::Spd);
    }
    non_negative(s).map(Ambient::Value).map_err(|e| format!("{e}; expected a number or `spd`"))
}

fn positive(s: &str) -> Result<f32, String> {
    number(s).and_then(|v| if v > 0.0 { Ok(v) } else { Err(format!("must be greater than 0 (got {v})")) })
}

fn unit_interval(s: &str) -> Result<f32, String> {
    number(s).and_then(|v| {
        if (0.0..1.0).contains(&v) {
            Ok(v)
        } else {
            Err(format!("must be in [0, 1) (got {v})"))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(args: &[&str]) -> Result<RenderConfig> {
        render_config_from(args.iter().copied())
    }

    #[test]
    fn values_are_checked_once_with_the_flag_named() {
        for (args, flag) in [
            (&["--light-size", "-1"][..], "--light-size"),
            (&["--grid-m", "nan"], "--grid-m"),
            (&["--focus", "0"], "--focus"),
            (&["--min-weight", "1"], "--min-weight"),
            (&["--width", "0"], "--width"),
            (&["--sampler", "halton"], "--sampler"),
        ] {
            let e = format!("{:#}", config(args).unwrap_err());
            assert!(e.contains(flag), "{args:?}: {e}");
        }
        let e = format!("{:#}", config(&["-o", "x.jpg"]).unwrap_err());
        assert!(e.contains("x.jpg") && e.contains(".png"), "{e}");
    }

    #[test]
    fn library_enums_are_the_command_line_choices() {
        use clap::ValueEnum;
        for k in SamplerKind::ALL {
            let c = config(&["--spp", "4", "--sampler", k.name()]).unwrap();
            assert_eq!(c.settings.sampler.kind, *k);
        }
        assert_eq!(<FilterKind as ValueEnum>::value_variants().len(), FilterKind::ALL.len());
        let c = config(&["--accel", "grid", "--light-shape", "disk", "--filter", "mitchell"]).unwrap();
        assert_eq!(c.prepare.accel.kind, AccelKind::Grid);
        assert_eq!(c.settings.shade.light_shape, LightShape::Disk);
        assert_eq!(c.settings.filter, FilterKind::Mitchell);
    }

    #[test]
    fn a_p3f_files_directives_yield_to_the_flags() {
        let d = Directives { spp: Some(9), accel: Some(1) };
        let mut c = config(&[]).unwrap();
        c.apply_directives(&d);
        assert_eq!((c.settings.sampler.spp, c.prepare.accel.kind), (9, AccelKind::Grid));
        let mut c = config(&["--spp", "16", "--accel", "none"]).unwrap();
        c.apply_directives(&d);
        assert_eq!((c.settings.sampler.spp, c.prepare.accel.kind), (16, AccelKind::None));
        let mut c = config(&[]).unwrap();
        c.apply_directives(&Directives { spp: Some(0), accel: Some(0) });
        assert_eq!((c.settings.sampler.spp, c.prepare.accel.kind), (1, AccelKind::Bvh));
        assert!(c.settings.centre_single_sample && c.notes.iter().any(|n| n.contains("accel 0")));
    }

    #[test]
    fn spd_stats_fixes_depth_and_weight() {
        let c = config(&["--spd-stats", "--depth", "9", "--min-weight", "0.1"]).unwrap();
        assert_eq!((c.settings.shade.max_depth, c.settings.shade.min_weight, c.stats), (5, 0.0, true));
    }
}
