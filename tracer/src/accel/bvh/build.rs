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
const _: () = assert!(std::mem::size_of::<BuildPrim>() == 32);

/// Deepest tree the traversal stack can hold; the builder makes leaves there.
const MAX_DEPTH: usize = 64;
/// Most bins per axis for the SAH (large nodes).
const BINS: usize = 16;
/// Fewest bins per axis (small nodes).
const MIN_BINS: usize = 4;

/// Bins for a node of `n` primitives: 4, 8 or 16 by its size. A small
/// node gains nothing from 16 bins, and with half a million spheres there
/// are 300,000 small nodes, each setting up and sweeping its bins; sizing
/// the arrays to the count ([`split_with`] is compiled for each) took about
/// 7% off the sphereflake's build.
#[inline]
fn bin_count(n: usize) -> usize {
    (n / 2).clamp(MIN_BINS, BINS).next_power_of_two().min(BINS)
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

/// A primitive's box and its id: 32 bytes, aligned so that moving one is
/// two aligned 16-byte copies (the partition swaps one per primitive per
/// level; at 28 bytes the swap went through overlapping stack copies that
/// defeated store forwarding: 18% of the split function's samples).
#[derive(Clone, Copy)]
#[repr(C, align(16))]
struct BuildPrim {
    min: [f32; 3],
    id: u32,
    max: [f32; 3],
}

impl BuildPrim {
    #[inline(always)]
    fn new(bounds: Aabb, id: u32) -> BuildPrim {
        BuildPrim { min: bounds.min.into(), id, max: bounds.max.into() }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb { min: Vec3A::from_array(self.min), max: Vec3A::from_array(self.max) }
    }

    /// Twice the centre of the box: binning only compares centroids, so
    /// the halving is left out.
    #[inline(always)]
    fn centroid(&self) -> Vec3A {
        Vec3A::from_array(self.min) + Vec3A::from_array(self.max)
    }
}

/// A range's box and the box of its primitives' centroids (doubled, as
/// [`BuildPrim::centroid`] gives them).
#[derive(Clone, Copy)]
struct Boxes {
    bounds: Aabb,
    centroids: Aabb,
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
    boxes: Boxes,
}

/// The binary tree over every primitive of `geom` and the primitive ids in
/// leaf order (the order `BvhNode::link` of a leaf indexes).
pub fn build_binary(geom: &Geometry) -> (Vec<BvhNode>, Vec<u32>) {
    let mut prims: Vec<BuildPrim> = (0..geom.bounded_len() as u32)
        .into_par_iter()
        .map(|id| BuildPrim::new(geom.bounds(id), id))
        .collect();
    let nodes = if prims.is_empty() {
        Vec::new()
    } else {
        let boxes = boxes_of(&prims);
        concat(build_subtree(&mut prims, 0, 0, boxes))
    };
    (nodes, prims.iter().map(|p| p.id).collect())
}

/// Subtrees larger than this are split and their halves built in parallel.
const PARALLEL_BUILD: usize = 1 << 16;

/// Part of the node array, built on one thread: its interior links count
/// from its own first node.
type Part = Vec<BvhNode>;

/// Build the subtree over `prims` (which start at `offset` in the whole
/// array, and whose boxes are `boxes`) at `depth`, as parts that follow
/// each other in the node array. Leaf links are absolute. Large subtrees
/// split once here and build their halves on both cores; the tree is the
/// same as a sequential build.
fn build_subtree(prims: &mut [BuildPrim], offset: usize, depth: usize, boxes: Boxes) -> Vec<Part> {
    if prims.len() <= PARALLEL_BUILD || depth + 1 >= MAX_DEPTH {
        let mut nodes = Vec::with_capacity(prims.len());
        build_nodes(prims, offset, depth, boxes, &mut nodes);
        return vec![nodes];
    }
    let b = boxes.bounds;
    let node = |count| BvhNode { min: b.min.into(), link: offset as u32, max: b.max.into(), count };
    let Some(split) = sah_split(prims, &boxes) else {
        return vec![vec![node(prims.len() as u32)]];
    };
    let (lp, rp) = prims.split_at_mut(split.mid);
    let (left, right) = rayon::join(
        || build_subtree(lp, offset, depth + 1, split.left),
        || build_subtree(rp, offset + split.mid, depth + 1, split.right),
    );
    let left_len: usize = left.iter().map(Vec::len).sum();
    let mut parts = Vec::with_capacity(1 + left.len() + right.len());
    parts.push(vec![BvhNode { link: (1 + left_len) as u32, ..node(0) }]);
    parts.extend(left);
    parts.extend(right);
    parts
}

/// The parts in one array, their interior links made absolute: each node
/// is copied once, however many levels were built in parallel.
fn concat(parts: Vec<Part>) -> Vec<BvhNode> {
    let mut nodes = Vec::with_capacity(parts.iter().map(Vec::len).sum());
    for part in parts {
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
fn build_nodes(prims: &mut [BuildPrim], offset: usize, depth: usize, boxes: Boxes, nodes: &mut Vec<BvhNode>) {
    let mut stack = vec![Task { start: 0, end: prims.len(), depth, parent: None, boxes }];
    while let Some(task) = stack.pop() {
        let index = nodes.len();
        if let Some(p) = task.parent {
            nodes[p].link = index as u32;
        }
        let range = &mut prims[task.start..task.end];
        let b = task.boxes.bounds;
        let mut node =
            BvhNode { min: b.min.into(), link: (offset + task.start) as u32, max: b.max.into(), count: 0 };
        let split = if task.depth + 1 >= MAX_DEPTH { None } else { sah_split(range, &task.boxes) };
        match split {
            None => {
                node.count = range.len() as u32;
                nodes.push(node);
            }
            Some(split) => {
                nodes.push(node);
                let mid = task.start + split.mid;
                let depth = task.depth + 1;
                stack.push(Task {
                    start: mid,
                    end: task.end,
                    depth,
                    parent: Some(index),
                    boxes: split.right,
                });
                stack.push(Task { start: task.start, end: mid, depth, parent: None, boxes: split.left });
            }
        }
    }
}

/// A range split in two: the size of the left part and both parts' boxes.
struct Split {
    mid: usize,
    left: Boxes,
    right: Boxes,
}

/// Partition `prims` by the cheapest binned SAH split; `None` when a leaf is
/// cheaper (or nothing can be split). The parts' boxes come from the split
/// itself: their bounds are unions of bins, their centroid bounds are
/// gathered by the partition, so no level reads its primitives twice.
fn sah_split(prims: &mut [BuildPrim], boxes: &Boxes) -> Option<Split> {
    let n = prims.len();
    if n <= 2 {
        return None;
    }
    match bin_count(n) {
        4 => split_with::<4>(prims, boxes),
        8 => split_with::<8>(prims, boxes),
        _ => split_with::<BINS>(prims, boxes),
    }
}

/// [`sah_split`] with `NB` bins per axis.
fn split_with<const NB: usize>(prims: &mut [BuildPrim], boxes: &Boxes) -> Option<Split> {
    let n = prims.len();
    let cb = &boxes.centroids;
    let extent = cb.size();
    // cost, axis, bin, left bounds, right bounds
    let mut best: Option<(f32, usize, usize, Aabb, Aabb)> = None;
    let all_bins = bin_all::<NB>(prims, cb);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let bins = &all_bins[axis];
        // Sweep from the right to get right-side boxes and counts.
        let mut right_box = [Aabb::EMPTY; NB];
        let mut right_count = [0u32; NB];
        let (mut rb, mut rc) = (Aabb::EMPTY, 0);
        for i in (1..NB).rev() {
            rb = rb.union(bins[i].bounds);
            rc += bins[i].count;
            right_box[i] = rb;
            right_count[i] = rc;
        }
        let (mut lb, mut lc) = (Aabb::EMPTY, 0);
        for i in 0..NB - 1 {
            lb = lb.union(bins[i].bounds);
            lc += bins[i].count;
            if lc == 0 || right_count[i + 1] == 0 {
                continue;
            }
            let cost = lc as f32 * lb.half_area() + right_count[i + 1] as f32 * right_box[i + 1].half_area();
            if best.as_ref().is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, i, lb, right_box[i + 1]));
            }
        }
    }
    let (cost, axis, bin, left_bounds, right_bounds) = best?;
    let area = boxes.bounds.half_area().max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + cost / area;
    if n <= MAX_LEAF && split_cost >= n as f32 {
        return None;
    }
    let (lo, scale) = bin_frame::<NB>(cb);
    let (mid, left_centroids, right_centroids) =
        partition(prims, |c| bin_indices::<NB>(c, lo, scale)[axis] <= bin);
    (mid > 0 && mid < n).then_some(Split {
        mid,
        left: Boxes { bounds: left_bounds, centroids: left_centroids },
        right: Boxes { bounds: right_bounds, centroids: right_centroids },
    })
}

/// 2^23: adding it to a float in [0, 2^23) leaves the float's value,
/// rounded to an integer, in the low bits of its representation.
const ROUNDER: f32 = 8_388_608.0;

/// Where a node's centroids fall into `NB` bins per axis: the low corner
/// and the scale, shared by binning and partitioning so both use the same
/// numbers.
#[inline(always)]
fn bin_frame<const NB: usize>(cb: &Aabb) -> (Vec3A, Vec3A) {
    let size = cb.size();
    (cb.min, Vec3A::select(size.cmpgt(Vec3A::ZERO), Vec3A::splat(NB as f32) / size, Vec3A::ZERO))
}

/// The bins of a centroid on all three axes: `(c - lo) * scale` rounded
/// down (a tie at an exact bin edge may go either way; binning and
/// partitioning both call this, so they always agree). Clamped in floating
/// point and turned into integers by [`ROUNDER`], a few vector instructions
/// where three saturating casts and clamps were (10-15% off the
/// sphereflake's build).
#[inline(always)]
fn bin_indices<const NB: usize>(c: Vec3A, lo: Vec3A, scale: Vec3A) -> [usize; 3] {
    let t = ((c - lo) * scale - Vec3A::splat(0.5)).max(Vec3A::ZERO).min(Vec3A::splat(NB as f32 - 1.0));
    let r = (t + Vec3A::splat(ROUNDER)).to_array();
    // (`min` last: a NaN ends in the last bin, never out of range.)
    r.map(|x| (x.to_bits().wrapping_sub(ROUNDER.to_bits()) as usize).min(NB - 1))
}

/// Bin the primitives' centroids along all three axes in one pass, into
/// `NB` bins per axis.
fn bin_all<const NB: usize>(prims: &[BuildPrim], cb: &Aabb) -> [[Bin; NB]; 3] {
    let (lo, scale) = bin_frame::<NB>(cb);
    let fill = |chunk: &[BuildPrim]| {
        let mut bins = [[EMPTY_BIN; NB]; 3];
        for p in chunk {
            let bounds = p.bounds();
            let index = bin_indices::<NB>(p.centroid(), lo, scale);
            for (axis_bins, i) in bins.iter_mut().zip(index) {
                let b = &mut axis_bins[i];
                b.bounds = b.bounds.union(bounds);
                b.count += 1;
            }
        }
        bins
    };
    if prims.len() > 1 << 15 {
        // Large nodes near the root: bin on all cores. The merge is exact
        // (unions and counts), so the tree does not depend on thread count.
        prims.par_chunks(1 << 13).map(fill).reduce(
            || [[EMPTY_BIN; NB]; 3],
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
fn boxes_of(prims: &[BuildPrim]) -> Boxes {
    let (bounds, centroids) = prims
        .par_iter()
        .fold(|| (Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| (b.union(p.bounds()), c.grow(p.centroid())))
        .reduce(|| (Aabb::EMPTY, Aabb::EMPTY), |(b0, c0), (b1, c1)| (b0.union(b1), c0.union(c1)));
    Boxes { bounds, centroids }
}

/// In-place partition by a predicate on the centroid; returns the number of
/// elements satisfying it and the centroid bounds of both parts.
/// Branch-free (every element is swapped, the count advances by the
/// predicate, the bounds grow by selection): the predicate is a coin toss
/// for a good split, and mispredicted branches were most of the build's
/// time.
fn partition(v: &mut [BuildPrim], pred: impl Fn(Vec3A) -> bool) -> (usize, Aabb, Aabb) {
    let (mut left, mut right) = (Aabb::EMPTY, Aabb::EMPTY);
    let mut i = 0;
    for j in 0..v.len() {
        let c = v[j].centroid();
        let go = pred(c);
        let (l, r) = (left.grow(c), right.grow(c));
        let mask = glam::BVec3A::splat(go);
        left = Aabb { min: Vec3A::select(mask, l.min, left.min), max: Vec3A::select(mask, l.max, left.max) };
        right =
            Aabb { min: Vec3A::select(mask, right.min, r.min), max: Vec3A::select(mask, right.max, r.max) };
        let (a, b) = (v[i], v[j]);
        v[i] = b;
        v[j] = a;
        i += usize::from(go);
    }
    (i, left, right)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No centroid, however odd, leaves the bins; inside the range the bin
    /// is the floor of the scaled value.
    #[test]
    fn bin_indices_stay_in_range_and_floor() {
        let specials =
            [0.0, -0.0, 1e-30, 0.49999997, 0.5, 1.0, 3.5, 7.999, 8.0, 1e30, f32::INFINITY, f32::NAN];
        let mut values: Vec<f32> = specials.iter().flat_map(|&v| [v, -v]).collect();
        values.extend((0..2000).map(|i| (i as f32 * 0.013_7).sin() * 9.0));
        let (lo, scale) = (Vec3A::new(-1.0, 0.0, 2.0), Vec3A::new(0.5, 1.5, 3.0));
        for w in values.windows(3) {
            let c = Vec3A::new(w[0], w[1], w[2]);
            assert!(bin_indices::<4>(c, lo, scale).iter().all(|&b| b < 4), "{c:?}");
            assert!(bin_indices::<16>(c, lo, scale).iter().all(|&b| b < 16), "{c:?}");
        }
        for k in 0..8 {
            for f in [0.25, 0.75] {
                let c = Vec3A::splat(k as f32 + f);
                assert_eq!(bin_indices::<8>(c, Vec3A::ZERO, Vec3A::ONE), [k; 3]);
            }
        }
    }

    /// The partition sends left exactly the primitives binning counted in
    /// the bins up to the split, on every axis and split bin.
    #[test]
    fn partition_agrees_with_binning() {
        let prims: Vec<BuildPrim> = (0..500u32)
            .map(|i| {
                let f = i as f32;
                let c = Vec3A::new((f * 0.37).sin(), (f * 0.11).cos() * 3.0, (f * 0.05).fract());
                let r = 0.01 + (f * 0.7).sin().abs() * 0.1;
                BuildPrim::new(Aabb { min: c - Vec3A::splat(r), max: c + Vec3A::splat(r) }, i)
            })
            .collect();
        let boxes = boxes_of(&prims);
        let bins = bin_all::<16>(&prims, &boxes.centroids);
        let (lo, scale) = bin_frame::<16>(&boxes.centroids);
        for (axis, axis_bins) in bins.iter().enumerate() {
            for bin in 0..16 {
                let expect: u32 = axis_bins[..=bin].iter().map(|b| b.count).sum();
                let mut v = prims.clone();
                let (mid, _, _) = partition(&mut v, |c| bin_indices::<16>(c, lo, scale)[axis] <= bin);
                assert_eq!(mid as u32, expect, "axis {axis}, bin {bin}");
            }
        }
    }
}
