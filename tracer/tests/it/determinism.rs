//! The image is a function of the scene and the settings only: not of the
//! thread count, nor of the accelerator.

use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::light::LightShape;
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use nffkit_tracer::render::{render, RenderSettings, ShadeSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};

fn scene() -> nffkit_formats::Scene {
    let src = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/spd/balls_s2.nff")).unwrap();
    nff::parse(&src, &ParseOptions::default()).unwrap().scene
}

fn settings() -> RenderSettings {
    RenderSettings {
        sampler: Sampler::new(SamplerKind::MultiJittered, 4, 9).0,
        centre_single_sample: false,
        shade: ShadeSettings { light_size: 0.5, light_shape: LightShape::Disk, ..Default::default() },
        ..Default::default()
    }
}

fn image(kind: AccelKind, threads: usize, aperture: f32) -> Vec<u8> {
    let opts = PrepareOptions {
        width: Some(48),
        height: Some(40),
        aperture,
        accel: AccelOptions { kind, ..Default::default() },
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let p = prepare(&scene(), &opts).unwrap();
        render(&p, &settings(), &|_, _| {})
            .film
            .pixels
            .iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_le_bytes)
            .collect()
    })
}

#[test]
fn same_image_on_one_and_two_threads() {
    assert_eq!(image(AccelKind::Bvh, 1, 0.05), image(AccelKind::Bvh, 2, 0.05));
    assert_eq!(image(AccelKind::Grid, 1, 0.0), image(AccelKind::Grid, 3, 0.0));
}

#[test]
fn every_accelerator_gives_the_same_bits() {
    let bvh = image(AccelKind::Bvh, 2, 0.0);
    assert_eq!(bvh, image(AccelKind::Grid, 2, 0.0));
    assert_eq!(bvh, image(AccelKind::None, 2, 0.0));
}

fn render_with_cache(
    kind: AccelKind,
    threads: usize,
    cache: bool,
) -> (Vec<f32>, nffkit_tracer::stats::Counters) {
    let opts = PrepareOptions {
        width: Some(48),
        height: Some(40),
        accel: AccelOptions { kind, ..Default::default() },
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let p = prepare(&scene(), &opts).unwrap();
        let out = render(&p, &RenderSettings { shadow_cache: cache, ..settings() }, &|_, _| {});
        (out.film.pixels.iter().flat_map(|p| p.to_array()).collect(), out.counters)
    })
}

#[test]
fn the_shadow_cache_changes_the_work_not_the_image() {
    for kind in [AccelKind::Bvh, AccelKind::Grid, AccelKind::None] {
        let (with, c_with) = render_with_cache(kind, 2, true);
        let (without, c_without) = render_with_cache(kind, 2, false);
        assert_eq!(with, without, "{kind}");
        assert!(c_with.shadow_cache_hits > 100, "{kind}: {} hits", c_with.shadow_cache_hits);
        assert_eq!(c_without.shadow_cache_hits, 0);
        assert_eq!(c_with.shadow, c_without.shadow);
        // Counts are per tile, so they do not depend on the thread count.
        assert_eq!(c_with, render_with_cache(kind, 1, true).1, "{kind}");
    }
}
