//! Classic NFF Whitted shading. `ambient · Kd · colour`, and for each light
//! whose shadow ray is clear:
//! `I · (Kd · colour · max(0, N·L) + Ks · max(0, R·V)^Shine)`; plus
//! `Ks · reflected` and `T · refracted` (Snell's law with the material's
//! index; on total internal reflection the reflection is traced instead);
//! no shadow ray when N·L ≤ 0; the background (or the cube map) for rays
//! that escape. P3F's specular colour tints the highlight and the mirror
//! ray (white in NFF, where the tint changes no bit).
//!
//! Which rays are spawned follows one of two rules ([`ShadeSettings::spd`]):
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
//!
//! A transmitter under the Fresnel rule (P3F's materials, or `--fresnel`)
//! spawns instead a mirror ray weighted by the Fresnel reflectance Kr and
//! a refracted ray weighted T·(1 − Kr), as the P3D course's tracers do; on
//! total internal reflection Kr = 1.
//!
//! This file traces ray by ray; [`packet`] traces the same shading for
//! packets of rays, sharing every decision made here.

mod packet;
mod wave;

pub(crate) use wave::EyeChunk;

use crate::accel::{test_prim, AnyHit, Intersector, Tracer};
use crate::geometry::Hit;
use crate::light::LightShape;
use crate::material::{fresnel_reflectance, WhittedMaterial};
use crate::math::{offset_ray_origin, reflect, refract, shadow_ray, Ray, RayQuery};
use crate::prepare::RenderScene;
use crate::sampling::Sampler;
use crate::shadow_cache::ShadowCache;
use crate::stats::Counters;
use glam::Vec3A;

/// Settings of the shader.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    /// The SPD testing procedure: rays spawned by its rules (module doc),
    /// and (in the render loop) one eye ray through each pixel corner.
    pub spd: bool,
}

impl Default for ShadeSettings {
    /// Depth 6 (the P3D report's), point lights, every ray traced, the
    /// plain NFF rule.
    fn default() -> Self {
        ShadeSettings {
            max_depth: 6,
            light_size: 0.0,
            light_shape: LightShape::Square,
            min_weight: 0.0,
            spd: false,
        }
    }
}

/// Which sample of which pixel a ray belongs to, for drawing light samples.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SampleId {
    /// Pixel x.
    pub px: u32,
    /// Pixel y.
    pub py: u32,
    /// Sample index within the pixel.
    pub index: u32,
}

/// Per-thread state: the tracing context and the shadow cache.
pub(crate) struct ThreadState<'a, I: Intersector> {
    /// The accelerator, the primitives, the thread's scratch and counters.
    pub tracer: Tracer<'a, I>,
    /// Last occluder per light and depth.
    pub shadow_cache: ShadowCache,
}

/// The shader over one scene.
pub(crate) struct Whitted<'a> {
    /// The scene.
    pub scene: &'a RenderScene,
    /// The sampler for light positions.
    pub sampler: &'a Sampler,
    /// Settings.
    pub settings: ShadeSettings,
}

/// Sample dimensions: 0 is the pixel position, 1 the lens; lights follow,
/// one dimension per light per bounce.
pub(crate) const FIRST_LIGHT_DIMENSION: u32 = 2;

/// What shading needs of a hit: the point, normals facing the incoming ray
/// (two-sided shading), the ray's direction and the material.
#[derive(Clone, Copy)]
struct ShadePoint<'s> {
    p: Vec3A,
    ng: Vec3A,
    ns: Vec3A,
    d: Vec3A,
    entering: bool,
    m: &'s WhittedMaterial,
}

/// A shadow ray toward one light, with the light direction and N·L that its
/// contribution needs when the ray is clear.
#[derive(Clone, Copy)]
struct LightRay {
    l: Vec3A,
    n_dot_l: f32,
    query: RayQuery,
    max: f32,
}

/// The rays a hit spawns, each with the share of the colour it carries: the
/// mirror ray, the mirror ray carrying the transmitted share on total
/// internal reflection (plain rule only), the refracted ray.
type Spawned = [Option<(Ray, f32)>; 3];

/// The shares of a [`Spawned`], without its rays.
type Shares = [Option<f32>; 3];

impl Whitted<'_> {
    /// Radiance along `ray`, which starts at distance `t_min` (the hither
    /// plane for eye rays), has path depth `depth` (1 for eye rays) and
    /// carries `weight`, the product of the Ks and T factors that led to it.
    pub fn li<I: Intersector>(
        &self,
        ray: Ray,
        t_min: f32,
        depth: u32,
        weight: f32,
        id: SampleId,
        th: &mut ThreadState<I>,
    ) -> Vec3A {
        let (mut color, Some(sp)) = self.local(ray, t_min, depth, id, th) else {
            return self.scene.miss(ray.d);
        };
        for (kind, spawned) in self.spawn(&sp, depth, weight, &mut th.tracer.counters).into_iter().enumerate()
        {
            let Some((ray, share)) = spawned else { continue };
            color += share * tint(kind, sp.m) * self.li(ray, 0.0, depth + 1, weight * share, id, th);
        }
        color
    }

    /// What `ray` (from `t_min`, at `depth`) sees before any ray it
    /// spawns: with its hit's shading record, the ambient and direct light
    /// there; without a hit, no record (the colour is then black, and
    /// [`RenderScene::miss`] says what the ray sees).
    #[inline]
    fn local<I: Intersector>(
        &self,
        ray: Ray,
        t_min: f32,
        depth: u32,
        id: SampleId,
        th: &mut ThreadState<I>,
    ) -> (Vec3A, Option<ShadePoint<'_>>) {
        let scene = self.scene;
        let q = RayQuery::new(ray, t_min);
        let Some(hit) = th.tracer.nearest(&q, f32::INFINITY) else { return (Vec3A::ZERO, None) };
        if depth == 1 {
            th.tracer.counters.eye_hits += 1;
        }
        let sp = self.shade_point(&q, &hit);
        let mut color = scene.ambient * sp.m.kd * sp.m.color;
        for k in 0..scene.lights.len() {
            let Some(lr) = self.light_ray(&sp, k, depth, id, &mut th.tracer.counters) else { continue };
            if !self.shadowed(&lr, k, depth, th) {
                color += self.direct(&sp, k, lr.l, lr.n_dot_l);
            }
        }
        (color, Some(sp))
    }

    /// The shading record of `hit` on the ray of `q`.
    #[inline]
    fn shade_point(&self, q: &RayQuery, hit: &Hit) -> ShadePoint<'_> {
        let scene = self.scene;
        let s = scene.geometry.surface(hit, q);
        let m = &scene.materials[scene.geometry.info[hit.prim as usize].material as usize];
        let d = q.ray.d;
        // Face the normals towards the incoming ray (two-sided shading).
        let entering = s.ng.dot(d) < 0.0;
        let flip = if entering { 1.0 } else { -1.0 };
        ShadePoint { p: s.p, ng: s.ng * flip, ns: s.ns * flip, d, entering, m }
    }

    /// What light `k`, in direction `l` with `n_dot_l` = N·L, adds at `sp`
    /// when its shadow ray is clear.
    #[inline]
    fn direct(&self, sp: &ShadePoint, k: usize, l: Vec3A, n_dot_l: f32) -> Vec3A {
        let m = sp.m;
        let r = reflect(-l, sp.ns);
        let spec = if m.ks > 0.0 { m.ks * r.dot(-sp.d).max(0.0).powf(m.shine) } else { 0.0 };
        self.scene.lights[k].intensity * (m.kd * n_dot_l * m.color + spec * m.specular)
    }

    /// The rays the rule in force spawns at `sp` ([`Spawned`]), counting
    /// them.
    fn spawn(&self, sp: &ShadePoint, depth: u32, weight: f32, c: &mut Counters) -> Spawned {
        if depth >= self.settings.max_depth {
            return [None; 3];
        }
        let ShadePoint { p, ng, ns, d, entering, m } = *sp;
        let refracted = if m.t > 0.0 {
            refract(d, ns, m.eta(entering))
                .filter(|t| t.dot(ng) < 0.0)
                .map(|t| Ray { o: offset_ray_origin(p, -ng), d: t })
        } else {
            None
        };
        self.choose_rays(
            sp,
            weight,
            refracted,
            || Ray { o: offset_ray_origin(p, ng), d: mirror(d, ns, ng) },
            c,
        )
    }

    /// Which rays a hit at `sp` spawns, given its refracted ray (`None` on
    /// total internal reflection or where its material transmits nothing)
    /// and its mirror ray: the rule of the module doc ([`Whitted::shares`]).
    #[inline(always)]
    fn choose_rays(
        &self,
        sp: &ShadePoint,
        weight: f32,
        refracted: Option<Ray>,
        mirror_ray: impl Fn() -> Ray,
        c: &mut Counters,
    ) -> Spawned {
        let [mirror, tir, refract] = self.shares(sp, weight, refracted.is_some(), c);
        [
            mirror.map(|share| (mirror_ray(), share)),
            tir.map(|share| (mirror_ray(), share)),
            refracted.zip(refract),
        ]
    }

    /// The shares of the colour carried by the rays a hit at `sp` spawns
    /// (a [`Spawned`] without the rays, which packets hold lane-wise),
    /// given whether it has a refracted ray: the rule of the module doc.
    /// Counts the rays.
    #[inline(always)]
    fn shares(&self, sp: &ShadePoint, weight: f32, refracts: bool, c: &mut Counters) -> Shares {
        let m = sp.m;
        let mut out = [None; 3];
        let min = self.settings.min_weight;
        let tir = m.t > 0.0 && !refracts;
        let mut mirror = |share: f32| {
            c.reflected += 1;
            Some(share)
        };
        if m.fresnel_weighted() && !self.settings.spd {
            let kr = if tir { 1.0 } else { fresnel_reflectance(-sp.d.dot(sp.ns), m.eta(sp.entering)) };
            if kr > 0.0 && weight * kr >= min {
                out[0] = mirror(kr);
            }
            let share = m.t * (1.0 - kr);
            if refracts && share > 0.0 && weight * share >= min {
                c.refracted += 1;
                out[2] = Some(share);
            }
            return out;
        }
        if self.settings.spd {
            // Rules 8 and 9: one reflection ray at any reflector or
            // transmitter, carrying the transmitted share on TIR.
            let share = m.ks + if tir { m.t } else { 0.0 };
            if m.spawns_rays() && weight * share >= min {
                out[0] = mirror(share);
            }
        } else {
            if m.ks > 0.0 && weight * m.ks >= min {
                out[0] = mirror(m.ks);
            }
            // Total internal reflection: the transmitted share reflects.
            if tir && weight * m.t >= min {
                out[1] = mirror(m.t);
            }
        }
        if refracts && weight * m.t >= min {
            c.refracted += 1;
            out[2] = Some(m.t);
        }
        out
    }

    /// The shadow ray toward light `k` ([`shadow_ray`]) when the light
    /// faces the point, counting it.
    #[inline]
    fn light_ray(
        &self,
        sp: &ShadePoint,
        k: usize,
        depth: u32,
        id: SampleId,
        c: &mut Counters,
    ) -> Option<LightRay> {
        let pos = self.light_position(k, sp.p, depth, id);
        let to_light = pos - sp.p;
        let dist = to_light.length();
        if dist == 0.0 {
            return None;
        }
        let l = to_light / dist;
        let n_dot_l = sp.ns.dot(l);
        if n_dot_l <= 0.0 {
            return None;
        }
        let side = if sp.ng.dot(l) >= 0.0 { sp.ng } else { -sp.ng };
        c.shadow += 1;
        let (ray, max) = shadow_ray(sp.p, pos, side)?;
        Some(LightRay { l, n_dot_l, query: RayQuery::new(ray, 0.0), max })
    }

    /// Whether anything blocks the shadow ray: the shadow cache's primitive
    /// for (light, depth) first (counting a cache hit), then the
    /// accelerator, whose blocker the cache remembers.
    #[inline]
    fn shadowed<I: Intersector>(
        &self,
        lr: &LightRay,
        light: usize,
        depth: u32,
        th: &mut ThreadState<I>,
    ) -> bool {
        let tr = &mut th.tracer;
        if let Some(id) = th.shadow_cache.get(light, depth) {
            if test_prim::<AnyHit>(tr.geom, id, &lr.query, &mut None, lr.max, &mut tr.counters) {
                tr.counters.shadow_cache_hits += 1;
                return true;
            }
        }
        match tr.occluder(&lr.query, lr.max) {
            Some(id) => {
                th.shadow_cache.set(light, depth, id);
                true
            }
            None => false,
        }
    }

    /// Light `k`'s position where every point sees it there: a point light
    /// (no `--light-size` and no shape of its own).
    #[inline]
    fn fixed_light_position(&self, k: usize) -> Option<Vec3A> {
        let light = &self.scene.lights[k];
        (self.settings.light_size <= 0.0 && light.rect.is_none()).then_some(light.position)
    }

    /// Where light `k` is seen from `p`: its position, or one sample of its
    /// area (P3D report §2.2: one light sample per light per primary
    /// sample, from the light's own dimension at this depth).
    #[inline]
    fn light_position(&self, k: usize, p: Vec3A, depth: u32, id: SampleId) -> Vec3A {
        if let Some(at) = self.fixed_light_position(k) {
            return at;
        }
        let (light, size) = (&self.scene.lights[k], self.settings.light_size);
        let n_lights = self.scene.lights.len() as u32;
        let dim = FIRST_LIGHT_DIMENSION + (depth - 1) * n_lights + k as u32;
        let u = self.sampler.sample(id.px, id.py, id.index, dim);
        light.seen_from(p, size, self.settings.light_shape, u)
    }
}

/// The colour a spawned ray of `kind` (its index in [`Spawned`]) is
/// seen through: the material's specular colour for mirror rays, white for
/// the refracted one.
#[inline]
fn tint(kind: usize, m: &WhittedMaterial) -> Vec3A {
    if kind < 2 {
        m.specular
    } else {
        Vec3A::ONE
    }
}

/// Mirror direction by the shading normal, falling back to the geometric
/// one when an interpolated normal would send the ray into the surface.
#[inline]
fn mirror(d: Vec3A, ns: Vec3A, ng: Vec3A) -> Vec3A {
    let r = reflect(d, ns);
    if r.dot(ng) > 0.0 {
        r
    } else {
        reflect(d, ng)
    }
}
