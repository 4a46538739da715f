//! A bounding volume hierarchy, one folder per form (as obvhs lays it out):
//! `build` decides the binary binned-SAH tree node by node, `wide` opens
//! those nodes straight into the 4-wide nodes that traversal uses, and this
//! file holds the traversal. Arrows run one way: `mod → wide → build`.

mod build;
mod packet;
mod wide;

pub use wide::Node4;

use super::{test_prim, test_shadow, AccelInfo, Intersector};
use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;
use crate::packet::{Mask, PacketHits, RayPacket, LANES};
use crate::stats::Counters;
use packet::PacketEntry;
use std::time::Instant;
use wide::{Entry, Ray4, STACK};

/// Per-thread traversal stacks, allocated once: one for single rays, one
/// for packets.
pub struct Stacks {
    single: Vec<Entry>,
    packet: Vec<PacketEntry>,
}

/// The hierarchy: 4-wide nodes made from the binary SAH tree's nodes as
/// they are decided (the binary tree is never stored).
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    /// 4-wide nodes, depth first; node 0 is the root.
    wide: Vec<Node4>,
    /// Primitive ids in leaf order.
    prims: Vec<u32>,
    build_seconds: f64,
}

impl Bvh {
    /// Build over every primitive of `geom`.
    pub fn build(geom: &Geometry) -> Bvh {
        let t0 = Instant::now();
        let (wide, prims) = Node4::build(geom);
        Bvh { wide, prims, build_seconds: t0.elapsed().as_secs_f64() }
    }

    /// [`Intersector::intersect_packet_bounded`] with the kernels built for
    /// `isa` (which falls back to the portable build where unsupported).
    pub fn intersect_packet_with(
        &self,
        isa: crate::simd::Isa,
        geom: &Geometry,
        p: &RayPacket,
        hits: &mut PacketHits,
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        packet::intersect_packet(isa, self, geom, p, hits, stacks, c);
    }

    /// [`Intersector::occluders_packet_bounded`] with the kernels built for
    /// `isa`.
    #[allow(clippy::too_many_arguments)]
    pub fn occluders_packet_with(
        &self,
        isa: crate::simd::Isa,
        geom: &Geometry,
        p: &RayPacket,
        mask: Mask,
        out: &mut [u32; LANES],
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        packet::occluders_packet(isa, self, geom, p, mask, out, stacks, c);
    }

    /// Size and build time.
    pub fn info(&self) -> AccelInfo {
        AccelInfo {
            build_seconds: self.build_seconds,
            bytes: self.wide.len() * std::mem::size_of::<Node4>() + self.prims.len() * 4,
            nodes: self.wide.len(),
            summary: "BVH (binned SAH, 4-wide)",
            unit: "nodes",
        }
    }
}

impl Intersector for Bvh {
    /// The traversal stacks, allocated once per thread.
    type Scratch = Stacks;

    fn scratch(&self, _: &Geometry) -> Stacks {
        Stacks { single: vec![Entry::default(); STACK], packet: vec![PacketEntry::default(); STACK] }
    }

    fn intersect_packet_bounded(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        hits: &mut PacketHits,
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        self.intersect_packet_with(crate::simd::isa(), geom, p, hits, stacks, c);
    }

    fn occluders_packet_bounded(
        &self,
        geom: &Geometry,
        p: &RayPacket,
        mask: Mask,
        out: &mut [u32; LANES],
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        self.occluders_packet_with(crate::simd::isa(), geom, p, mask, out, stacks, c);
    }

    #[inline]
    fn intersect_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        stacks: &mut Stacks,
        c: &mut Counters,
    ) -> Option<Hit> {
        if self.wide.is_empty() {
            return None;
        }
        let root = Entry { child: 0, count: 0, t: q.t_min };
        self.nearest_from(root, geom, q, t_max, None, &mut stacks.single, c)
    }

    #[inline]
    fn occluder_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        stacks: &mut Stacks,
        c: &mut Counters,
    ) -> Option<u32> {
        if self.wide.is_empty() {
            return None;
        }
        let root = Entry { child: 0, count: 0, t: q.t_min };
        self.occluder_from(root, geom, q, t_max, &mut stacks.single, c)
    }
}

/// Single-ray traversal from any node or leaf, so a packet whose lanes
/// have scattered can finish them one by one.
impl Bvh {
    /// The nearest hit below `start`, better than `best`, within
    /// `(q.t_min, t_max)` (the rule of [`Intersector::intersect_bounded`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn nearest_from(
        &self,
        start: Entry,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        mut best: Option<Hit>,
        stack: &mut [Entry],
        c: &mut Counters,
    ) -> Option<Hit> {
        let r = Ray4::new(q);
        let stack = &mut stack[..STACK];
        let (mut e, mut sp) = (start, 0);
        // The nearest child hit is entered at once; the others wait on the
        // stack, farthest deepest.
        loop {
            let limit = best.map_or(t_max, |h| h.t);
            // (An entry farther than the best hit: skipped.)
            if e.t <= limit {
                if e.count > 0 {
                    for &id in &self.prims[e.child as usize..(e.child + e.count) as usize] {
                        test_prim(geom, id, q, &mut best, t_max, c);
                    }
                } else {
                    c.visits += 1;
                    let node = &self.wide[e.child as usize];
                    let (t, mut mask) = node.hit(&r, limit);
                    let mut hits = [(0.0f32, 0usize); 4];
                    let mut n = 0;
                    while mask != 0 {
                        let slot = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let ts = t[slot];
                        let mut k = n;
                        while k > 0 && hits[k - 1].0 < ts {
                            hits[k] = hits[k - 1];
                            k -= 1;
                        }
                        hits[k] = (ts, slot);
                        n += 1;
                    }
                    if n > 0 {
                        for &(ts, slot) in &hits[..n - 1] {
                            stack[sp] = node.entry(slot, ts);
                            sp += 1;
                        }
                        let (ts, slot) = hits[n - 1];
                        e = node.entry(slot, ts);
                        continue;
                    }
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            e = stack[sp];
        }
        best
    }

    /// A primitive below `start` blocking the ray within `(q.t_min,
    /// t_max)`, the first found.
    #[inline(always)]
    pub(crate) fn occluder_from(
        &self,
        start: Entry,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        stack: &mut [Entry],
        c: &mut Counters,
    ) -> Option<u32> {
        let r = Ray4::new(q);
        let stack = &mut stack[..STACK];
        let (mut e, mut sp) = (start, 0);
        // One child hit (the last) is entered at once, the others stacked.
        loop {
            if e.count > 0 {
                for &id in &self.prims[e.child as usize..(e.child + e.count) as usize] {
                    if test_shadow(geom, id, q, t_max, c) {
                        return Some(id);
                    }
                }
            } else {
                c.visits += 1;
                let node = &self.wide[e.child as usize];
                let (t, mut mask) = node.hit(&r, t_max);
                if mask != 0 {
                    while mask & (mask - 1) != 0 {
                        let slot = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        stack[sp] = node.entry(slot, t[slot]);
                        sp += 1;
                    }
                    let slot = mask.trailing_zeros() as usize;
                    e = node.entry(slot, t[slot]);
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            e = stack[sp];
        }
        None
    }
}
