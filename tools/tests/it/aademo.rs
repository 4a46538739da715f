//! The anti-aliasing demo: stratified and low-discrepancy samplers beat
//! random on the checkerboard and converge faster; the sample-pattern SVGs
//! hold exactly the samples with the strata's guarantees; and the page, made
//! by the binary at a small size, shows every sampler, filter and figure with
//! every image it references on disk.

use nffkit_tools::demo::{contact_sheet, convergence_svg, fitted_slope, patterns, run, table, DemoConfig};
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::sampling::SamplerKind;
use std::path::Path;
use std::process::Command;

#[test]
fn stratified_samplers_beat_random_at_16_spp() {
    let cfg = DemoConfig { size: 48, spps: vec![4, 16], reference_spp: 256, ..Default::default() };
    let result = run(&cfg, &|_, _| {}).unwrap();
    let err = |k: SamplerKind| result.tiles.iter().find(|t| t.kind == k && t.spp == 16).unwrap().rmse;
    let random = err(SamplerKind::Random);
    for k in [
        SamplerKind::MultiJittered,
        SamplerKind::CorrelatedMultiJittered,
        SamplerKind::Hammersley,
        SamplerKind::Sobol,
        SamplerKind::Jittered,
    ] {
        assert!(err(k) < random, "{k}: {} vs random {random}", err(k));
    }
    assert_eq!(result.filter_tiles.len(), FilterKind::ALL.len());
    let sheet = contact_sheet(&result, &cfg);
    assert_eq!(sheet.width, 3 * (48 + 4) + 4);
    let t = table(&result, &cfg);
    assert_eq!(t.lines().count(), 2 + SamplerKind::ALL.len());
    let svg = convergence_svg(&result, &cfg);
    assert_eq!(svg.matches("<polyline").count(), SamplerKind::ALL.len());
    assert_eq!(svg.matches("class=\"reference-slope\"").count(), 2);
    assert_eq!(svg.matches("(slope ").count(), SamplerKind::ALL.len());
}

#[test]
fn jittered_converges_faster_than_random_at_128x128() {
    let cfg = DemoConfig {
        size: 128,
        spps: vec![1, 4, 16, 64],
        samplers: vec![SamplerKind::Random, SamplerKind::Jittered],
        filters: vec![],
        reference_spp: 256,
        ..Default::default()
    };
    let result = run(&cfg, &|_, _| {}).unwrap();
    let random = fitted_slope(result.sampler_tiles(SamplerKind::Random)).unwrap();
    let jittered = fitted_slope(result.sampler_tiles(SamplerKind::Jittered)).unwrap();
    assert!(jittered < random - 0.1, "jittered slope {jittered} vs random {random}");
    assert!((random + 0.5).abs() < 0.15, "random converges as N^-1/2: {random}");
}

/// `(x, y)` of every `<circle class="sample">` in a pattern SVG.
fn samples(svg: &str) -> Vec<(f64, f64)> {
    svg.lines()
        .filter(|l| l.contains("class=\"sample"))
        .map(|l| (attr(l, "cx").parse().unwrap(), attr(l, "cy").parse().unwrap()))
        .collect()
}

fn attr<'a>(tag: &'a str, name: &str) -> &'a str {
    let start = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
    let end = start + tag[start..].find('"').unwrap();
    &tag[start..end]
}

#[test]
fn pattern_svgs_hold_the_samples_and_their_strata() {
    for &kind in SamplerKind::ALL {
        for n in [16, 64] {
            let pts = samples(&patterns::svg(kind, n, 1, 128));
            assert_eq!(pts.len(), n as usize, "{kind} {n}");
            assert!(pts.iter().all(|&(x, y)| (0.0..1.0).contains(&x) && (0.0..1.0).contains(&y)), "{kind}");
            let one_per_row_and_column = matches!(
                kind,
                SamplerKind::NRooks | SamplerKind::MultiJittered | SamplerKind::CorrelatedMultiJittered
            );
            if one_per_row_and_column {
                for axis in 0..2 {
                    let mut count = vec![0; n as usize];
                    for p in &pts {
                        count[((if axis == 0 { p.0 } else { p.1 }) * n as f64) as usize] += 1;
                    }
                    assert!(count.iter().all(|&c| c == 1), "{kind} {n}: {count:?}");
                }
            }
        }
    }
    // The drawn strata: multi-jittered shows its coarse grid and sub-grid.
    let mj = patterns::svg(SamplerKind::MultiJittered, 16, 1, 128);
    assert_eq!((mj.matches("class=\"coarse\"").count(), mj.matches("class=\"fine\"").count()), (3, 15));
    // One sample highlighted, with its fine row and column and its cell;
    // dots fit inside the fine cells.
    assert_eq!(mj.matches("class=\"sample first\"").count(), 1);
    for class in ["row", "column", "cell"] {
        assert_eq!(mj.matches(&format!("class=\"{class}\"")).count(), 1, "{class}");
    }
    let mj64 = patterns::svg(SamplerKind::MultiJittered, 64, 1, 160);
    let r: f64 = attr(mj64.lines().find(|l| l.contains("class=\"sample\"")).unwrap(), "r").parse().unwrap();
    assert!(r <= 1.0 / 64.0 / 2.0, "radius {r}");
    assert!(mj64.contains("vector-effect=\"non-scaling-stroke\""));
}

#[test]
fn the_page_shows_everything_and_every_image_exists() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = Command::new(env!("CARGO_BIN_EXE_aademo"))
        .args(["--out", out.to_str().unwrap(), "--size", "32", "--spp", "1,3,16", "--reference-spp", "64"])
        .args(["--figures", "--table1-size", "32", "-q"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let srcs: Vec<&str> = html.match_indices(" src=\"").map(|(i, _)| attr(&html[i..], "src")).collect();
    assert!(srcs.len() > 50, "{} images", srcs.len());
    for src in &srcs {
        assert!(!src.starts_with("http") && !src.starts_with('/'), "not local: {src}");
        assert!(Path::new(&out).join(src).is_file(), "missing {src}");
    }
    for &kind in SamplerKind::ALL {
        for n in [16, 64] {
            assert!(srcs.contains(&format!("patterns/{kind}-{n}.svg").as_str()), "{kind} {n}");
        }
        // Grid patterns (cmj too) take 4 samples for 3 asked, and say so.
        let grid = matches!(
            kind,
            SamplerKind::Regular
                | SamplerKind::Jittered
                | SamplerKind::MultiJittered
                | SamplerKind::CorrelatedMultiJittered
        );
        for spp in [1, if grid { 4 } else { 3 }, 16] {
            assert!(srcs.contains(&format!("crops/{kind}-{spp}.png").as_str()), "{kind} crop {spp}");
        }
    }
    for f in FilterKind::ALL {
        assert!(srcs.contains(&format!("profiles/{f}.svg").as_str()), "{f}");
        assert!(srcs.contains(&format!("crops/filter-{f}.png").as_str()), "{f}");
        assert!(srcs.contains(&format!("crops/filter-{f}-reference.png").as_str()), "{f} reference");
    }
    for n in 4..=8 {
        assert!(srcs.contains(&format!("figures/fig{n}.png").as_str()), "figure {n}");
        assert!(html.contains(&format!("Figure {n}:")), "caption {n}");
    }
    assert!(html.contains("planegen --nx 16 --ny 16 | render - --width 256 --height 256 --spp 64"));
    assert!(html.contains("<th>BVH speedup</th>") && html.matches("<tr>").count() > 6, "Table 1");
    assert!(
        html.contains("convergence.svg")
            && html.contains("convergence-turned.svg")
            && !html.contains("<script")
    );
    assert!(html.contains("4 spp · RMSE") && html.contains("3 spp · RMSE"));
    assert!(
        html.contains("alt=\"regular, 4 spp, horizon\"") && html.contains("alt=\"random, 3 spp, horizon\"")
    );
    assert!(html.contains("Why regular does well") && html.contains("turned 10°, it is"));
    assert!(html.contains("From <code>table1</code> at 32x32 (the report's 512x512 scaled down by 256x"));
    // The renders carry the crop's outline (yellow) where it belongs.
    let render = image::open(out.join("renders/regular-16.png")).unwrap().to_rgb8();
    let (x0, y0, _, _) = DemoConfig { size: 32, ..Default::default() }.crop();
    assert_eq!(render.get_pixel(x0 - 1, y0 - 1).0, [255, 230, 0]);
}
