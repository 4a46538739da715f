//! The BVH's traversal form: the binary SAH tree collapsed into 4-wide
//! nodes whose four child boxes are tested at once with SIMD (glam's `Vec4`,
//! SSE on x86-64). Each node is 128 bytes: the boxes in struct-of-arrays
//! form, then the children.
//!
//! A child with `count == 0` is an interior node (its index in `nodes`);
//! otherwise it is a leaf holding `prims[child..child + count]`. Unused slots
//! have empty boxes (min = +inf, max = −inf), which the slab test never hits
//! because near and far planes are chosen by the sign of 1/d.

use super::build::BvhNode;
use crate::aabb::SLAB_WIDEN;
use crate::math::RayQuery;
use crate::packet::{Mask, RayPacket, LANES};
use crate::simd::vector::{group_active, group_bits, F32s};
use glam::Vec4;

/// A 4-wide node.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub struct Node4 {
    min: [Vec4; 3],
    max: [Vec4; 3],
    child: [u32; 4],
    count: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<Node4>() == 128);

/// Entries of the traversal stack: a node or a leaf, and its entry distance.
#[derive(Clone, Copy, Default)]
pub struct Entry {
    /// Node index, or first primitive of a leaf.
    pub child: u32,
    /// 0 for a node, else the leaf's primitive count.
    pub count: u32,
    /// Where the ray enters its box.
    pub t: f32,
}

/// Deep enough for any tree the builder makes (depth ≤ 64, three siblings
/// pushed per level); the per-thread stack is allocated once at this size.
pub const STACK: usize = 256;

impl Node4 {
    /// Collapse a binary tree (depth-first, first child at `i + 1`) into
    /// 4-wide nodes, depth first; node 0 is the root.
    pub fn collapse(bin: &[BvhNode]) -> Vec<Node4> {
        collapse(bin)
    }
}

fn collapse(bin: &[BvhNode]) -> Vec<Node4> {
    let mut out = Vec::with_capacity(bin.len() / 2 + 1);
    if bin.is_empty() {
        return out;
    }
    if bin[0].is_leaf() {
        out.push(node_from(&[0], bin));
        return out;
    }
    build(0, bin, &mut out);
    out
}

fn children(i: usize, bin: &[BvhNode]) -> [usize; 2] {
    [i + 1, bin[i].link as usize]
}

/// Emit the 4-wide node for binary interior node `i`; returns its index.
fn build(i: usize, bin: &[BvhNode], out: &mut Vec<Node4>) -> u32 {
    // Open the largest interior child until there are four (on the stack:
    // one node per 4-wide node, hundreds of thousands of them).
    let mut kids = [0usize; 4];
    kids[..2].copy_from_slice(&children(i, bin));
    let mut len = 2;
    while len < 4 {
        let open = (0..len)
            .filter(|&j| !bin[kids[j]].is_leaf())
            .max_by(|&a, &b| bin[kids[a]].bounds().half_area().total_cmp(&bin[kids[b]].bounds().half_area()));
        let Some(j) = open else { break };
        // The opened child's children take the last place and its own,
        // in the order a list removal and append would give.
        let [first, second] = children(kids[j], bin);
        kids.copy_within(j + 1..len, j);
        kids[len - 1] = first;
        kids[len] = second;
        len += 1;
    }
    let kids = &kids[..len];
    let index = out.len();
    out.push(node_from(&[], bin));
    let mut node = node_from(kids, bin);
    for (slot, &k) in kids.iter().enumerate() {
        if !bin[k].is_leaf() {
            node.child[slot] = build(k, bin, out);
        }
    }
    out[index] = node;
    index as u32
}

fn node_from(kids: &[usize], bin: &[BvhNode]) -> Node4 {
    let mut min = [[f32::INFINITY; 4]; 3];
    let mut max = [[f32::NEG_INFINITY; 4]; 3];
    let mut child = [0u32; 4];
    let mut count = [0u32; 4];
    for (slot, &k) in kids.iter().enumerate() {
        let b = bin[k].bounds();
        for a in 0..3 {
            min[a][slot] = b.min[a];
            max[a][slot] = b.max[a];
        }
        if bin[k].is_leaf() {
            child[slot] = bin[k].link;
            count[slot] = bin[k].count;
        }
    }
    Node4 { min: min.map(Vec4::from_array), max: max.map(Vec4::from_array), child, count }
}

impl Node4 {
    /// Entry distances of the ray into the four child boxes within
    /// `(t_min, t_max)`, and the mask of boxes hit. The same conservative
    /// slab test as [`Aabb::hit`], four boxes at a time.
    #[inline(always)]
    pub fn hit(&self, r: &Ray4, t_max: f32) -> (Vec4, u32) {
        let (nx, fx) = if r.neg[0] { (self.max[0], self.min[0]) } else { (self.min[0], self.max[0]) };
        let (ny, fy) = if r.neg[1] { (self.max[1], self.min[1]) } else { (self.min[1], self.max[1]) };
        let (nz, fz) = if r.neg[2] { (self.max[2], self.min[2]) } else { (self.min[2], self.max[2]) };
        let t_near = ((nx - r.o[0]) * r.inv[0])
            .max((ny - r.o[1]) * r.inv[1])
            .max((nz - r.o[2]) * r.inv[2])
            .max(r.t_min);
        let t_far = (((fx - r.o[0]) * r.inv[0]).min((fy - r.o[1]) * r.inv[1]).min((fz - r.o[2]) * r.inv[2])
            * SLAB_WIDEN)
            .min(Vec4::splat(t_max));
        let mask = t_near.cmple(t_far).bitmask();
        (t_near, mask)
    }

    /// The packet form of [`Node4::hit`], with vectors `V`: per child
    /// slot, the lanes of `mask` whose rays enter the box before their
    /// `far` distance, and the nearest entry among them (infinity when
    /// none). Near and far planes come from min and max of the two slab
    /// distances, which for the non-empty boxes tested equals choosing them
    /// by the sign of 1/d.
    ///
    /// With `NEAREST` false (shadow rays, which need no order), the entry
    /// distances are not gathered and come back infinite.
    #[inline(always)]
    pub fn hit_packet<V: F32s, const NEAREST: bool>(
        &self,
        p: &RayPacket,
        far: &[f32; LANES],
        mask: Mask,
    ) -> ([Mask; 4], [f32; 4]) {
        let mut masks = [0; 4];
        let mut nearest = [f32::INFINITY; 4];
        let inf = V::splat(f32::INFINITY);
        for slot in 0..4 {
            let lo = [self.min[0][slot], self.min[1][slot], self.min[2][slot]];
            let hi = [self.max[0][slot], self.max[1][slot], self.max[2][slot]];
            if lo[0].partial_cmp(&hi[0]).is_none_or(|o| o.is_gt()) {
                continue; // an unused slot
            }
            let mut m: Mask = 0;
            let mut near_min = inf;
            for g in 0..LANES / V::W {
                if !group_active::<V>(mask, g) {
                    continue;
                }
                let mut t_near = V::load(&p.t_min.0, g);
                let mut t_far = inf;
                for a in 0..3 {
                    let (o, inv) = (V::load(&p.o[a].0, g), V::load(&p.inv[a].0, g));
                    let t0 = V::splat(lo[a]).sub(o).mul(inv);
                    let t1 = V::splat(hi[a]).sub(o).mul(inv);
                    t_near = t_near.max(t0.min(t1));
                    t_far = t_far.min(t0.max(t1));
                }
                let t_far = t_far.mul(V::splat(SLAB_WIDEN)).min(V::load(far, g));
                let hit = t_near.le(t_far);
                m |= group_bits::<V>(hit, g);
                if NEAREST {
                    near_min = near_min.min(V::select(hit, t_near, inf));
                }
            }
            masks[slot] = m & mask;
            if NEAREST && masks[slot] != 0 {
                nearest[slot] = near_min.hmin();
            }
        }
        (masks, nearest)
    }

    /// Child `slot` as a stack entry.
    #[inline(always)]
    pub fn entry(&self, slot: usize, t: f32) -> Entry {
        Entry { child: self.child[slot], count: self.count[slot], t }
    }
}

/// A ray splatted for 4-wide box tests.
pub struct Ray4 {
    o: [Vec4; 3],
    inv: [Vec4; 3],
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
            neg: q.neg,
            t_min: Vec4::splat(q.t_min),
        }
    }
}
