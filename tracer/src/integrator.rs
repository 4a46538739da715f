//! Classic NFF Whitted shading. `ambient · Kd · colour`, and for each light
//! whose shadow ray is clear:
//! `I · (Kd · colour · max(0, N·L) + Ks · max(0, R·V)^Shine)`; plus
//! `Ks · reflected` and `T · refracted` (Snell's law with the material's
//! index; on total internal reflection the reflection is traced instead);
//! no shadow ray when N·L ≤ 0; the background for rays that escape.
//!
//! Which rays are spawned follows one of two rules ([`ShadeSettings::spd_rules`]):
//!
//! - Plain rendering, the NFF reading: a reflection ray when Ks > 0, a
//!   refraction ray when T > 0. A glass written with Ks = 0 shows no
//!   reflection, as its file says; on total internal reflection its
//!   transmitted share reflects (counted as a reflected ray).
//! - The SPD testing procedure (`--spd-stats`, SPD Readme rules 8 and 9):
//!   every hit on a reflective *or transmitting* surface spawns a
//!   reflection ray, weighted Ks (its share of the image, possibly 0), and a
//!   transmitter spawns a refraction ray unless there is total internal
//!   reflection, when the transmitted share goes to that one reflection ray.

use crate::accel::{test_shadow, Intersector};
use crate::math::{basis, offset_ray_origin, reflect, refract, shadow_ray, Ray, RayQuery};
use crate::prepare::RenderScene;
use crate::sampling::{concentric_disk, Sampler};
use crate::shadow_cache::ShadowCache;
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
    /// Spawn rays by the SPD testing procedure (module doc) instead of the
    /// plain NFF rule.
    pub spd_rules: bool,
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

/// Per-thread state: the accelerator's scratch, the shadow cache and the
/// counters.
pub struct ThreadState<S> {
    /// The accelerator's scratch (the grid's mailbox).
    pub scratch: S,
    /// Last occluder per light and depth.
    pub shadow_cache: ShadowCache,
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
        if depth == 1 {
            th.counters.eye_hits += 1;
        }
        let s = scene.geometry.surface(&hit, &q);
        let info = scene.geometry.info[hit.prim as usize];
        let m = scene.materials[info.material as usize];
        let d = ray.d;
        // Face the normals towards the incoming ray (two-sided shading).
        let entering = s.ng.dot(d) < 0.0;
        let flip = if entering { 1.0 } else { -1.0 };
        let (ng, ns) = (s.ng * flip, s.ns * flip);
        let mut color = scene.ambient * m.kd * m.color;
        let view = -d;
        for (k, light) in scene.lights.iter().enumerate() {
            let pos = self.light_position(k, light.position, s.p, depth, id);
            let Some((l, n_dot_l)) = self.lit(s.p, pos, ng, ns, (k, depth), th) else { continue };
            let r = reflect(-l, ns);
            let spec = if m.ks > 0.0 { m.ks * r.dot(view).max(0.0).powf(m.shine) } else { 0.0 };
            color += light.intensity * (m.kd * n_dot_l * m.color + Vec3A::splat(spec));
        }
        if depth >= self.settings.max_depth {
            return color;
        }
        let min = self.settings.min_weight;
        let refracted = if m.t > 0.0 {
            let eta = if entering { 1.0 / m.ior } else { m.ior };
            refract(d, ns, eta).filter(|t| t.dot(ng) < 0.0)
        } else {
            None
        };
        let tir = m.t > 0.0 && refracted.is_none();
        let trace_mirror = |share: f32, th: &mut ThreadState<I::Scratch>| {
            th.counters.reflected += 1;
            let o = offset_ray_origin(s.p, ng);
            share * self.li(Ray { o, d: self.mirror(d, ns, ng) }, 0.0, depth + 1, weight * share, id, th)
        };
        if self.settings.spd_rules {
            // Rules 8 and 9: one reflection ray at any reflector or
            // transmitter, carrying the transmitted share on TIR.
            let share = m.ks + if tir { m.t } else { 0.0 };
            if (m.ks > 0.0 || m.t > 0.0) && weight * share >= min {
                color += trace_mirror(share, th);
            }
        } else {
            if m.ks > 0.0 && weight * m.ks >= min {
                color += trace_mirror(m.ks, th);
            }
            // Total internal reflection: the transmitted share reflects.
            if tir && weight * m.t >= min {
                color += trace_mirror(m.t, th);
            }
        }
        if let Some(t) = refracted {
            if weight * m.t >= min {
                th.counters.refracted += 1;
                let o = offset_ray_origin(s.p, -ng);
                color += m.t * self.li(Ray { o, d: t }, 0.0, depth + 1, weight * m.t, id, th);
            }
        }
        color
    }

    /// The direction to a light at `pos` and N·L, when the light faces the
    /// point and its shadow ray ([`shadow_ray`]) is clear, counting the
    /// shadow ray. The shadow cache's primitive for (light, depth) is tested
    /// first.
    #[inline]
    fn lit(
        &self,
        p: Vec3A,
        pos: Vec3A,
        ng: Vec3A,
        ns: Vec3A,
        (light, depth): (usize, u32),
        th: &mut ThreadState<I::Scratch>,
    ) -> Option<(Vec3A, f32)> {
        let to_light = pos - p;
        let dist = to_light.length();
        if dist == 0.0 {
            return None;
        }
        let l = to_light / dist;
        let n_dot_l = ns.dot(l);
        if n_dot_l <= 0.0 {
            return None;
        }
        let side = if ng.dot(l) >= 0.0 { ng } else { -ng };
        th.counters.shadow += 1;
        let (ray, max) = shadow_ray(p, pos, side)?;
        let sq = RayQuery::new(ray, 0.0);
        let geom = &self.scene.geometry;
        if let Some(id) = th.shadow_cache.get(light, depth) {
            if test_shadow(geom, id, &sq, max, &mut th.counters) {
                th.counters.shadow_cache_hits += 1;
                return None;
            }
        }
        match self.accel.occluder(geom, &sq, max, &mut th.scratch, &mut th.counters) {
            Some(id) => {
                th.shadow_cache.set(light, depth, id);
                None
            }
            None => Some((l, n_dot_l)),
        }
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
