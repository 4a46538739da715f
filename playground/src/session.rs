//! One worker's render: a band of rows refined one sample per pass, with
//! its image kept as floats (for the error against the reference) and as
//! canvas bytes.

use crate::settings::Settings;
use nffkit_formats::image_io::to_u8;
use nffkit_tracer::prepare::{prepare, RenderScene};
use nffkit_tracer::progressive::{samples_per_pixel, Accumulator};
use nffkit_tracer::render::{PixelWindow, RenderSettings};

/// A prepared scene and the running sums of one band.
pub struct Session {
    scene: RenderScene,
    settings: RenderSettings,
    acc: Accumulator,
    pixels: Vec<f32>,
    rgba: Vec<u8>,
    pattern: Vec<f32>,
    command: String,
}

impl Session {
    /// Build the scene for `settings` and start on rows `y0..y1` (cut to
    /// the image).
    pub fn new(settings: &Settings, y0: u32, y1: u32) -> Result<Session, String> {
        let scene = prepare(&settings.scene()?, &settings.prepare_options()).map_err(|e| e.to_string())?;
        let render = settings.render_settings();
        let (w, h) = scene.camera.resolution();
        let (y0, y1) = (y0.min(h), y1.clamp(y0.min(h), h));
        let acc = Accumulator::new(PixelWindow { x0: 0, x1: w, y0, y1 }, &render);
        let mut session = Session {
            scene,
            settings: render,
            acc,
            pixels: Vec::new(),
            rgba: Vec::new(),
            pattern: Vec::new(),
            command: settings.command(),
        };
        session.refresh();
        Ok(session)
    }

    /// One more sample per pixel; the samples taken so far.
    pub fn pass(&mut self) -> u32 {
        self.acc.add_sample(&self.scene, &self.settings);
        self.refresh();
        self.acc.samples()
    }

    /// The band's image as floats and as canvas bytes, once per pass: RGBA
    /// quantised as `render` writes its PNGs (linear, no sRGB curve).
    fn refresh(&mut self) {
        let film = self.acc.film();
        self.pixels.clear();
        self.rgba.clear();
        for p in &film.pixels {
            let c = p.to_array();
            self.pixels.extend(c);
            self.rgba.extend(c.map(|v| to_u8(v, false)));
            self.rgba.push(255);
        }
    }

    /// Samples per pixel in all.
    pub fn total(&self) -> u32 {
        samples_per_pixel(&self.scene, &self.settings)
    }

    /// The command line that renders the same image.
    pub fn command(&self) -> &str {
        &self.command
    }

    /// Image width.
    pub fn width(&self) -> u32 {
        self.scene.camera.resolution().0
    }

    /// Image height.
    pub fn height(&self) -> u32 {
        self.scene.camera.resolution().1
    }

    /// The band so far, linear RGB.
    pub fn pixels(&self) -> &[f32] {
        &self.pixels
    }

    /// The band so far as canvas RGBA.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// The strata the pattern guarantees, as `coarse << 16 | fine` cells
    /// per side ([`nffkit_tracer::sampling::SamplerKind::strata`]).
    pub fn strata(&self) -> u32 {
        let s = &self.settings.sampler;
        let (coarse, fine) = s.kind.strata(s.spp);
        coarse << 16 | fine
    }

    /// The unit-square positions of pixel (`px`, `py`)'s samples, as the
    /// sampler places them before the filter warps them.
    pub fn pattern(&mut self, px: u32, py: u32) -> &[f32] {
        let sampler = &self.settings.sampler;
        let p = sampler.pattern(px, py, 0);
        self.pattern.clear();
        self.pattern.extend((0..sampler.spp).flat_map(|i| sampler.sample_of(p, i).to_array()));
        &self.pattern
    }
}
