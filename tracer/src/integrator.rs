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
use crate::bounce_lanes::{bounces, BounceLanes};
use crate::geometry::Hit;
use crate::material::WhittedMaterial;
use crate::math::{basis, offset_ray_origin, reflect, refract, shadow_ray, Ray, RayQuery};
use crate::packet::{for_lanes, lane, occludes, set_lane, Lanes, PacketHits, RayPacket, LANES, NO_PRIM};
use crate::prepare::RenderScene;
use crate::sampling::{concentric_disk, Sampler};
use crate::shadow_cache::ShadowCache;
use crate::shadow_lanes::{shadow_rays, LightLanes, PointLanes};
use crate::stats::Counters;
use crate::surface_lanes::surfaces;
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
        let sp = self.shade_point(&q, &hit);
        let mut color = scene.ambient * sp.m.kd * sp.m.color;
        for k in 0..scene.lights.len() {
            let Some(lr) = self.light_ray(&sp, k, depth, id, &mut th.counters) else { continue };
            if !self.shadowed(&lr, k, depth, th) {
                color += self.direct(&sp, k, lr.l, lr.n_dot_l);
            }
        }
        self.secondary(&sp, color, depth, weight, id, th)
    }

    /// Radiance along rays traced as one packet (at most [`LANES`]):
    /// `rays[i]` is `(ray, t_min, weight)` of sample `ids[i]` at path depth
    /// `depth`; its colour goes to `out[i]`. The rays, the shadow rays of
    /// their hits toward each light, and each kind of ray they spawn
    /// (mirror, mirror on total internal reflection, refracted) travel as
    /// packets. Every lane's colour equals what [`Whitted::li`] gives for
    /// its ray: the same hits, and the same sums in the same order.
    pub fn li_packet(
        &self,
        rays: &[(Ray, f32, f32)],
        depth: u32,
        ids: &[SampleId],
        th: &mut ThreadState<I::Scratch>,
        out: &mut [Vec3A],
    ) {
        let scene = self.scene;
        let geom = &scene.geometry;
        let packet = RayPacket::new(rays.iter().map(|&(ray, t_min, _)| (ray, t_min, f32::INFINITY)));
        let mut hits = PacketHits::new(&packet);
        self.accel.intersect_packet(geom, &packet, &mut hits, &mut th.scratch, &mut th.counters);
        let mut points = [None; LANES];
        let mut at = PointLanes::default();
        let mut color = [Vec3A::ZERO; LANES];
        let hit = (0..rays.len()).filter(|&i| hits.prim[i] != NO_PRIM).fold(0, |m, i| m | 1 << i);
        let entering = surfaces(crate::simd::isa(), geom, &packet, &hits, hit, &mut at);
        for (i, o) in out.iter_mut().enumerate().take(rays.len()) {
            if hit >> i & 1 == 0 {
                *o = scene.background;
                continue;
            }
            if depth == 1 {
                th.counters.eye_hits += 1;
            }
            let m = &scene.materials[geom.info[hits.prim[i] as usize].material as usize];
            let (p, ng, ns, d) = (lane(&at.p, i), lane(&at.ng, i), lane(&at.ns, i), lane(&packet.d, i));
            color[i] = scene.ambient * m.kd * m.color;
            points[i] = Some(ShadePoint { p, ng, ns, d, entering: entering >> i & 1 != 0, m });
        }
        let mut shadow = RayPacket::new(std::iter::empty());
        for k in 0..scene.lights.len() {
            self.light_packet(k, depth, &points, &at, ids, &mut color, &mut shadow, th);
        }
        // Spawned rays, gathered per kind so that each kind is one packet.
        // (Most packets, on matte surfaces or at the last level, spawn
        // nothing: then neither the lanes' rays nor their packets are set up.)
        let b = self.bounce_lanes(&points, &at, &packet, depth);
        if b.want != 0 {
            let mut spawned = [[None; LANES]; 3];
            let mut any = [false; 3];
            for_lanes(b.want, |i| {
                let Some(sp) = &points[i] else { return };
                let rays_i = self.spawn_lane(sp.m, &b, i, rays[i].2, &mut th.counters);
                for (kind, r) in rays_i.into_iter().enumerate() {
                    any[kind] |= r.is_some();
                    spawned[kind][i] = r;
                }
            });
            for (kind, _) in spawned.iter().zip(any).filter(|k| k.1) {
                self.trace_spawned(kind, depth + 1, rays, ids, &mut color, th);
            }
        }
        for (i, sp) in points.iter().enumerate() {
            if sp.is_some() {
                out[i] = color[i];
            }
        }
    }

    /// The bounces ([`bounces`]) of the lanes of `points` (at `depth`)
    /// that may spawn rays: their material reflects or transmits, and the
    /// depth limit is not reached. `at` holds the points, `packet` the rays.
    fn bounce_lanes(
        &self,
        points: &[Option<ShadePoint>; LANES],
        at: &PointLanes,
        packet: &RayPacket,
        depth: u32,
    ) -> BounceLanes {
        let mut b = BounceLanes::default();
        if depth >= self.settings.max_depth {
            return b;
        }
        let mut eta = Lanes([0.0; LANES]);
        for (i, sp) in points.iter().enumerate() {
            let Some(sp) = sp else { continue };
            if sp.m.ks > 0.0 || sp.m.t > 0.0 {
                eta.0[i] = if sp.entering { 1.0 / sp.m.ior } else { sp.m.ior };
                b.want |= 1 << i;
            }
        }
        if b.want != 0 {
            bounces(crate::simd::isa(), at, &packet.d, &eta, b.want, &mut b);
        }
        b
    }

    /// Add light `k` to the lanes of `points` whose shadow rays, set up
    /// lane-wise and traced as one packet (in `shadow`) after the shadow
    /// cache had its say, are clear. `at` holds the points' positions and
    /// normals.
    #[allow(clippy::too_many_arguments)]
    fn light_packet(
        &self,
        k: usize,
        depth: u32,
        points: &[Option<ShadePoint>; LANES],
        at: &PointLanes,
        ids: &[SampleId],
        color: &mut [Vec3A; LANES],
        shadow: &mut RayPacket,
        th: &mut ThreadState<I::Scratch>,
    ) {
        let center = self.scene.lights[k].position;
        let mut pos = [Lanes([0.0; LANES]); 3];
        let mut valid = 0;
        for (i, sp) in points.iter().enumerate() {
            let Some(sp) = sp else { continue };
            set_lane(&mut pos, i, self.light_position(k, center, sp.p, depth, ids[i]));
            valid |= 1 << i;
        }
        let mut dirs = LightLanes::default();
        let lanes = shadow_rays(crate::simd::isa(), at, &pos, valid, shadow, &mut dirs);
        th.counters.shadow += u64::from(lanes.counted.count_ones());
        let geom = &self.scene.geometry;
        if let Some(id) = th.shadow_cache.get(k, depth) {
            let cached = occludes(crate::simd::isa(), geom, id, shadow, shadow.active, &mut th.counters);
            th.counters.shadow_cache_hits += u64::from(cached.count_ones());
            shadow.active &= !cached;
        }
        if shadow.is_empty() {
            return;
        }
        let blockers = self.accel.occluders_packet(geom, shadow, &mut th.scratch, &mut th.counters);
        for_lanes(shadow.active, |i| match blockers[i] {
            NO_PRIM => {
                if let Some(sp) = &points[i] {
                    color[i] += self.direct(sp, k, lane(&dirs.l, i), dirs.n_dot_l.0[i]);
                }
            }
            id => th.shadow_cache.set(k, depth, id),
        });
    }

    /// Trace one kind of spawned ray (`(ray, share)` per lane, or none) at
    /// `depth`, as a packet when more than one lane has one, adding
    /// `share × radiance` to the lane's colour.
    fn trace_spawned(
        &self,
        spawned: &[Option<(Ray, f32)>; LANES],
        depth: u32,
        parents: &[(Ray, f32, f32)],
        ids: &[SampleId],
        color: &mut [Vec3A; LANES],
        th: &mut ThreadState<I::Scratch>,
    ) {
        let mut lanes = [0usize; LANES];
        let mut rays = [(Ray { o: Vec3A::ZERO, d: Vec3A::Z }, 0.0, 0.0); LANES];
        let mut sub_ids = [SampleId { px: 0, py: 0, index: 0 }; LANES];
        let mut n = 0;
        for (i, s) in spawned.iter().enumerate() {
            if let Some((ray, share)) = *s {
                (lanes[n], rays[n], sub_ids[n]) = (i, (ray, 0.0, parents[i].2 * share), ids[i]);
                n += 1;
            }
        }
        let mut radiance = [Vec3A::ZERO; LANES];
        if n == 1 {
            let (ray, _, weight) = rays[0];
            radiance[0] = self.li(ray, 0.0, depth, weight, sub_ids[0], th);
        } else if n > 1 {
            self.li_packet(&rays[..n], depth, &sub_ids[..n], th, &mut radiance);
        }
        for j in 0..n {
            let i = lanes[j];
            let share = spawned[i].map_or(0.0, |s| s.1);
            color[i] += share * radiance[j];
        }
    }

    /// The shading record of `hit` on the ray of `q`.
    #[inline]
    fn shade_point(&self, q: &RayQuery, hit: &Hit) -> ShadePoint<'_> {
        let scene = self.scene;
        let s = scene.geometry.surface(hit, q);
        let info = scene.geometry.info[hit.prim as usize];
        let m = &scene.materials[info.material as usize];
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
        self.scene.lights[k].intensity * (m.kd * n_dot_l * m.color + Vec3A::splat(spec))
    }

    /// Add the reflected and refracted light at `sp` to `color`, tracing
    /// the rays [`Whitted::spawn`] gives one by one, in their order.
    fn secondary(
        &self,
        sp: &ShadePoint,
        mut color: Vec3A,
        depth: u32,
        weight: f32,
        id: SampleId,
        th: &mut ThreadState<I::Scratch>,
    ) -> Vec3A {
        for (ray, share) in self.spawn(sp, depth, weight, &mut th.counters).into_iter().flatten() {
            color += share * self.li(ray, 0.0, depth + 1, weight * share, id, th);
        }
        color
    }

    /// The rays the rule in force spawns at `sp`, each with the share of
    /// the colour it carries, in the order their light is added: the
    /// mirror ray, the mirror ray carrying the transmitted share on total
    /// internal reflection (plain rule only), the refracted ray. Counts
    /// them.
    fn spawn(&self, sp: &ShadePoint, depth: u32, weight: f32, c: &mut Counters) -> [Option<(Ray, f32)>; 3] {
        if depth >= self.settings.max_depth {
            return [None; 3];
        }
        let ShadePoint { p, ng, ns, d, entering, m } = *sp;
        let refracted = if m.t > 0.0 {
            let eta = if entering { 1.0 / m.ior } else { m.ior };
            refract(d, ns, eta)
                .filter(|t| t.dot(ng) < 0.0)
                .map(|t| Ray { o: offset_ray_origin(p, -ng), d: t })
        } else {
            None
        };
        self.choose_rays(
            m,
            weight,
            refracted,
            || Ray { o: offset_ray_origin(p, ng), d: self.mirror(d, ns, ng) },
            c,
        )
    }

    /// [`Whitted::spawn`] for lane `i` of a packet whose bounces were
    /// computed lane-wise ([`bounces`]).
    fn spawn_lane(
        &self,
        m: &WhittedMaterial,
        b: &BounceLanes,
        i: usize,
        weight: f32,
        c: &mut Counters,
    ) -> [Option<(Ray, f32)>; 3] {
        let refracted = (m.t > 0.0 && b.refracts >> i & 1 != 0)
            .then(|| Ray { o: lane(&b.refract_o, i), d: lane(&b.refract_d, i) });
        self.choose_rays(m, weight, refracted, || Ray { o: lane(&b.mirror_o, i), d: lane(&b.mirror_d, i) }, c)
    }

    /// Which rays a hit on material `m` spawns, given its refracted ray
    /// (`None` on total internal reflection or where `m` transmits nothing)
    /// and its mirror ray: the rule of [`Whitted::spawn`].
    fn choose_rays(
        &self,
        m: &WhittedMaterial,
        weight: f32,
        refracted: Option<Ray>,
        mirror_ray: impl Fn() -> Ray,
        c: &mut Counters,
    ) -> [Option<(Ray, f32)>; 3] {
        let mut out = [None; 3];
        let min = self.settings.min_weight;
        let tir = m.t > 0.0 && refracted.is_none();
        let mut mirror = |share: f32| {
            c.reflected += 1;
            Some((mirror_ray(), share))
        };
        if self.settings.spd_rules {
            // Rules 8 and 9: one reflection ray at any reflector or
            // transmitter, carrying the transmitted share on TIR.
            let share = m.ks + if tir { m.t } else { 0.0 };
            if (m.ks > 0.0 || m.t > 0.0) && weight * share >= min {
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
        if let Some(ray) = refracted {
            if weight * m.t >= min {
                c.refracted += 1;
                out[2] = Some((ray, m.t));
            }
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
        let pos = self.light_position(k, self.scene.lights[k].position, sp.p, depth, id);
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
    fn shadowed(&self, lr: &LightRay, light: usize, depth: u32, th: &mut ThreadState<I::Scratch>) -> bool {
        let geom = &self.scene.geometry;
        if let Some(id) = th.shadow_cache.get(light, depth) {
            if test_shadow(geom, id, &lr.query, lr.max, &mut th.counters) {
                th.counters.shadow_cache_hits += 1;
                return true;
            }
        }
        match self.accel.occluder(geom, &lr.query, lr.max, &mut th.scratch, &mut th.counters) {
            Some(id) => {
                th.shadow_cache.set(light, depth, id);
                true
            }
            None => false,
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
