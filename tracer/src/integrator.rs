//! Classic NFF Whitted shading. For each light whose shadow ray is clear:
//! `I · (Kd · colour · max(0, N·L) + Ks · max(0, R·V)^Shine)`; plus
//! `Ks · reflected` and `T · refracted` (Snell's law with the material's
//! index; on total internal reflection the reflection is traced instead);
//! no shadow ray when N·L ≤ 0; the background for rays that escape.

use crate::accel::Intersector;
use crate::math::{basis, offset_ray_origin, reflect, refract, Ray, RayQuery};
use crate::prepare::RenderScene;
use crate::sampling::{concentric_disk, Sampler};
use crate::stats::Counters;
use glam::{Vec2, Vec3A};
use strum::{Display, IntoStaticStr, VariantArray};

/// Shape of the area that `--light-size` gives each point light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum LightShape {
    /// A square of side `size`, facing the shaded point.
    #[default]
    Square,
    /// A disc of diameter `size`, facing the shaded point.
    Disk,
}

/// Settings of the shader.
#[derive(Debug, Clone, Copy)]
pub struct ShadeSettings {
    /// Longest ray path, counting the eye ray as depth 1.
    pub max_depth: u32,
    /// Side (square) or diameter (disc) of each light; 0 for point lights.
    pub light_size: f32,
    /// Shape of the light area.
    pub light_shape: LightShape,
    /// Adaptive depth control: secondary rays whose weight (the product of
    /// the Ks and T factors along their path) falls below this are not
    /// traced. 0 traces every ray up to `max_depth` (the classic rule);
    /// POV-Ray's default `adc_bailout` is 1/255.
    pub min_weight: f32,
}

/// Which sample of which pixel a ray belongs to, for drawing light samples.
#[derive(Debug, Clone, Copy)]
pub struct SampleId {
    /// Pixel x.
    pub px: u32,
    /// Pixel y.
    pub py: u32,
    /// Sample index within the pixel.
    pub index: u32,
}

/// Per-thread state: the accelerator's scratch and the counters.
pub struct ThreadState<S> {
    /// The accelerator's scratch (the grid's mailbox).
    pub scratch: S,
    /// Work counters.
    pub counters: Counters,
}

/// The shader over one scene and accelerator.
pub struct Whitted<'a, I: Intersector> {
    /// The scene.
    pub scene: &'a RenderScene,
    /// The accelerator.
    pub accel: &'a I,
    /// The sampler for light positions.
    pub sampler: &'a Sampler,
    /// Settings.
    pub settings: ShadeSettings,
}

/// Sample dimensions: 0 is the pixel position, 1 the lens; lights follow,
/// one dimension per light per bounce.
pub const FIRST_LIGHT_DIMENSION: u32 = 2;

impl<I: Intersector> Whitted<'_, I> {
    /// Radiance along `ray`, which starts at distance `t_min` (the hither
    /// plane for eye rays), has path depth `depth` (1 for eye rays) and
    /// carries `weight`, the product of the Ks and T factors that led to it.
    pub fn li(
        &self,
        ray: Ray,
        t_min: f32,
        depth: u32,
        weight: f32,
        id: SampleId,
        th: &mut ThreadState<I::Scratch>,
    ) -> Vec3A {
        let scene = self.scene;
        let q = RayQuery::new(ray, t_min);
        let hit = self.accel.intersect(&scene.geometry, &q, f32::INFINITY, &mut th.scratch, &mut th.counters);
        let Some(hit) = hit else { return scene.background };
        let s = scene.geometry.surface(&hit, &q);
        let info = scene.geometry.info[hit.prim as usize];
        let m = scene.materials[info.material as usize];
        let d = ray.d;
        // Face the normals towards the incoming ray (two-sided shading).
        let entering = s.ng.dot(d) < 0.0;
        let flip = if entering { 1.0 } else { -1.0 };
        let (ng, ns) = (s.ng * flip, s.ns * flip);
        let mut color = Vec3A::ZERO;
        let view = -d;
        for (k, light) in scene.lights.iter().enumerate() {
            let pos = self.light_position(k, light.position, s.p, depth, id);
            let to_light = pos - s.p;
            let dist = to_light.length();
            if dist == 0.0 {
                continue;
            }
            let l = to_light / dist;
            let n_dot_l = ns.dot(l);
            if n_dot_l <= 0.0 {
                continue;
            }
            let side = if ng.dot(l) >= 0.0 { ng } else { -ng };
            let origin = offset_ray_origin(s.p, side);
            let sq = RayQuery::new(Ray { o: origin, d: (pos - origin).normalize() }, 0.0);
            th.counters.shadow += 1;
            let max = (pos - origin).length();
            if self.accel.occluded(&scene.geometry, &sq, max, &mut th.scratch, &mut th.counters) {
                continue;
            }
            let r = reflect(-l, ns);
            let spec = if m.ks > 0.0 { m.ks * r.dot(view).max(0.0).powf(m.shine) } else { 0.0 };
            color += light.intensity * (m.kd * n_dot_l * m.color + Vec3A::splat(spec));
        }
        if depth >= self.settings.max_depth {
            return color;
        }
        let min = self.settings.min_weight;
        if m.ks > 0.0 && weight * m.ks >= min {
            th.counters.reflected += 1;
            let r = self.mirror(d, ns, ng);
            let o = offset_ray_origin(s.p, ng);
            color += m.ks * self.li(Ray { o, d: r }, 0.0, depth + 1, weight * m.ks, id, th);
        }
        if m.t > 0.0 && weight * m.t >= min {
            th.counters.refracted += 1;
            let eta = if entering { 1.0 / m.ior } else { m.ior };
            let traced = match refract(d, ns, eta) {
                Some(t) if t.dot(ng) < 0.0 => self.li(
                    Ray { o: offset_ray_origin(s.p, -ng), d: t },
                    0.0,
                    depth + 1,
                    weight * m.t,
                    id,
                    th,
                ),
                _ => {
                    // Total internal reflection: the transmitted share reflects.
                    let r = self.mirror(d, ns, ng);
                    self.li(Ray { o: offset_ray_origin(s.p, ng), d: r }, 0.0, depth + 1, weight * m.t, id, th)
                }
            };
            color += m.t * traced;
        }
        color
    }

    /// Mirror direction by the shading normal, falling back to the geometric
    /// one when an interpolated normal would send the ray into the surface.
    #[inline]
    fn mirror(&self, d: Vec3A, ns: Vec3A, ng: Vec3A) -> Vec3A {
        let r = reflect(d, ns);
        if r.dot(ng) > 0.0 {
            r
        } else {
            reflect(d, ng)
        }
    }

    /// Where light `k` is seen from `p`: its position, or one sample on the
    /// square or disc of `light_size` facing `p` (P3D report §2.2: one light sample
    /// per light per primary sample, from the light's own dimension).
    #[inline]
    fn light_position(&self, k: usize, center: Vec3A, p: Vec3A, depth: u32, id: SampleId) -> Vec3A {
        let size = self.settings.light_size;
        if size <= 0.0 {
            return center;
        }
        let n_lights = self.scene.lights.len() as u32;
        let dim = FIRST_LIGHT_DIMENSION + (depth - 1) * n_lights + k as u32;
        let u = self.sampler.sample(id.px, id.py, id.index, dim);
        let offset = match self.settings.light_shape {
            LightShape::Square => (u - Vec2::splat(0.5)) * size,
            LightShape::Disk => concentric_disk(u) * (0.5 * size),
        };
        let w = (p - center).normalize_or_zero();
        if w == Vec3A::ZERO {
            return center;
        }
        let (a, b) = basis(w);
        center + a * offset.x + b * offset.y
    }
}
