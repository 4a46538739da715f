//! The binned surface-area heuristic that shapes the BVH: 4 to 16 bins by
//! node size, all three axes binned in one pass (in parallel near the
//! root). It decides the binary tree one node at a time ([`Binary`]) and
//! stores none of it: [`super::wide`] opens binary nodes straight into its
//! 4-wide nodes, so no binary node array is written, copied and collapsed
//! (a large scene's peak memory is the smaller for it).
//!
//! A node's primitives are a range of the [`BuildPrim`] array; splitting
//! it partitions that range in place (in parallel near the root too), so
//! the leaves end up as ranges, and the array's order is the primitive
//! order leaves index.

use super::presplit::Presplit;
use crate::aabb::Aabb;
use crate::geometry::{Geometry, Kind};
use crate::simd::vector::prefetch;
use glam::{BVec4A, Vec3A, Vec4};
use rayon::prelude::*;

const _: () = assert!(std::mem::size_of::<BuildPrim>() == 32);

/// Deepest tree the traversal stack can hold; the builder makes leaves there.
const MAX_DEPTH: usize = 64;
/// Most bins per axis for the SAH (large nodes).
const BINS: usize = 16;
/// Fewest bins per axis (small nodes).
const MIN_BINS: usize = 4;

/// Bins for a node of `n` primitives: 4 below 16, 8 below 128, else 16.
/// A small node gains little from more bins (lowering these counts moved
/// the SPD scenes' SAH costs by 2.4% at most, rings_s1's), and a large
/// scene has hundreds of thousands of small nodes, each setting up and
/// sweeping its bins ([`split_with`] is compiled for each count).
#[inline]
fn bin_count(n: usize) -> usize {
    match n {
        ..16 => MIN_BINS,
        16..128 => 8,
        _ => BINS,
    }
}
/// Leaves never hold more than this unless the primitives cannot be split;
/// ranges this small are never split (see [`sah_split`]).
const MAX_LEAF: usize = 4;

/// A primitive's box and its id: 32 bytes, two aligned vectors, the
/// first's fourth lane carrying the id, so that reading a box is
/// two aligned loads and a mask (not six scalar loads and shuffles), and
/// moving one is two aligned 16-byte copies (the partition swaps one per
/// primitive per level, and unaligned copies defeat store forwarding).
#[derive(Clone, Copy)]
#[repr(C, align(16))]
pub(super) struct BuildPrim {
    /// Box minimum; the fourth lane holds the id's bits.
    min: Vec4,
    /// Box maximum; the fourth lane holds 0.
    max: Vec4,
}

/// The first three lanes of a [`BuildPrim`] vector, the fourth cleared (an
/// id's bits read as a float may be subnormal, and arithmetic on
/// subnormals is slow).
#[inline(always)]
fn xyz(v: Vec4) -> Vec3A {
    const XYZ: BVec4A = BVec4A::new(true, true, true, false);
    Vec3A::from_vec4(Vec4::select(XYZ, v, Vec4::ZERO))
}

impl BuildPrim {
    #[inline(always)]
    fn new(bounds: Aabb, id: u32) -> BuildPrim {
        BuildPrim { min: bounds.min.extend(f32::from_bits(id)), max: bounds.max.extend(0.0) }
    }

    #[inline(always)]
    pub(super) fn id(&self) -> u32 {
        self.min.w.to_bits()
    }

    #[inline(always)]
    pub(super) fn bounds(&self) -> Aabb {
        Aabb { min: xyz(self.min), max: xyz(self.max) }
    }

    /// Twice the centre of the box: binning only compares centroids, so
    /// the halving is left out.
    #[inline(always)]
    fn centroid(&self) -> Vec3A {
        xyz(self.min) + xyz(self.max)
    }
}

/// Every bounded primitive of `geom`, in id order: the build's
/// references, several for a triangle [`Presplit`] cuts.
pub(super) fn build_prims(geom: &Geometry) -> Vec<BuildPrim> {
    match Presplit::plan(geom) {
        None => (0..geom.bounded_len() as u32)
            .into_par_iter()
            .map(|id| BuildPrim::new(geom.bounds(id), id))
            .collect(),
        Some(plan) => references(geom, &plan),
    }
}

/// [`build_prims`] with triangles as the pieces `plan` cuts them into, each
/// a reference to its triangle's id: every primitive in id order (a cut
/// triangle as its first piece), written in place on all cores, then the
/// cut triangles' other pieces.
fn references(geom: &Geometry, plan: &Presplit) -> Vec<BuildPrim> {
    let first = |id: u32| match geom.locate(id) {
        (Kind::Triangle, i) if plan.is_cut(i) => {
            plan.pieces(geom, i, 0).next().unwrap_or_else(|| geom.bounds(id))
        }
        _ => geom.bounds(id),
    };
    let mut prims = Vec::with_capacity(plan.references);
    prims.par_extend((0..geom.bounded_len() as u32).into_par_iter().map(|id| BuildPrim::new(first(id), id)));
    let tri = geom.first_id(Kind::Triangle);
    prims.par_extend(
        plan.cut().flat_map_iter(|i| plan.pieces(geom, i, 1).map(move |b| BuildPrim::new(b, tri + i as u32))),
    );
    prims
}

/// Write the ids of a leaf's primitives to its slots of the id array.
#[inline]
pub(super) fn write_ids(prims: &[BuildPrim], ids: &mut [u32]) {
    for (id, p) in ids.iter_mut().zip(prims) {
        *id = p.id();
    }
}

/// A range's box and the box of its primitives' centroids (doubled, as
/// [`BuildPrim::centroid`] gives them).
#[derive(Clone, Copy)]
struct Boxes {
    bounds: Aabb,
    centroids: Aabb,
}

/// `NB` bins per axis: each bin's box and primitive count, the boxes and
/// the counts in arrays apart (a box is then 32 bytes, found by a shift).
#[derive(Clone, Copy)]
struct Bins<const NB: usize> {
    bounds: [[Aabb; NB]; 3],
    counts: [[u32; NB]; 3],
}

/// A node of the binary SAH tree: its primitives `start..end` (positions
/// in the slice it was made from), its depth and its boxes. It is split
/// only when asked ([`Binary::split`]), so a node is a few vectors, not
/// its children's boxes too: the 4-wide builder moves its nodes about.
#[derive(Clone, Copy)]
pub(super) struct Binary {
    /// First primitive.
    pub start: usize,
    /// One past the last primitive.
    pub end: usize,
    depth: usize,
    boxes: Boxes,
}

impl Binary {
    /// The root over all of `prims`.
    pub fn root(prims: &[BuildPrim]) -> Binary {
        Binary { start: 0, end: prims.len(), depth: 0, boxes: boxes_of(prims) }
    }

    /// The node's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.boxes.bounds
    }

    /// Number of primitives.
    #[inline]
    pub fn len(&self) -> usize {
        self.end - self.start
    }

    /// The same node counted from `base` in the slice: for handing its
    /// range to another thread as a slice of its own.
    pub fn rebased(self, base: usize) -> Binary {
        Binary { start: self.start - base, end: self.end - base, ..self }
    }

    /// The node's two children, its range partitioned between them by the
    /// cheapest split; `None` for a leaf (its primitives are tested one by
    /// one). Splitting a range only reorders that range, so the order in
    /// which nodes are split does not change the tree.
    #[inline]
    pub fn split(&self, prims: &mut [BuildPrim]) -> Option<[Binary; 2]> {
        if self.depth + 1 >= MAX_DEPTH {
            return None;
        }
        let split = sah_split(&mut prims[self.start..self.end], &self.boxes)?;
        let (mid, depth) = (self.start + split.mid, self.depth + 1);
        Some([
            Binary { start: self.start, end: mid, depth, boxes: split.left },
            Binary { start: mid, end: self.end, depth, boxes: split.right },
        ])
    }
}

/// A range split in two: the size of the left part and both parts' boxes.
#[derive(Clone, Copy)]
struct Split {
    mid: usize,
    left: Boxes,
    right: Boxes,
}

/// Partition `prims` by the cheapest binned SAH split; `None` for at most
/// [`MAX_LEAF`] primitives, or when nothing can be split. So few stay one
/// leaf whatever the SAH says: its cost model (a box step costs what a
/// primitive test does) splits almost every such group, for no faster
/// render and a slower build; a single ray tests a leaf of spheres one by
/// one, cheaply, and one of triangles all at once (`tri_block`). The
/// parts' boxes come from the split
/// itself: their bounds are unions of bins, their centroid bounds are
/// gathered by the partition, so no level reads its primitives twice.
fn sah_split(prims: &mut [BuildPrim], boxes: &Boxes) -> Option<Split> {
    let n = prims.len();
    if n <= MAX_LEAF {
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
    let mut all_bins = empty_bins::<NB>();
    bin_all::<NB>(prims, cb, &mut all_bins);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let (bounds, counts) = (&all_bins.bounds[axis], &all_bins.counts[axis]);
        // Sweep from the right to get right-side boxes and counts.
        let mut right_box = [Aabb::EMPTY; NB];
        let mut right_count = [0u32; NB];
        let (mut rb, mut rc) = (Aabb::EMPTY, 0);
        for i in (1..NB).rev() {
            rb = rb.union(bounds[i]);
            rc += counts[i];
            right_box[i] = rb;
            right_count[i] = rc;
        }
        let (mut lb, mut lc) = (Aabb::EMPTY, 0);
        for i in 0..NB - 1 {
            lb = lb.union(bounds[i]);
            lc += counts[i];
            if lc == 0 || right_count[i + 1] == 0 {
                continue;
            }
            let cost = lc as f32 * lb.half_area() + right_count[i + 1] as f32 * right_box[i + 1].half_area();
            if best.as_ref().is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, i, lb, right_box[i + 1]));
            }
        }
    }
    // (Only ranges past MAX_LEAF get here: the SAH picks where to split
    // them, not whether.)
    let (_, axis, bin, left_bounds, right_bounds) = best?;
    let (mid, left_centroids, right_centroids) = partition::<NB>(prims, cb, axis, bin);
    (mid > 0 && mid < n).then_some(Split {
        mid,
        left: Boxes { bounds: left_bounds, centroids: left_centroids },
        right: Boxes { bounds: right_bounds, centroids: right_centroids },
    })
}

/// 2^23: adding it to a float in [0, 2^23) leaves the float's value,
/// rounded to an integer, in the low bits of its representation (the
/// representation of 2^23 itself has them all zero).
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
/// partitioning both use [`rounded_bins`] and [`bin_of`], so they always
/// agree). Clamped in floating point and turned into integers by
/// [`ROUNDER`]: a few vector instructions, not three saturating casts and
/// clamps.
#[inline(always)]
fn bin_indices<const NB: usize>(c: Vec3A, lo: Vec3A, scale: Vec3A) -> [usize; 3] {
    rounded_bins::<NB>(c, lo, scale).to_array().map(bin_of::<NB>)
}

/// The bin a [`rounded_bins`] lane names: its low bits (`NB` is a power of
/// two). Whatever the lane holds, NaN included, the bin is in range.
#[inline(always)]
fn bin_of<const NB: usize>(rounded: f32) -> usize {
    const { assert!(NB.is_power_of_two() && ROUNDER.to_bits() as usize & (NB - 1) == 0) };
    rounded.to_bits() as usize & (NB - 1)
}

/// [`ROUNDER`] plus the bins of a centroid on all three axes: whole numbers
/// from 2^23 to 2^23 + NB − 1 (or NaN, where `max` keeps a NaN).
#[inline(always)]
fn rounded_bins<const NB: usize>(c: Vec3A, lo: Vec3A, scale: Vec3A) -> Vec3A {
    let t = ((c - lo) * scale - Vec3A::splat(0.5)).max(Vec3A::ZERO).min(Vec3A::splat(NB as f32 - 1.0));
    t + Vec3A::splat(ROUNDER)
}

/// Ranges larger than this are binned and partitioned on all cores.
pub(super) const PARALLEL_SPLIT: usize = 1 << 15;
/// The blocks a parallel split cuts its range into. A fixed size, so the
/// order a parallel partition leaves does not depend on the thread count.
const SPLIT_BLOCK: usize = 1 << 13;
/// Ranges at least this large are binned into two sets of bins, the even
/// and the odd primitives apart, then merged (see [`bin_all`]).
const TWO_BIN_SETS: usize = 128;
/// How far ahead of the pair being binned [`bin_all`] prefetches, in bytes
/// (32 primitives).
const PREFETCH_AHEAD: usize = 1024;

/// Bin the primitives' centroids along all three axes in one pass, into
/// `NB` bins per axis: `bins`, empty on entry, filled in place (returned,
/// they would be copied, and the sweep's loads would wait on the copy).
fn bin_all<const NB: usize>(prims: &[BuildPrim], cb: &Aabb, bins: &mut Bins<NB>) {
    let (lo, scale) = bin_frame::<NB>(cb);
    let fill = |chunk: &[BuildPrim], bins: &mut Bins<NB>| {
        if chunk.len() < TWO_BIN_SETS {
            for p in chunk {
                add_to_bins(bins, p, lo, scale);
            }
            return;
        }
        // Neighbours in the array are neighbours in space and mostly fall
        // into the same bins: in one set, each would wait for the last
        // one's box to be stored. Two sets halve those chains; the merge
        // is exact. Ranges this large may not be in the nearest caches:
        // the primitives a few pairs on are asked for early.
        let mut odd = empty_bins::<NB>();
        let pairs = chunk.chunks_exact(2);
        if let [p] = pairs.remainder() {
            add_to_bins(bins, p, lo, scale);
        }
        for pair in pairs {
            prefetch(pair, PREFETCH_AHEAD);
            add_to_bins(bins, &pair[0], lo, scale);
            add_to_bins(&mut odd, &pair[1], lo, scale);
        }
        merge_bins(bins, &odd);
    };
    if prims.len() > PARALLEL_SPLIT {
        // Large nodes near the root: bin on all cores. The merge is exact
        // (unions and counts), so the tree does not depend on thread count.
        *bins = prims
            .par_chunks(SPLIT_BLOCK)
            .map(|chunk| {
                let mut bins = empty_bins();
                fill(chunk, &mut bins);
                bins
            })
            .reduce(empty_bins, |mut a, b| {
                merge_bins(&mut a, &b);
                a
            });
    } else {
        fill(prims, bins);
    }
}

/// `NB` empty bins per axis. The infinity goes through `black_box` so that
/// the compiler stores each bin in place: from a constant, it copies a
/// constant array with stores wider than the bins' loads, which then stall
/// on store forwarding.
#[inline(always)]
fn empty_bins<const NB: usize>() -> Bins<NB> {
    let inf = std::hint::black_box(f32::INFINITY);
    Bins { bounds: [[Aabb { min: Vec3A::splat(inf), max: Vec3A::splat(-inf) }; NB]; 3], counts: [[0; NB]; 3] }
}

/// Count `p` in its bin on each axis.
#[inline(always)]
fn add_to_bins<const NB: usize>(bins: &mut Bins<NB>, p: &BuildPrim, lo: Vec3A, scale: Vec3A) {
    let bounds = p.bounds();
    let index = bin_indices::<NB>(p.centroid(), lo, scale);
    for (axis, i) in index.into_iter().enumerate() {
        let b = &mut bins.bounds[axis][i];
        *b = b.union(bounds);
        bins.counts[axis][i] += 1;
    }
}

/// Add `more`'s primitives to `bins`.
#[inline(always)]
fn merge_bins<const NB: usize>(bins: &mut Bins<NB>, more: &Bins<NB>) {
    for (aa, ba) in bins.bounds.iter_mut().flatten().zip(more.bounds.iter().flatten()) {
        *aa = aa.union(*ba);
    }
    for (aa, ba) in bins.counts.iter_mut().flatten().zip(more.counts.iter().flatten()) {
        *aa += ba;
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

/// In-place partition: the primitives whose centroid's bin on `axis` is at
/// most `bin` (`bin < NB − 1`) first. Returns their number and the centroid
/// bounds of both parts.
fn partition<const NB: usize>(
    v: &mut [BuildPrim],
    cb: &Aabb,
    axis: usize,
    bin: usize,
) -> (usize, Aabb, Aabb) {
    match axis {
        0 => partition_on::<NB, 0>(v, cb, bin),
        1 => partition_on::<NB, 1>(v, cb, bin),
        _ => partition_on::<NB, 2>(v, cb, bin),
    }
}

/// [`partition`] on axis `AXIS`. The parts' centroid boxes are gathered
/// after the primitives are moved.
#[inline(always)]
fn partition_on<const NB: usize, const AXIS: usize>(
    v: &mut [BuildPrim],
    cb: &Aabb,
    bin: usize,
) -> (usize, Aabb, Aabb) {
    let (lo, scale) = bin_frame::<NB>(cb);
    if v.len() > PARALLEL_SPLIT {
        return partition_in_blocks::<NB, AXIS>(v, lo, scale, bin);
    }
    let mid = partition_block::<NB, AXIS>(v, lo, scale, bin);
    (mid, centroid_bounds(&v[..mid]), centroid_bounds(&v[mid..]))
}

/// [`partition_on`] for a large range, on all cores: block by block, then
/// the primitives left on the wrong side of the split (the right-going
/// ones of blocks before it, the left-going ones of blocks after it) are
/// swapped pairwise, each moved once.
fn partition_in_blocks<const NB: usize, const AXIS: usize>(
    v: &mut [BuildPrim],
    lo: Vec3A,
    scale: Vec3A,
    bin: usize,
) -> (usize, Aabb, Aabb) {
    let lefts: Vec<usize> =
        v.par_chunks_mut(SPLIT_BLOCK).map(|b| partition_block::<NB, AXIS>(b, lo, scale, bin)).collect();
    let (n, mid) = (v.len(), lefts.iter().sum());
    let block_start = |k: usize| k * SPLIT_BLOCK;
    let wrong_right = lefts.iter().enumerate().flat_map(|(k, &l)| {
        let end = (block_start(k) + SPLIT_BLOCK).min(n);
        block_start(k) + l..end.min(mid)
    });
    let wrong_left = lefts.iter().enumerate().flat_map(|(k, &l)| block_start(k).max(mid)..block_start(k) + l);
    let (front, back) = v.split_at_mut(mid);
    for (i, j) in wrong_right.zip(wrong_left) {
        std::mem::swap(&mut front[i], &mut back[j - mid]);
    }
    let bounds = |part: &[BuildPrim]| {
        part.par_chunks(SPLIT_BLOCK).map(centroid_bounds).reduce(|| Aabb::EMPTY, Aabb::union)
    };
    (mid, bounds(&v[..mid]), bounds(&v[mid..]))
}

/// Partition `v` in place, the primitives whose centroid's bin on `AXIS`
/// (as [`bin_indices`] gives it) is at most `bin` first; their number.
/// Branch-free (every element is swapped, the count advances by the
/// comparison): the comparison is a coin toss for a good split, which a
/// branch would mispredict half the time.
#[inline(always)]
fn partition_block<const NB: usize, const AXIS: usize>(
    v: &mut [BuildPrim],
    lo: Vec3A,
    scale: Vec3A,
    bin: usize,
) -> usize {
    let mut i = 0;
    for j in 0..v.len() {
        let go = bin_of::<NB>(rounded_bins::<NB>(v[j].centroid(), lo, scale)[AXIS]) <= bin;
        v.swap(i, j);
        i += usize::from(go);
    }
    i
}

/// The box of the primitives' centroids, gathered four at a time.
fn centroid_bounds(prims: &[BuildPrim]) -> Aabb {
    let mut acc = [Aabb::EMPTY; 4];
    let quads = prims.chunks_exact(4);
    for (a, p) in acc.iter_mut().zip(quads.remainder()) {
        *a = a.grow(p.centroid());
    }
    for q in quads {
        for (a, p) in acc.iter_mut().zip(q) {
            *a = a.grow(p.centroid());
        }
    }
    acc[0].union(acc[1]).union(acc[2].union(acc[3]))
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

    /// Up to four primitives stay one leaf even where the SAH would split
    /// them; five are split.
    #[test]
    fn small_groups_stay_leaves() {
        let group = |n: usize| -> Vec<BuildPrim> {
            (0..n)
                .map(|i| {
                    let c = Vec3A::new(i as f32 * 10.0, 0.0, 0.0);
                    BuildPrim::new(Aabb { min: c - Vec3A::ONE, max: c + Vec3A::ONE }, i as u32)
                })
                .collect()
        };
        for n in 1..=MAX_LEAF {
            assert!(sah_split(&mut group(n), &boxes_of(&group(n))).is_none(), "{n} primitives");
        }
        let five = group(MAX_LEAF + 1);
        assert!(sah_split(&mut five.clone(), &boxes_of(&five)).is_some(), "more than a leaf holds");
    }

    /// Each bin holds the count and box of its primitives (both ranges are
    /// binned in two sets of bins, the large one block by block), and the
    /// partition sends left exactly the primitives binning counted in
    /// the bins up to the split, on every axis and split bin, keeps every
    /// primitive, and gives each part the box of its own centroids: on a
    /// small range, and on one large enough to be partitioned block by
    /// block (half of it in runs, half scattered, so primitives end up on
    /// the wrong side of the split both ways).
    #[test]
    fn partition_agrees_with_binning() {
        let prim = |i: u32, f: f32| {
            let c = Vec3A::new((f * 0.37).sin(), (f * 0.11).cos() * 3.0, (f * 0.05).fract());
            let r = 0.01 + (f * 0.7).sin().abs() * 0.1;
            BuildPrim::new(Aabb { min: c - Vec3A::splat(r), max: c + Vec3A::splat(r) }, i)
        };
        let small: Vec<BuildPrim> = (0..500).map(|i| prim(i, i as f32)).collect();
        let n = PARALLEL_SPLIT as u32 * 3 / 2;
        let large: Vec<BuildPrim> = (0..n)
            .map(|i| {
                prim(
                    i,
                    if i < n / 2 { i as f32 * 1e-4 } else { (i.wrapping_mul(2_654_435_761) % 9973) as f32 },
                )
            })
            .collect();
        for prims in [small, large] {
            let boxes = boxes_of(&prims);
            let mut bins = empty_bins::<16>();
            bin_all::<16>(&prims, &boxes.centroids, &mut bins);
            let (lo, scale) = bin_frame::<16>(&boxes.centroids);
            for (axis, counts) in bins.counts.iter().enumerate() {
                for bin in 0..16 {
                    let members =
                        prims.iter().filter(|p| bin_indices::<16>(p.centroid(), lo, scale)[axis] == bin);
                    let (count, bounds) =
                        members.fold((0, Aabb::EMPTY), |(n, b), p| (n + 1, b.union(p.bounds())));
                    assert_eq!(
                        (counts[bin], bins.bounds[axis][bin]),
                        (count, bounds),
                        "axis {axis}, bin {bin}"
                    );
                    let expect: u32 = counts[..=bin].iter().sum();
                    let mut v = prims.clone();
                    let (mid, left, right) = partition::<16>(&mut v, &boxes.centroids, axis, bin);
                    assert_eq!(mid as u32, expect, "axis {axis}, bin {bin}");
                    let mut ids: Vec<u32> = v.iter().map(BuildPrim::id).collect();
                    ids.sort_unstable();
                    assert!(ids.iter().copied().eq(0..prims.len() as u32), "a permutation");
                    let side = |p: &BuildPrim| bin_indices::<16>(p.centroid(), lo, scale)[axis] <= bin;
                    assert!(
                        v[..mid].iter().all(side) && !v[mid..].iter().any(side),
                        "axis {axis}, bin {bin}"
                    );
                    let centroids =
                        |part: &[BuildPrim]| part.iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid()));
                    assert_eq!(
                        (left, right),
                        (centroids(&v[..mid]), centroids(&v[mid..])),
                        "axis {axis}, bin {bin}"
                    );
                }
            }
        }
    }
}
