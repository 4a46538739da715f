//! The tracer's fuzz target bodies (see `nffkit_formats::fuzzing` for the
//! reader's), here so that the fuzzer (`fuzz/`) and the regular test that
//! replays every input it ever failed on
//! (`tracer/tests/fuzz-regressions/<target>/`) run the same code.

use crate::accel::{AccelKind, AccelOptions};
use crate::prepare::{prepare, PrepareOptions, RenderScene, PRECISION_RANGE};
use crate::render::{render, RenderSettings};
use nffkit_formats::fuzzing::Target;
use nffkit_formats::nff::{self, ParseOptions};

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
    let vertices: usize = scene.primitives.iter().map(|p| p.shape.vertices().map_or(1, <[_]>::len)).sum();
    if scene.view.is_none()
        || scene.primitives.len() > MAX_PRIMITIVES
        || vertices > MAX_VERTICES
        || scene.lights.len() > MAX_LIGHTS
    {
        return;
    }
    let prepared = |kind: AccelKind| {
        let accel = AccelOptions { kind, ..Default::default() };
        prepare(&scene, &PrepareOptions { width: Some(8), height: Some(8), accel, ..Default::default() }).ok()
    };
    let image = |scene: &RenderScene, packets: bool| {
        let film = render(scene, &RenderSettings { packets, ..Default::default() }, &|_, _| {}).film;
        film.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<u32>>()
    };
    let Some(bvh) = prepared(AccelKind::Bvh) else { return };
    // Past single precision's dynamic range the accelerators may settle
    // rounding differently (render warns of such scenes).
    if bvh.dynamic_range() > PRECISION_RANGE {
        return;
    }
    let reference = image(&bvh, true);
    for &kind in AccelKind::ALL {
        let scene = prepared(kind).expect("a scene prepared for one accelerator is for all");
        for packets in [true, false] {
            assert!(image(&scene, packets) == reference, "{kind} (packets {packets}) differs from the BVH");
        }
    }
}
