//! The image is a function of the scene and the settings only: not of the
//! thread count, nor of the accelerator.

use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tracer::accel::{AccelKind, AccelOptions};
use nffkit_tracer::light::LightShape;
use nffkit_tracer::prepare::{prepare, prepare_freeing, PrepareOptions};
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
    image_prepared_by(kind, threads, aperture, |s, o| prepare(&s, o).unwrap())
}

/// [`image`], the scene prepared by `prepare`.
fn image_prepared_by(
    kind: AccelKind,
    threads: usize,
    aperture: f32,
    prepare: impl Fn(nffkit_formats::Scene, &PrepareOptions) -> nffkit_tracer::prepare::RenderScene + Sync,
) -> Vec<u8> {
    let opts = PrepareOptions {
        width: Some(48),
        height: Some(40),
        aperture: Some(aperture),
        accel: AccelOptions { kind, ..Default::default() },
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let p = prepare(scene(), &opts);
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

/// Freeing the file's primitives before the build changes nothing but
/// memory, and leaves the rest of the scene.
#[test]
fn preparing_that_frees_the_primitives_gives_the_same_image() {
    let freeing = |mut s: nffkit_formats::Scene, o: &PrepareOptions| {
        let (lights, materials) = (s.lights.len(), s.materials.len());
        let p = prepare_freeing(&mut s, o).unwrap();
        assert!(s.primitives.is_empty());
        assert_eq!((s.lights.len(), s.materials.len()), (lights, materials));
        assert!(s.view.is_some());
        p
    };
    assert_eq!(image(AccelKind::Bvh, 2, 0.05), image_prepared_by(AccelKind::Bvh, 2, 0.05, freeing));
    assert_eq!(image(AccelKind::Grid, 1, 0.0), image_prepared_by(AccelKind::Grid, 1, 0.0, freeing));
}

#[test]
fn every_accelerator_gives_the_same_bits() {
    let bvh = image(AccelKind::Bvh, 2, 0.0);
    assert_eq!(bvh, image(AccelKind::Grid, 2, 0.0));
    assert_eq!(bvh, image(AccelKind::None, 2, 0.0));
}

/// A Cornell-box corner: walls in the planes x = 0 and y = 0 (through the
/// origin), a `p 3` and a `pp` wall at z = 550, lit by a light just below
/// the ceiling's plane and one in the plane x = 0.5.
const CORNER: &str = "v from 275 275 -800 at 275 275 0 up 0 1 0 angle 37 hither 1 resolution 64 64
b 0 0 0
l 275 549 275
l 0.5 300 100 0.5 0.5 0.5
f 0.8 0.2 0.2 1 0 1 0 1
p 4 0 0 550 0 0 0 0 550 0 0 550 550
f 0.8 0.8 0.8 1 0 1 0 1
p 4 0 0 0 550 0 0 550 0 550 0 0 550
p 3 0 0 550 550 0 550 550 550 550
pp 3 0 0 550 0 0 -1 550 550 550 0 0 -1 0 550 550 0 0 -1
f 0.2 0.8 0.2 0.5 0.5 20 0 1
p 4 0.5 100 100 0.5 200 100 0.5 200 300 0.5 100 300
";

#[test]
fn every_accelerator_draws_walls_through_the_origin_alike() {
    // Brute force and the grid found a wall at x = 0 a hair in front of the
    // shadow rays leaving it (black speckles); the BVH's single rays broke
    // the tie where two walls meet. Every accelerator, with packets or
    // without, must give the same bits.
    let scene = nff::parse(CORNER.as_bytes(), &ParseOptions::default()).unwrap().scene;
    let image = |kind: AccelKind, packets: bool| {
        let opts =
            PrepareOptions { accel: AccelOptions { kind, ..Default::default() }, ..Default::default() };
        let p = prepare(&scene, &opts).unwrap();
        let settings = RenderSettings { packets, ..Default::default() };
        render(&p, &settings, &|_, _| {}).film.pixels.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>()
    };
    let reference = image(AccelKind::Bvh, true);
    assert!(reference.iter().filter(|&&v| v > 0.0).count() > 2000, "the walls are lit");
    for &kind in AccelKind::ALL {
        for packets in [true, false] {
            let other = image(kind, packets);
            let differ = reference.chunks(3).zip(other.chunks(3)).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "{kind}, packets {packets}: {differ} pixels differ from the BVH's");
        }
    }
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
