//! A bounding volume hierarchy, one folder per form (as obvhs lays it out):
//! `build` decides the binary binned-SAH tree node by node, `wide` opens
//! those nodes straight into the 4-wide nodes that traversal uses (its
//! parts built on all cores wait in an `arena`), and this file holds the
//! traversal. Before the build, `presplit` gives long thin triangles
//! several references with small boxes. Leaves of a few triangles are
//! also packed into a `tri_block` each, which a single ray tests at once.
//! Arrows run one way: `mod → wide → build → presplit`, `wide → arena`,
//! `mod → tri_block → wide`.

mod arena;
mod build;
mod packet;
mod presplit;
mod tri_block;
mod wide;

use super::{hit_limit, take_hit, test_prim_by, AccelInfo, Intersector, Query, Tracer};
use crate::aabb::ENTRY_SLACK;
use crate::geometry::{Geometry, Hit, Kind};
use crate::math::RayQuery;
use crate::packet::{LaneHits, RayPacket};
use crate::simd::lanes::Mask;
use crate::stats::Counters;
use crate::stopwatch::Stopwatch;
use packet::PacketEntry;
use tri_block::{TriangleBlock, TriangleBlocks};
pub(crate) use wide::Node4;
use wide::{Entry, Ray4, STACK};
#[cfg(feature = "gpu")]
pub(crate) use wide::{MAX, MIN};

/// Per-thread traversal stacks, allocated once: one for single rays, one
/// for packets.
pub(crate) struct Stacks {
    single: Vec<Entry>,
    packet: Vec<PacketEntry>,
}

/// The hierarchy: 4-wide nodes made from the binary SAH tree's nodes as
/// they are decided (the binary tree is never stored).
#[derive(Debug, Clone, Default)]
pub(crate) struct Bvh {
    /// 4-wide nodes, each node's children side by side after it; node 0
    /// is the root.
    wide: Vec<Node4>,
    /// Primitive ids in leaf order.
    prims: Vec<u32>,
    /// The leaves of two to four triangles, packed for single rays.
    blocks: TriangleBlocks,
    build_seconds: f64,
    /// The tree's SAH cost ([`wide::sah_cost`]).
    sah_cost: f64,
}

impl Bvh {
    /// Build over every primitive of `geom`.
    pub fn build(geom: &Geometry) -> Bvh {
        let t0 = Stopwatch::start();
        let (wide, prims) = Node4::build(geom);
        let blocks = TriangleBlocks::build(geom, &wide, &prims);
        let build_seconds = t0.seconds();
        Bvh { sah_cost: wide::sah_cost(&wide), wide, prims, blocks, build_seconds }
    }

    /// The 4-wide nodes, each before its children (node 0 is the root), and the
    /// primitive ids in the order leaves index them.
    #[cfg(feature = "gpu")]
    pub(crate) fn nodes(&self) -> (&[Node4], &[u32]) {
        (&self.wide, &self.prims)
    }

    /// Size, build time and the tree's SAH cost.
    pub fn info(&self) -> AccelInfo {
        AccelInfo {
            build_seconds: self.build_seconds,
            bytes: self.wide.len() * std::mem::size_of::<Node4>()
                + self.prims.len() * 4
                + self.blocks.bytes(),
            nodes: self.wide.len(),
            summary: "BVH (binned SAH, 4-wide)",
            unit: "nodes",
            warning: None,
            sah_cost: Some(self.sah_cost),
        }
    }

    /// The leaf's primitive ids.
    #[inline(always)]
    fn leaf(&self, e: &Entry) -> &[u32] {
        &self.prims[e.child as usize..(e.child + e.count) as usize]
    }

    /// The block of leaf `e` (whose ids are `ids`), if it has one: only a
    /// leaf of triangles may, so a sphere leaf costs a comparison.
    #[inline(always)]
    fn triangle_block(&self, e: &Entry, ids: &[u32], geom: &Geometry) -> Option<TriangleBlock<'_>> {
        if e.count < 2 || self.blocks.is_empty() || geom.locate(ids[0]).0 != Kind::Triangle {
            return None;
        }
        self.blocks.get(e.child as usize, e.count as usize)
    }
}

impl Intersector for Bvh {
    /// The traversal stacks, allocated once per thread.
    type Scratch = Stacks;

    fn scratch(&self, _: &Geometry) -> Stacks {
        Stacks { single: vec![Entry::default(); STACK], packet: vec![PacketEntry::default(); STACK] }
    }

    #[inline]
    fn trace_bounded<Q: Query>(
        tr: &mut Tracer<'_, Self>,
        q: &RayQuery,
        t_max: f32,
        best: Option<Hit>,
    ) -> Option<Hit> {
        let bvh = tr.accel;
        if bvh.wide.is_empty() {
            return best;
        }
        let root = Entry { child: 0, count: 0, t: q.t_min };
        bvh.trace_from::<Q>(root, tr.geom, q, t_max, best, &mut tr.scratch.single, &mut tr.counters)
    }

    fn trace_packet_bounded<H: LaneHits>(tr: &mut Tracer<'_, Self>, p: &RayPacket, mask: Mask, hits: &mut H) {
        Bvh::trace_packet_with(crate::simd::isa(), tr, p, mask, hits);
    }
}

/// Single-ray traversal from any node or leaf, so a packet whose lanes
/// have scattered can finish them one by one.
impl Bvh {
    /// [`Intersector::trace_bounded`] below `start`: the nearest hit better
    /// than `best`, or any hit, within `(q.t_min, t_max)`.
    /// The nearest child box hit is entered at once, the others wait on the
    /// stack, farthest deepest; any-hit rays take the children in slot
    /// order (the highest entered at once).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn trace_from<Q: Query>(
        &self,
        start: Entry,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        best: Option<Hit>,
        stack: &mut [Entry],
        c: &mut Counters,
    ) -> Option<Hit> {
        let mut walk = SingleRay::<Q>::new(q, t_max, best);
        let stack = &mut stack[..STACK];
        let (mut e, mut sp) = (start, 0);
        'walk: loop {
            // (A nearest-hit entry farther than the box limit: skipped.)
            if Q::ANY_HIT || e.t <= walk.box_limit {
                if e.count > 0 {
                    let ids = self.leaf(&e);
                    if let Some(block) = self.triangle_block(&e, ids, geom) {
                        if walk.test_block(geom, block, ids) {
                            break 'walk;
                        }
                    } else {
                        for &id in ids {
                            if walk.test(geom, id) {
                                break 'walk;
                            }
                        }
                    }
                } else {
                    walk.counters.visits += 1;
                    let node = &self.wide[e.child as usize];
                    let (t, mut mask) = node.hit(&walk.ray, walk.box_limit);
                    if mask != 0 {
                        if Q::ANY_HIT {
                            // In slot order: all but the last stacked.
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
                        // One box: entered at once. Two: the nearer entered,
                        // the other stacked (at equal distances the higher
                        // slot is entered, as the sort below would order them).
                        let first = mask.trailing_zeros() as usize;
                        let rest = mask & (mask - 1);
                        if rest == 0 {
                            e = node.entry(first, t[first]);
                            continue;
                        }
                        if rest & (rest - 1) == 0 {
                            let second = rest.trailing_zeros() as usize;
                            let (near, far) =
                                if t[second] <= t[first] { (second, first) } else { (first, second) };
                            stack[sp] = node.entry(far, t[far]);
                            sp += 1;
                            e = node.entry(near, t[near]);
                            continue;
                        }
                        // Sorted by entry distance, farthest first.
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
        walk.finish(c)
    }
}

/// One ray's walk through the tree: its splatted form, the best hit, the
/// distance boxes are entered up to, and its counts, all locals of the
/// walk; the counts reach the thread's counters once, at the end. (Reading
/// the box limit back out of the best hit at every step, and counting
/// straight into the thread's counters, made the same walk up to twice as
/// slow in some callers.)
struct SingleRay<'q, Q: Query> {
    ray: Ray4,
    q: &'q RayQuery,
    t_max: f32,
    best: Option<Hit>,
    /// Boxes entered before this: the best hit's distance or the ray's
    /// end, with [`ENTRY_SLACK`].
    box_limit: f32,
    counters: Counters,
    _query: std::marker::PhantomData<Q>,
}

impl<'q, Q: Query> SingleRay<'q, Q> {
    #[inline(always)]
    fn new(q: &'q RayQuery, t_max: f32, best: Option<Hit>) -> Self {
        let mut walk = SingleRay {
            ray: Ray4::new(q),
            q,
            t_max,
            best,
            box_limit: 0.0,
            counters: Counters::default(),
            _query: std::marker::PhantomData,
        };
        walk.bound();
        walk
    }

    /// The box limit for the best hit.
    #[inline(always)]
    fn bound(&mut self) {
        let end = if Q::ANY_HIT { self.t_max } else { self.best.map_or(self.t_max, |h| h.t) };
        self.box_limit = end * ENTRY_SLACK;
    }

    /// Test primitive `id` by [`test_prim`](super::test_prim), with the
    /// sphere test inline; true when an any-hit walk is done.
    #[inline(always)]
    fn test(&mut self, geom: &Geometry, id: u32) -> bool {
        let (q, best, c) = (self.q, &mut self.best, &mut self.counters);
        let done = test_prim_by::<Q>(Geometry::intersect_spheres_inline, geom, id, q, best, self.t_max, c);
        self.bound();
        done
    }

    /// Test the triangles `ids` of `block` at once, then take their hits
    /// in leaf order as [`SingleRay::test`] would take them one by one
    /// (lanes left to the scalar test are tested so, in their turn); true
    /// when an any-hit walk is done. (Tested against the best hit at the
    /// leaf's entry, a lane that a nearer lane's hit would have cut off
    /// cannot beat that hit: the result is the same.)
    #[inline(always)]
    fn test_block(&mut self, geom: &Geometry, block: TriangleBlock<'_>, ids: &[u32]) -> bool {
        let hits = block.hit(self.q, hit_limit::<Q>(&self.best, self.t_max));
        for (lane, &id) in ids.iter().enumerate() {
            if hits.slow >> lane & 1 != 0 {
                if self.test(geom, id) {
                    return true;
                }
                continue;
            }
            self.counters.tests[Kind::Triangle] += 1;
            if hits.found >> lane & 1 == 0 {
                continue;
            }
            let h = Hit { t: hits.t[lane], prim: id, u: hits.u[lane], v: hits.v[lane] };
            if take_hit::<Q>(&mut self.best, h) {
                return true;
            }
        }
        self.bound();
        false
    }

    /// The best hit, the counts added to `c`.
    #[inline(always)]
    fn finish(self, c: &mut Counters) -> Option<Hit> {
        *c += self.counters;
        self.best
    }
}
