//! The Whitted shading of [`super`] for packets of rays: the rays, the
//! shadow rays of their hits toward each light, and each kind of ray they
//! spawn (mirror, mirror on total internal reflection, refracted) travel as
//! packets, their geometry set up lane-wise by [`crate::packet`]; every
//! decision (colours, which rays to spawn) is made lane by lane by the same
//! code as for single rays, so each lane's colour equals what
//! [`Whitted::li`] gives for its ray: the same hits, and the same sums in
//! the same order.

use super::{tint, SampleId, ShadePoint, Spawned, ThreadState, Whitted};
use crate::accel::Intersector;
use crate::math::Ray;
use crate::packet::bounce::{bounces, BounceLanes};
use crate::packet::prims::occludes;
use crate::packet::shadow::{shadow_rays, LightLanes};
use crate::packet::surface::surfaces;
use crate::packet::{PacketHits, PointLanes, RayPacket, NO_PRIM};
use crate::simd::lanes::{for_lanes, lane, set_lane, Lanes, LANES};
use crate::stats::Counters;
use glam::Vec3A;

/// The shading records of a packet's lanes (`None`: no hit).
type Points<'s> = [Option<ShadePoint<'s>>; LANES];

impl Whitted<'_> {
    /// Radiance along rays traced as one packet (at most [`LANES`]):
    /// `rays[i]` is `(ray, t_min, weight)` of sample `ids[i]` at path depth
    /// `depth`; its colour goes to `out[i]`.
    pub fn li_packet<I: Intersector>(
        &self,
        rays: &[(Ray, f32, f32)],
        depth: u32,
        ids: &[SampleId],
        th: &mut ThreadState<I>,
        out: &mut [Vec3A],
    ) {
        let scene = self.scene;
        let geom = &scene.geometry;
        let packet = RayPacket::new(rays.iter().map(|&(ray, t_min, _)| (ray, t_min, f32::INFINITY)));
        let mut hits = PacketHits::new(&packet);
        th.tracer.nearest_packet(&packet, &mut hits);
        let mut points = [None; LANES];
        let mut at = PointLanes::default();
        let mut color = [Vec3A::ZERO; LANES];
        let hit = hits.found();
        let entering = surfaces(crate::simd::isa(), geom, &packet, &hits, hit, &mut at);
        for (i, o) in out.iter_mut().enumerate().take(rays.len()) {
            if hit >> i & 1 == 0 {
                *o = scene.miss(lane(&packet.d, i));
                continue;
            }
            if depth == 1 {
                th.tracer.counters.eye_hits += 1;
            }
            let m = &scene.materials[geom.info[hits.prim[i] as usize].material as usize];
            let (p, ng, ns, d) = (lane(&at.p, i), lane(&at.ng, i), lane(&at.ns, i), lane(&packet.d, i));
            color[i] = scene.ambient * m.kd * m.color;
            points[i] = Some(ShadePoint { p, ng, ns, d, entering: entering >> i & 1 != 0, m });
        }
        let mut shadow = RayPacket::empty();
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
                let rays_i = self.spawn_lane(sp, &b, i, rays[i].2, &mut th.tracer.counters);
                for (kind, r) in rays_i.into_iter().enumerate() {
                    any[kind] |= r.is_some();
                    spawned[kind][i] = r;
                }
            });
            for (kind, (of_kind, _)) in spawned.iter().zip(any).enumerate().filter(|k| k.1 .1) {
                self.trace_spawned(of_kind, kind, &points, depth + 1, rays, ids, &mut color, th);
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
    fn bounce_lanes(&self, points: &Points, at: &PointLanes, packet: &RayPacket, depth: u32) -> BounceLanes {
        let mut b = BounceLanes::default();
        if depth >= self.settings.max_depth {
            return b;
        }
        let mut eta = Lanes::ZERO;
        for (i, sp) in points.iter().enumerate() {
            let Some(sp) = sp else { continue };
            if sp.m.spawns_rays() {
                eta.0[i] = sp.m.eta(sp.entering);
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
    fn light_packet<I: Intersector>(
        &self,
        k: usize,
        depth: u32,
        points: &Points,
        at: &PointLanes,
        ids: &[SampleId],
        color: &mut [Vec3A; LANES],
        shadow: &mut RayPacket,
        th: &mut ThreadState<I>,
    ) {
        // A point light is where it is in every lane: filled whole, not
        // lane by lane (the kernel's vector loads would wait on those
        // single-lane stores).
        let fixed = self.fixed_light_position(k);
        let mut pos = fixed.map_or([Lanes::ZERO; 3], |at| [0, 1, 2].map(|a| Lanes([at[a]; LANES])));
        let mut valid = 0;
        for (i, sp) in points.iter().enumerate() {
            let Some(sp) = sp else { continue };
            if fixed.is_none() {
                set_lane(&mut pos, i, self.light_position(k, sp.p, depth, ids[i]));
            }
            valid |= 1 << i;
        }
        let mut dirs = LightLanes::default();
        let lanes = shadow_rays(crate::simd::isa(), at, &pos, valid, shadow, &mut dirs);
        let tr = &mut th.tracer;
        tr.counters.shadow += u64::from(lanes.counted.count_ones());
        if let Some(id) = th.shadow_cache.get(k, depth) {
            let cached = occludes(crate::simd::isa(), tr.geom, id, shadow, shadow.active, &mut tr.counters);
            tr.counters.shadow_cache_hits += u64::from(cached.count_ones());
            shadow.active &= !cached;
        }
        if shadow.is_empty() {
            return;
        }
        let blockers = tr.occluders_packet(shadow);
        for_lanes(shadow.active, |i| match blockers.0[i] {
            NO_PRIM => {
                if let Some(sp) = &points[i] {
                    color[i] += self.direct(sp, k, lane(&dirs.l, i), dirs.n_dot_l.0[i]);
                }
            }
            id => th.shadow_cache.set(k, depth, id),
        });
    }

    /// Trace one kind of spawned ray (`(ray, share)` per lane, or none;
    /// `kind` its index in [`Spawned`]) at `depth`, as a packet when more
    /// than one lane has one, adding `share × tint × radiance` to the
    /// lane's colour (`points` holding the lanes' materials).
    #[allow(clippy::too_many_arguments)]
    fn trace_spawned<I: Intersector>(
        &self,
        spawned: &[Option<(Ray, f32)>; LANES],
        kind: usize,
        points: &Points,
        depth: u32,
        parents: &[(Ray, f32, f32)],
        ids: &[SampleId],
        color: &mut [Vec3A; LANES],
        th: &mut ThreadState<I>,
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
            let tint = points[i].as_ref().map_or(Vec3A::ONE, |sp| tint(kind, sp.m));
            color[i] += share * tint * radiance[j];
        }
    }

    /// [`Whitted::spawn`] for lane `i` of a packet whose bounces were
    /// computed lane-wise ([`bounces`]).
    #[inline(always)]
    fn spawn_lane(
        &self,
        sp: &ShadePoint,
        b: &BounceLanes,
        i: usize,
        weight: f32,
        c: &mut Counters,
    ) -> Spawned {
        let refracted = (sp.m.t > 0.0 && b.refracts >> i & 1 != 0)
            .then(|| Ray { o: lane(&b.refract_o, i), d: lane(&b.refract_d, i) });
        self.choose_rays(
            sp,
            weight,
            refracted,
            || Ray { o: lane(&b.mirror_o, i), d: lane(&b.mirror_d, i) },
            c,
        )
    }
}
