//! Acceleration structures behind one interface: brute force, the P3D report's
//! uniform grid with mailboxes, and a binned-SAH BVH (the default).
//!
//! The renderer matches on [`Accel`] once per image and then runs code
//! generic over [`Intersector`], so the hot loop has no dynamic dispatch.
//!
//! Infinite planes (the course files' `pl`) have no box, so no structure
//! holds them: each is built over the bounded ids only, and
//! [`Intersector::intersect`] and [`Intersector::occluder`] test the planes
//! beside it, under the same tie rule (planes have the highest ids).

mod brute;
mod bvh;
mod grid;

pub use brute::BruteForce;
pub use bvh::{Bvh, Stacks};
pub use grid::{Grid, Mailbox};

use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;
use crate::packet::{for_lanes, Mask, PacketHits, RayPacket, LANES, NO_PRIM};
use crate::stats::Counters;
use strum::{Display, IntoStaticStr, VariantArray};

/// Nearest-hit and any-hit queries over a [`Geometry`].
pub trait Intersector: Sync {
    /// Per-thread mutable state (the grid's mailbox); `()` when none.
    type Scratch: Send;

    /// Fresh scratch state for one render thread.
    fn scratch(&self, geom: &Geometry) -> Self::Scratch;

    /// The nearest hit among the bounded primitives (ids
    /// `0..geom.bounded_len()`) in `(q.t_min, t_max)`; at equal distance,
    /// the lowest primitive id (so every accelerator returns the same hit).
    fn intersect_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> Option<Hit>;

    /// A bounded primitive lying in `(q.t_min, t_max)`, the first one found
    /// (not necessarily the nearest): shadow rays stop there.
    fn occluder_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> Option<u32>;

    /// For each active lane of `p`, the nearest bounded hit in `(t_min,
    /// t_max)` by the rule of [`Intersector::intersect_bounded`], merged
    /// into `hits`. The default traces lane by lane; the BVH traces the
    /// packet together.
    fn intersect_packet_bounded(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        hits: &mut PacketHits,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) {
        for_lanes(p.active, |i| {
            if let Some(h) = self.intersect_bounded(geom, &p.query(i), p.t_max.0[i], scratch, c) {
                hits.keep(i, h);
            }
        });
    }

    /// For each lane of `mask` (among `p`'s active ones), a bounded
    /// primitive blocking it within `(t_min, t_max)`, written to `out`
    /// (lanes left clear keep their value).
    fn occluders_packet_bounded(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        mask: Mask,
        out: &mut [u32; LANES],
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) {
        for_lanes(mask & p.active, |i| {
            if let Some(id) = self.occluder_bounded(geom, &p.query(i), p.t_max.0[i], scratch, c) {
                out[i] = id;
            }
        });
    }

    /// [`Intersector::intersect`] for every active lane of a packet.
    #[inline]
    fn intersect_packet(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        hits: &mut PacketHits,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) {
        self.intersect_packet_bounded(geom, p, hits, scratch, c);
        for id in geom.plane_ids() {
            for_lanes(p.active, |i| {
                c.tests[geom.locate(id).0] += 1;
                hits.test_scalar(geom, id, &p.query(i), i);
            });
        }
    }

    /// [`Intersector::occluder`] for every active lane of a packet: each
    /// lane's blocker, or [`NO_PRIM`] when its shadow ray is clear.
    #[inline]
    fn occluders_packet(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> [u32; LANES] {
        let mut out = [NO_PRIM; LANES];
        let mut open = p.active;
        for id in geom.plane_ids() {
            for_lanes(open, |i| {
                if test_shadow(geom, id, &p.query(i), p.t_max.0[i], c) {
                    out[i] = id;
                    open &= !(1 << i);
                }
            });
        }
        self.occluders_packet_bounded(geom, p, open, &mut out, scratch, c);
        out
    }

    /// The nearest hit in `(q.t_min, t_max)` over every primitive, planes
    /// included; ties go to the lowest id.
    #[inline]
    fn intersect(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> Option<Hit> {
        let mut best = self.intersect_bounded(geom, q, t_max, scratch, c);
        for id in geom.plane_ids() {
            test_prim(geom, id, q, &mut best, t_max, c);
        }
        best
    }

    /// A primitive lying in `(q.t_min, t_max)` (a shadow ray's blocker),
    /// planes first: they are few and, being infinite, likely to block.
    #[inline]
    fn occluder(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> Option<u32> {
        match geom.plane_ids().find(|&id| test_shadow(geom, id, q, t_max, c)) {
            Some(id) => Some(id),
            None => self.occluder_bounded(geom, q, t_max, scratch, c),
        }
    }

    /// Whether anything lies in `(q.t_min, t_max)`.
    #[inline]
    fn occluded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        scratch: &mut Self::Scratch,
        c: &mut Counters,
    ) -> bool {
        self.occluder(geom, q, t_max, scratch, c).is_some()
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

/// Options for building an accelerator.
#[derive(Debug, Clone, Copy)]
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
pub enum Accel {
    /// Brute force.
    None(BruteForce),
    /// Uniform grid.
    Grid(Grid),
    /// BVH.
    Bvh(Bvh),
}

/// What an accelerator costs: for the statistics.
#[derive(Debug, Clone, Copy, Default)]
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
}

impl Accel {
    /// Build the chosen structure over `geom`.
    pub fn build(geom: &Geometry, opts: &AccelOptions) -> Accel {
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
#[macro_export]
macro_rules! with_accel {
    ($accel:expr, $a:ident => $body:expr) => {
        match $accel {
            $crate::accel::Accel::None($a) => $body,
            $crate::accel::Accel::Grid($a) => $body,
            $crate::accel::Accel::Bvh($a) => $body,
        }
    };
}

/// Test one primitive, counting the test, keeping the better of two hits.
/// `limit` is `t_max` nudged up one ulp so that an equal-distance hit with a
/// lower id can still win the tie.
#[inline(always)]
pub(crate) fn test_prim(
    geom: &Geometry,
    id: u32,
    q: &RayQuery,
    best: &mut Option<Hit>,
    t_max: f32,
    c: &mut Counters,
) {
    let limit = match best {
        Some(b) => f32::from_bits(b.t.to_bits() + 1),
        None => t_max,
    };
    c.tests[geom.locate(id).0] += 1;
    if let Some(h) = geom.intersect(id, q, limit) {
        if h.beats(best) {
            *best = Some(h);
        }
    }
}

/// Whether primitive `id` occludes the shadow ray, counting the test.
#[inline(always)]
pub fn test_shadow(geom: &Geometry, id: u32, q: &RayQuery, t_max: f32, c: &mut Counters) -> bool {
    c.tests[geom.locate(id).0] += 1;
    geom.intersect(id, q, t_max).is_some()
}
