//! The binary build of the BVH: binned surface-area heuristic (4 to 16 bins by node size,
//! all three axes binned in one pass, in parallel near the root), flattened
//! depth-first into 32-byte [`BvhNode`]s with `u32` links. Large subtrees
//! build their halves on both cores; the tree does not depend on it.
//!
//! Layout: the first child of an interior node is the next node in the
//! array; `link` holds the second. A leaf's `link` is the start of its
//! primitives in the primitive order this build returns, and `count` their
//! number (interior nodes have count 0).

use crate::aabb::Aabb;
use crate::geometry::Geometry;
use glam::Vec3A;
use rayon::prelude::*;

/// One node, 32 bytes: bounds, link, primitive count.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct BvhNode {
    min: [f32; 3],
    /// Second child (interior) or first primitive in `Bvh::prims` (leaf).
    pub(crate) link: u32,
    max: [f32; 3],
    /// Primitives in a leaf; 0 for interior nodes.
    pub(crate) count: u32,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

/// Deepest tree the traversal stack can hold; the builder makes leaves there.
const MAX_DEPTH: usize = 64;
/// Most bins per axis for the SAH (large nodes).
const BINS: usize = 16;
/// Fewest bins per axis (small nodes).
const MIN_BINS: usize = 4;

/// Bins for a node of `n` primitives: a small node gains nothing from 16
/// bins, and sweeping 3 x 16 bins per node would dominate the build of a
/// scene with many small nodes (half a million spheres make 300,000 nodes).
#[inline]
fn bin_count(n: usize) -> usize {
    (n / 2).clamp(MIN_BINS, BINS)
}
/// Leaves never hold more than this unless the primitives cannot be split.
const MAX_LEAF: usize = 4;
/// Cost of a traversal step relative to a primitive test.
const TRAVERSAL_COST: f32 = 1.0;

impl BvhNode {
    /// The node's box.
    #[inline(always)]
    pub(crate) fn bounds(&self) -> Aabb {
        Aabb { min: Vec3A::from_array(self.min), max: Vec3A::from_array(self.max) }
    }

    /// Whether the node is a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A primitive's box and its id: 48 bytes.
#[derive(Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    id: u32,
}

impl BuildPrim {
    #[inline(always)]
    fn centroid(&self) -> Vec3A {
        self.bounds.center()
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

const EMPTY_BIN: Bin = Bin { bounds: Aabb::EMPTY, count: 0 };

/// A range of build primitives waiting to become a subtree.
struct Task {
    start: usize,
    end: usize,
    depth: usize,
    /// Interior node whose `link` must point at this subtree (right child).
    parent: Option<usize>,
}

/// The binary tree over every primitive of `geom` and the primitive ids in
/// leaf order (the order `BvhNode::link` of a leaf indexes).
pub fn build_binary(geom: &Geometry) -> (Vec<BvhNode>, Vec<u32>) {
    let mut prims: Vec<BuildPrim> = (0..geom.bounded_len() as u32)
        .into_par_iter()
        .map(|id| {
            let bounds = geom.bounds(id);
            BuildPrim { bounds, id }
        })
        .collect();
    let nodes = if prims.is_empty() { Vec::new() } else { build_subtree(&mut prims, 0, 0) };
    (nodes, prims.iter().map(|p| p.id).collect())
}

/// Subtrees larger than this are split and their halves built in parallel.
const PARALLEL_BUILD: usize = 1 << 16;

/// Build the subtree over `prims` (which start at `offset` in the whole
/// array) at `depth`. Links of interior nodes are relative to the returned
/// vector; leaf links are absolute. Large subtrees split once here and build
/// their halves on both cores; the tree is the same as a sequential build.
fn build_subtree(prims: &mut [BuildPrim], offset: usize, depth: usize) -> Vec<BvhNode> {
    if prims.len() <= PARALLEL_BUILD || depth + 1 >= MAX_DEPTH {
        let mut nodes = Vec::with_capacity(prims.len());
        build_nodes(prims, offset, depth, &mut nodes);
        return nodes;
    }
    let (bounds, cb) = bounds_of(prims);
    let node = |count| BvhNode { min: bounds.min.into(), link: offset as u32, max: bounds.max.into(), count };
    let Some(mid) = sah_split(prims, &bounds, &cb) else {
        return vec![node(prims.len() as u32)];
    };
    let (lp, rp) = prims.split_at_mut(mid);
    let (left, right) =
        rayon::join(|| build_subtree(lp, offset, depth + 1), || build_subtree(rp, offset + mid, depth + 1));
    let mut nodes = Vec::with_capacity(1 + left.len() + right.len());
    nodes.push(BvhNode { link: (1 + left.len()) as u32, ..node(0) });
    for part in [left, right] {
        // The part's interior links were relative to its own first node.
        let base = nodes.len() as u32;
        nodes.extend(part.into_iter().map(|mut n| {
            if !n.is_leaf() {
                n.link += base;
            }
            n
        }));
    }
    nodes
}

/// Iterative depth-first build: the left child is always built right after
/// its parent, so it sits at `parent + 1`. Interior links are indices into
/// `nodes`; leaf links are `offset +` positions in `prims`.
fn build_nodes(prims: &mut [BuildPrim], offset: usize, depth: usize, nodes: &mut Vec<BvhNode>) {
    let mut stack = vec![Task { start: 0, end: prims.len(), depth, parent: None }];
    while let Some(task) = stack.pop() {
        let index = nodes.len();
        if let Some(p) = task.parent {
            nodes[p].link = index as u32;
        }
        let range = &mut prims[task.start..task.end];
        let (bounds, cb) = bounds_of(range);
        let mut node = BvhNode {
            min: bounds.min.into(),
            link: (offset + task.start) as u32,
            max: bounds.max.into(),
            count: 0,
        };
        let split = if task.depth + 1 >= MAX_DEPTH { None } else { sah_split(range, &bounds, &cb) };
        match split {
            None => {
                node.count = range.len() as u32;
                nodes.push(node);
            }
            Some(mid) => {
                nodes.push(node);
                let mid = task.start + mid;
                let depth = task.depth + 1;
                stack.push(Task { start: mid, end: task.end, depth, parent: Some(index) });
                stack.push(Task { start: task.start, end: mid, depth, parent: None });
            }
        }
    }
}

/// Partition `prims` by the cheapest binned SAH split; `None` when a leaf is
/// cheaper (or nothing can be split). Returns the size of the left part.
fn sah_split(prims: &mut [BuildPrim], bounds: &Aabb, cb: &Aabb) -> Option<usize> {
    let n = prims.len();
    if n <= 2 {
        return None;
    }
    let extent = cb.size();
    let mut best: Option<(f32, usize, usize)> = None; // cost, axis, bin
    let nb = bin_count(n);
    let all_bins = bin_all(prims, cb, nb);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let bins = &all_bins[axis];
        // Sweep from the right to get right-side areas and counts.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0u32; BINS];
        let (mut rb, mut rc) = (Aabb::EMPTY, 0);
        for i in (1..nb).rev() {
            rb = rb.union(bins[i].bounds);
            rc += bins[i].count;
            right_area[i] = rb.half_area();
            right_count[i] = rc;
        }
        let (mut lb, mut lc) = (Aabb::EMPTY, 0);
        for i in 0..nb - 1 {
            lb = lb.union(bins[i].bounds);
            lc += bins[i].count;
            if lc == 0 || right_count[i + 1] == 0 {
                continue;
            }
            let cost = lc as f32 * lb.half_area() + right_count[i + 1] as f32 * right_area[i + 1];
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, i));
            }
        }
    }
    let (cost, axis, bin) = best?;
    let area = bounds.half_area().max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + cost / area;
    if n <= MAX_LEAF && split_cost >= n as f32 {
        return None;
    }
    let scale = nb as f32 / extent[axis];
    let lo = cb.min[axis];
    let mid = partition(prims, |p| bin_index(p.centroid()[axis], lo, scale, nb) <= bin);
    (mid > 0 && mid < n).then_some(mid)
}

/// The bin of a centroid coordinate (converted through `i32`, which is
/// one instruction; a float to `usize` cast is a longer sequence on x86-64).
#[inline(always)]
fn bin_index(c: f32, lo: f32, scale: f32, nb: usize) -> usize {
    (((c - lo) * scale) as i32).clamp(0, nb as i32 - 1) as usize
}

/// Bin the primitives' centroids along all three axes in one pass, into the
/// first `nb` bins of each axis.
fn bin_all(prims: &[BuildPrim], cb: &Aabb, nb: usize) -> [[Bin; BINS]; 3] {
    let size = cb.size();
    let scale = Vec3A::select(size.cmpgt(Vec3A::ZERO), Vec3A::splat(nb as f32) / size, Vec3A::ZERO);
    let lo = cb.min;
    let fill = |chunk: &[BuildPrim]| {
        let mut bins = [[EMPTY_BIN; BINS]; 3];
        for p in chunk {
            let c = p.centroid();
            for (axis, axis_bins) in bins.iter_mut().enumerate() {
                let b = &mut axis_bins[bin_index(c[axis], lo[axis], scale[axis], nb)];
                b.bounds = b.bounds.union(p.bounds);
                b.count += 1;
            }
        }
        bins
    };
    if prims.len() > 1 << 15 {
        // Large nodes near the root: bin on all cores. The merge is exact
        // (unions and counts), so the tree does not depend on thread count.
        prims.par_chunks(1 << 13).map(fill).reduce(
            || [[EMPTY_BIN; BINS]; 3],
            |mut a, b| {
                for (aa, ba) in a.iter_mut().zip(&b) {
                    for (x, y) in aa.iter_mut().zip(ba) {
                        x.bounds = x.bounds.union(y.bounds);
                        x.count += y.count;
                    }
                }
                a
            },
        )
    } else {
        fill(prims)
    }
}

/// Bounds of the primitives and of their centroids, in one pass.
fn bounds_of(prims: &[BuildPrim]) -> (Aabb, Aabb) {
    prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| (b.union(p.bounds), c.grow(p.centroid())))
}

/// In-place partition; returns the number of elements satisfying `pred`.
/// Branch-free (every element is swapped, the count advances by the
/// predicate): the predicate is a coin toss for a good split, and
/// mispredicted branches were most of the build's time.
fn partition<T>(v: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..v.len() {
        let go = pred(&v[j]);
        v.swap(i, j);
        i += usize::from(go);
    }
    i
}
