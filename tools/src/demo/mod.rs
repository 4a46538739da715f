//! The anti-aliasing demonstration: the checkerboard rendered with every
//! sampler at several sample counts and with every filter, compared with a
//! high-sample reference. Produces the demo page ([`page`]: sample patterns,
//! magnified crops of the horizon, errors, a log-log convergence plot with
//! fitted slopes, and optionally the P3D report's figures), plus a labelled
//! contact sheet, an error table and the plot as separate files.
//!
//! Every render is a job run in parallel (each render is itself parallel
//! over tiles), and every image is a pure function of its settings, so the
//! page is the same on any number of cores.

pub mod figures;
pub mod page;
pub mod patterns;
pub mod playground;
pub mod serve;
pub mod text;

use crate::gen::planegen::Board;
use crate::qa::metrics;
use anyhow::{Context, Result};
use nffkit_formats::image_io::RgbImage;
use nffkit_tracer::film::Film;
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::prepare::{prepare, PrepareOptions, RenderScene};
use nffkit_tracer::render::{render, RenderSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use rayon::prelude::*;
use std::fmt::Write as _;
use text::draw_text;

/// What to render.
#[derive(Debug, Clone)]
pub struct DemoConfig {
    /// Tile size in pixels (square).
    pub size: u32,
    /// Sample counts to compare.
    pub spps: Vec<u32>,
    /// Samplers to compare.
    pub samplers: Vec<SamplerKind>,
    /// Filters to compare, on `filter_sampler` at `filter_spp`.
    pub filters: Vec<FilterKind>,
    /// The pattern of the filter row.
    pub filter_sampler: SamplerKind,
    /// The sample count of the filter row.
    pub filter_spp: u32,
    /// Samples per pixel of the reference (Sobol).
    pub reference_spp: u32,
    /// Squares per side of the board.
    pub squares: u32,
    /// Seed of the random patterns.
    pub seed: u32,
    /// The second board's turn in degrees: its squares' edges cross the
    /// pixel grid at a slant instead of along the rows, which changes how
    /// a regular grid of samples errs.
    pub rotation: f64,
}

impl Default for DemoConfig {
    fn default() -> Self {
        DemoConfig {
            size: 256,
            spps: vec![1, 4, 16, 64],
            samplers: SamplerKind::ALL.to_vec(),
            filters: FilterKind::ALL.to_vec(),
            filter_sampler: SamplerKind::MultiJittered,
            filter_spp: 16,
            reference_spp: 1024,
            squares: 32,
            seed: 1,
            rotation: 10.0,
        }
    }
}

impl DemoConfig {
    /// The magnified region: just below the board's horizon, where the
    /// squares shrink below a pixel, as `(x0, y0, width, height)`.
    pub fn crop(&self) -> (u32, u32, u32, u32) {
        let s = self.size;
        let (w, h) = ((s / 8).max(4), (s * 3 / 32).max(3));
        ((s - w) / 2, (s * 5 / 16).min(s - h), w, h)
    }
}

/// One rendered tile and its error.
pub struct DemoTile {
    /// Sampler.
    pub kind: SamplerKind,
    /// Filter.
    pub filter: FilterKind,
    /// Samples per pixel actually taken.
    pub spp: u32,
    /// The image.
    pub film: Film,
    /// Root-mean-square error against the reference (over RGB).
    pub rmse: f64,
    /// Mean structural similarity (luminance, 8x8 windows) to the reference.
    pub ssim: f64,
    /// Mean FLIP error against the reference.
    pub flip: f64,
}

/// Everything the demo produced.
pub struct DemoResult {
    /// The reference image (box filter).
    pub reference: Film,
    /// Tiles, sampler-major, one per sample count, all with the box filter.
    pub tiles: Vec<DemoTile>,
    /// One tile per filter, on the filter row's pattern and count, each
    /// measured against a reference through the same filter.
    pub filter_tiles: Vec<DemoTile>,
    /// The references of the filter row, one per filter.
    pub filter_references: Vec<Film>,
    /// The turned board's reference (box filter).
    pub rotated_reference: Film,
    /// The turned board's tiles, as `tiles`.
    pub rotated_tiles: Vec<DemoTile>,
}

impl DemoResult {
    /// The tiles of one sampler, by increasing sample count.
    pub fn sampler_tiles(&self, kind: SamplerKind) -> impl Iterator<Item = &DemoTile> {
        self.tiles.iter().filter(move |t| t.kind == kind)
    }
}

/// The board the demo renders, turned `rotate` degrees, prepared at the
/// demo's size.
pub fn board(cfg: &DemoConfig, rotate: f64) -> Result<RenderScene> {
    let scene = Board { nx: cfg.squares, ny: cfg.squares, rotate, ..Default::default() }.scene();
    let opts = PrepareOptions { width: Some(cfg.size), height: Some(cfg.size), ..Default::default() };
    Ok(prepare(&scene, &opts)?)
}

/// One render of the demo: which board (0 upright, 1 turned), pattern,
/// count and filter.
type Job = (usize, SamplerKind, u32, FilterKind);

/// Render every tile, in parallel; `tick` is called after each render with
/// (done, total).
pub fn run(cfg: &DemoConfig, tick: &(dyn Fn(usize, usize) + Sync)) -> Result<DemoResult> {
    let boards = [board(cfg, 0.0)?, board(cfg, cfg.rotation)?];
    let shoot = |&(b, kind, spp, filter): &Job| {
        let settings = RenderSettings {
            sampler: Sampler::new(kind, spp, cfg.seed).0,
            centre_single_sample: false,
            filter,
            ..Default::default()
        };
        render(&boards[b], &settings, &|_, _| {}).film
    };
    // References first (Sobol): the upright board through box and through
    // each other filter of the filter row, then the turned board through
    // box; then each board's samplers x counts; then the filter row.
    let mut reference_filters = vec![FilterKind::Box];
    reference_filters.extend(cfg.filters.iter().filter(|&&f| f != FilterKind::Box));
    let reference = |b, filter| (b, SamplerKind::Sobol, cfg.reference_spp, filter);
    let mut jobs: Vec<Job> = reference_filters.iter().map(|&f| reference(0, f)).collect();
    jobs.push(reference(1, FilterKind::Box));
    let references = jobs.len();
    for b in 0..2 {
        for &kind in &cfg.samplers {
            jobs.extend(cfg.spps.iter().map(|&spp| (b, kind, spp, FilterKind::Box)));
        }
    }
    jobs.extend(cfg.filters.iter().map(|&f| (0, cfg.filter_sampler, cfg.filter_spp, f)));
    // Which reference job each tile is measured against.
    let reference_of = |b: usize, filter: FilterKind| match b {
        0 => reference_filters.iter().position(|&f| f == filter).unwrap_or(0),
        _ => references - 1,
    };
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut films: Vec<Film> = jobs
        .par_iter()
        .map(|job| {
            let film = shoot(job);
            tick(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, jobs.len());
            film
        })
        .collect();
    let rest = films.split_off(references);
    let images: Vec<RgbImage> = films.iter().map(Film::to_image).collect();
    let mut tiles: Vec<DemoTile> = jobs[references..]
        .par_iter()
        .zip(rest)
        .map(|(&(b, kind, spp, filter), film)| {
            let image = film.to_image();
            let reference = &images[reference_of(b, filter)];
            DemoTile {
                kind,
                filter,
                spp: Sampler::new(kind, spp, cfg.seed).0.spp,
                rmse: metrics::rmse(&image, reference),
                ssim: metrics::mean_ssim(&image, reference),
                flip: metrics::flip(reference, &image).mean,
                film,
            }
        })
        .collect();
    let per_board = cfg.samplers.len() * cfg.spps.len();
    let filter_tiles = tiles.split_off(2 * per_board);
    let rotated_tiles = tiles.split_off(per_board);
    let filter_references = cfg.filters.iter().map(|&f| films[reference_of(0, f)].clone()).collect();
    let rotated_reference = films.pop().context("the turned board's reference was not rendered")?;
    let reference = films.swap_remove(0);
    Ok(DemoResult { reference, tiles, filter_tiles, filter_references, rotated_reference, rotated_tiles })
}

/// Least-squares slope of log(RMSE) against log(spp): the convergence rate
/// (−1/2 for independent random samples, steeper for stratified patterns);
/// `None` with fewer than two sample counts.
pub fn fitted_slope<'a>(tiles: impl Iterator<Item = &'a DemoTile>) -> Option<f64> {
    let pts: Vec<(f64, f64)> = tiles.map(|t| ((t.spp as f64).ln(), t.rmse.max(1e-9).ln())).collect();
    let n = pts.len() as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// A fitted slope for the page: two decimals, or a dash.
pub fn slope_text(slope: Option<f64>) -> String {
    slope.map_or("—".into(), |s| format!("{s:.2}"))
}

/// `film`'s pixels in the window `(x0, y0, w, h)`, each repeated `k` x `k`
/// times (nearest neighbour, so every pixel stays exact).
pub fn magnify(film: &Film, (x0, y0, w, h): (u32, u32, u32, u32), k: u32) -> RgbImage {
    let (ow, oh) = (w * k, h * k);
    let pixels = (0..ow * oh).map(|i| film.get(x0 + (i % ow) / k, y0 + (i / ow) / k).to_array()).collect();
    RgbImage { width: ow, height: oh, pixels }
}

/// The contact sheet: one row per sampler, one column per sample count, the
/// reference at the end of the first row; each tile labelled.
pub fn contact_sheet(result: &DemoResult, cfg: &DemoConfig) -> RgbImage {
    let (s, label, gap) = (cfg.size, 12u32, 4u32);
    let cols = cfg.spps.len() as u32 + 1;
    let rows = cfg.samplers.len() as u32;
    let (w, h) = (cols * (s + gap) + gap, rows * (s + label + gap) + gap);
    let mut img = RgbImage { width: w, height: h, pixels: vec![[0.12, 0.12, 0.12]; (w * h) as usize] };
    let mut blit = |film: &Film, col: u32, row: u32, text: &str| {
        let (x0, y0) = (gap + col * (s + gap), gap + row * (s + label + gap));
        draw_text(&mut img, x0, y0 + 1, text, [1.0, 1.0, 1.0]);
        for y in 0..s {
            for x in 0..s {
                img.pixels[((y0 + label + y) * w + x0 + x) as usize] = film.get(x, y).to_array();
            }
        }
    };
    for (i, t) in result.tiles.iter().enumerate() {
        let (row, col) = ((i / cfg.spps.len()) as u32, (i % cfg.spps.len()) as u32);
        blit(&t.film, col, row, &format!("{} {}", t.kind, t.spp));
    }
    blit(&result.reference, cols - 1, 0, &format!("ref {}", cfg.reference_spp));
    img
}

/// The error table as markdown.
pub fn table(result: &DemoResult, cfg: &DemoConfig) -> String {
    let mut out = String::from("| sampler |");
    for spp in &cfg.spps {
        let _ = write!(out, " RMSE {spp} spp | SSIM {spp} spp |");
    }
    out += "\n|---|";
    out += &"---:|---:|".repeat(cfg.spps.len());
    out += "\n";
    for chunk in result.tiles.chunks(cfg.spps.len()) {
        let _ = write!(out, "| {} |", chunk[0].kind);
        for t in chunk {
            let _ = write!(out, " {:.5} | {:.4} |", t.rmse, t.ssim);
        }
        out += "\n";
    }
    out
}

/// The convergence plot of the upright board (see [`convergence_plot`]).
pub fn convergence_svg(result: &DemoResult, cfg: &DemoConfig) -> String {
    let title = format!(
        "RMSE against a {}-spp reference (checkerboard, {}x{}), log-log",
        cfg.reference_spp, cfg.size, cfg.size
    );
    convergence_plot(&result.tiles, cfg, &title)
}

/// Line styles of the plot, one per sampler: colour, dash pattern, width.
/// Multi-jittered, the report's pattern, is drawn widest; the other
/// stratified patterns, which lie close to it, differ in dashes too.
fn line_style(kind: SamplerKind, k: usize) -> (&'static str, &'static str, f64) {
    const COLORS: [&str; 8] =
        ["#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00", "#a65628", "#f781bf", "#333333"];
    const DASHES: [&str; 4] = ["none", "8 4", "2 3", "10 3 2 3"];
    match kind {
        SamplerKind::MultiJittered => ("#000000", "none", 4.0),
        _ => (COLORS[k % COLORS.len()], DASHES[k % DASHES.len()], 2.0),
    }
}

/// RMSE against spp, log-log, one line per sampler (`tiles` sampler-major,
/// one per count), labelled at its right end with its name and fitted
/// slope, and dashed reference slopes −1/2 (independent random samples)
/// and −1 from the worst 1-spp error.
pub fn convergence_plot(tiles: &[DemoTile], cfg: &DemoConfig, title: &str) -> String {
    let (w, h, m, labels) = (960.0, 560.0, 64.0, 230.0);
    let errs: Vec<f64> = tiles.iter().map(|t| t.rmse.max(1e-6)).collect();
    let (emin, emax) = errs.iter().fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    let (lemin, lemax) = (emin.log10().floor(), emax.log10().ceil().max(emin.log10().floor() + 1.0));
    let spps: Vec<f64> = tiles.iter().map(|t| t.spp as f64).collect();
    let (smin, smax) = spps.iter().fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    let (lsmin, lsmax) = (smin.log2(), smax.log2().max(smin.log2() + 1.0));
    let x1 = w - m - labels;
    let px = |spp: f64| m + (spp.log2() - lsmin) / (lsmax - lsmin) * (x1 - m);
    let py = |e: f64| h - m - (e.max(1e-6).log10() - lemin) / (lemax - lemin) * (h - 2.0 * m);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"14\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">{title}</text>\n",
        w / 2.0
    );
    let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{}\" x2=\"{x1}\" y2=\"{}\" stroke=\"black\"/>", h - m, h - m);
    let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{m}\" x2=\"{m}\" y2=\"{}\" stroke=\"black\"/>", h - m);
    let mut counts: Vec<u32> = tiles.iter().map(|t| t.spp).collect();
    counts.sort_unstable();
    counts.dedup();
    for spp in counts {
        let x = px(spp as f64);
        let _ = writeln!(s, "<text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">{spp}</text>", h - m + 20.0);
        let _ = writeln!(s, "<line x1=\"{x}\" y1=\"{m}\" x2=\"{x}\" y2=\"{}\" stroke=\"#eee\"/>", h - m);
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">samples per pixel taken (log scale)</text>",
        (m + x1) / 2.0,
        h - 18.0
    );
    let mut e = lemin;
    while e <= lemax {
        let y = py(10f64.powf(e));
        let _ = writeln!(s, "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{e}</text>", m - 6.0, y + 4.0);
        let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{y}\" x2=\"{x1}\" y2=\"{y}\" stroke=\"#ddd\"/>");
        e += 1.0;
    }
    // Reference slopes from the largest 1-spp error, clipped to the plot.
    let e0 = tiles.iter().filter(|t| t.spp as f64 == smin).map(|t| t.rmse).fold(emax, f64::max);
    for (slope, label) in [(-0.5, "slope −1/2"), (-1.0, "slope −1")] {
        let floor = 10f64.powf(lemin);
        let end = smax.min(smin * (floor / e0).powf(1.0 / slope));
        let e1 = e0 * (end / smin).powf(slope);
        let _ = writeln!(
            s,
            "<line class=\"reference-slope\" x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#888\" stroke-dasharray=\"6 4\"/>",
            px(smin),
            py(e0),
            px(end),
            py(e1)
        );
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"#666\" text-anchor=\"end\">{label}</text>",
            px(end) - 4.0,
            py(e1) - 8.0
        );
    }
    // Direct labels at each line's end, pushed apart to stay legible.
    let lines: Vec<&[DemoTile]> = tiles.chunks(cfg.spps.len().max(1)).collect();
    let mut ends: Vec<(f64, usize)> =
        lines.iter().enumerate().map(|(k, c)| (py(c[c.len() - 1].rmse), k)).collect();
    ends.sort_by(|a, b| a.0.total_cmp(&b.0));
    for i in 1..ends.len() {
        ends[i].0 = ends[i].0.max(ends[i - 1].0 + 17.0);
    }
    for (label_y, k) in ends {
        let chunk = lines[k];
        let kind = chunk[0].kind;
        let (color, dash, width) = line_style(kind, k);
        let points: Vec<String> =
            chunk.iter().map(|t| format!("{:.1},{:.1}", px(t.spp as f64), py(t.rmse))).collect();
        let _ = writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"{width}\" stroke-dasharray=\"{dash}\" points=\"{}\"/>",
            points.join(" ")
        );
        let last = &chunk[chunk.len() - 1];
        let (lx, ly) = (px(last.spp as f64), py(last.rmse));
        let _ = writeln!(
            s,
            "<line x1=\"{lx:.1}\" y1=\"{ly:.1}\" x2=\"{:.1}\" y2=\"{label_y:.1}\" stroke=\"{color}\" stroke-width=\"1\"/>",
            x1 + 14.0
        );
        let weight = if kind == SamplerKind::MultiJittered { " font-weight=\"bold\"" } else { "" };
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{:.1}\" fill=\"{color}\"{weight}>{kind} (slope {})</text>",
            x1 + 18.0,
            label_y + 5.0,
            slope_text(fitted_slope(chunk.iter()))
        );
    }
    s += "</svg>\n";
    s
}
