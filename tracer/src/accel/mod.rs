//! Acceleration structures behind one interface: brute force, the P3D
//! report's uniform grid with mailboxes, and a binned-SAH BVH (the default).
//!
//! The renderer matches on [`Accel`] once per image ([`with_accel!`]) and
//! then runs code generic over [`Intersector`], so the hot loop has no
//! dynamic dispatch. Each structure writes its traversal once, for both
//! queries a ray tracer asks: the nearest hit (eye, mirror and refracted
//! rays) and any hit (shadow rays), chosen by a [`Query`] type ([`Nearest`]
//! or [`AnyHit`]), as obvhs writes one traversal skeleton for both.
//!
//! A traversal reads and writes, besides the structure, the primitives, the
//! thread's scratch (the grid's mailbox, the BVH's stacks) and its
//! counters: one [`Tracer`] per render thread holds all four.
//!
//! Infinite planes (the course files' `pl`) have no box, so no structure
//! holds them: each is built over the bounded ids only, and [`Tracer`]
//! tests the planes beside it, under the same tie rule (planes have the
//! highest ids).

mod brute;
mod bvh;
#[cfg(feature = "gpu")]
pub(crate) use bvh::{Node4, MAX, MIN};
mod grid;
#[cfg(test)]
mod tests;

pub(crate) use brute::BruteForce;
pub(crate) use bvh::Bvh;
pub(crate) use grid::Grid;

use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;
use crate::packet::{Blockers, LaneHits, PacketHits, RayPacket};
pub(crate) use crate::query::{AnyHit, Nearest, Query};
use crate::simd::lanes::{for_lanes, Mask};
use crate::stats::Counters;
use strum::{Display, IntoStaticStr, VariantArray};

/// The queries an acceleration structure answers over the bounded
/// primitives (ids `0..geom.bounded_len()`) of its [`Tracer`]'s geometry.
pub(crate) trait Intersector: Sync + Sized {
    /// Per-thread mutable state (the grid's mailbox); `()` when none.
    type Scratch: Send;

    /// Fresh scratch state for one render thread.
    fn scratch(&self, geom: &Geometry) -> Self::Scratch;

    /// For [`Nearest`], the nearest hit in `(q.t_min, t_max)` better than
    /// `best` (at equal distance the lowest primitive id, so every structure
    /// returns the same hit); for [`AnyHit`], the first hit found in that
    /// range (a shadow ray's blocker).
    fn trace_bounded<Q: Query>(
        tr: &mut Tracer<'_, Self>,
        q: &RayQuery,
        t_max: f32,
        best: Option<Hit>,
    ) -> Option<Hit>;

    /// [`Intersector::trace_bounded`] for the lanes of `mask`, each within
    /// `(t_min, t_max)` and better than its best in `hits`, taken into
    /// `hits`. The default traces lane by lane; the BVH traces the packet
    /// together.
    fn trace_packet_bounded<H: LaneHits>(tr: &mut Tracer<'_, Self>, p: &RayPacket, mask: Mask, hits: &mut H) {
        for_lanes(mask, |i| {
            if let Some(h) = Self::trace_bounded::<H::Query>(tr, &p.query(i), p.t_max.0[i], hits.best(i)) {
                hits.take(i, h);
            }
        });
    }
}

/// One render thread's tracing context: the structure, the primitives, the
/// thread's scratch and its counters.
pub(crate) struct Tracer<'a, I: Intersector> {
    /// The acceleration structure.
    pub accel: &'a I,
    /// The primitives it was built over.
    pub geom: &'a Geometry,
    /// The thread's scratch for `accel`.
    pub scratch: I::Scratch,
    /// The thread's work counters.
    pub counters: Counters,
}

impl<'a, I: Intersector> Tracer<'a, I> {
    /// A context for one thread.
    pub fn new(accel: &'a I, geom: &'a Geometry) -> Tracer<'a, I> {
        Tracer { accel, geom, scratch: accel.scratch(geom), counters: Counters::default() }
    }

    /// The nearest hit in `(q.t_min, t_max)` over every primitive, planes
    /// included; ties go to the lowest id.
    #[inline]
    pub fn nearest(&mut self, q: &RayQuery, t_max: f32) -> Option<Hit> {
        self.trace::<Nearest>(q, t_max)
    }

    /// A primitive lying in `(q.t_min, t_max)` (a shadow ray's blocker).
    #[inline]
    pub fn occluder(&mut self, q: &RayQuery, t_max: f32) -> Option<u32> {
        self.trace::<AnyHit>(q, t_max).map(|h| h.prim)
    }

    /// Whether anything lies in `(q.t_min, t_max)`.
    #[inline]
    pub fn occluded(&mut self, q: &RayQuery, t_max: f32) -> bool {
        self.occluder(q, t_max).is_some()
    }

    /// The nearest hit or any hit, planes included: for any hit the planes
    /// go first (they are few and, being infinite, likely to block), for
    /// the nearest last (their ids are the highest).
    #[inline]
    fn trace<Q: Query>(&mut self, q: &RayQuery, t_max: f32) -> Option<Hit> {
        let geom = self.geom;
        let mut best = None;
        if Q::ANY_HIT {
            for id in geom.plane_ids() {
                if test_prim::<AnyHit>(geom, id, q, &mut best, t_max, &mut self.counters) {
                    return best;
                }
            }
        }
        best = I::trace_bounded::<Q>(self, q, t_max, None);
        if !Q::ANY_HIT {
            for id in geom.plane_ids() {
                test_prim::<Nearest>(geom, id, q, &mut best, t_max, &mut self.counters);
            }
        }
        best
    }

    /// [`Tracer::nearest`] for every active lane of a packet, into `hits`.
    #[inline]
    pub fn nearest_packet(&mut self, p: &RayPacket, hits: &mut PacketHits) {
        I::trace_packet_bounded(self, p, p.active, hits);
        let geom = self.geom;
        for id in geom.plane_ids() {
            for_lanes(p.active, |i| {
                let mut best = hits.best(i);
                test_prim::<Nearest>(geom, id, &p.query(i), &mut best, p.t_max.0[i], &mut self.counters);
                if let Some(h) = best {
                    hits.take(i, h);
                }
            });
        }
    }

    /// [`Tracer::occluder`] for every active lane of a packet: each lane's
    /// blocker, or none when its shadow ray is clear.
    #[inline]
    pub fn occluders_packet(&mut self, p: &RayPacket) -> Blockers {
        let mut blockers = Blockers::new();
        let mut open = p.active;
        let geom = self.geom;
        for id in geom.plane_ids() {
            for_lanes(open, |i| {
                let mut found = None;
                if test_prim::<AnyHit>(geom, id, &p.query(i), &mut found, p.t_max.0[i], &mut self.counters) {
                    blockers.0[i] = id;
                    open &= !(1 << i);
                }
            });
        }
        if open != 0 {
            I::trace_packet_bounded(self, p, open, &mut blockers);
        }
        blockers
    }
}

/// The accelerator kinds a user chooses from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum AccelKind {
    /// Test every primitive.
    None,
    /// The P3D report's uniform grid.
    Grid,
    /// Bounding volume hierarchy.
    #[default]
    Bvh,
}

impl AccelKind {
    /// Every kind (derived by strum, so a new one is not left out).
    pub const ALL: &'static [AccelKind] = <AccelKind as VariantArray>::VARIANTS;

    /// The name in tables and reports (the command line's is `Display`).
    pub fn title(self) -> &'static str {
        match self {
            AccelKind::None => "none",
            AccelKind::Grid => "grid",
            AccelKind::Bvh => "BVH",
        }
    }
}

/// Options for building an accelerator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelOptions {
    /// Which structure.
    pub kind: AccelKind,
    /// The grid's density multiplier M (formula (1) of the P3D report).
    pub grid_m: f32,
    /// Whether the grid uses mailboxes.
    pub mailbox: bool,
}

impl Default for AccelOptions {
    fn default() -> Self {
        AccelOptions { kind: AccelKind::Bvh, grid_m: 2.0, mailbox: true }
    }
}

/// A built accelerator.
#[derive(Debug, Clone)]
pub(crate) enum Accel {
    /// Brute force.
    None(BruteForce),
    /// Uniform grid.
    Grid(Grid),
    /// BVH.
    Bvh(Bvh),
}

/// What an accelerator costs: for the statistics.
#[derive(Debug, Clone, Default)]
pub struct AccelInfo {
    /// Build time in seconds.
    pub build_seconds: f64,
    /// Bytes used by the structure (not counting the primitives).
    pub bytes: usize,
    /// Nodes (BVH) or cells (grid).
    pub nodes: usize,
    /// A one-line description.
    pub summary: &'static str,
    /// What `nodes` counts, for reports: "nodes" or "cells".
    pub unit: &'static str,
    /// What the user should know about how it was built (a grid made
    /// coarser than asked), if anything.
    pub warning: Option<String>,
    /// The tree's cost by the surface-area heuristic (expected box steps
    /// and primitive tests of a ray through the scene's box; BVH only).
    pub sah_cost: Option<f64>,
}

impl Accel {
    /// Build the chosen structure over `geom`.
    pub(crate) fn build(geom: &Geometry, opts: &AccelOptions) -> Accel {
        match opts.kind {
            AccelKind::None => Accel::None(BruteForce),
            AccelKind::Grid => Accel::Grid(Grid::build(geom, opts.grid_m, opts.mailbox)),
            AccelKind::Bvh => Accel::Bvh(Bvh::build(geom)),
        }
    }

    /// Size and build time.
    pub fn info(&self) -> AccelInfo {
        match self {
            Accel::None(_) => {
                AccelInfo { summary: "none (brute force)", unit: "nodes", ..Default::default() }
            }
            Accel::Grid(g) => g.info(),
            Accel::Bvh(b) => b.info(),
        }
    }
}

/// Run `f` with the concrete accelerator: the one place dynamic choice meets
/// the generic hot loop.
macro_rules! with_accel {
    ($accel:expr, $a:ident => $body:expr) => {
        match $accel {
            $crate::accel::Accel::None($a) => $body,
            $crate::accel::Accel::Grid($a) => $body,
            $crate::accel::Accel::Bvh($a) => $body,
        }
    };
}
pub(crate) use with_accel;

/// Test primitive `id` on the ray of `q`, counting the test. [`Nearest`]:
/// keep the better of the hit and `best`, testing below `best`'s distance
/// nudged up one ulp, so that an equal-distance hit with a lower id can
/// still win the tie; returns false. [`AnyHit`]: a hit in `(q.t_min,
/// t_max)` becomes `best` and the answer is true (stop).
#[inline(always)]
pub(crate) fn test_prim<Q: Query>(
    geom: &Geometry,
    id: u32,
    q: &RayQuery,
    best: &mut Option<Hit>,
    t_max: f32,
    c: &mut Counters,
) -> bool {
    test_prim_by::<Q>(Geometry::intersect, geom, id, q, best, t_max, c)
}

/// [`test_prim`], testing by `intersect` ([`Geometry::intersect`] or a
/// form of it).
#[inline(always)]
pub(crate) fn test_prim_by<Q: Query>(
    intersect: impl FnOnce(&Geometry, u32, &RayQuery, f32) -> Option<Hit>,
    geom: &Geometry,
    id: u32,
    q: &RayQuery,
    best: &mut Option<Hit>,
    t_max: f32,
    c: &mut Counters,
) -> bool {
    c.tests[geom.locate(id).0] += 1;
    intersect(geom, id, q, hit_limit::<Q>(best, t_max)).is_some_and(|h| take_hit::<Q>(best, h))
}

/// The distance a primitive is tested below, given `best`: for
/// [`Nearest`], the best hit's distance nudged up one ulp (so that an
/// equal-distance hit with a lower id can still win the tie), else `t_max`.
#[inline(always)]
pub(crate) fn hit_limit<Q: Query>(best: &Option<Hit>, t_max: f32) -> f32 {
    match best {
        Some(b) if !Q::ANY_HIT => f32::from_bits(b.t.to_bits() + 1),
        _ => t_max,
    }
}

/// Take a hit found below [`hit_limit`] into `best`: for [`Nearest`] the
/// better of the two; for [`AnyHit`] the hit, answering true (stop).
#[inline(always)]
pub(crate) fn take_hit<Q: Query>(best: &mut Option<Hit>, h: Hit) -> bool {
    if Q::ANY_HIT {
        *best = Some(h);
        return true;
    }
    if h.beats(best) {
        *best = Some(h);
    }
    false
}
