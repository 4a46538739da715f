//! The BVH's traversal form: the binary SAH tree's nodes, opened four at a
//! time as the builder decides them, into 4-wide nodes whose four child
//! boxes are tested at once with SIMD (glam's `Vec4`, SSE on x86-64). Each
//! node is 128 bytes: the boxes in struct-of-arrays form, then the
//! children.
//!
//! Every node's interior children lie side by side, after it (see
//! [`fill`]): a ray entering two siblings reads neighbouring memory.
//!
//! A child with `count == 0` is an interior node (its index in `nodes`);
//! otherwise it is a leaf holding `prims[child..child + count]`. Unused slots
//! have empty boxes (min = +inf, max = −inf), which the slab test never hits
//! because near and far planes are chosen by the sign of 1/d.

use super::arena::Arena;
use super::build::{self, Binary, BuildPrim};
use crate::aabb::{ENTRY_SLACK, SLAB_WIDEN};
use crate::geometry::Geometry;
use crate::math::RayQuery;
use crate::packet::RayPacket;
use crate::query::Query;
use crate::simd::lanes::{Mask, LANES};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};
use glam::Vec4;
use rayon::prelude::*;

/// A 4-wide node.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Node4 {
    /// Box minima (`bounds[MIN]`) and maxima (`bounds[MAX]`) per axis,
    /// one lane per child slot: a ray picks its near and far planes per
    /// axis by index, without a select.
    pub(crate) bounds: [[Vec4; 3]; 2],
    /// Node index or first primitive per slot.
    pub(crate) child: [u32; 4],
    /// 0 for a node, else the leaf's primitive count.
    pub(crate) count: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<Node4>() == 128);

/// [`Node4::bounds`]' sides.
pub(crate) const MIN: usize = 0;
pub(crate) const MAX: usize = 1;

/// Entries of the traversal stack: a node or a leaf, and its entry distance.
#[derive(Clone, Copy, Default)]
pub(crate) struct Entry {
    /// Node index, or first primitive of a leaf.
    pub child: u32,
    /// 0 for a node, else the leaf's primitive count.
    pub count: u32,
    /// Where the ray enters its box.
    pub t: f32,
}

/// Deep enough for any tree the builder makes (depth ≤ 64, three siblings
/// pushed per level); the per-thread stack is allocated once at this size.
pub(crate) const STACK: usize = 256;

/// Nodes whose SAH cost [`sah_cost`] sums in one run.
const SAH_COST_RUN: usize = 1 << 12;

/// Binary nodes larger than this have their subtrees built in parallel.
const PARALLEL_BUILD: usize = 1 << 14;

/// Part of the node array, built on one thread: its place in the
/// [`Arena`]; its interior links count from its own first node.
type Part = std::ops::Range<usize>;

/// The parts of the node array as they are finished, until [`concat`]
/// gathers them in the tree's order.
type Parts = Arena<Node4>;

impl Node4 {
    /// No children: every box empty.
    const EMPTY: Node4 = Node4 {
        bounds: [[Vec4::splat(f32::INFINITY); 3], [Vec4::splat(f32::NEG_INFINITY); 3]],
        child: [0; 4],
        count: [0; 4],
    };

    /// The 4-wide BVH over every bounded primitive of `geom`: the nodes,
    /// laid out by [`fill`] (node 0 is the root), and the primitive ids in the order
    /// leaves index. Large subtrees are built on both cores; the tree does
    /// not depend on it.
    pub fn build(geom: &Geometry) -> (Vec<Node4>, Vec<u32>) {
        Node4::build_with(geom, PARALLEL_BUILD)
    }

    /// [`Node4::build`], building subtrees over more than `parallel`
    /// primitives in parallel.
    fn build_with(geom: &Geometry, parallel: usize) -> (Vec<Node4>, Vec<u32>) {
        let mut prims = build::build_prims(geom);
        if prims.is_empty() {
            return (Vec::new(), Vec::new());
        }
        let root = Binary::root(&prims);
        // Every primitive is in one leaf, which writes its id.
        let mut ids = vec![0; prims.len()];
        // (A sphere scene has about one node for six primitives.)
        let arena = Parts::new(prims.len() / 4 + 1);
        let parts = match parts(&mut prims, &mut ids, 0, root, parallel, &arena) {
            // The root first, its links past itself.
            Some((mut top, below)) => {
                top.shift_links(1);
                std::iter::once(arena.push(&[top])).chain(below).collect()
            }
            None => {
                let mut node = Node4::EMPTY;
                node.set_leaf(0, &root, 0);
                build::write_ids(&prims, &mut ids);
                vec![arena.push(&[node])]
            }
        };
        // Freed before the nodes are gathered: the gathered array may then
        // reuse its pages instead of new ones.
        drop(prims);
        (concat(&arena.into_items(), parts), ids)
    }

    /// Slot `slot` holds `b`'s box, and `child` and `count` as [`Entry`]
    /// reads them.
    fn set(&mut self, slot: usize, b: &Binary, child: u32, count: u32) {
        let bounds = b.bounds();
        for a in 0..3 {
            self.bounds[MIN][a][slot] = bounds.min[a];
            self.bounds[MAX][a][slot] = bounds.max[a];
        }
        self.child[slot] = child;
        self.count[slot] = count;
    }

    /// Interior links moved `by` places on (leaf links kept).
    fn shift_links(&mut self, by: u32) {
        for slot in 0..4 {
            if self.used(slot) && self.count[slot] == 0 {
                self.child[slot] += by;
            }
        }
    }

    /// Slot `slot` holds leaf `b`, whose positions count from `offset` in
    /// the whole primitive array.
    fn set_leaf(&mut self, slot: usize, b: &Binary, offset: usize) {
        self.set(slot, b, (offset + b.start) as u32, b.len() as u32);
    }
}

/// The (up to) four binary nodes that become one 4-wide node's children,
/// and which of them are known to be leaves.
struct Kids {
    nodes: [Binary; 4],
    leaf: [bool; 4],
    len: usize,
}

impl Kids {
    /// A split node's two children, then, while there are fewer than four,
    /// the one with the largest surface that is not a leaf replaced by its
    /// children (the last of equals; the opened node's children go last).
    /// Opening takes the place of collapsing a stored binary tree, and
    /// gives the same nodes.
    fn open(prims: &mut [BuildPrim], [first, second]: [Binary; 2]) -> Kids {
        let mut kids = Kids { nodes: [first, second, first, second], leaf: [false; 4], len: 2 };
        while kids.len < 4 {
            let area = |j: usize| kids.nodes[j].bounds().half_area();
            let widest =
                (0..kids.len).filter(|&j| !kids.leaf[j]).max_by(|&a, &b| area(a).total_cmp(&area(b)));
            let Some(j) = widest else { break };
            let Some([first, second]) = kids.nodes[j].split(prims) else {
                kids.leaf[j] = true;
                continue;
            };
            let len = kids.len;
            kids.nodes.copy_within(j + 1..len, j);
            kids.leaf.copy_within(j + 1..len, j);
            kids.nodes[len - 1] = first;
            kids.nodes[len] = second;
            kids.leaf[len - 1] = false;
            kids.leaf[len] = false;
            kids.len += 1;
        }
        kids
    }

    /// Split kid `slot`: its two children, or `None` for a leaf.
    fn split(&self, prims: &mut [BuildPrim], slot: usize) -> Option<[Binary; 2]> {
        if self.leaf[slot] {
            return None;
        }
        self.nodes[slot].split(prims)
    }
}

/// The 4-wide node over a split node's children `two`, its subtree
/// appended to `out` in the tree's layout: the node's interior children side
/// by side at the next free places, then each child's subtree below them in
/// slot order, laid out the same way. A ray that enters two children of a
/// node reads neighbouring nodes. The node's links count from `out`'s start;
/// leaf links are `offset` plus positions in `prims`, and the leaves write
/// their primitives' ids to `ids`, the id array's part at the same
/// positions as `prims`.
fn fill(
    prims: &mut [BuildPrim],
    ids: &mut [u32],
    offset: usize,
    two: [Binary; 2],
    out: &mut Vec<Node4>,
) -> Node4 {
    let kids = Kids::open(prims, two);
    let mut wide = Node4::EMPTY;
    // The interior children's slots and splits, in slot order.
    let mut inner = [(0, two); 4];
    let mut n = 0;
    for (slot, k) in kids.nodes[..kids.len].iter().enumerate() {
        match kids.split(prims, slot) {
            None => {
                build::write_ids(&prims[k.start..k.end], &mut ids[k.start..k.end]);
                wide.set_leaf(slot, k, offset);
            }
            Some(two) => {
                inner[n] = (slot, two);
                n += 1;
            }
        }
    }
    let first = out.len();
    for (j, &(slot, _)) in inner[..n].iter().enumerate() {
        wide.set(slot, &kids.nodes[slot], (first + j) as u32, 0);
    }
    out.resize(first + n, Node4::EMPTY);
    for (j, &(_, two)) in inner[..n].iter().enumerate() {
        out[first + j] = fill(prims, ids, offset, two, out);
    }
    wide
}

/// A subtree as [`fill`] lays it out: its root, whose links count from the
/// start of the first part, and the parts that follow it in the node array
/// (each part's links counting from that part's start).
type Subtree = (Node4, Vec<Part>);

/// The 4-wide subtree of `node` over `prims` (which start at `offset` in
/// the whole array); `None` when `node` is a leaf (its ids are then not
/// written). A large node's children are built in parallel, each on its
/// own slices of `prims` and `ids`; the parts are laid out as [`fill`]
/// would lay them, so the tree does not depend on `parallel`.
fn parts(
    prims: &mut [BuildPrim],
    ids: &mut [u32],
    offset: usize,
    node: Binary,
    parallel: usize,
    arena: &Parts,
) -> Option<Subtree> {
    let two = node.split(prims)?;
    if node.len() <= parallel {
        let (root, part) = arena.build(|out| fill(prims, ids, offset, two, out));
        return Some((root, vec![part]));
    }
    let kids = Kids::open(prims, two);
    let nodes = &kids.nodes[..kids.len];
    // The children tile the node's range: cut it into their slices in
    // range order, then build them in parallel (a leaf's job only writes
    // its ids).
    let mut by_start: Vec<usize> = (0..kids.len).collect();
    by_start.sort_by_key(|&s| nodes[s].start);
    let mut jobs = Vec::with_capacity(kids.len);
    let (mut rest, mut rest_ids) = (&mut prims[node.start..node.end], &mut ids[node.start..node.end]);
    for &slot in &by_start {
        let (mine, tail) = std::mem::take(&mut rest).split_at_mut(nodes[slot].len());
        let (my_ids, ids_tail) = std::mem::take(&mut rest_ids).split_at_mut(nodes[slot].len());
        (rest, rest_ids) = (tail, ids_tail);
        let k = nodes[slot];
        jobs.push((slot, mine, my_ids, offset + k.start, k.rebased(k.start), kids.leaf[slot]));
    }
    let mut built: [Option<Subtree>; 4] = Default::default();
    let subtrees: Vec<_> = jobs
        .into_par_iter()
        .map(|(slot, mine, my_ids, at, k, leaf)| {
            let sub = if leaf { None } else { parts(mine, my_ids, at, k, parallel, arena) };
            if sub.is_none() {
                build::write_ids(mine, my_ids);
            }
            (slot, sub)
        })
        .collect();
    for (slot, sub) in subtrees {
        built[slot] = sub;
    }
    // As `fill` lays them out: the children's roots side by side, then
    // each child's other nodes.
    let inner = built.iter().filter(|b| b.is_some()).count() as u32;
    let mut wide = Node4::EMPTY;
    let mut roots = Vec::with_capacity(inner as usize);
    let mut below = Vec::new();
    let mut placed = inner;
    for ((slot, k), sub) in nodes.iter().enumerate().zip(built) {
        let Some((mut root, sub)) = sub else {
            wide.set_leaf(slot, k, offset);
            continue;
        };
        wide.set(slot, k, roots.len() as u32, 0);
        root.shift_links(placed);
        roots.push(root);
        placed += sub.iter().map(|p| p.len()).sum::<usize>() as u32;
        below.extend(sub);
    }
    let mut out = vec![arena.push(&roots)];
    out.extend(below);
    Some((wide, out))
}

/// The parts of `arena` in one array in the order of `parts`, their
/// interior links made absolute: each node is copied from the arena once,
/// however many levels were built in parallel.
fn concat(arena: &[Node4], parts: Vec<Part>) -> Vec<Node4> {
    // (The parts tile the arena.)
    let mut nodes = Vec::with_capacity(arena.len());
    for part in parts {
        let base = nodes.len() as u32;
        // (Copied on all cores, in order: the nodes do not depend on it.)
        nodes.par_extend(arena[part].par_iter().map(|&(mut n)| {
            n.shift_links(base);
            n
        }));
    }
    nodes
}

/// The tree's cost by the surface-area heuristic, the model the builder
/// minimises (MacDonald and Booth 1990): every node a ray may enter costs
/// one box step (four boxes at once) and every primitive of a leaf one
/// test, each weighted by the chance that a ray through the root's box
/// meets its box (surface area over the root's). Lower is a better tree;
/// printed beside the build time so a faster build is not a worse tree.
pub(crate) fn sah_cost(nodes: &[Node4]) -> f64 {
    let Some(root) = nodes.first() else { return 0.0 };
    let area = |lo: [f32; 3], hi: [f32; 3]| -> f64 {
        let d = [0, 1, 2].map(|a| (hi[a] - lo[a]) as f64);
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    };
    // The root's box: the union of its children's (min and max are exact).
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for slot in (0..4).filter(|&s| root.used(s)) {
        for a in 0..3 {
            lo[a] = lo[a].min(root.bounds[MIN][a][slot]);
            hi[a] = hi[a].max(root.bounds[MAX][a][slot]);
        }
    }
    let root_area = area(lo, hi);
    if root_area <= 0.0 || !root_area.is_finite() {
        return 0.0;
    }
    let node_cost = |n: &Node4| {
        // `area` for the four slots at once, with the same operations.
        let d = |a: usize| (n.bounds[MAX][a] - n.bounds[MIN][a]).as_dvec4();
        let (dx, dy, dz) = (d(0), d(1), d(2));
        let areas = (dx * dy + dy * dz + dz * dx).to_array();
        let steps = |slot: usize| if n.count[slot] == 0 { 1.0 } else { n.count[slot] as f64 };
        (0..4).filter(|&s| n.used(s)).map(|slot| steps(slot) * areas[slot]).sum::<f64>()
    };
    // Summed in fixed runs on all cores, then in order: the same sum
    // whatever the thread count.
    let runs: Vec<f64> = nodes.par_chunks(SAH_COST_RUN).map(|run| run.iter().map(node_cost).sum()).collect();
    let cost = root_area + runs.iter().sum::<f64>(); // the root is always entered
    cost / root_area
}

impl Node4 {
    /// Entry distances of the ray into the four child boxes within
    /// `(t_min, t_max)`, and the mask of boxes hit: the slab test of
    /// [`Aabb::hit`], four boxes at a time, with the same entry distances.
    /// The exit distances are widened through the reciprocal
    /// ([`Ray4::inv_far`], as Ize's robust traversal does, JCGT 2013)
    /// instead of after the product, and the reductions pair up: each
    /// node's test is on the chain of loads the walk waits on, and this
    /// takes a multiply and a step off it.
    /// The distances come back as an array: a `Vec4` indexed by a
    /// variable slot compiles to a jump table.
    #[inline(always)]
    pub fn hit(&self, r: &Ray4, t_max: f32) -> ([f32; 4], u32) {
        // The near plane is the minimum where the ray goes up the axis.
        let near = |a: usize| self.bounds[r.neg[a] as usize][a];
        let far = |a: usize| self.bounds[!r.neg[a] as usize][a];
        let (nx, fx, ny, fy, nz, fz) = (near(0), far(0), near(1), far(1), near(2), far(2));
        let t_near = ((nx - r.o[0]) * r.inv[0])
            .max((ny - r.o[1]) * r.inv[1])
            .max(((nz - r.o[2]) * r.inv[2]).max(r.t_min));
        let t_far = ((fx - r.o[0]) * r.inv_far[0])
            .min((fy - r.o[1]) * r.inv_far[1])
            .min(((fz - r.o[2]) * r.inv_far[2]).min(Vec4::splat(t_max)));
        let mask = t_near.cmple(t_far).bitmask();
        (t_near.to_array(), mask)
    }

    /// The packet form of [`Node4::hit`], with vectors `V`: per child
    /// slot, the lanes of `mask` whose rays enter the box before their
    /// `far` distance (give or take [`ENTRY_SLACK`]), and the nearest entry
    /// among them (infinity when none). Near and far planes come from min and max of the two slab
    /// distances, which for the non-empty boxes tested equals choosing them
    /// by the sign of 1/d.
    ///
    /// For [`AnyHit`](crate::accel::AnyHit) (shadow rays, which need no
    /// order), the entry distances are not gathered and come back infinite.
    #[inline(always)]
    pub fn hit_packet<V: F32s, Q: Query>(
        &self,
        s: Simd<V>,
        p: &RayPacket,
        far: &[f32; LANES],
        mask: Mask,
    ) -> ([Mask; 4], [f32; 4]) {
        let mut masks = [0; 4];
        let inf = s.splat(f32::INFINITY);
        // Per slot, the entry distances of the lanes that hit (else
        // infinity), reduced for all four slots at once below.
        let mut near_min = [inf; 4];
        let used = self.used_slots();
        let [lo, hi] = &self.bounds;
        // Group by group, the group's rays loaded once for the four boxes.
        for g in 0..LANES / V::W {
            if !group_active::<V>(mask, g) {
                continue;
            }
            // (No closures: one is compiled without the instruction set.)
            let o = [s.load(&p.o[0].0, g), s.load(&p.o[1].0, g), s.load(&p.o[2].0, g)];
            let inv = [s.load(&p.inv[0].0, g), s.load(&p.inv[1].0, g), s.load(&p.inv[2].0, g)];
            let t_min = s.load(&p.t_min.0, g);
            let far = s.load(far, g).mul(s.splat(ENTRY_SLACK));
            for slot in 0..4 {
                if used >> slot & 1 == 0 {
                    continue;
                }
                let mut t_near = t_min;
                let mut t_far = inf;
                for a in 0..3 {
                    let t0 = s.splat(lo[a][slot]).sub(o[a]).mul(inv[a]);
                    let t1 = s.splat(hi[a][slot]).sub(o[a]).mul(inv[a]);
                    t_near = t_near.max(t0.min(t1));
                    t_far = t_far.min(t0.max(t1));
                }
                let hit = t_near.le(t_far.mul(s.splat(SLAB_WIDEN)).min(far));
                masks[slot] |= group_bits::<V>(hit, g) & mask;
                if !Q::ANY_HIT {
                    near_min[slot] = near_min[slot].min(V::select(hit, t_near, inf));
                }
            }
        }
        if Q::ANY_HIT || masks == [0; 4] {
            return (masks, [f32::INFINITY; 4]);
        }
        let nearest = V::hmin4(near_min);
        (masks, std::array::from_fn(|slot| if masks[slot] != 0 { nearest[slot] } else { f32::INFINITY }))
    }

    /// Whether child `slot` holds anything: its bit of [`Node4::used_slots`].
    #[inline(always)]
    pub fn used(&self, slot: usize) -> bool {
        self.used_slots() >> slot & 1 != 0
    }

    /// The slots holding anything, as bits (slot `k` is bit `k`): an unused
    /// slot's box is empty, its minimum above its maximum (on x, compared
    /// for all four slots at once).
    #[inline(always)]
    pub fn used_slots(&self) -> u32 {
        self.bounds[MIN][0].cmple(self.bounds[MAX][0]).bitmask()
    }

    /// Child `slot` as a stack entry.
    #[inline(always)]
    pub fn entry(&self, slot: usize, t: f32) -> Entry {
        Entry { child: self.child[slot], count: self.count[slot], t }
    }
}

/// A ray splatted for 4-wide box tests.
pub(crate) struct Ray4 {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    /// `inv` widened by [`SLAB_WIDEN`] for the far planes: one rounding
    /// more than widening the product, well inside the widening's margin.
    inv_far: [Vec4; 3],
    neg: [bool; 3],
    t_min: Vec4,
}

impl Ray4 {
    /// From a ray query.
    #[inline(always)]
    pub fn new(q: &RayQuery) -> Ray4 {
        let (o, inv) = (q.ray.o, q.inv_d);
        Ray4 {
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            inv_far: [inv.x, inv.y, inv.z].map(|i| Vec4::splat(i * SLAB_WIDEN)),
            neg: q.neg,
            t_min: Vec4::splat(q.t_min),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{spheres, uniform};
    use glam::Vec3A;

    /// Spheres of many sizes in clusters, by a fixed xorshift.
    fn clustered_spheres(n: usize) -> Geometry {
        let mut rnd = uniform(0x2545_f491_4f6c_dd1d);
        spheres(n, |i| {
            let cluster = Vec3A::splat((i % 7) as f32 * 3.0);
            (cluster + Vec3A::new(rnd(), rnd(), rnd()) * 4.0, 0.01 + rnd() * rnd() * 0.6)
        })
    }

    /// The 4-wide box test hits the boxes [`Aabb::hit`] hits, at the same
    /// entry distances, and never an unused slot: boxes flat on an axis,
    /// rays along an axis, along faces and through edges, near and far
    /// limits. (Without the far planes' widening it misses boxes here.)
    #[test]
    fn node_test_is_the_box_test_four_at_a_time() {
        use crate::aabb::Aabb;
        use crate::math::{Ray, RayQuery};
        let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
        let mut coord = || (rnd() * 8.0).round() * 0.25 - 1.0;
        let (mut hits, mut checked) = (0, 0);
        for _ in 0..4000 {
            let mut node = Node4::EMPTY;
            let mut boxes = [Aabb::EMPTY; 4];
            for (slot, b) in boxes.iter_mut().enumerate().take(1 + checked % 4) {
                let (p, q) = (Vec3A::new(coord(), coord(), coord()), Vec3A::new(coord(), coord(), coord()));
                *b = Aabb::new(p.min(q), p.max(q));
                for a in 0..3 {
                    node.bounds[MIN][a][slot] = b.min[a];
                    node.bounds[MAX][a][slot] = b.max[a];
                }
            }
            // Origins on the same quarter grid, aimed at a corner, edge or
            // face centre of the first box: rays along axes, along faces
            // and through edges.
            let o = Vec3A::new(coord(), coord(), coord()) * 2.0;
            let f = Vec3A::new(coord(), coord(), coord()).clamp(Vec3A::ZERO, Vec3A::ONE).round() * 0.5;
            let d = boxes[0].min + (boxes[0].max - boxes[0].min) * f - o;
            if d == Vec3A::ZERO {
                continue;
            }
            let t_min = [0.0, 0.5][checked % 2];
            let t_max = [f32::INFINITY, 1.5, 3.0][checked % 3];
            let q = RayQuery::new(Ray::new(o, d), t_min);
            let (t, mask) = node.hit(&Ray4::new(&q), t_max);
            for (slot, b) in boxes.iter().enumerate() {
                if *b == Aabb::EMPTY {
                    assert!(mask & 1 << slot == 0, "unused slot hit");
                } else if let Some((near, _)) = b.hit(&q, t_min, t_max) {
                    assert!(mask & 1 << slot != 0, "box {b:?} missed by {q:?}");
                    assert_eq!(t[slot], near);
                    hits += 1;
                }
            }
            checked += 1;
        }
        assert!(hits > 1000 && checked > 3000, "{hits} hits in {checked} nodes");
    }

    /// The used slots' bits are the slots whose box is not empty (its
    /// minimum at most its maximum on every axis): in built trees (with
    /// partly filled nodes), in an empty node, and where a slot's box is
    /// flat (its minimum equal to its maximum).
    #[test]
    fn used_slots_are_the_slots_with_boxes() {
        let filled = |n: &Node4, s: usize| (0..3).all(|a| n.bounds[MIN][a][s] <= n.bounds[MAX][a][s]);
        let bits = |n: &Node4| (0..4).filter(|&s| filled(n, s)).fold(0, |m, s| m | 1 << s);
        let mut partial = 0;
        for n in [1, 2, 3, 5, 7, 40, 3000] {
            let (nodes, _) = Node4::build(&clustered_spheres(n));
            for node in &nodes {
                assert_eq!(node.used_slots(), bits(node), "{n} spheres");
                partial += usize::from(node.used_slots() != 0b1111);
            }
        }
        assert!(partial > 0, "no partly filled node");
        assert_eq!(Node4::EMPTY.used_slots(), 0);
        let mut flat = Node4::EMPTY;
        for a in 0..3 {
            (flat.bounds[MIN][a][2], flat.bounds[MAX][a][2]) = (1.5, 1.5);
        }
        assert_eq!((flat.used_slots(), bits(&flat)), (0b100, 0b100));
    }

    /// The SAH cost of a tree that is one leaf is the root step plus a
    /// test per primitive; a built tree over many primitives costs far
    /// less than testing them all, and at least the root step.
    #[test]
    fn sah_cost_counts_steps_and_tests_by_area() {
        for n in 1..=4 {
            let (nodes, _) = Node4::build(&clustered_spheres(n));
            assert!(nodes.len() == 1 && nodes[0].count == [n as u32, 0, 0, 0], "one leaf");
            assert_eq!(sah_cost(&nodes), 1.0 + n as f64, "{n} spheres in one leaf");
        }
        let (nodes, _) = Node4::build(&clustered_spheres(3000));
        let cost = sah_cost(&nodes);
        assert!(cost > 1.0 && cost < 100.0, "{cost}");
        assert_eq!(sah_cost(&[]), 0.0);
    }

    /// The SAH cost, taken four slots at a time, has the bits of summing
    /// slot by slot in double precision, in the same order.
    #[test]
    fn sah_cost_is_the_slot_by_slot_sum() {
        let (nodes, _) = Node4::build(&clustered_spheres(5000));
        let area = |n: &Node4, s: usize| {
            let d = [0, 1, 2].map(|a| (n.bounds[MAX][a][s] - n.bounds[MIN][a][s]) as f64);
            d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
        };
        let mut root = Node4::EMPTY;
        for a in 0..3 {
            root.bounds[MIN][a][0] = (0..4).map(|s| nodes[0].bounds[MIN][a][s]).fold(f32::INFINITY, f32::min);
            root.bounds[MAX][a][0] =
                (0..4).map(|s| nodes[0].bounds[MAX][a][s]).fold(f32::NEG_INFINITY, f32::max);
        }
        // Summed as `sah_cost` sums: slots, then nodes in runs, then runs.
        let node_cost = |n: &Node4| {
            let steps = |s: usize| if n.count[s] == 0 { 1.0 } else { n.count[s] as f64 };
            (0..4).filter(|&s| n.used(s)).map(|s| steps(s) * area(n, s)).sum::<f64>()
        };
        let runs = nodes.chunks(SAH_COST_RUN).map(|run| run.iter().map(node_cost).sum::<f64>());
        let cost = area(&root, 0) + runs.sum::<f64>();
        assert!(nodes.len() > 100);
        assert_eq!(sah_cost(&nodes).to_bits(), (cost / area(&root, 0)).to_bits());
    }

    /// The tree and the primitive order do not depend on how many threads
    /// build them, with ranges large enough to be binned and partitioned
    /// on all cores.
    #[test]
    fn the_tree_does_not_depend_on_the_thread_count() {
        let g = clustered_spheres(3 * build::PARALLEL_SPLIT);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            pool.install(|| Node4::build(&g))
        };
        let one = on(1);
        assert!(one == on(3), "one thread against three");
    }

    /// The layout [`fill`] promises: every node's interior children side by
    /// side at the next free places, then their subtrees in slot order,
    /// each laid out the same way; no node left over.
    #[test]
    fn children_lie_side_by_side_below_their_parent() {
        fn lay(nodes: &[Node4], at: usize, next: &mut usize) {
            let kids: Vec<usize> = (0..4)
                .filter(|&s| nodes[at].used(s) && nodes[at].count[s] == 0)
                .map(|s| nodes[at].child[s] as usize)
                .collect();
            assert_eq!(kids, (*next..*next + kids.len()).collect::<Vec<_>>(), "children of node {at}");
            *next += kids.len();
            for k in kids {
                lay(nodes, k, next);
            }
        }
        for (n, parallel) in [(3000, usize::MAX), (3000, 16), (20_000, PARALLEL_BUILD)] {
            let (nodes, _) = Node4::build_with(&clustered_spheres(n), parallel);
            let mut next = 1;
            lay(&nodes, 0, &mut next);
            assert_eq!(next, nodes.len(), "{n} spheres, parallel below {parallel}");
        }
    }

    /// Building subtrees in parallel (down to tiny ones here) lays out the
    /// very nodes the sequential build does: the links between parts are
    /// right, and the tree does not depend on the thread count.
    #[test]
    fn parallel_parts_give_the_sequential_tree() {
        for n in [1, 2, 5, 40, 3000] {
            let g = clustered_spheres(n);
            let (nodes, ids) = Node4::build_with(&g, usize::MAX);
            for parallel in [4, 16, 100] {
                assert!(
                    Node4::build_with(&g, parallel) == (nodes.clone(), ids.clone()),
                    "{n} prims, {parallel}"
                );
            }
            // Every primitive is in exactly one leaf, reached from the root.
            let mut seen = vec![0u32; n];
            let mut stack = vec![0usize];
            while let Some(i) = stack.pop() {
                let node = &nodes[i];
                for slot in 0..4 {
                    if !node.used(slot) {
                        continue;
                    }
                    let (child, count) = (node.child[slot] as usize, node.count[slot] as usize);
                    if count == 0 {
                        assert!(child > i, "children follow their parent");
                        stack.push(child);
                    } else {
                        ids[child..child + count].iter().for_each(|&id| seen[id as usize] += 1);
                    }
                }
            }
            assert!(seen.iter().all(|&k| k == 1), "{n} prims");
        }
    }
}
