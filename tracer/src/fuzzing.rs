//! The tracer's fuzz target bodies (see `nffkit_formats::fuzzing` for the
//! reader's), here so that the fuzzer (`fuzz/`) and the regular test that
//! replays every input it ever failed on
//! (`tracer/tests/fuzz-regressions/<target>/`) run the same code.

use crate::accel::{AccelKind, AccelOptions};
use crate::prepare::{prepare, PrepareOptions, PRECISION_RANGE};
use crate::render::{render, RenderSettings};
use nffkit_formats::fuzzing::Target;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Shape;

/// Every target, by the name of its fuzz binary and regression folder.
pub const TARGETS: [Target; 1] = [("render_nff", render_nff)];

/// Scenes larger than this are not rendered (a fuzzer wants many small
/// runs; the size limits have tests of their own).
const MAX_PRIMITIVES: usize = 256;
const MAX_VERTICES: usize = 4096;
const MAX_LIGHTS: usize = 8;

/// A scene the reader accepts renders without panicking, to the same bits
/// with every accelerator, with packets or without (the bits only within
/// single precision's dynamic range).
pub fn render_nff(data: &[u8]) {
    let Ok(parsed) = nff::parse(data, &ParseOptions { lenient: true, ..Default::default() }) else { return };
    let scene = parsed.scene;
    let vertices: usize = scene
        .primitives
        .iter()
        .map(|p| match &p.shape {
            Shape::Polygon { vertices } | Shape::Patch { vertices, .. } => vertices.len(),
            _ => 1,
        })
        .sum();
    if scene.view.is_none()
        || scene.primitives.len() > MAX_PRIMITIVES
        || vertices > MAX_VERTICES
        || scene.lights.len() > MAX_LIGHTS
    {
        return;
    }
    let image = |kind: AccelKind, packets: bool| {
        let accel = AccelOptions { kind, ..Default::default() };
        let opts = PrepareOptions { width: Some(8), height: Some(8), accel, ..Default::default() };
        let prepared = prepare(&scene, &opts).ok()?;
        let settings = RenderSettings { packets, ..Default::default() };
        let film = render(&prepared, &settings, &|_, _| {}).film;
        Some(film.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<u32>>())
    };
    // Past single precision's dynamic range the accelerators may settle
    // rounding differently (render warns of such scenes).
    let opts = PrepareOptions { width: Some(8), height: Some(8), ..Default::default() };
    if prepare(&scene, &opts).is_ok_and(|p| p.dynamic_range() > PRECISION_RANGE) {
        return;
    }
    let reference = image(AccelKind::Bvh, true);
    for &kind in AccelKind::ALL {
        for packets in [true, false] {
            assert!(image(kind, packets) == reference, "{kind} (packets {packets}) differs from the BVH");
        }
    }
}
