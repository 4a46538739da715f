//! A render that refines: every pixel of a window takes one more sample per
//! pass, and the image after the last pass is the one [`crate::render`]
//! makes with the same settings, bit for bit. `render` sums a pixel's
//! samples in sample order and divides once; a pass adds sample `k` of
//! every pixel to the same running sums, so the sums are the same numbers
//! added in the same order. The browser playground draws the image after
//! each pass.

use crate::accel::{with_accel, Intersector, Tracer};
use crate::film::Film;
use crate::filter::Filter;
use crate::integrator::{EyeChunk, SampleId, ThreadState, Whitted};
use crate::prepare::RenderScene;
use crate::render::{resolve, trace_chunks, PixelSamples, PixelWindow, RenderSettings};
use crate::shadow_cache::ShadowCache;
use crate::simd::lanes::LANES;
use glam::{Vec2, Vec3A};

/// The running sums of a window's pixels.
pub struct Accumulator {
    window: PixelWindow,
    filter: Filter,
    sums: Vec<Vec3A>,
    weights: Vec<f32>,
    samples: u32,
}

impl Accumulator {
    /// No samples yet over `window` (the render's filter taken from
    /// `settings`).
    pub fn new(window: PixelWindow, settings: &RenderSettings) -> Accumulator {
        let n = (window.width() * window.height()) as usize;
        Accumulator {
            window,
            filter: Filter::new(settings.filter),
            sums: vec![Vec3A::ZERO; n],
            weights: vec![0.0; n],
            samples: 0,
        }
    }

    /// Samples per pixel taken so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Whether every sample of `settings`' pattern has been taken.
    pub fn done(&self, scene: &RenderScene, settings: &RenderSettings) -> bool {
        self.samples >= samples_per_pixel(scene, settings)
    }

    /// Take the next sample of every pixel (nothing once [`Self::done`]).
    /// The window must lie inside the image; the SPD's corner procedure
    /// (`shade.spd`) is not progressive and is not taken.
    pub fn add_sample(&mut self, scene: &RenderScene, settings: &RenderSettings) {
        if self.done(scene, settings) {
            return;
        }
        with_accel!(&scene.accel, a => self.add_sample_with(scene, a, settings));
        self.samples += 1;
    }

    fn add_sample_with<I: Intersector>(&mut self, scene: &RenderScene, accel: &I, settings: &RenderSettings) {
        let camera = &scene.camera;
        let sampler = &settings.sampler;
        let shader = Whitted { scene, sampler, settings: settings.shade };
        let mut th = ThreadState {
            tracer: Tracer::new(accel, &scene.geometry),
            shadow_cache: ShadowCache::new(
                scene.lights.len(),
                settings.shade.max_depth,
                settings.shadow_cache,
            ),
        };
        let centre = settings.pixel_centre_only(camera);
        let index = self.samples;
        let win = self.window;
        let width = win.width() as usize;
        let len = self.sums.len();
        let aim = |c: usize, chunk: &mut EyeChunk| {
            let first = c * LANES;
            chunk.n = (len - first).min(LANES);
            for i in 0..chunk.n {
                let (px, py) = (win.x0 + ((first + i) % width) as u32, win.y0 + ((first + i) / width) as u32);
                let (raster, lens, weight) = if centre {
                    (Vec2::new(px as f32 + 0.5, py as f32 + 0.5), Vec2::ZERO, 1.0)
                } else {
                    PixelSamples::new(camera, sampler, &self.filter, px, py).point(index)
                };
                chunk.eye.set(i, raster, lens);
                (chunk.weights[i], chunk.ids[i]) = (weight, SampleId { px, py, index });
            }
        };
        let (sums, weights) = (&mut self.sums, &mut self.weights);
        let take = |c: usize, w: &[f32], colors: &[Vec3A]| {
            for (i, (&w, &color)) in w.iter().zip(colors).enumerate() {
                sums[c * LANES + i] += w * color;
                weights[c * LANES + i] += w;
            }
        };
        trace_chunks(&shader, settings, len.div_ceil(LANES), &mut th, aim, take);
    }

    /// The image so far (black before the first sample).
    pub fn film(&self) -> Film {
        let spp = self.samples.max(1);
        let pixels = self.sums.iter().zip(&self.weights).map(|(&s, &w)| resolve(s, w, spp)).collect();
        Film { width: self.window.width(), height: self.window.height(), pixels }
    }
}

/// How many samples each pixel takes: the pattern's count, or one through
/// the centre.
pub fn samples_per_pixel(scene: &RenderScene, settings: &RenderSettings) -> u32 {
    if settings.pixel_centre_only(&scene.camera) {
        1
    } else {
        settings.sampler.spp
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::FilterKind;
    use crate::prepare::{prepare, PrepareOptions};
    use crate::render::render;
    use crate::sampling::{Sampler, SamplerKind};
    use nffkit_formats::nff::{parse, ParseOptions};

    // A mirror ball and a glass ball over a checker of two squares, lit by
    // two lights: reflection, refraction and shadows in every pixel.
    const SCENE: &str = "v\nfrom 0 -6 2\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 24 20\n\
        b 0.2 0.3 0.5\nl 3 -4 6\nl -3 -2 5\nf 1 0.2 0.2 0.3 0.7 30 0 1\ns -0.8 0 0.5 0.6\n\
        f 0.8 0.9 1 0.1 0.3 30 0.7 1.5\ns 0.8 0.3 0.5 0.6\n\
        f 0.9 0.9 0.9 1 0 1 0 1\np 4\n-4 -4 0\n4 -4 0\n4 0 0\n-4 0 0\n\
        f 0.1 0.1 0.1 1 0 1 0 1\np 4\n-4 0 0\n4 0 0\n4 4 0\n-4 4 0\n";

    fn settings(
        kind: SamplerKind,
        spp: u32,
        filter: FilterKind,
        light_size: f32,
        packets: bool,
    ) -> RenderSettings {
        let mut s = RenderSettings {
            sampler: Sampler::new(kind, spp, 3).0,
            centre_single_sample: false,
            filter,
            packets,
            ..Default::default()
        };
        s.shade.light_size = light_size;
        s
    }

    #[test]
    fn the_last_pass_is_the_render_bit_for_bit() {
        let scene = parse(SCENE.as_bytes(), &ParseOptions::default()).unwrap().scene;
        for aperture in [None, Some(0.3)] {
            let opts = PrepareOptions { aperture, focus: Some(6.0), ..Default::default() };
            let prepared = prepare(&scene, &opts).unwrap();
            for (kind, spp, filter, light, packets) in [
                (SamplerKind::MultiJittered, 16, FilterKind::Box, 0.0, true),
                (SamplerKind::Sobol, 5, FilterKind::Mitchell, 0.0, false),
                (SamplerKind::Jittered, 4, FilterKind::Gaussian, 0.8, true),
                (SamplerKind::Random, 1, FilterKind::Tent, 0.0, true),
            ] {
                let s = settings(kind, spp, filter, light, packets);
                let want = render(&prepared, &s, &|_, _| {}).film;
                let mut acc = Accumulator::new(PixelWindow::full(24, 20), &s);
                let mut passes = 0;
                while !acc.done(&prepared, &s) {
                    acc.add_sample(&prepared, &s);
                    passes += 1;
                }
                assert_eq!(passes, s.sampler.spp);
                assert_eq!(acc.film().pixels, want.pixels, "{kind} {spp} {filter} aperture {aperture:?}");
                // A band of rows is the same rows of the whole.
                let band = PixelWindow { x0: 0, x1: 24, y0: 7, y1: 13 };
                let mut part = Accumulator::new(band, &s);
                while !part.done(&prepared, &s) {
                    part.add_sample(&prepared, &s);
                }
                assert_eq!(part.film().pixels[..], want.pixels[7 * 24..13 * 24]);
            }
        }
    }

    #[test]
    fn a_single_centred_sample_is_the_classic_render() {
        let scene = parse(SCENE.as_bytes(), &ParseOptions::default()).unwrap().scene;
        let prepared = prepare(&scene, &PrepareOptions::default()).unwrap();
        let s = RenderSettings::default();
        let mut acc = Accumulator::new(PixelWindow::full(24, 20), &s);
        acc.add_sample(&prepared, &s);
        acc.add_sample(&prepared, &s);
        assert_eq!(acc.samples(), 1);
        assert_eq!(acc.film().pixels, render(&prepared, &s, &|_, _| {}).film.pixels);
    }
}
