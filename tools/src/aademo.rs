//! The anti-aliasing demonstration: the checkerboard rendered with every
//! sampler at several sample counts, compared with a high-sample reference.
//! Produces a labelled contact sheet, an error table and a log-log
//! convergence plot.

use crate::metrics;
use crate::planegen::Board;
use crate::text::draw_text;
use anyhow::Result;
use nffkit_formats::image_io::RgbImage;
use nffkit_tracer::film::Film;
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use nffkit_tracer::render::{render, RenderSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::fmt::Write as _;

/// What to render.
#[derive(Debug, Clone)]
pub struct DemoConfig {
    /// Tile size in pixels (square).
    pub size: u32,
    /// Sample counts to compare.
    pub spps: Vec<u32>,
    /// Samplers to compare.
    pub samplers: Vec<SamplerKind>,
    /// Samples per pixel of the reference (Sobol).
    pub reference_spp: u32,
    /// Squares per side of the board.
    pub squares: u32,
    /// Seed of the random patterns.
    pub seed: u32,
}

impl Default for DemoConfig {
    fn default() -> Self {
        DemoConfig {
            size: 128,
            spps: vec![1, 4, 16, 64],
            samplers: SamplerKind::ALL.to_vec(),
            reference_spp: 1024,
            squares: 32,
            seed: 1,
        }
    }
}

/// One rendered tile and its error.
pub struct DemoTile {
    /// Sampler.
    pub kind: SamplerKind,
    /// Samples per pixel actually taken.
    pub spp: u32,
    /// The image.
    pub film: Film,
    /// Root-mean-square error against the reference (over RGB).
    pub rmse: f64,
    /// Mean structural similarity (luminance, 8x8 windows) to the reference.
    pub ssim: f64,
}

/// Everything the demo produced.
pub struct DemoResult {
    /// The reference image.
    pub reference: Film,
    /// Tiles, sampler-major.
    pub tiles: Vec<DemoTile>,
}

/// Render every tile.
pub fn run(cfg: &DemoConfig, progress: &dyn Fn(&str)) -> Result<DemoResult> {
    let board = Board { nx: cfg.squares, ny: cfg.squares, ..Default::default() };
    let scene = board.scene();
    let opts = PrepareOptions { width: Some(cfg.size), height: Some(cfg.size), ..Default::default() };
    let prepared = prepare(&scene, &opts)?;
    let shoot = |kind: SamplerKind, spp: u32| {
        let settings = RenderSettings {
            sampler: Sampler::new(kind, spp, cfg.seed).0,
            centre_single_sample: false,
            ..Default::default()
        };
        render(&prepared, &settings, &|_, _| {}).film
    };
    progress(&format!("reference: sobol, {} spp", cfg.reference_spp));
    let reference = shoot(SamplerKind::Sobol, cfg.reference_spp);
    let reference_image = reference.to_image();
    let mut tiles = Vec::new();
    for &kind in &cfg.samplers {
        for &spp in &cfg.spps {
            let sampler = Sampler::new(kind, spp, cfg.seed).0;
            progress(&format!("{kind}, {} spp", sampler.spp));
            let film = shoot(kind, spp);
            let image = film.to_image();
            let rmse = metrics::rmse(&image, &reference_image);
            let ssim = metrics::mean_ssim(&image, &reference_image);
            tiles.push(DemoTile { kind, spp: sampler.spp, film, rmse, ssim });
        }
    }
    Ok(DemoResult { reference, tiles })
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

/// The convergence plot: RMSE against spp, log-log, one line per sampler.
pub fn convergence_svg(result: &DemoResult, cfg: &DemoConfig) -> String {
    const COLORS: [&str; 8] =
        ["#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00", "#a65628", "#f781bf", "#333333"];
    let (w, h, m) = (640.0, 420.0, 60.0);
    let errs: Vec<f64> = result.tiles.iter().map(|t| t.rmse.max(1e-6)).collect();
    let (emin, emax) = errs.iter().fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    let (lemin, lemax) = (emin.log10().floor(), emax.log10().ceil().max(emin.log10().floor() + 1.0));
    let spps: Vec<f64> = result.tiles.iter().map(|t| t.spp as f64).collect();
    let (smin, smax) = spps.iter().fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    let (lsmin, lsmax) = (smin.log2(), smax.log2().max(smin.log2() + 1.0));
    let px = |spp: f64| m + (spp.log2() - lsmin) / (lsmax - lsmin) * (w - 2.0 * m - 120.0);
    let py = |e: f64| h - m - (e.max(1e-6).log10() - lemin) / (lemax - lemin) * (h - 2.0 * m);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">RMSE against a {}-spp reference (checkerboard, {}x{})</text>\n",
        w / 2.0,
        cfg.reference_spp,
        cfg.size,
        cfg.size
    );
    let x1 = w - m - 120.0;
    let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{}\" x2=\"{x1}\" y2=\"{}\" stroke=\"black\"/>", h - m, h - m);
    let _ = writeln!(s, "<line x1=\"{m}\" y1=\"{m}\" x2=\"{m}\" y2=\"{}\" stroke=\"black\"/>", h - m);
    for &spp in &cfg.spps {
        let x = px(spp as f64);
        let _ = writeln!(s, "<text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">{spp}</text>", h - m + 16.0);
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">samples per pixel (log)</text>",
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
    for (k, chunk) in result.tiles.chunks(cfg.spps.len()).enumerate() {
        let color = COLORS[k % COLORS.len()];
        let points: Vec<String> =
            chunk.iter().map(|t| format!("{:.1},{:.1}", px(t.spp as f64), py(t.rmse))).collect();
        let _ = writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"2\" points=\"{}\"/>",
            points.join(" ")
        );
        let ly = m + 18.0 * k as f64;
        let _ = writeln!(
            s,
            "<line x1=\"{}\" y1=\"{ly}\" x2=\"{}\" y2=\"{ly}\" stroke=\"{color}\" stroke-width=\"2\"/>",
            x1 + 10.0,
            x1 + 30.0
        );
        let _ = writeln!(s, "<text x=\"{}\" y=\"{}\">{}</text>", x1 + 35.0, ly + 4.0, chunk[0].kind);
    }
    s += "</svg>\n";
    s
}
