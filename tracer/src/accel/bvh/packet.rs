//! Packet traversal of the 4-wide BVH: the rays of a [`RayPacket`] walk the
//! tree together, each node's four boxes tested against every lane at once,
//! and a child is entered by the lanes that hit it (Wald, Slusallek, Benthin
//! and Wagner, "Interactive Rendering with Coherent Ray Tracing", 2001).
//! Per-lane nearest distances keep culling exact, so each lane finds the
//! hit its ray finds alone (the tie rule is applied per lane in
//! [`crate::packet`]). Compiled per instruction set with
//! [`dispatch!`](crate::dispatch).

use super::wide::{Entry, Node4};
use super::{Bvh, Stacks};
use crate::geometry::Geometry;
use crate::packet::{for_lanes, occludes_packet, test_prim_packet, Mask, PacketHits, RayPacket, LANES};
use crate::simd::vector::{group_bits, F32s};
use crate::stats::Counters;

/// A node reached by this many lanes or fewer is finished ray by ray
/// (Benthin, Wald, Woop, Ernst and Mark, "Combining Single and Packet-Ray
/// Tracing for Arbitrary Ray Distributions on the Intel MIC
/// Architecture", 2012): vectors over sixteen lanes cost more than a few
/// single-ray traversals. Measured at 16 spp, 256x256, one thread (best of
/// four): never 0.95 s on balls_s4 and 0.97 s on mount_s7, at most 2 lanes
/// 0.87 and 0.91 s, at most 4 lanes 0.92 and 0.99 s.
const SINGLE_AT_MOST: u32 = 2;

/// An entry of the packet traversal stack: a node or a leaf with the
/// nearest entry distance of the lanes that entered its box (a single-ray
/// [`Entry`], from which those lanes can go on alone), and those lanes.
#[derive(Clone, Copy, Default)]
pub struct PacketEntry {
    entry: Entry,
    mask: Mask,
}

impl Bvh {
    /// The leaf's primitive ids.
    #[inline(always)]
    fn leaf(&self, e: &Entry) -> &[u32] {
        &self.prims[e.child as usize..(e.child + e.count) as usize]
    }

    /// Push the children of `node` hit by some lane of `mask`, the
    /// farthest first so the nearest is popped next.
    #[inline(always)]
    fn push_children(node: &Node4, hit: ([Mask; 4], [f32; 4]), stack: &mut [PacketEntry], sp: &mut usize) {
        let (masks, near) = hit;
        let mut order = [0usize; 4];
        let mut n = 0;
        for slot in 0..4 {
            if masks[slot] == 0 {
                continue;
            }
            let mut k = n;
            while k > 0 && near[order[k - 1]] < near[slot] {
                order[k] = order[k - 1];
                k -= 1;
            }
            order[k] = slot;
            n += 1;
        }
        for &slot in &order[..n] {
            stack[*sp] = PacketEntry { entry: node.entry(slot, near[slot]), mask: masks[slot] };
            *sp += 1;
        }
    }
}

/// Nearest hits of the packet's lanes among the bounded primitives.
#[inline(always)]
fn intersect_body<V: F32s>(
    bvh: &Bvh,
    geom: &Geometry,
    p: &RayPacket,
    hits: &mut PacketHits,
    stacks: &mut Stacks,
    c: &mut Counters,
) {
    if bvh.wide.is_empty() || p.active == 0 {
        return;
    }
    let Stacks { single, packet: stack } = stacks;
    stack[0] = PacketEntry { entry: Entry { child: 0, count: 0, t: f32::NEG_INFINITY }, mask: p.active };
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let PacketEntry { entry: e, mask } = stack[sp];
        // Lanes whose best hit is nearer than the box cannot improve in it.
        let mut keep: Mask = 0;
        for g in 0..LANES / V::W {
            keep |= group_bits::<V>(V::splat(e.t).le(V::load(&hits.t.0, g)), g);
        }
        let mask = mask & keep;
        if mask == 0 {
            continue;
        }
        if mask.count_ones() <= SINGLE_AT_MOST {
            // Too few lanes left for vectors to pay: finish them alone.
            for_lanes(mask, |i| {
                let (q, t_max) = (&p.query(i), p.t_max.0[i]);
                if let Some(h) = bvh.nearest_from(e, geom, q, t_max, hits.get(i), single, c) {
                    hits.keep(i, h);
                }
            });
            continue;
        }
        if e.count > 0 {
            for &id in bvh.leaf(&e) {
                test_prim_packet::<V>(geom, id, p, mask, hits, c);
            }
            continue;
        }
        c.visits += 1;
        let node = &bvh.wide[e.child as usize];
        Bvh::push_children(node, node.hit_packet::<V, true>(p, &hits.t.0, mask), stack, &mut sp);
    }
}

/// Per lane of `mask`, a bounded primitive blocking it (the first found).
#[inline(always)]
fn occluders_body<V: F32s>(
    bvh: &Bvh,
    geom: &Geometry,
    p: &RayPacket,
    mask: Mask,
    out: &mut [u32; LANES],
    stacks: &mut Stacks,
    c: &mut Counters,
) {
    let mut alive = mask & p.active;
    if bvh.wide.is_empty() || alive == 0 {
        return;
    }
    let Stacks { single, packet: stack } = stacks;
    stack[0] = PacketEntry { entry: Entry { child: 0, count: 0, t: 0.0 }, mask: alive };
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let PacketEntry { entry: e, mask } = stack[sp];
        let mut mask = mask & alive;
        if mask == 0 {
            continue;
        }
        if mask.count_ones() <= SINGLE_AT_MOST {
            for_lanes(mask, |i| {
                let (q, t_max) = (&p.query(i), p.t_max.0[i]);
                if let Some(id) = bvh.occluder_from(e, geom, q, t_max, single, c) {
                    out[i] = id;
                    alive &= !(1 << i);
                }
            });
            if alive == 0 {
                return;
            }
            continue;
        }
        if e.count > 0 {
            for &id in bvh.leaf(&e) {
                let blocked = occludes_packet::<V>(geom, id, p, mask, c);
                for_lanes(blocked, |i| out[i] = id);
                alive &= !blocked;
                mask &= !blocked;
                if mask == 0 {
                    break;
                }
            }
            if alive == 0 {
                return;
            }
            continue;
        }
        c.visits += 1;
        let node = &bvh.wide[e.child as usize];
        let (masks, _) = node.hit_packet::<V, false>(p, &p.t_max.0, mask);
        for (slot, &m) in masks.iter().enumerate() {
            if m != 0 {
                stack[sp] = PacketEntry { entry: node.entry(slot, 0.0), mask: m };
                sp += 1;
            }
        }
    }
}

crate::dispatch! {
    /// [`intersect_body`] compiled for `isa`.
    pub(super) fn intersect_packet(
        isa: Isa,
        bvh: &Bvh,
        geom: &Geometry,
        p: &RayPacket,
        hits: &mut PacketHits,
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        intersect_body::<V>(bvh, geom, p, hits, stacks, c)
    }
}

crate::dispatch! {
    /// [`occluders_body`] compiled for `isa`.
    pub(super) fn occluders_packet(
        isa: Isa,
        bvh: &Bvh,
        geom: &Geometry,
        p: &RayPacket,
        mask: Mask,
        out: &mut [u32; LANES],
        stacks: &mut Stacks,
        c: &mut Counters,
    ) {
        occluders_body::<V>(bvh, geom, p, mask, out, stacks, c)
    }
}
