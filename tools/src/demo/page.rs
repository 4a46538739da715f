//! The demo page: `index.html` and the images it shows, written into one
//! folder. Plain HTML and CSS, images as files beside it, no script and no
//! network, so the folder can be opened from disk, zipped or served as is.

use super::figures::{Figure, FIGURES};
use super::{
    convergence_plot, convergence_svg, fitted_slope, magnify, patterns, slope_text, table, DemoConfig,
    DemoResult, DemoTile,
};
use anyhow::{Context, Result};
use nffkit_formats::atomic;
use nffkit_formats::image_io::{self, ImageKind, RgbImage};
use nffkit_tracer::film::Film;
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::fmt::Write as _;
use std::path::Path;

/// Magnification of the horizon crops.
pub const ZOOM: u32 = 6;
/// Sample counts whose patterns are drawn.
pub const PATTERN_COUNTS: [u32; 2] = [16, 64];

/// The optional section with the P3D report's figures and Table 1.
pub struct FiguresSection {
    /// Figures 4 to 8, in [`FIGURES`] order.
    pub images: Vec<RgbImage>,
    /// `table1` output (markdown).
    pub table1: String,
    /// The side of Table 1's images.
    pub table1_size: u32,
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

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em auto;padding:0 1.5em;max-width:1400px;color:#222;line-height:1.4}\
h1{font-size:1.6em}h2{margin-top:2em;border-bottom:1px solid #ccc}\
.scroll{overflow-x:auto;max-width:100%}table{border-collapse:collapse}\
td,th{padding:4px 8px;text-align:center;vertical-align:top}th{background:#f3f3f3}\
img{max-width:100%;height:auto}img.px{image-rendering:pixelated}\
figure{margin:0}figcaption{font-size:.85em;color:#444;max-width:280px}\
code{background:#f3f3f3;padding:1px 4px}.m{font-size:.85em;color:#555;display:block}\
.card{display:flex;flex-wrap:wrap;gap:12px 16px;align-items:flex-start;border-top:1px solid #ddd;padding:10px 0}\
.card.crops{border:0;padding:0}.card h3{flex:0 0 150px;margin:0;font-size:1.05em}.look{background:#f6f8fb;border-left:4px solid #5577aa;padding:.5em 1em;max-width:70em}\
.figs{display:grid;grid-template-columns:repeat(auto-fill,minmax(260px,1fr));gap:1em;align-items:start}\
td.name{text-align:left;font-weight:bold}";

fn metrics_line(t: &DemoTile) -> String {
    format!("<span class=\"m\">{} spp · RMSE {:.4} · FLIP {:.4}</span>", t.spp, t.rmse, t.flip)
}

/// `film` with the crop's outline drawn one pixel outside it, in yellow.
fn marked(film: &Film, (x0, y0, w, h): (u32, u32, u32, u32)) -> RgbImage {
    let mut img = film.to_image();
    let (x0, y0) = (x0 as i64 - 1, y0 as i64 - 1);
    let (x1, y1) = (x0 + w as i64 + 1, y0 + h as i64 + 1);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let edge = x == x0 || x == x1 || y == y0 || y == y1;
            if edge && (0..img.width as i64).contains(&x) && (0..img.height as i64).contains(&y) {
                img.pixels[(y as u32 * img.width + x as u32) as usize] = [1.0, 0.9, 0.0];
            }
        }
    }
    img
}

/// What the reader should look for, per section.
const LOOK_PATTERNS: &str = "Each pattern's samples for one pixel in the unit square, over the strata it \
    guarantees: a jittered pattern puts one sample in each cell of the coarse √n x √n grid; n-rooks puts one in \
    each row and each column of the fine n x n grid (the highlighted sample's row and column, in yellow, hold no \
    other); multi-jittered does both; Hammersley and Sobol at powers of two are (0,m,2)-nets, which include the \
    n-rooks property. Random guarantees nothing: look for clumps and holes. In the crops, look at the far squares: \
    where they shrink below a pixel a good pattern averages them to an even grey, a poor one leaves noise or \
    moiré. The render has the crop's place outlined in yellow.";

const LOOK_ROTATED: &str = "Why a regular grid does well here: the board's squares run along the image's rows \
    and columns, so the far edges are nearly horizontal, and a regular grid of √n rows estimates how much of a \
    pixel a horizontal edge covers to within 1/(2√n), in every pixel, with no noise at all; random patterns pay \
    for their freedom in noise. Turn the board and its edges cross the pixel grid at a slant: the grid's rows \
    then fall on the same side of an edge across a run of pixels and the wrong side across the next, so its \
    errors line up into bands (moiré; compare the crops below), while multi-jittered, one sample per row, \
    column and cell placed at random within them, keeps its error as fine noise. The table gives every \
    pattern's RMSE on both boards; the sentence below reads it.";

const LOOK_FILTERS: &str = "A wider filter blends each sample into the neighbouring pixels: tent and Gaussian blur, \
    Mitchell blurs less and sharpens with its negative lobes. Each is measured against a reference made through \
    the same filter, so the error is the noise the pattern leaves, not the blur the filter adds on purpose \
    (against a box-filtered reference the wide filters would look several times worse for being wide).";

const LOOK_CONVERGENCE: &str = "RMSE against samples per pixel on log-log axes: a straight line's slope is the \
    convergence rate. Independent random samples converge as N<sup>−1/2</sup>; stratified patterns converge \
    faster on edges like these, towards N<sup>−3/4</sup>. Multi-jittered, the P3D report's pattern, is the wide \
    black line; each line is labelled at its end with its fitted slope.";

/// The section of one board's tiles as cards, one per sampler.
fn pattern_cards(
    dir: &Path,
    cfg: &DemoConfig,
    result: &DemoResult,
    zoom: &dyn Fn(&Film) -> RgbImage,
) -> Result<String> {
    let crop = cfg.crop();
    let shown_spp = *cfg.spps.iter().filter(|&&s| s <= 16).max().unwrap_or(&cfg.spps[0]);
    let mut h = String::new();
    for &kind in &cfg.samplers {
        let slope = slope_text(fitted_slope(result.sampler_tiles(kind)));
        let _ = write!(h, "<div class=\"card\"><h3>{kind}<span class=\"m\">fitted slope {slope}</span></h3>");
        for n in PATTERN_COUNTS {
            let taken = rounded_spp(kind, n, cfg.seed);
            let rel = text(dir, &format!("patterns/{kind}-{n}.svg"), &patterns::svg(kind, n, cfg.seed, 160))?;
            let _ = write!(
                h,
                "<figure><img src=\"{rel}\" width=\"160\" height=\"160\" alt=\"{kind}, {taken} samples\">\
                 <figcaption>{taken} samples</figcaption></figure>"
            );
        }
        let shown = rounded_spp(kind, shown_spp, cfg.seed);
        for t in result.sampler_tiles(kind) {
            if t.spp == shown {
                let full = png(dir, &format!("renders/{kind}-{}.png", t.spp), &marked(&t.film, crop))?;
                let _ = write!(
                    h,
                    "<figure><img class=\"px\" src=\"{full}\" width=\"{0}\" height=\"{0}\" alt=\"{kind} render\"><figcaption>render{1}</figcaption></figure>",
                    cfg.size,
                    metrics_line(t)
                );
            }
        }
        h += "<div class=\"card crops\">";
        for t in result.sampler_tiles(kind) {
            let c = png(dir, &format!("crops/{kind}-{}.png", t.spp), &zoom(&t.film))?;
            let _ = write!(
                h,
                "<figure><img class=\"px\" src=\"{c}\" alt=\"{kind}, {} spp, horizon\"><figcaption>horizon{}</figcaption></figure>",
                t.spp,
                metrics_line(t)
            );
        }
        h += "</div></div>\n";
    }
    Ok(h)
}

/// Write the page and every image it uses into `dir` (linking the
/// playground when `playground`); returns the path of `index.html`.
pub fn write(
    dir: &Path,
    cfg: &DemoConfig,
    result: &DemoResult,
    figures: Option<&FiguresSection>,
    command: &str,
    playground: bool,
) -> Result<std::path::PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let crop = cfg.crop();
    let zoom = |film: &Film| magnify(film, crop, ZOOM);
    let asked = cfg.spps.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ");
    let mut h = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>nffkit anti-aliasing demo</title>\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <style>{STYLE}</style></head><body>\n<h1>Anti-aliasing on the checkerboard</h1>\n\
         <p>Made by <code>{}</code>. The board of the P3D report's plane generator ({sq}x{sq} squares), \
         {size}x{size} pixels, rendered with every sample pattern at {asked} samples per pixel asked for (the grid \
         patterns, regular, jittered, multi-jittered and cmj, take the next square count: each image says what it took), \
         and compared with a {refspp}-sample Sobol reference. Crops show the region below the horizon \
         ({cw}x{ch} pixels at ({cx}, {cy}), outlined in yellow on the renders), each pixel magnified {ZOOM}x with no \
         smoothing.{play}</p>\n",
        html_escape(command),
        sq = cfg.squares,
        size = cfg.size,
        refspp = cfg.reference_spp,
        cw = crop.2,
        ch = crop.3,
        cx = crop.0,
        cy = crop.1,
        play = if playground {
            " <a href=\"playground/index.html\">The playground</a> traces the same board live in the browser: turn \
             the knobs and watch it converge."
        } else {
            ""
        },
    );
    let reference = png(dir, "renders/reference.png", &marked(&result.reference, crop))?;
    let reference_crop = png(dir, "crops/reference.png", &zoom(&result.reference))?;
    let _ = write!(
        h,
        "<h2>What the horizon should look like</h2>\n<div class=\"card\"><figure><img class=\"px\" src=\"{reference}\" \
         width=\"{0}\" height=\"{0}\" alt=\"reference\"><figcaption>reference: sobol, {1} spp</figcaption></figure>\
         <figure><img class=\"px\" src=\"{reference_crop}\" alt=\"reference horizon\"><figcaption>its horizon, \
         magnified</figcaption></figure></div>\n",
        cfg.size, cfg.reference_spp
    );
    let _ = write!(
        h,
        "<h2>Sample patterns, renders and magnified horizons</h2>\n<p class=\"look\">{LOOK_PATTERNS}</p>\n{}",
        pattern_cards(dir, cfg, result, &zoom)?
    );
    h += &rotated_section(dir, cfg, result, &zoom)?;
    h += &filters_section(dir, cfg, result, &zoom)?;
    let _ = write!(
        h,
        "<h2>Errors against the reference</h2>\n<div class=\"scroll\">{}</div>",
        markdown_table_to_html(&table(result, cfg))
    );
    let plot = text(dir, "convergence.svg", &convergence_svg(result, cfg))?;
    let title =
        format!("The board turned {}°: RMSE against its {}-spp reference", cfg.rotation, cfg.reference_spp);
    let turned = text(dir, "convergence-turned.svg", &convergence_plot(&result.rotated_tiles, cfg, &title))?;
    let _ = write!(
        h,
        "<h2>Convergence</h2>\n<p class=\"look\">{LOOK_CONVERGENCE}</p>\n\
         <img src=\"{plot}\" alt=\"convergence plot\" width=\"960\">\n<img src=\"{turned}\" alt=\"convergence on the \
         turned board\" width=\"960\">\n"
    );
    if let Some(f) = figures {
        h += &figures_section(dir, f)?;
    }
    h += "</body></html>\n";
    let index = dir.join("index.html");
    atomic::write_bytes(&index, h.as_bytes())?;
    Ok(index)
}

/// The upright and the turned board side by side: errors per pattern and
/// the crops of regular and multi-jittered at the lowest stratified count.
fn rotated_section<'a>(
    dir: &Path,
    cfg: &DemoConfig,
    result: &'a DemoResult,
    zoom: &dyn Fn(&Film) -> RgbImage,
) -> Result<String> {
    let low = cfg.spps.iter().copied().find(|&s| s >= 4).unwrap_or(cfg.spps[0]);
    // The tile of `kind` at the count `low` asks for (grid patterns round).
    let tile = |tiles: &'a [DemoTile], kind| {
        let want = rounded_spp(kind, low, cfg.seed);
        tiles.iter().find(|t| t.kind == kind && t.spp == want)
    };
    let rmse = |tiles: &'a [DemoTile], kind| tile(tiles, kind).map(|t| t.rmse);
    let (r, mj, j) = (SamplerKind::Regular, SamplerKind::MultiJittered, SamplerKind::Jittered);
    let reading = match (
        (rmse(&result.tiles, r), rmse(&result.tiles, mj), rmse(&result.tiles, j)),
        (rmse(&result.rotated_tiles, r), rmse(&result.rotated_tiles, mj), rmse(&result.rotated_tiles, j)),
    ) {
        ((Some(ru), Some(mu), Some(ju)), (Some(rt), Some(mt), Some(jt))) => {
            let verdict = |a: f64, b: f64| if a < b { "below" } else { "above" };
            format!(
                "<p>Here, at {low} spp asked ({size}x{size}): on the upright board regular's RMSE is {ru:.4}, {} \
                 multi-jittered's {mu:.4} and {} jittered's {ju:.4}; turned {rot}°, it is {rt:.4}, {} \
                 multi-jittered's {mt:.4} and {} jittered's {jt:.4}.</p>\n",
                verdict(ru, mu),
                verdict(ru, ju),
                verdict(rt, mt),
                verdict(rt, jt),
                size = cfg.size,
                rot = cfg.rotation,
            )
        }
        _ => String::new(),
    };
    let mut h = format!(
        "<h2>Why regular does well on this board, and what turning it changes</h2>\n<p class=\"look\">{LOOK_ROTATED}</p>\n\
         {reading}<div class=\"scroll\"><table><tr><th>pattern</th>"
    );
    for spp in &cfg.spps {
        let _ = write!(h, "<th>upright, {spp} spp asked</th><th>turned {}°</th>", cfg.rotation);
    }
    h += "</tr>\n";
    let per = cfg.spps.len();
    for (k, (up, turned)) in result.tiles.chunks(per).zip(result.rotated_tiles.chunks(per)).enumerate() {
        let _ = write!(h, "<tr><td class=\"name\">{}</td>", cfg.samplers[k]);
        for (a, b) in up.iter().zip(turned) {
            let _ = write!(h, "<td>{:.4}</td><td>{:.4}</td>", a.rmse, b.rmse);
        }
        h += "</tr>\n";
    }
    h += "</table></div>\n<div class=\"card\">";
    let turned_crop = png(dir, "crops/turned-reference.png", &zoom(&result.rotated_reference))?;
    let _ = write!(
        h,
        "<figure><img class=\"px\" src=\"{turned_crop}\" alt=\"turned reference horizon\"><figcaption>turned board, \
         reference</figcaption></figure>"
    );
    for kind in [SamplerKind::Regular, SamplerKind::MultiJittered] {
        for (b, tiles, name) in [(0, &result.tiles, "upright"), (1, &result.rotated_tiles, "turned")] {
            if let Some(t) = tile(tiles, kind) {
                let c = png(dir, &format!("crops/board{b}-{kind}-{}.png", t.spp), &zoom(&t.film))?;
                let _ = write!(
                    h,
                    "<figure><img class=\"px\" src=\"{c}\" alt=\"{kind} {name}\"><figcaption>{name}, {kind}{}</figcaption></figure>",
                    metrics_line(t)
                );
            }
        }
    }
    h += "</div>\n";
    Ok(h)
}

fn filters_section(
    dir: &Path,
    cfg: &DemoConfig,
    result: &DemoResult,
    zoom: &dyn Fn(&Film) -> RgbImage,
) -> Result<String> {
    let mut h = format!(
        "<h2>Reconstruction filters</h2>\n<p class=\"look\">{LOOK_FILTERS}</p>\n<p>The same pattern ({}, {} spp \
         asked) through each filter: the filter's profile, the render, the magnified horizon and the reference's \
         horizon through the same filter.</p>\n",
        cfg.filter_sampler, cfg.filter_spp
    );
    for (t, reference) in result.filter_tiles.iter().zip(&result.filter_references) {
        h += "\n";
        let f = t.filter;
        let profile = text(dir, &format!("profiles/{f}.svg"), &filter_profile_svg(f))?;
        let full = png(dir, &format!("renders/filter-{f}.png"), &marked(&t.film, cfg.crop()))?;
        let c = png(dir, &format!("crops/filter-{f}.png"), &zoom(&t.film))?;
        let rc = png(dir, &format!("crops/filter-{f}-reference.png"), &zoom(reference))?;
        let _ = write!(
            h,
            "<div class=\"card\"><h3>{f}</h3><figure><img src=\"{profile}\" alt=\"{f} profile\"><figcaption>profile\
             </figcaption></figure><figure><img class=\"px\" src=\"{full}\" width=\"{0}\" height=\"{0}\" alt=\"{f} \
             render\"><figcaption>render{1}</figcaption></figure><figure><img class=\"px\" src=\"{c}\" alt=\"{f} \
             horizon\"><figcaption>horizon{1}</figcaption></figure><figure><img class=\"px\" src=\"{rc}\" alt=\"{f} \
             reference horizon\"><figcaption>reference ({2} spp) through {f}</figcaption></figure></div>",
            cfg.size,
            metrics_line(t),
            cfg.reference_spp
        );
    }
    Ok(h)
}

fn figures_section(dir: &Path, f: &FiguresSection) -> Result<String> {
    let mut h = String::from(
        "<h2>The P3D report's figures</h2>\n<p>Figures 4 to 8 of the 2017 report, rebuilt with this project's \
         generators and renderer; the command under each made it.</p>\n<div class=\"figs\">",
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
        "</div>\n<h2>The P3D report's Table 1</h2>\n<p>From <code>table1</code> at {0}x{0}{1}: this machine's times \
         beside the report's (512x512).</p>\n<div class=\"scroll\">{2}</div>",
        f.table1_size,
        if f.table1_size == 512 {
            ", the report's size".to_string()
        } else {
            format!(
                " (the report's 512x512 scaled down by {:.0}x in pixels; for the report's times, divide its \
                 figures by that, or run aademo --figures --table1-size 512)",
                (512.0 / f.table1_size as f64).powi(2)
            )
        },
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
