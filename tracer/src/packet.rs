//! Ray packets: up to [`LANES`] coherent rays (the samples of one pixel, or
//! a block of neighbouring pixel centres) traced together, stored as
//! structure of arrays so one vector instruction serves every lane.
//!
//! The lane-wise primitive tests here repeat the single-ray tests of
//! [`crate::geometry`] operation for operation (the same products and sums
//! in the same order), so a lane finds bit for bit the hit its ray finds
//! alone, and the tie rule (nearest, then lowest id) is the same. Where the
//! single-ray test takes a rare slow path (the triangle test's
//! double-precision edge case) the lane falls back to it.

use crate::geometry::{Cull, Geometry, Hit, Kind, Sphere, Triangle};
use crate::math::{Ray, RayQuery};
use crate::simd::vector::{group_active, group_bits, F32s};
use crate::stats::Counters;

/// Rays in a packet: 16, one AVX-512 register of f32 (two AVX2 ones).
pub const LANES: usize = 16;

/// One bit per lane (bit `i`: lane `i`).
pub type Mask = u32;

/// "No primitive" in [`PacketHits::prim`] and occluder lists.
pub const NO_PRIM: u32 = u32::MAX;

/// Per-lane f32 values, aligned for vector loads.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct Lanes(pub [f32; LANES]);

/// Lane `i` of three per-axis lane arrays, as a vector.
#[inline(always)]
pub fn lane(v: &[Lanes; 3], i: usize) -> glam::Vec3A {
    glam::Vec3A::new(v[0].0[i], v[1].0[i], v[2].0[i])
}

/// Set lane `i` of three per-axis lane arrays to `x`.
#[inline(always)]
pub fn set_lane(v: &mut [Lanes; 3], i: usize, x: glam::Vec3A) {
    for a in 0..3 {
        v[a].0[i] = x[a];
    }
}

/// Up to [`LANES`] rays with the per-ray constants of [`RayQuery`], in
/// structure-of-arrays form.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub struct RayPacket {
    /// Origins, per axis.
    pub o: [Lanes; 3],
    /// Unit directions, per axis.
    pub d: [Lanes; 3],
    /// Clamped 1/d, per axis (see [`RayQuery::inv_d`]).
    pub inv: [Lanes; 3],
    /// Shear constants of the watertight triangle test (Sx, Sy, Sz).
    pub shear: [Lanes; 3],
    /// Smallest accepted distance.
    pub t_min: Lanes,
    /// Largest accepted distance (infinity for eye rays, the light's
    /// distance for shadow rays).
    pub t_max: Lanes,
    /// Per axis, the lanes whose 1/d is negative.
    pub neg: [Mask; 3],
    /// The lanes holding a ray.
    pub active: Mask,
    /// The triangle test's axis permutation when every active lane shares
    /// it (then triangles are tested lane-wise), else `None`.
    pub shared_k: Option<[usize; 3]>,
    /// Each lane's axis permutation of the triangle test (see
    /// [`RayQuery::k`]), for rebuilding its query.
    pub k: [[u8; 3]; LANES],
}

impl RayPacket {
    /// A packet of `rays`, each `(ray, t_min, t_max)`; at most [`LANES`].
    pub fn new(rays: impl IntoIterator<Item = (Ray, f32, f32)>) -> RayPacket {
        let mut p = RayPacket {
            o: [Lanes([0.0; LANES]); 3],
            d: [Lanes([0.0; LANES]); 3],
            inv: [Lanes([0.0; LANES]); 3],
            shear: [Lanes([0.0; LANES]); 3],
            t_min: Lanes([0.0; LANES]),
            t_max: Lanes([f32::NEG_INFINITY; LANES]),
            neg: [0; 3],
            active: 0,
            shared_k: None,
            k: [[0; 3]; LANES],
        };
        let mut mask = 0;
        for (i, (ray, t_min, t_max)) in rays.into_iter().enumerate().take(LANES) {
            set_lane(&mut p.o, i, ray.o);
            set_lane(&mut p.d, i, ray.d);
            p.t_min.0[i] = t_min;
            p.t_max.0[i] = t_max;
            mask |= 1 << i;
        }
        if mask != 0 {
            ray_constants(crate::simd::isa(), &mut p, mask);
        }
        p
    }

    /// Put query `q` with far limit `t_max` in lane `i`.
    pub fn set(&mut self, i: usize, q: RayQuery, t_max: f32) {
        set_lane(&mut self.o, i, q.ray.o);
        set_lane(&mut self.d, i, q.ray.d);
        set_lane(&mut self.inv, i, q.inv_d);
        set_lane(&mut self.shear, i, q.shear);
        for a in 0..3 {
            let bit = 1 << i;
            self.neg[a] = if q.neg[a] { self.neg[a] | bit } else { self.neg[a] & !bit };
        }
        self.t_min.0[i] = q.t_min;
        self.t_max.0[i] = t_max;
        self.k[i] = q.k.map(|a| a as u8);
        self.activate(self.active | 1 << i);
    }

    /// Lane `i`'s ray as a single-ray query (for the shapes and cases
    /// without a lane-wise test), rebuilt from the lanes bit for bit.
    #[inline(always)]
    pub fn query(&self, i: usize) -> RayQuery {
        RayQuery {
            ray: Ray { o: lane(&self.o, i), d: lane(&self.d, i) },
            inv_d: lane(&self.inv, i),
            neg: [0, 1, 2].map(|a| self.neg[a] >> i & 1 != 0),
            k: self.k[i].map(usize::from),
            shear: lane(&self.shear, i),
            t_min: self.t_min.0[i],
        }
    }

    /// Empty every lane, for reuse (the lanes' old values stay, unread:
    /// every kernel looks only at active lanes' results).
    pub fn clear(&mut self) {
        self.active = 0;
        self.neg = [0; 3];
        self.shared_k = None;
    }

    /// Make the lanes of `mask` the active ones, their values already in
    /// place (see [`crate::shadow_lanes`]).
    pub fn activate(&mut self, mask: Mask) {
        self.active = mask;
        let mut lanes = (0..LANES).filter(|i| mask >> i & 1 != 0).map(|i| self.k[i]);
        let first = lanes.next();
        self.shared_k = first.filter(|k| lanes.all(|o| o == *k)).map(|k| k.map(usize::from));
    }

    /// Number of lanes in use (highest active lane + 1).
    pub fn len(&self) -> usize {
        (Mask::BITS - self.active.leading_zeros()) as usize
    }

    /// True when no lane holds a ray.
    pub fn is_empty(&self) -> bool {
        self.active == 0
    }
}

/// The per-ray constants of [`RayQuery::new`] computed lane-wise, bit for
/// bit: 1/d clamped, its signs, and the watertight triangle test's axis
/// permutation and shear. Gathered per vector group by [`Permutations::add`]
/// (which also stores 1/d, its signs and the shear), then written per lane by
/// [`Permutations::finish`].
#[derive(Default)]
pub(crate) struct Permutations {
    x_major: Mask,
    y_major: Mask,
    negative: Mask,
}

impl Permutations {
    /// Compute group `g`'s constants from its directions `d` into `out`.
    #[inline(always)]
    pub(crate) fn add<V: F32s>(&mut self, out: &mut RayPacket, d: [V; 3], g: usize) {
        let zero = V::splat(0.0);
        for (a, &da) in d.iter().enumerate() {
            let inv = V::splat(1.0).div(da).max(V::splat(-1e30)).min(V::splat(1e30));
            inv.store(&mut out.inv[a].0, g);
            out.neg[a] |= group_bits::<V>(inv.lt(zero), g);
        }
        let abs = [d[0].copysign(zero), d[1].copysign(zero), d[2].copysign(zero)];
        let x_major = V::and(abs[1].le(abs[0]), abs[2].le(abs[0]));
        let y_major = V::andnot(x_major, abs[2].le(abs[1]));
        let dz = V::select(x_major, d[0], V::select(y_major, d[1], d[2]));
        let neg = dz.lt(zero);
        let dx = pick(x_major, y_major, neg, [d[1], d[2]], [d[2], d[0]], [d[0], d[1]]);
        let dy = pick(x_major, y_major, neg, [d[2], d[1]], [d[0], d[2]], [d[1], d[0]]);
        dx.div(dz).store(&mut out.shear[0].0, g);
        dy.div(dz).store(&mut out.shear[1].0, g);
        V::splat(1.0).div(dz).store(&mut out.shear[2].0, g);
        self.x_major |= group_bits::<V>(x_major, g);
        self.y_major |= group_bits::<V>(y_major, g);
        self.negative |= group_bits::<V>(neg, g);
    }

    /// Write each lane's permutation (`[kx, ky, kz]` of `RayQuery::new`).
    pub(crate) fn finish(&self, out: &mut RayPacket) {
        for i in 0..LANES {
            let bit = |m: Mask| m >> i & 1 != 0;
            let kz: u8 = if bit(self.x_major) {
                0
            } else if bit(self.y_major) {
                1
            } else {
                2
            };
            let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
            out.k[i] = if bit(self.negative) { [ky, kx, kz] } else { [kx, ky, kz] };
        }
    }
}

/// The lane's value of `d` along its (x, y) shear axes: by the major axis
/// (`x_major`, `y_major`, else z) and the sign along it (`neg`), as the
/// table of `RayQuery::new`. (A function, not a closure: closures are
/// compiled without the kernel's instruction set.)
#[inline(always)]
fn pick<V: F32s>(x_major: V::M, y_major: V::M, neg: V::M, x: [V; 2], y: [V; 2], z: [V; 2]) -> V {
    let (x, y, z) = (V::select(neg, x[1], x[0]), V::select(neg, y[1], y[0]), V::select(neg, z[1], z[0]));
    V::select(x_major, x, V::select(y_major, y, z))
}

crate::dispatch! {
    /// Fill the per-ray constants of the lanes of `mask` from their
    /// directions, and make those lanes the active ones.
    fn ray_constants(isa: Isa, p: &mut RayPacket, mask: Mask) {
        let mut perm = Permutations::default();
        p.neg = [0; 3];
        for g in 0..LANES / V::W {
            if group_active::<V>(mask, g) {
                let d = [V::load(&p.d[0].0, g), V::load(&p.d[1].0, g), V::load(&p.d[2].0, g)];
                perm.add::<V>(p, d, g);
            }
        }
        perm.finish(p);
        p.activate(mask);
    }
}

/// The nearest hit of each lane so far: `t` starts at the lane's `t_max`
/// with `prim == NO_PRIM`.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub struct PacketHits {
    /// Distance of the best hit, or the lane's `t_max` while there is none.
    pub t: Lanes,
    /// What a new hit must lie below: the rule of
    /// [`crate::accel::test_prim`], `t_max` while there is no hit, then the
    /// best distance nudged one ulp up (so that a lower id at equal
    /// distance can still win). Kept beside `t` as hits are taken.
    limit: Lanes,
    /// Barycentric of vertex 1 (triangles).
    pub u: Lanes,
    /// Barycentric of vertex 2 (triangles).
    pub v: Lanes,
    /// Primitive of the best hit, or [`NO_PRIM`].
    pub prim: [u32; LANES],
}

impl PacketHits {
    /// No hits yet for the rays of `p`.
    pub fn new(p: &RayPacket) -> PacketHits {
        let zero = Lanes([0.0; LANES]);
        PacketHits { t: p.t_max, limit: p.t_max, u: zero, v: zero, prim: [NO_PRIM; LANES] }
    }

    /// Lane `i`'s hit, if any.
    #[inline]
    pub fn get(&self, i: usize) -> Option<Hit> {
        (self.prim[i] != NO_PRIM).then(|| Hit {
            t: self.t.0[i],
            prim: self.prim[i],
            u: self.u.0[i],
            v: self.v.0[i],
        })
    }

    /// Make `h` lane `i`'s hit if it beats the one there ([`Hit::beats`]).
    #[inline(always)]
    pub fn keep(&mut self, i: usize, h: Hit) {
        if h.beats(&self.get(i)) {
            self.t.0[i] = h.t;
            self.limit.0[i] = f32::from_bits(h.t.to_bits().wrapping_add(1));
            self.prim[i] = h.prim;
            self.u.0[i] = h.u;
            self.v.0[i] = h.v;
        }
    }

    /// Lane `i`'s single-ray test of primitive `id` (the fallback for
    /// shapes and cases without a lane-wise test).
    #[inline(always)]
    pub fn test_scalar(&mut self, geom: &Geometry, id: u32, q: &RayQuery, i: usize) {
        if let Some(h) = geom.intersect(id, q, self.limit.0[i]) {
            self.keep(i, h);
        }
    }
}

/// The lanes in `mask` that hit primitive `id` within their `(t_min,
/// limit)` and beat their best hit; updates the hits. Spheres and, when
/// the lanes share the axis permutation, triangles are tested lane-wise
/// with vectors `V`; the rest ray by ray.
#[inline(always)]
pub fn test_prim_packet<V: F32s>(
    geom: &Geometry,
    id: u32,
    p: &RayPacket,
    mask: Mask,
    hits: &mut PacketHits,
    c: &mut Counters,
) {
    let (kind, index) = geom.locate(id);
    c.tests[kind] += u64::from(mask.count_ones());
    let cull = if geom.any_cull { geom.info[id as usize].cull } else { Cull::None };
    match kind {
        Kind::Sphere => {
            let mut t = [0.0f32; LANES];
            let found = sphere_lanes::<V>(&geom.spheres[index], p, mask, &hits.limit.0, cull, &mut t);
            accept(id, mask & found, &t, hits, None);
        }
        Kind::Triangle if p.shared_k.is_some() => {
            let mut out = TriangleLanes::default();
            triangle_lanes::<V>(&geom.triangles[index], p, mask, &hits.limit.0, cull, &mut out);
            accept(id, mask & out.found, &out.t, hits, Some((&out.u, &out.v)));
            for_lanes(mask & out.slow, |i| hits.test_scalar(geom, id, &p.query(i), i));
        }
        _ => for_lanes(mask, |i| hits.test_scalar(geom, id, &p.query(i), i)),
    }
}

/// The lanes in `mask` that primitive `id` blocks within `(t_min, t_max)`.
#[inline(always)]
pub fn occludes_packet<V: F32s>(
    geom: &Geometry,
    id: u32,
    p: &RayPacket,
    mask: Mask,
    c: &mut Counters,
) -> Mask {
    let (kind, index) = geom.locate(id);
    c.tests[kind] += u64::from(mask.count_ones());
    let cull = if geom.any_cull { geom.info[id as usize].cull } else { Cull::None };
    let scalar = |m: Mask| {
        let mut blocked = 0;
        for_lanes(m, |i| {
            if geom.intersect(id, &p.query(i), p.t_max.0[i]).is_some() {
                blocked |= 1 << i;
            }
        });
        blocked
    };
    match kind {
        Kind::Sphere => {
            let mut t = [0.0f32; LANES];
            mask & sphere_lanes::<V>(&geom.spheres[index], p, mask, &p.t_max.0, cull, &mut t)
        }
        Kind::Triangle if p.shared_k.is_some() => {
            let mut out = TriangleLanes::default();
            triangle_lanes::<V>(&geom.triangles[index], p, mask, &p.t_max.0, cull, &mut out);
            (mask & out.found) | scalar(mask & out.slow)
        }
        _ => scalar(mask),
    }
}

crate::dispatch! {
    /// [`occludes_packet`] compiled for `isa`: the lanes of `mask` that
    /// primitive `id` blocks (the shadow cache's test of a packet).
    pub fn occludes(isa: Isa, geom: &Geometry, id: u32, p: &RayPacket, mask: Mask, c: &mut Counters) -> Mask {
        occludes_packet::<V>(geom, id, p, mask, c)
    }
}

/// Call `f` with each lane of `mask`, lowest first.
#[inline(always)]
pub fn for_lanes(mut mask: Mask, mut f: impl FnMut(usize)) {
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        f(i);
    }
}

/// Keep the hits of `found` lanes that beat the lane's best.
#[inline(always)]
fn accept(
    id: u32,
    found: Mask,
    t: &[f32; LANES],
    hits: &mut PacketHits,
    uv: Option<(&[f32; LANES], &[f32; LANES])>,
) {
    for_lanes(found, |i| {
        let (u, v) = uv.map_or((0.0, 0.0), |(u, v)| (u[i], v[i]));
        hits.keep(i, Hit { t: t[i], prim: id, u, v });
    });
}

/// [`crate::geometry::intersect_sphere`] on the lanes of `mask` (in vector
/// groups: other lanes of a group are computed and ignored): the lanes with
/// a root in `(t_min, limit)`, that root written to `t`.
#[inline(always)]
fn sphere_lanes<V: F32s>(
    s: &Sphere,
    p: &RayPacket,
    mask: Mask,
    limit: &[f32; LANES],
    cull: Cull,
    t: &mut [f32; LANES],
) -> Mask {
    let (cx, cy, cz) = (V::splat(s.center.x), V::splat(s.center.y), V::splat(s.center.z));
    let r2 = V::splat(s.radius * s.radius);
    let zero = V::splat(0.0);
    let mut found: Mask = 0;
    for g in 0..LANES / V::W {
        if !group_active::<V>(mask, g) {
            continue;
        }
        let (dx, dy, dz) = (V::load(&p.d[0].0, g), V::load(&p.d[1].0, g), V::load(&p.d[2].0, g));
        let fx = V::load(&p.o[0].0, g).sub(cx);
        let fy = V::load(&p.o[1].0, g).sub(cy);
        let fz = V::load(&p.o[2].0, g).sub(cz);
        let b = fx.mul(dx).add(fy.mul(dy)).add(fz.mul(dz)).neg();
        let (lx, ly, lz) = (fx.add(b.mul(dx)), fy.add(b.mul(dy)), fz.add(b.mul(dz)));
        let disc = r2.sub(lx.mul(lx).add(ly.mul(ly)).add(lz.mul(lz)));
        let cc = fx.mul(fx).add(fy.mul(fy)).add(fz.mul(fz)).sub(r2);
        let qq = b.add(disc.sqrt().copysign(b));
        let is_zero = qq.eq(zero);
        let a0 = V::select(is_zero, zero, cc.div(qq));
        let a1 = V::select(is_zero, zero, qq);
        let swap = a1.lt(a0);
        let (t0, t1) = (V::select(swap, a1, a0), V::select(swap, a0, a1));
        let (lo, hi) = (V::load(&p.t_min.0, g), V::load(limit, g));
        let ok0 = V::and(lo.lt(t0), t0.lt(hi));
        let ok1 = V::and(lo.lt(t1), t1.lt(hi));
        let (hit, tg) = match cull {
            Cull::None => (V::or(ok0, ok1), V::select(ok0, t0, t1)),
            Cull::Back => (ok0, t0),
            Cull::Front => (ok1, t1),
        };
        tg.store(t, g);
        // disc < 0 misses; a NaN disc gives NaN roots, which `ok` rejects.
        found |= group_bits::<V>(V::and(hit, zero.le(disc)), g);
    }
    found
}

/// Lane-wise results of [`triangle_lanes`].
#[derive(Default)]
struct TriangleLanes {
    /// Lanes with a hit in `(t_min, limit)`.
    found: Mask,
    /// Lanes on an edge in single precision, which need the single-ray
    /// test's double-precision path.
    slow: Mask,
    t: [f32; LANES],
    u: [f32; LANES],
    v: [f32; LANES],
}

/// [`crate::geometry::intersect_triangle`] on every lane, for a packet whose
/// lanes share the axis permutation.
#[inline(always)]
fn triangle_lanes<V: F32s>(
    tri: &Triangle,
    p: &RayPacket,
    mask: Mask,
    limit: &[f32; LANES],
    cull: Cull,
    out: &mut TriangleLanes,
) {
    let [kx, ky, kz] = p.shared_k.unwrap_or([0, 1, 2]);
    let vtx = tri.v;
    let (okx, oky, okz) = (&p.o[kx].0, &p.o[ky].0, &p.o[kz].0);
    let zero = V::splat(0.0);
    for g in 0..LANES / V::W {
        if !group_active::<V>(mask, g) {
            continue;
        }
        let (ox, oy, oz) = (V::load(okx, g), V::load(oky, g), V::load(okz, g));
        let (sx, sy, sz) = (V::load(&p.shear[0].0, g), V::load(&p.shear[1].0, g), V::load(&p.shear[2].0, g));
        // (Plain code, no closure: a closure is compiled without the
        // instruction set, and the intrinsics in it would not inline.)
        let (a_x, a_y, a_z) =
            (V::splat(vtx[0][kx]).sub(ox), V::splat(vtx[0][ky]).sub(oy), V::splat(vtx[0][kz]).sub(oz));
        let (b_x, b_y, b_z) =
            (V::splat(vtx[1][kx]).sub(ox), V::splat(vtx[1][ky]).sub(oy), V::splat(vtx[1][kz]).sub(oz));
        let (c_x, c_y, c_z) =
            (V::splat(vtx[2][kx]).sub(ox), V::splat(vtx[2][ky]).sub(oy), V::splat(vtx[2][kz]).sub(oz));
        let (ax, ay) = (a_x.sub(sx.mul(a_z)), a_y.sub(sy.mul(a_z)));
        let (bx, by) = (b_x.sub(sx.mul(b_z)), b_y.sub(sy.mul(b_z)));
        let (cx, cy) = (c_x.sub(sx.mul(c_z)), c_y.sub(sy.mul(c_z)));
        let u = cx.mul(by).sub(cy.mul(bx));
        let v = ax.mul(cy).sub(ay.mul(cx));
        let w = bx.mul(ay).sub(by.mul(ax));
        let edge = V::or(V::or(u.eq(zero), v.eq(zero)), w.eq(zero));
        let any_neg = V::or(V::or(u.lt(zero), v.lt(zero)), w.lt(zero));
        let any_pos = V::or(V::or(zero.lt(u), zero.lt(v)), zero.lt(w));
        let det = u.add(v).add(w);
        let t = u.mul(sz.mul(a_z)).add(v.mul(sz.mul(b_z))).add(w.mul(sz.mul(c_z))).div(det);
        let inside = V::and(V::load(&p.t_min.0, g).lt(t), t.lt(V::load(limit, g)));
        let inv = V::splat(1.0).div(det);
        t.store(&mut out.t, g);
        v.mul(inv).store(&mut out.u, g);
        w.mul(inv).store(&mut out.v, g);
        // Accepted: inside all edges (or outside all, seen from the back),
        // det != 0 (NaN t then fails `inside`), not culled, t in range.
        let facing = match cull {
            Cull::None => u32::MAX,
            Cull::Back => !V::bits(det.lt(zero)),
            Cull::Front => !V::bits(zero.lt(det)),
        };
        let nonzero = !V::bits(det.eq(zero));
        let bits = V::bits(inside) & !V::bits(V::and(any_neg, any_pos)) & nonzero & facing & !V::bits(edge);
        out.found |= (bits & ((1 << V::W) - 1)) << (g * V::W);
        out.slow |= group_bits::<V>(edge, g);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    #[test]
    fn lanes_and_masks() {
        let rays = (0..5).map(|i| (Ray::new(Vec3A::new(i as f32, 0.0, 0.0), Vec3A::Z), 0.0, f32::INFINITY));
        let p = RayPacket::new(rays);
        assert_eq!((p.active, p.len(), p.shared_k), (0b11111, 5, Some([0, 1, 2])));
        let mut seen = vec![];
        for_lanes(0b1010_0001, |i| seen.push(i));
        assert_eq!(seen, [0, 5, 7]);
        let mut q = p.clone();
        q.set(5, RayQuery::new(Ray::new(Vec3A::ZERO, Vec3A::X), 0.0), 1.0);
        assert_eq!(q.shared_k, None);
    }
}
