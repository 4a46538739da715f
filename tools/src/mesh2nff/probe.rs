//! A look at the converted geometry before the view and lights are
//! written, to choose them by what the camera would actually see: the NFF
//! body is read back and one accelerator built; each query traces
//! [`SIZE`]² eye rays for a view and shadow rays from what they hit to the
//! lights, and weighs the diffuse light each point gets.

use super::emission::Emission;
use anyhow::{Context, Result};
use glam::{DVec3, Vec3A};
use nffkit_formats::nff::{parse, ParseOptions};
use nffkit_formats::{Light, View};
use nffkit_tracer::camera::Camera;
use nffkit_tracer::prepare::{point_lights, prepare, Ambient, PrepareOptions, RenderScene};
use nffkit_tracer::probe::{light_reaching, sightings, Sighting};

/// Eye rays per side of a probe's view.
pub const SIZE: u32 = 32;

/// A point counts as lit when its lights give it at least this share of
/// its colour (a white triangle showing 2% grey is not lit).
const LIT: f32 = 0.1;

/// What a probe saw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seen {
    /// Eye rays that hit the model, as a fraction of all.
    pub covered: f64,
    /// Of the hits on surfaces with a colour, the fraction lit.
    pub lit: f64,
    /// Mean brightness of the diffuse shading over the whole view.
    pub brightness: f64,
}

/// How the model's emitting faces light what a view sees, against other
/// lights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weighing {
    /// The emitters' share of the light the seen surfaces get (1 when the
    /// view sees nothing but emitters).
    pub share: f64,
    /// The intensity the emission lights must have together (brightest
    /// channel) to give the seen surfaces what the emitters would.
    pub total: f64,
    /// The mean brightness of the view lit by the emission lights alone at
    /// a total of 1 (emitting faces included).
    pub brightness: f64,
}

/// The converted geometry, ready for probes.
pub struct Probe {
    scene: RenderScene,
    /// Per material of the scene, whether emitting faces use it.
    emitting: Vec<bool>,
}

impl Probe {
    /// Read back `body` (materials and geometry as written) with `view` as
    /// a placeholder camera; `emitting[k]` tells whether the body's `k`-th
    /// `f` line is one of emitting faces.
    pub fn new(body: &[u8], view: &View, emitting: &[bool]) -> Result<Probe> {
        let mut scene = parse(body, &ParseOptions { fragment: true, ..Default::default() })
            .map_err(|e| anyhow::anyhow!("{e}"))
            .context("reading back the converted geometry")?
            .scene;
        scene.view = Some(view.clone());
        let opts = PrepareOptions { width: Some(SIZE), height: Some(SIZE), ..Default::default() };
        let scene = prepare(&scene, &opts)?;
        // Material 0 is the default, before any `f`.
        let emitting = std::iter::once(false).chain(emitting.iter().copied()).collect();
        Ok(Probe { scene, emitting })
    }

    fn sight(&mut self, view: &View) -> Vec<Sighting> {
        self.scene.camera = Camera::new(view, SIZE, SIZE);
        sightings(&self.scene, SIZE)
    }

    /// What `view` sees lit by `lights` (intensities as the renderer gives
    /// them: a light without a colour gets 1/sqrt(n)).
    pub fn look(&mut self, view: &View, lights: &[Light]) -> Seen {
        let seen = self.sight(view);
        let lights = point_lights(lights, Ambient::default()).0;
        let positions: Vec<Vec3A> = lights.iter().map(|l| l.position).collect();
        let reach = light_reaching(&self.scene, &seen, &positions);
        let (mut coloured, mut lit, mut brightness) = (0u32, 0u32, 0.0);
        for (s, r) in seen.iter().zip(reach.chunks_exact(lights.len().max(1))) {
            let light: Vec3A = lights.iter().zip(r).map(|(l, c)| l.intensity * *c).sum();
            let shown = s.albedo * light;
            brightness += f64::from(shown.min(Vec3A::ONE).element_sum()) / 3.0;
            let a = s.albedo.max_element();
            if a > 0.0 {
                coloured += 1;
                lit += u32::from(shown.max_element() >= LIT * a.min(1.0));
            }
        }
        let rays = f64::from(SIZE * SIZE);
        Seen {
            covered: seen.len() as f64 / rays,
            lit: if coloured > 0 { f64::from(lit) / f64::from(coloured) } else { 0.0 },
            brightness: brightness / rays,
        }
    }

    /// How `emission` lights what `view` sees, against `others` (module
    /// doc of [`super::emission`]); surfaces of emitting faces are not
    /// counted, as they show their own colour.
    pub fn weigh(&mut self, view: &View, emission: &Emission, others: &[Light]) -> Weighing {
        let seen = self.sight(view);
        let unit = emission.lights(1.0);
        let mut positions: Vec<Vec3A> = unit.iter().map(|l| l.position.as_vec3a()).collect();
        let others = point_lights(others, Ambient::default()).0;
        positions.extend(others.iter().map(|l| l.position));
        let reach = light_reaching(&self.scene, &seen, &positions);
        let (mut receivers, mut physical, mut per_unit, mut other, mut brightness) = (0, 0.0, 0.0, 0.0, 0.0);
        for (s, r) in seen.iter().zip(reach.chunks_exact(positions.len().max(1))) {
            let (r_emit, r_other) = r.split_at(unit.len());
            let light: DVec3 =
                unit.iter().zip(r_emit).map(|(l, c)| l.color.unwrap_or_default() * f64::from(*c)).sum();
            brightness += mean((s.albedo.as_dvec3() * light).min(DVec3::ONE));
            if self.emitting[s.material as usize] {
                continue;
            }
            receivers += 1;
            physical += emission.irradiance(s.point.as_dvec3(), r_emit);
            per_unit += mean(light);
            other += others
                .iter()
                .zip(r_other)
                .map(|(l, c)| f64::from(l.intensity.element_sum() / 3.0 * c))
                .sum::<f64>();
        }
        let share = if receivers == 0 {
            1.0
        } else if physical + other > 0.0 {
            physical / (physical + other)
        } else {
            0.0
        };
        let total = if per_unit > 0.0 { physical / per_unit } else { 0.0 };
        Weighing { share, total, brightness: brightness / f64::from(SIZE * SIZE) }
    }
}

fn mean(c: DVec3) -> f64 {
    c.element_sum() / 3.0
}
