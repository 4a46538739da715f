//! Renders with packets equal renders without: the same image, bit for
//! bit, whether eye rays (a pixel's samples, or 4x4 pixel centres) and the
//! rays they spawn travel as SIMD packets or one by one. (That each packet
//! kernel computes what single rays compute is tested beside the kernels.)

use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tracer::light::LightShape;
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use nffkit_tracer::render::{render, RenderSettings, ShadeSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};

fn image(scene: &str, spp: u32, packets: bool, depth: u32) -> Vec<f32> {
    let path = format!("{}/../scenes/spd/{scene}.nff", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read(path).unwrap();
    let scene = nff::parse(&src, &ParseOptions::default()).unwrap().scene;
    let opts = PrepareOptions { width: Some(40), height: Some(36), ..Default::default() };
    let p = prepare(&scene, &opts).unwrap();
    let settings = RenderSettings {
        sampler: Sampler::new(SamplerKind::MultiJittered, spp, 3).0,
        centre_single_sample: true,
        shade: ShadeSettings {
            light_size: if spp > 4 { 0.3 } else { 0.0 },
            light_shape: LightShape::Square,
            max_depth: depth,
            ..Default::default()
        },
        packets,
        ..Default::default()
    };
    render(&p, &settings, &|_, _| {}).film.pixels.iter().flat_map(|p| p.to_array()).collect()
}

#[test]
fn renders_with_packets_equal_renders_without() {
    // Pixel centres in 4x4 blocks (1 spp), a pixel's samples (4, 16, and
    // 20: a full packet and a partial one), soft shadows, glass and mirrors.
    for (scene, spp) in
        [("balls_s2", 1), ("mount_s1", 16), ("balls_s1", 4), ("teapot_s1", 20), ("gears_s1", 16)]
    {
        let with = image(scene, spp, true, 6);
        let without = image(scene, spp, false, 6);
        assert!(with.iter().any(|&v| v > 0.0), "{scene}: black image");
        assert_eq!(with, without, "{scene} at {spp} spp");
    }
}
