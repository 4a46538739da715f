//! Small test renders of the converted geometry, to choose a view and its
//! lights by what the camera would actually see: the NFF body is read back
//! and one accelerator built; each query swaps the camera and the lights and
//! renders [`SIZE`]² pixels at one sample, depth 2.

use anyhow::{Context, Result};
use glam::Vec3A;
use nffkit_formats::nff::{parse, ParseOptions};
use nffkit_formats::{Light, View};
use nffkit_tracer::camera::Camera;
use nffkit_tracer::prepare::{point_lights, prepare, Ambient, PrepareOptions, RenderScene};
use nffkit_tracer::render::{render, RenderSettings, ShadeSettings};

/// Side of a probe image in pixels.
pub const SIZE: u32 = 40;

/// What a probe render saw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seen {
    /// Pixels whose eye ray hit the model, as a fraction of the image.
    pub covered: f64,
    /// Of those, the fraction that came out lit (not black).
    pub lit: f64,
    /// Mean pixel brightness over the whole image.
    pub brightness: f64,
}

/// The converted geometry, ready for probe renders.
pub struct Probe {
    scene: RenderScene,
}

impl Probe {
    /// Read back `body` (materials and geometry as written) with `view` as
    /// a placeholder camera.
    pub fn new(body: &[u8], view: &View) -> Result<Probe> {
        let mut scene = parse(body, &ParseOptions { fragment: true, ..Default::default() })
            .map_err(|e| anyhow::anyhow!("{e}"))
            .context("reading back the converted geometry")?
            .scene;
        scene.view = Some(view.clone());
        let opts = PrepareOptions { width: Some(SIZE), height: Some(SIZE), ..Default::default() };
        let mut scene = prepare(&scene, &opts)?;
        scene.background = Vec3A::ZERO;
        Ok(Probe { scene })
    }

    /// Render from `view` with `lights` (intensities as the renderer gives
    /// them: a light without a colour gets 1/sqrt(n)).
    pub fn look(&mut self, view: &View, lights: &[Light]) -> Seen {
        self.scene.camera = Camera::new(view, SIZE, SIZE);
        self.scene.lights = point_lights(lights, Ambient::default()).0;
        let settings = RenderSettings {
            shade: ShadeSettings { max_depth: 2, ..Default::default() },
            ..Default::default()
        };
        let out = render(&self.scene, &settings, &|_, _| {});
        let pixels = (SIZE * SIZE) as f64;
        let (mut lit, mut sum) = (0u32, 0.0);
        for y in 0..SIZE {
            for x in 0..SIZE {
                let c = out.film.get(x, y).min(Vec3A::ONE);
                let l = (c.x + c.y + c.z) as f64 / 3.0;
                sum += l;
                lit += u32::from(l > 0.02);
            }
        }
        let hits = out.counters.eye_hits as f64;
        Seen {
            covered: hits / pixels,
            lit: if hits > 0.0 { (lit as f64 / hits).min(1.0) } else { 0.0 },
            brightness: sum / pixels,
        }
    }
}
