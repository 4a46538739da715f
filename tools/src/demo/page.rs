//! The demo page: `index.html` and the images it shows, written into one
//! folder. Plain HTML and CSS, images as files beside it, no script and no
//! network, so the folder can be opened from disk, zipped or served as is.

use super::figures::{Figure, FIGURES};
use super::{convergence_svg, fitted_slope, magnify, patterns, table, DemoConfig, DemoResult, DemoTile};
use anyhow::{Context, Result};
use nffkit_formats::atomic;
use nffkit_formats::image_io::{self, ImageKind, RgbImage};
use nffkit_tracer::film::Film;
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::fmt::Write as _;
use std::path::Path;

/// Magnification of the horizon crops.
pub const ZOOM: u32 = 8;
/// Sample counts whose patterns are drawn.
pub const PATTERN_COUNTS: [u32; 2] = [16, 64];

/// The optional section with the P3D report's figures and Table 1.
pub struct FiguresSection {
    /// Figures 4 to 8, in [`FIGURES`] order.
    pub images: Vec<RgbImage>,
    /// `table1 --quick` output (markdown).
    pub table1: String,
}

/// Write `bytes` to `dir/rel`, making its folder; returns `rel` for the
/// page's `src`.
fn file(dir: &Path, rel: &str, bytes: &[u8]) -> Result<String> {
    let path = dir.join(rel);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).with_context(|| format!("cannot create {}", parent.display()))?;
    }
    atomic::write_bytes(&path, bytes)?;
    Ok(rel.to_string())
}

fn png(dir: &Path, rel: &str, img: &RgbImage) -> Result<String> {
    file(dir, rel, &image_io::encode(img, ImageKind::Png, false)?)
}

fn text(dir: &Path, rel: &str, content: &str) -> Result<String> {
    file(dir, rel, content.as_bytes())
}

/// The 1D profile of a filter over its support, as an SVG.
pub fn filter_profile_svg(f: FilterKind) -> String {
    let (w, h, r) = (200.0, 110.0, 2.0f32);
    let px = |x: f32| 10.0 + (x + r) / (2.0 * r) * (w - 20.0);
    // Mitchell dips below zero: leave room under the axis.
    let py = |v: f32| 80.0 - v * 65.0;
    let pts: Vec<String> = (0..=200)
        .map(|i| {
            let x = -r + 2.0 * r * i as f32 / 200.0;
            let v = f.eval(x) / f.eval(0.0);
            format!("{:.1},{:.1}", px(x), py(v))
        })
        .collect();
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"10\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <line x1=\"10\" y1=\"{0}\" x2=\"{1}\" y2=\"{0}\" stroke=\"#999\"/>\n",
        py(0.0),
        w - 10.0
    );
    for x in [-2.0f32, -1.0, 0.0, 1.0, 2.0] {
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\" fill=\"#666\">{x}</text>",
            px(x),
            h - 4.0
        );
    }
    let _ = writeln!(
        s,
        "<polyline fill=\"none\" stroke=\"#1f5fa0\" stroke-width=\"2\" points=\"{}\"/>",
        pts.join(" ")
    );
    let _ = writeln!(s, "<text x=\"12\" y=\"12\">{f}, radius {}</text>\n</svg>", f.radius());
    s
}

const STYLE: &str = "body{font-family:sans-serif;margin:2em;max-width:1400px;color:#222}\
h1{font-size:1.6em}h2{margin-top:2em;border-bottom:1px solid #ccc}\
table{border-collapse:collapse}td,th{padding:4px 8px;text-align:center;vertical-align:top}\
tr.sampler td{border-top:1px solid #ddd}th{background:#f3f3f3}\
img.px{image-rendering:pixelated}figure{display:inline-block;margin:0 1em 1em 0}\
figcaption{font-size:.9em;max-width:300px}code{background:#f3f3f3;padding:1px 4px}\
.m{font-size:.8em;color:#555;display:block}td.name{text-align:left;font-weight:bold}";

fn metrics_line(t: &DemoTile) -> String {
    format!("<span class=\"m\">RMSE {:.4} · FLIP {:.4}</span>", t.rmse, t.flip)
}

/// Write the page and every image it uses into `dir`; returns the path of
/// `index.html`.
pub fn write(
    dir: &Path,
    cfg: &DemoConfig,
    result: &DemoResult,
    figures: Option<&FiguresSection>,
    command: &str,
) -> Result<std::path::PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let crop = cfg.crop();
    let zoom = |film: &Film| magnify(film, crop, ZOOM);
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>nffkit anti-aliasing demo</title>\
         <style>{STYLE}</style></head><body>\n<h1>Anti-aliasing on the checkerboard</h1>\n\
         <p>Made by <code>{}</code>. The board of the P3D report's plane generator ({sq}x{sq} squares), \
         {size}x{size} pixels, rendered with every sample pattern at {spps} samples per pixel, and compared \
         with a {refspp}-sample Sobol reference. Crops show the region below the horizon ({cw}x{ch} pixels at \
         ({cx}, {cy})), each pixel magnified {ZOOM}x with no smoothing.</p>\n",
        html_escape(command),
        sq = cfg.squares,
        size = cfg.size,
        spps = cfg.spps.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", "),
        refspp = cfg.reference_spp,
        cw = crop.2,
        ch = crop.3,
        cx = crop.0,
        cy = crop.1,
    );
    let reference = png(dir, "renders/reference.png", &result.reference.to_image())?;
    let reference_crop = png(dir, "crops/reference.png", &zoom(&result.reference))?;
    h += "<h2>Sample patterns, renders and magnified horizons</h2>\n<table>\n<tr><th>pattern</th>";
    for n in PATTERN_COUNTS {
        let _ = write!(h, "<th>{n} samples</th>");
    }
    let shown_spp = *cfg.spps.iter().filter(|&&s| s <= 16).max().unwrap_or(&cfg.spps[0]);
    let _ = write!(h, "<th>render, {shown_spp} spp</th>");
    for spp in &cfg.spps {
        let _ = write!(h, "<th>horizon, {spp} spp</th>");
    }
    h += "</tr>\n";
    for &kind in &cfg.samplers {
        let slope = fitted_slope(result.sampler_tiles(kind));
        let _ = write!(
            h,
            "<tr class=\"sampler\"><td class=\"name\">{kind}<span class=\"m\">slope {slope:.2}</span></td>"
        );
        for n in PATTERN_COUNTS {
            let rel = text(dir, &format!("patterns/{kind}-{n}.svg"), &patterns::svg(kind, n, cfg.seed, 128))?;
            let _ = write!(
                h,
                "<td><img src=\"{rel}\" width=\"128\" height=\"128\" alt=\"{kind}, {n} samples\"></td>"
            );
        }
        let mut cells = String::new();
        let mut shown = String::new();
        for t in result.sampler_tiles(kind) {
            let full = png(dir, &format!("renders/{kind}-{}.png", t.spp), &t.film.to_image())?;
            if t.spp == rounded_spp(kind, shown_spp, cfg.seed) {
                shown = format!(
                    "<td><img class=\"px\" src=\"{full}\" alt=\"{kind} render\">{}</td>",
                    metrics_line(t)
                );
            }
            let c = png(dir, &format!("crops/{kind}-{}.png", t.spp), &zoom(&t.film))?;
            let _ = write!(
                cells,
                "<td><img class=\"px\" src=\"{c}\" alt=\"{kind}, {} spp, horizon\">{}</td>",
                t.spp,
                metrics_line(t)
            );
        }
        h += &shown;
        h += &cells;
        h += "</tr>\n";
    }
    let _ = write!(
        h,
        "<tr class=\"sampler\"><td class=\"name\">reference<span class=\"m\">sobol, {} spp</span></td><td></td><td></td>\
         <td><img class=\"px\" src=\"{reference}\" alt=\"reference\"></td><td><img class=\"px\" src=\"{reference_crop}\" alt=\"reference horizon\"></td></tr>\n</table>\n",
        cfg.reference_spp
    );
    h += &filters_section(dir, cfg, result, &zoom)?;
    let _ =
        write!(h, "<h2>Errors against the reference</h2>\n{}", markdown_table_to_html(&table(result, cfg)));
    let plot = text(dir, "convergence.svg", &convergence_svg(result, cfg))?;
    let _ = write!(
        h,
        "<h2>Convergence</h2>\n<p>RMSE against samples per pixel on log-log axes: a straight line's slope is the \
         convergence rate. Independent random samples converge as N<sup>−1/2</sup>; stratified patterns converge \
         faster on edges like these. The legend gives each pattern's least-squares slope.</p>\n\
         <img src=\"{plot}\" alt=\"convergence plot\">\n"
    );
    if let Some(f) = figures {
        h += &figures_section(dir, f)?;
    }
    h += "</body></html>\n";
    let index = dir.join("index.html");
    atomic::write_bytes(&index, h.as_bytes())?;
    Ok(index)
}

fn filters_section(
    dir: &Path,
    cfg: &DemoConfig,
    result: &DemoResult,
    zoom: &dyn Fn(&Film) -> RgbImage,
) -> Result<String> {
    let mut h = format!(
        "<h2>Reconstruction filters</h2>\n<p>The same pattern ({}, {} spp) through each filter: the filter's \
         profile, the render and the magnified horizon.</p>\n<table><tr>",
        cfg.filter_sampler, cfg.filter_spp
    );
    for t in &result.filter_tiles {
        let _ = write!(h, "<th>{}</th>", t.filter);
    }
    h += "</tr>\n<tr>";
    for t in &result.filter_tiles {
        let rel = text(dir, &format!("profiles/{}.svg", t.filter), &filter_profile_svg(t.filter))?;
        let _ = write!(h, "<td><img src=\"{rel}\" alt=\"{} profile\"></td>", t.filter);
    }
    h += "</tr>\n<tr>";
    for t in &result.filter_tiles {
        let full = png(dir, &format!("renders/filter-{}.png", t.filter), &t.film.to_image())?;
        let c = png(dir, &format!("crops/filter-{}.png", t.filter), &zoom(&t.film))?;
        let _ = write!(
            h,
            "<td><img class=\"px\" src=\"{full}\" alt=\"{0} render\"><br><img class=\"px\" src=\"{c}\" alt=\"{0} horizon\">{1}</td>",
            t.filter,
            metrics_line(t)
        );
    }
    h += "</tr></table>\n";
    Ok(h)
}

fn figures_section(dir: &Path, f: &FiguresSection) -> Result<String> {
    let mut h = String::from(
        "<h2>The P3D report's figures</h2>\n<p>Figures 4 to 8 of the 2017 report, rebuilt with this project's \
         generators and renderer; the command under each made it.</p>\n",
    );
    for (fig, img) in FIGURES.iter().zip(&f.images) {
        let Figure { number, caption, .. } = fig;
        let rel = png(dir, &format!("figures/fig{number}.png"), img)?;
        let _ = write!(
            h,
            "<figure><img src=\"{rel}\" alt=\"Figure {number}\"><figcaption>Figure {number}: {caption}<br><code>{}</code></figcaption></figure>",
            html_escape(&fig.command())
        );
    }
    let _ = write!(
        h,
        "<h2>The P3D report's Table 1</h2>\n<p>From <code>table1 --quick</code> (128x128, brute force estimated \
         past a 1 s cap).</p>\n{}",
        markdown_table_to_html(&f.table1)
    );
    Ok(h)
}

/// A markdown pipe table (and any lines after it) as HTML.
pub fn markdown_table_to_html(md: &str) -> String {
    let mut h = String::from("<table>\n");
    let mut rest = String::new();
    let mut header = true;
    for line in md.lines() {
        let t = line.trim();
        if !t.starts_with('|') {
            if !t.is_empty() {
                let _ = writeln!(rest, "<p>{}</p>", html_escape(t));
            }
            continue;
        }
        if t.trim_matches(|c| c == '|' || c == '-' || c == ':').is_empty() {
            continue;
        }
        let tag = if header { "th" } else { "td" };
        header = false;
        h += "<tr>";
        for cell in t.trim_matches('|').split('|') {
            let _ = write!(h, "<{tag}>{}</{tag}>", html_escape(cell.trim()));
        }
        h += "</tr>\n";
    }
    h += "</table>\n";
    h + &rest
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The sample count a pattern really takes for `spp` (grid patterns take
/// squares).
fn rounded_spp(kind: SamplerKind, spp: u32, seed: u32) -> u32 {
    Sampler::new(kind, spp, seed).0.spp
}
