//! Packet traversal of the 4-wide BVH: the rays of a [`RayPacket`] walk the
//! tree together, each node's four boxes tested against every lane at once,
//! and a child is entered by the lanes that hit it (Wald, Slusallek, Benthin
//! and Wagner, "Interactive Rendering with Coherent Ray Tracing", 2001).
//! Per-lane best distances keep culling exact, so each lane finds the hit
//! its ray finds alone (the tie rule is applied per lane by
//! [`PacketHits::take`]). One traversal serves the nearest hit and any
//! hit, compiled per instruction set with [`dispatch!`].

use super::wide::{Entry, Node4};
use super::{Bvh, Stacks};
use crate::aabb::ENTRY_SLACK;
use crate::accel::Tracer;
use crate::packet::prims::test_prim;
use crate::packet::{LaneHits, RayPacket};
use crate::query::Query;
use crate::simd::dispatch;
use crate::simd::lanes::{for_lanes, Mask, LANES};
use crate::simd::vector::{group_bits, F32s, Simd};
use crate::simd::Isa;

/// The most lanes a node may be reached by and be finished ray by ray
/// (Benthin, Wald, Woop, Ernst and Mark, "Combining Single and Packet-Ray
/// Tracing for Arbitrary Ray Distributions on the Intel MIC
/// Architecture", 2012): vectors over sixteen lanes cost more than a few
/// single-ray traversals. Where one vector holds all sixteen lanes, a
/// packet step costs the same however few lanes are left, and already two
/// single-ray walks cost more than it: only a lone lane goes on alone.
#[inline(always)]
fn single_at_most<V: F32s>() -> u32 {
    if V::W >= LANES {
        1
    } else {
        2
    }
}

/// An entry of the packet traversal stack: a node or a leaf with the
/// nearest entry distance of the lanes that entered its box (a single-ray
/// [`Entry`], from which those lanes can go on alone), and those lanes.
#[derive(Clone, Copy, Default)]
pub(crate) struct PacketEntry {
    entry: Entry,
    mask: Mask,
}

impl Bvh {
    /// [`crate::accel::Intersector::trace_packet_bounded`] with the kernels
    /// built for `isa` (which falls back to the portable build where
    /// unsupported).
    pub(crate) fn trace_packet_with<H: LaneHits>(
        isa: Isa,
        tr: &mut Tracer<'_, Bvh>,
        p: &RayPacket,
        mask: Mask,
        hits: &mut H,
    ) {
        traverse_with(isa, tr, p, mask, hits);
    }

    /// Push the children of `node` hit by some lane, given per child slot
    /// the lanes and their nearest entry distance: for the nearest hit the
    /// farthest first, so the nearest is popped next (equal distances in
    /// slot order); for any hit in slot order.
    #[inline(always)]
    fn push_children<Q: Query>(
        node: &Node4,
        masks: &[Mask; 4],
        near: &[f32; 4],
        stack: &mut [PacketEntry],
        sp: &mut usize,
    ) {
        if Q::ANY_HIT {
            for (slot, &mask) in masks.iter().enumerate() {
                if mask != 0 {
                    stack[*sp] = PacketEntry { entry: node.entry(slot, near[slot]), mask };
                    *sp += 1;
                }
            }
            return;
        }
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

/// The traversal: for the lanes of `mask` (among `p`'s active ones), the
/// nearest hits or the first blockers among the bounded primitives, taken
/// into `hits`.
#[inline(always)]
fn traverse<V: F32s, H: LaneHits>(
    s: Simd<V>,
    tr: &mut Tracer<'_, Bvh>,
    p: &RayPacket,
    mask: Mask,
    hits: &mut H,
) {
    let any_hit = <H::Query as Query>::ANY_HIT;
    let Tracer { accel: bvh, geom, scratch: Stacks { single, packet: stack }, counters: c } = tr;
    let (bvh, geom) = (*bvh, *geom);
    // Lanes still looking: an any-hit lane stops at its first blocker.
    let mut open = mask & p.active;
    if bvh.wide.is_empty() || open == 0 {
        return;
    }
    stack[0] = PacketEntry { entry: Entry { child: 0, count: 0, t: f32::NEG_INFINITY }, mask: open };
    let mut sp = 1;
    while sp > 0 {
        sp -= 1;
        let PacketEntry { entry: e, mask } = stack[sp];
        let mut mask = mask & open;
        if !any_hit {
            // Lanes whose best hit is nearer than the box cannot improve in it.
            let mut keep: Mask = 0;
            for g in 0..LANES / V::W {
                let far = s.load(hits.far(p), g).mul(s.splat(ENTRY_SLACK));
                keep |= group_bits::<V>(s.splat(e.t).le(far), g);
            }
            mask &= keep;
        }
        if mask == 0 {
            continue;
        }
        if mask.count_ones() <= single_at_most::<V>() {
            // Too few lanes left for vectors to pay: finish them alone.
            for_lanes(mask, |i| {
                let (q, t_max) = (&p.query(i), p.t_max.0[i]);
                if let Some(h) = bvh.trace_from::<H::Query>(e, geom, q, t_max, hits.best(i), single, c) {
                    hits.take(i, h);
                    if any_hit {
                        open &= !(1 << i);
                    }
                }
            });
        } else if e.count > 0 {
            for &id in bvh.leaf(&e) {
                let found = test_prim(s, geom, id, p, mask, hits, c);
                if any_hit {
                    open &= !found;
                    mask &= !found;
                    if mask == 0 {
                        break;
                    }
                }
            }
        } else {
            c.visits += 1;
            let node = &bvh.wide[e.child as usize];
            let (masks, near) = node.hit_packet::<V, H::Query>(s, p, hits.far(p), mask);
            Bvh::push_children::<H::Query>(node, &masks, &near, stack, &mut sp);
        }
        if any_hit && open == 0 {
            return;
        }
    }
}

dispatch! {
    /// [`traverse`] compiled for `isa`.
    fn traverse_with<H: LaneHits>(isa: Isa, tr: &mut Tracer<'_, Bvh>, p: &RayPacket, mask: Mask, hits: &mut H) {
        |s| traverse(s, tr, p, mask, hits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{AnyHit, Grid, Intersector, Nearest};
    use crate::geometry::Geometry;
    use crate::packet::{Blockers, PacketHits, NO_PRIM};
    use crate::testing::{check_surfaces, random_scene, rays};
    use proptest::prelude::*;

    /// Every lane of `p` through `isa`'s kernels and alone: equal hits and
    /// equal occlusion.
    fn check(g: &Geometry, bvh: &Bvh, p: &RayPacket, isa: Isa) {
        let mut tr = Tracer::new(bvh, g);
        let mut hits = PacketHits::new(p);
        Bvh::trace_packet_with(isa, &mut tr, p, p.active, &mut hits);
        let mut blockers = Blockers::new();
        Bvh::trace_packet_with(isa, &mut tr, p, p.active, &mut blockers);
        for i in 0..LANES {
            let q = p.query(i);
            let t_max = p.t_max.0[i];
            if p.active >> i & 1 == 0 {
                assert_eq!((hits.get(i), blockers.0[i]), (None, NO_PRIM), "masked lane {i} was traced");
                continue;
            }
            let alone = Bvh::trace_bounded::<Nearest>(&mut tr, &q, t_max, None);
            assert_eq!(hits.get(i), alone, "{isa}: lane {i} nearest hit");
            let blocked = Bvh::trace_bounded::<AnyHit>(&mut tr, &q, t_max, None).is_some();
            assert_eq!(blockers.0[i] != NO_PRIM, blocked, "{isa}: lane {i} occlusion");
            if blocked {
                assert!(
                    g.intersect(blockers.0[i], &q, t_max).is_some(),
                    "{isa}: lane {i} blocker does not block"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

        #[test]
        fn packets_find_what_single_rays_find(
            seed in any::<u64>(),
            n in 1usize..300,
            one_sided in any::<bool>(),
            origin in prop::array::uniform3(-8.0f32..8.0),
            dir in prop::array::uniform3(-1.0f32..1.0),
            spread in prop::sample::select(vec![0.0f32, 0.05, 0.5, 4.0]),
            jitter in prop::collection::vec(prop::array::uniform6(-1.0f32..1.0), LANES),
            mask in any::<u16>(),
        ) {
            let g = random_scene(seed, n, one_sided);
            let bvh = Bvh::build(&g);
            let p = rays(&g, &bvh, (origin, dir), spread, &jitter, u32::from(mask) | 1);
            for isa in Isa::available() {
                check(&g, &bvh, &p, isa);
                check_surfaces(&g, &bvh, &p, isa);
            }
            // With planes: the tracing context's packet queries against the
            // single ones, for the BVH and for the default lane-by-lane form.
            let grid = Grid::build(&g, 2.0, true);
            let (mut tb, mut tg) = (Tracer::new(&bvh, &g), Tracer::new(&grid, &g));
            let (mut hb, mut hg) = (PacketHits::new(&p), PacketHits::new(&p));
            tb.nearest_packet(&p, &mut hb);
            tg.nearest_packet(&p, &mut hg);
            let ob = tb.occluders_packet(&p);
            let og = tg.occluders_packet(&p);
            for i in (0..LANES).filter(|i| p.active >> i & 1 != 0) {
                let (q, t_max) = (p.query(i), p.t_max.0[i]);
                let alone = tb.nearest(&q, t_max);
                prop_assert_eq!(hb.get(i), alone);
                prop_assert_eq!(hg.get(i), alone);
                let blocked = tb.occluded(&q, t_max);
                prop_assert_eq!(ob.0[i] != NO_PRIM, blocked);
                prop_assert_eq!(og.0[i] != NO_PRIM, blocked);
            }
        }
    }

    #[test]
    fn the_kernels_of_every_instruction_set_agree_with_the_portable_ones() {
        // Coherent packets over a dense scene, where the lane-wise sphere and
        // triangle tests (not the single-ray fallbacks) do the work.
        let g = random_scene(11, 3000, false);
        let bvh = Bvh::build(&g);
        let available = Isa::available();
        assert!(available.contains(&Isa::Portable));
        let mut lanes_tested = 0;
        let mut tr = Tracer::new(&bvh, &g);
        for k in 0..200 {
            let a = k as f32 * 0.61;
            let jitter: Vec<[f32; 6]> = (0..LANES)
                .map(|i| {
                    let (x, y) = ((i % 4) as f32 / 3.0 - 0.5, (i / 4) as f32 / 3.0 - 0.5);
                    [x, y, 0.0, x, y, 0.0]
                })
                .collect();
            let base = ([a.sin() * 9.0, a.cos() * 9.0, (a * 0.3).sin() * 3.0], [-a.sin(), -a.cos(), 0.1]);
            let p = rays(&g, &bvh, base, 0.3, &jitter, 0xffff);
            let mut portable = PacketHits::new(&p);
            Bvh::trace_packet_with(Isa::Portable, &mut tr, &p, p.active, &mut portable);
            for &isa in &available {
                let mut hits = PacketHits::new(&p);
                Bvh::trace_packet_with(isa, &mut tr, &p, p.active, &mut hits);
                for i in 0..LANES {
                    assert_eq!(hits.get(i), portable.get(i), "{isa} lane {i} of packet {k}");
                }
                check(&g, &bvh, &p, isa);
            }
            lanes_tested += portable.found().count_ones();
        }
        assert!(lanes_tested > 500, "too few hits to compare: {lanes_tested}");
    }
}
