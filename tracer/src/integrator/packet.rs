//! The Whitted shading of [`super`] for packets of rays: the rays, the
//! shadow rays of their hits toward each light, and each kind of ray they
//! spawn (mirror, mirror on total internal reflection, refracted) travel as
//! packets, their geometry set up lane-wise by [`crate::packet`]. A kind
//! that every lane spawns goes on at once as a packet of their lanes; a
//! kind that only some lanes spawn is deferred to the [`Wave`], which
//! regroups such rays of many packets into full packets. Every
//! decision (colours, which rays to spawn) is made lane by lane by the same
//! code as for single rays, so each lane's colour equals what
//! [`Whitted::li`] gives for its ray: the same hits, and the same sums in
//! the same order.

use super::wave::{Wave, NO_NODE};
use super::{tint, SampleId, ShadePoint, ThreadState, Whitted};
use crate::accel::Intersector;
use crate::math::Ray;
use crate::packet::bounce::{bounces, BounceLanes};
use crate::packet::camera::{eye_rays, EyeLanes};
use crate::packet::prims::occludes;
use crate::packet::shadow::{shadow_rays, LightLanes};
use crate::packet::surface::surfaces;
use crate::packet::{PacketHits, PointLanes, RayPacket, NO_PRIM};
use crate::simd::lanes::{first_lanes, for_lanes, lane, set_lane, Lanes, Mask, LANES};
use glam::Vec3A;

/// The shading records of a packet's lanes (`None`: no hit).
type Points<'s> = [Option<ShadePoint<'s>>; LANES];

impl Whitted<'_> {
    /// Radiance along the eye rays of samples `ids` (at most [`LANES`]),
    /// aimed lane by lane as `eye` says and set up lane-wise
    /// ([`eye_rays`]), into `out` (no lane waiting yet).
    pub(super) fn li_eye_packet<I: Intersector>(
        &self,
        eye: &EyeLanes,
        ids: &[SampleId],
        th: &mut ThreadState<I>,
        wave: &mut Wave,
        out: &mut LaneRadiance,
    ) {
        let n = ids.len().min(LANES);
        let mut packet = RayPacket::empty();
        eye_rays(crate::simd::isa(), &self.scene.camera, eye, first_lanes(n), &mut packet);
        let mut lane_ids = [SampleId::default(); LANES];
        lane_ids[..n].copy_from_slice(&ids[..n]);
        self.li_lanes(&packet, &Lanes([1.0; LANES]), 1, &lane_ids, th, wave, out);
    }

    /// Radiance along the rays of the active lanes of `packet`, wherever
    /// they are, at path depth `depth`: lane `i` carries `weights[i]` for
    /// sample `ids[i]`. Its radiance goes to `out.color[i]`, or, where it
    /// waits on rays the wave defers, to the wave's node `out.node[i]`
    /// (marked in `out.waiting`; made here for a lane not yet waiting, and a
    /// lane the caller gave a node ends there).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn li_lanes<I: Intersector>(
        &self,
        packet: &RayPacket,
        weights: &Lanes,
        depth: u32,
        ids: &[SampleId; LANES],
        th: &mut ThreadState<I>,
        wave: &mut Wave,
        out: &mut LaneRadiance,
    ) {
        let scene = self.scene;
        let geom = &scene.geometry;
        let mut hits = PacketHits::new(packet);
        th.tracer.nearest_packet(packet, &mut hits);
        let mut points = [None; LANES];
        let mut at = PointLanes::default();
        let color = &mut out.color;
        let hit = hits.found();
        let entering = surfaces(crate::simd::isa(), geom, packet, &hits, hit, &mut at);
        for_lanes(packet.active, |i| {
            if hit >> i & 1 == 0 {
                color[i] = scene.miss(lane(&packet.d, i));
                return;
            }
            if depth == 1 {
                th.tracer.counters.eye_hits += 1;
            }
            let m = &scene.materials[geom.info[hits.prim[i] as usize].material as usize];
            let (p, ng, ns, d) = (lane(&at.p, i), lane(&at.ng, i), lane(&at.ns, i), lane(&packet.d, i));
            color[i] = scene.ambient * m.kd * m.color;
            points[i] = Some(ShadePoint { p, ng, ns, d, entering: entering >> i & 1 != 0, m });
        });
        let shaded = hit & packet.active;
        if shaded != 0 {
            let mut shadow = RayPacket::empty();
            for k in 0..scene.lights.len() {
                self.light_packet(k, depth, &points, shaded, &at, ids, color, &mut shadow, th);
            }
        }
        // Lanes whose colour sum has moved to their node.
        let mut in_node: Mask = 0;
        // The spawned rays, their geometry taken as the bounce kernel left
        // it. (Most packets, on matte surfaces or at the last level, spawn
        // nothing: then no bounce is computed, nor its lanes cleared.)
        let (want, eta) = self.spawning(&points, depth);
        if want != 0 {
            let mut b = BounceLanes::default();
            bounces(crate::simd::isa(), &at, &packet.d, &eta, want, &mut b);
            let mut shares = [Lanes::ZERO; 3];
            let mut spawned: [Mask; 3] = [0; 3];
            for_lanes(want, |i| {
                let Some(sp) = &points[i] else { return };
                let refracts = sp.m.t > 0.0 && b.refracts >> i & 1 != 0;
                let lane_shares = self.shares(sp, weights.0[i], refracts, &mut th.tracer.counters);
                for (kind, share) in lane_shares.into_iter().enumerate() {
                    if let Some(share) = share {
                        shares[kind].0[i] = share;
                        spawned[kind] |= 1 << i;
                    }
                }
            });
            for kind in (0..3).filter(|&kind| spawned[kind] != 0) {
                let of_kind = SpawnedLanes { kind, lanes: spawned[kind], shares: &shares[kind] };
                self.trace_spawned(
                    &b,
                    &of_kind,
                    &points,
                    depth + 1,
                    weights,
                    ids,
                    th,
                    wave,
                    out,
                    &mut in_node,
                );
            }
        }
        // A lane given a node ends there.
        for_lanes(packet.active & out.waiting & !in_node, |i| wave.set_color(out.node[i], out.color[i]));
    }

    /// The lanes of `points` (at `depth`) that may spawn rays: their
    /// material reflects or transmits, and the depth limit is not reached;
    /// and each one's ratio of indices of refraction, for [`bounces`].
    fn spawning(&self, points: &Points, depth: u32) -> (Mask, Lanes) {
        let (mut want, mut eta) = (0, Lanes::ZERO);
        if depth >= self.settings.max_depth {
            return (want, eta);
        }
        for (i, sp) in points.iter().enumerate() {
            let Some(sp) = sp else { continue };
            if sp.m.spawns_rays() {
                eta.0[i] = sp.m.eta(sp.entering);
                want |= 1 << i;
            }
        }
        (want, eta)
    }

    /// Add light `k` to the lanes of `points` whose shadow rays, set up
    /// lane-wise and traced as one packet (in `shadow`) after the shadow
    /// cache had its say, are clear. `valid` holds the lanes that have a
    /// point, `at` the points' positions and normals.
    #[allow(clippy::too_many_arguments)]
    fn light_packet<I: Intersector>(
        &self,
        k: usize,
        depth: u32,
        points: &Points,
        valid: Mask,
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
        if fixed.is_none() {
            for (i, sp) in points.iter().enumerate() {
                if let Some(sp) = sp {
                    set_lane(&mut pos, i, self.light_position(k, sp.p, depth, ids[i]));
                }
            }
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

    /// The rays of one kind, `of_kind`, at `depth` from the bounces `b`
    /// (`points` holding the lanes' materials, `parents` their weights):
    /// traced at once as a packet of their parents' lanes when every lane
    /// spawned one, their `share × tint × radiance` added to each lane's
    /// colour; else deferred to the wave, to be regrouped (while it has
    /// room: else traced at once all the same). A lane whose colour waits
    /// on a deferred ray moves its sum to its node (marked in `in_node`),
    /// and what follows goes there in order.
    #[allow(clippy::too_many_arguments)]
    fn trace_spawned<I: Intersector>(
        &self,
        b: &BounceLanes,
        of_kind: &SpawnedLanes,
        points: &Points,
        depth: u32,
        parents: &Lanes,
        ids: &[SampleId; LANES],
        th: &mut ThreadState<I>,
        wave: &mut Wave,
        out: &mut LaneRadiance,
        in_node: &mut Mask,
    ) {
        let SpawnedLanes { kind, lanes, shares } = *of_kind;
        let (o, d) = if kind == 2 { (&b.refract_o, &b.refract_d) } else { (&b.mirror_o, &b.mirror_d) };
        let mut weights = Lanes::ZERO;
        for_lanes(lanes, |i| weights.0[i] = parents.0[i] * shares.0[i]);
        let factor = |i: usize| shares.0[i] * points[i].as_ref().map_or(Vec3A::ONE, |sp| tint(kind, sp.m));
        if (lanes.count_ones() as usize) < LANES && wave.has_room() {
            for_lanes(lanes, |i| {
                let node = out.open(i, depth - 1, in_node, wave);
                let ray = Ray { o: lane(o, i), d: lane(d, i) };
                wave.defer(node, kind, ray, depth, weights.0[i], factor(i), ids[i]);
            });
            return;
        }
        let mut radiance = LaneRadiance::default();
        if lanes.count_ones() == 1 {
            // A lone ray (the wave full) goes ray by ray: no packet set-up.
            let i = lanes.trailing_zeros() as usize;
            let ray = Ray { o: lane(o, i), d: lane(d, i) };
            radiance.color[i] = self.li(ray, 0.0, depth, weights.0[i], ids[i], th);
        } else {
            let packet = RayPacket::from_lanes(o, d, lanes);
            self.li_lanes(&packet, &weights, depth, ids, th, wave, &mut radiance);
        }
        if (radiance.waiting | *in_node) & lanes == 0 {
            for_lanes(lanes, |i| out.color[i] += factor(i) * radiance.color[i]);
            return;
        }
        for_lanes(lanes, |i| {
            let waiting = radiance.waiting >> i & 1 != 0;
            if waiting || *in_node >> i & 1 != 0 {
                // Its radiance waits, or goes after what waits: a child
                // node (a leaf when known, seen through the same factor).
                let node = out.open(i, depth - 1, in_node, wave);
                let child = if waiting { radiance.node[i] } else { wave.add_node(radiance.color[i], depth) };
                wave.link(node, kind, child, factor(i));
            } else {
                out.color[i] += factor(i) * radiance.color[i];
            }
        });
    }
}

/// What a packet's lanes see: lane `i`'s radiance is `color[i]`, or, in
/// the lanes of `waiting`, wave node `node[i]`'s once the wave is resolved.
#[derive(Debug, Clone)]
pub(super) struct LaneRadiance {
    pub color: [Vec3A; LANES],
    pub node: [u32; LANES],
    pub waiting: Mask,
}

impl Default for LaneRadiance {
    fn default() -> Self {
        LaneRadiance { color: [Vec3A::ZERO; LANES], node: [NO_NODE; LANES], waiting: 0 }
    }
}

impl LaneRadiance {
    /// Lane `i`'s node (its ray at `depth`), with its colour so far moved
    /// there (once: `in_node` marks the lanes moved), made where it has
    /// none.
    fn open(&mut self, i: usize, depth: u32, in_node: &mut Mask, wave: &mut Wave) -> u32 {
        if *in_node >> i & 1 == 0 {
            if self.waiting >> i & 1 == 0 {
                self.node[i] = wave.add_node(self.color[i], depth);
                self.waiting |= 1 << i;
            } else {
                wave.set_color(self.node[i], self.color[i]);
            }
            *in_node |= 1 << i;
        }
        self.node[i]
    }
}

/// The rays of one kind of [`super::Spawned`] that a packet's hits spawn:
/// the kind, its lanes and the share each carries.
struct SpawnedLanes<'a> {
    kind: usize,
    lanes: Mask,
    shares: &'a Lanes,
}
