//! Ray packets: up to [`LANES`] coherent rays (the samples of one pixel, or
//! a block of neighbouring pixel centres) traced together, stored as
//! structure of arrays so one vector instruction serves every lane.
//!
//! Every lane-wise kernel here repeats the single-ray code operation for
//! operation (the same products and sums in the same order, with the
//! three-vector helpers of [`crate::simd::vec3`]), so a lane gets bit for
//! bit what its ray gets alone and images do not depend on packets. One
//! file per job:
//!
//! - this file: the packet ([`RayPacket`], its per-ray constants by
//!   [`RayConstants`]) and what a traversal keeps per lane ([`LaneHits`]:
//!   the nearest hits, [`PacketHits`], or any hit's blocker, [`Blockers`]);
//! - [`camera`]: a pixel's eye rays;
//! - [`prims`]: the lane-wise sphere and triangle tests;
//! - [`surface`]: the hits' points and normals ([`PointLanes`]);
//! - [`shadow`]: the shadow rays of those points toward a light;
//! - [`bounce`]: their mirror and refracted rays.

pub(crate) mod bounce;
pub(crate) mod camera;
pub(crate) mod prims;
pub(crate) mod shadow;
pub(crate) mod surface;

pub(crate) use surface::PointLanes;

use crate::geometry::Hit;
use crate::math::{Ray, RayQuery};
use crate::query::{AnyHit, Nearest, Query};
use crate::simd::lanes::{for_lanes, lane, set_lane, Lanes, Mask, LANES};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};

/// "No primitive" in [`PacketHits::prim`].
pub(crate) const NO_PRIM: u32 = u32::MAX;

/// Up to [`LANES`] rays with the per-ray constants of [`RayQuery`], in
/// structure-of-arrays form.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct RayPacket {
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
    pub k: Permutations,
}

impl RayPacket {
    /// A packet with no rays.
    pub fn empty() -> RayPacket {
        RayPacket {
            o: [Lanes::ZERO; 3],
            d: [Lanes::ZERO; 3],
            inv: [Lanes::ZERO; 3],
            shear: [Lanes::ZERO; 3],
            t_min: Lanes::ZERO,
            t_max: Lanes([f32::NEG_INFINITY; LANES]),
            neg: [0; 3],
            active: 0,
            shared_k: None,
            k: Permutations::default(),
        }
    }

    /// A packet of `rays`, each `(ray, t_min, t_max)`; at most [`LANES`].
    /// (For tests: the renderer and the benchmarks set up packets lane-wise.)
    #[cfg(test)]
    pub fn new(rays: impl IntoIterator<Item = (Ray, f32, f32)>) -> RayPacket {
        let mut p = RayPacket::empty();
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

    /// A packet of the rays with origins `o` and directions `d` in the
    /// lanes of `mask` (where they are: the other lanes are left out),
    /// from distance 0 on without end.
    pub fn from_lanes(o: &[Lanes; 3], d: &[Lanes; 3], mask: Mask) -> RayPacket {
        let mut p = RayPacket { o: *o, d: *d, ..RayPacket::empty() };
        for_lanes(mask, |i| p.t_max.0[i] = f32::INFINITY);
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
        self.k.set(i, q.k);
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
            k: self.k.lane(i),
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

    /// Make the lanes of `mask` the active ones, their values (and
    /// permutations) already in place.
    fn activate(&mut self, mask: Mask) {
        self.active = mask;
        self.shared_k = self.k.shared(mask);
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

/// Each lane's axis permutation of the watertight triangle test
/// (`[kx, ky, kz]` of [`RayQuery::new`]) as three masks: the lanes whose
/// direction is largest along x, along y (else z), and negative along that
/// axis. The kernels set them a vector group at a time; a lane's
/// permutation is read from them only when the lane needs its own query.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Permutations {
    x_major: Mask,
    y_major: Mask,
    negative: Mask,
}

/// `[kx, ky, kz]` by major axis `kz` and its sign, at `2 kz + negative`:
/// `kx, ky` follow `kz` cyclically, swapped where the direction along `kz`
/// is negative (which keeps the triangles' winding).
const PERMUTATIONS: [[usize; 3]; 6] = [[1, 2, 0], [2, 1, 0], [2, 0, 1], [0, 2, 1], [0, 1, 2], [1, 0, 2]];

impl Permutations {
    /// Lane `i`'s permutation.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> [usize; 3] {
        let bit = |m: Mask| (m >> i & 1) as usize;
        // The major-axis masks exclude each other.
        let kz = 2 - 2 * bit(self.x_major) - bit(self.y_major);
        PERMUTATIONS[2 * kz + bit(self.negative)]
    }

    /// Give lane `i` permutation `k` (one of [`PERMUTATIONS`]).
    fn set(&mut self, i: usize, k: [usize; 3]) {
        let at = |m: &mut Mask, on: bool| *m = *m & !(1 << i) | Mask::from(on) << i;
        at(&mut self.x_major, k[2] == 0);
        at(&mut self.y_major, k[2] == 1);
        at(&mut self.negative, PERMUTATIONS[2 * k[2] + 1] == k);
    }

    /// The permutation every lane of `mask` has, if they share one: they
    /// do when they agree on the major axis and on its sign.
    fn shared(&self, mask: Mask) -> Option<[usize; 3]> {
        let uniform = |m: Mask| m & mask == 0 || m & mask == mask;
        let shared = mask != 0 && uniform(self.x_major) && uniform(self.y_major) && uniform(self.negative);
        shared.then(|| self.lane(mask.trailing_zeros() as usize))
    }
}

/// The per-ray constants of [`RayQuery::new`] computed lane-wise, bit for
/// bit: 1/d clamped, its signs, and the watertight triangle test's axis
/// permutation and shear. [`RayConstants::add`] computes a vector group's
/// (storing 1/d, its signs and the shear at once) and gathers each lane's
/// permutation; [`RayConstants::finish`] hands the permutations over.
#[derive(Default)]
pub(crate) struct RayConstants {
    k: Permutations,
}

impl RayConstants {
    /// Compute group `g`'s constants from its directions `d` into `out`.
    #[inline(always)]
    pub(crate) fn add<V: F32s>(&mut self, s: Simd<V>, out: &mut RayPacket, d: [V; 3], g: usize) {
        let zero = s.splat(0.0);
        for (a, &da) in d.iter().enumerate() {
            let inv = s.splat(1.0).div(da).max(s.splat(-1e30)).min(s.splat(1e30));
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
        s.splat(1.0).div(dz).store(&mut out.shear[2].0, g);
        self.k.x_major |= group_bits::<V>(x_major, g);
        self.k.y_major |= group_bits::<V>(y_major, g);
        self.k.negative |= group_bits::<V>(neg, g);
    }

    /// Write the lanes' permutations and make the lanes of `mask` the
    /// active ones.
    pub(crate) fn finish(&self, out: &mut RayPacket, mask: Mask) {
        out.k = self.k;
        out.activate(mask);
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

/// [`ray_constants`]' body: the constants of the lanes of `mask`.
#[inline(always)]
fn ray_constants_body<V: F32s>(s: Simd<V>, p: &mut RayPacket, mask: Mask) {
    let mut constants = RayConstants::default();
    p.neg = [0; 3];
    for g in 0..LANES / V::W {
        if group_active::<V>(mask, g) {
            let d = [s.load(&p.d[0].0, g), s.load(&p.d[1].0, g), s.load(&p.d[2].0, g)];
            constants.add(s, p, d, g);
        }
    }
    constants.finish(p, mask);
}

crate::simd::dispatch! {
    /// Fill the per-ray constants of the lanes of `mask` from their
    /// directions, and make those lanes the active ones.
    fn ray_constants(isa: Isa, p: &mut RayPacket, mask: Mask) { |s| ray_constants_body(s, p, mask) }
}

/// What a packet traversal keeps per lane, and so which query it answers.
pub(crate) trait LaneHits {
    /// The query: [`Nearest`] or [`AnyHit`].
    type Query: Query;
    /// Per lane, the distance below which a new hit is taken.
    fn limit<'a>(&'a self, p: &'a RayPacket) -> &'a [f32; LANES];
    /// Per lane, how far boxes are worth entering.
    fn far<'a>(&'a self, p: &'a RayPacket) -> &'a [f32; LANES];
    /// Lane `i`'s best hit so far, which a new one must beat.
    fn best(&self, i: usize) -> Option<Hit>;
    /// Take `h`, found below the lane's limit, as lane `i`'s hit.
    fn take(&mut self, i: usize, h: Hit);
    /// Take primitive `id`'s hits at `t` (barycentrics `u`, `v`), found
    /// below their limits in the lanes of `found`: what [`LaneHits::take`]
    /// does lane by lane.
    #[inline(always)]
    fn take_lanes<V: F32s>(&mut self, _: Simd<V>, found: Mask, id: u32, t: &Lanes, u: &Lanes, v: &Lanes) {
        for_lanes(found, |i| self.take(i, Hit { t: t.0[i], prim: id, u: u.0[i], v: v.0[i] }));
    }
}

/// The nearest hit of each lane so far: `t` starts at the lane's `t_max`
/// with `prim == NO_PRIM`.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct PacketHits {
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
        PacketHits { t: p.t_max, limit: p.t_max, u: Lanes::ZERO, v: Lanes::ZERO, prim: [NO_PRIM; LANES] }
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

    /// The lanes with a hit.
    pub fn found(&self) -> Mask {
        found(&self.prim)
    }
}

impl LaneHits for PacketHits {
    type Query = Nearest;

    #[inline(always)]
    fn limit<'a>(&'a self, _: &'a RayPacket) -> &'a [f32; LANES] {
        &self.limit.0
    }

    #[inline(always)]
    fn far<'a>(&'a self, _: &'a RayPacket) -> &'a [f32; LANES] {
        &self.t.0
    }

    #[inline(always)]
    fn best(&self, i: usize) -> Option<Hit> {
        self.get(i)
    }

    /// [`LaneHits::take`] with vectors: the kept values are blended into
    /// the lanes a vector at a time, so that the traversal's next vector
    /// loads of the distances and limits are served by these stores (lane
    /// by lane stores make a vector load that spans them wait for them to
    /// reach the cache).
    #[inline(always)]
    fn take_lanes<V: F32s>(&mut self, s: Simd<V>, found: Mask, id: u32, t: &Lanes, u: &Lanes, v: &Lanes) {
        for g in 0..LANES / V::W {
            let bits = found >> (g * V::W) & ((1 << V::W) - 1);
            if bits == 0 {
                continue;
            }
            let (new, best) = (s.load(&t.0, g), s.load(&self.t.0, g));
            // A hit found below the limit is at most the best distance
            // (the limit is one ulp above it): it beats the best when it is
            // nearer, or as near with a lower id (`Hit::beats`).
            let mut keep = V::bits(new.lt(best)) & bits;
            for_lanes(V::bits(new.eq(best)) & bits, |j| {
                keep |= u32::from(id < self.prim[g * V::W + j]) << j;
            });
            if keep == 0 {
                continue;
            }
            let lanes = keep << (g * V::W);
            let m = V::from_bits(keep);
            V::select(m, new, best).store(&mut self.t.0, g);
            let limit = new.add_i32(s.splat(f32::from_bits(1)));
            V::select(m, limit, s.load(&self.limit.0, g)).store(&mut self.limit.0, g);
            V::select(m, s.load(&u.0, g), s.load(&self.u.0, g)).store(&mut self.u.0, g);
            V::select(m, s.load(&v.0, g), s.load(&self.v.0, g)).store(&mut self.v.0, g);
            for_lanes(lanes, |i| self.prim[i] = id);
        }
    }

    /// Keep `h` if it beats the lane's hit ([`Hit::beats`]).
    #[inline(always)]
    fn take(&mut self, i: usize, h: Hit) {
        if h.beats(&self.get(i)) {
            self.t.0[i] = h.t;
            self.limit.0[i] = f32::from_bits(h.t.to_bits().wrapping_add(1));
            self.prim[i] = h.prim;
            self.u.0[i] = h.u;
            self.v.0[i] = h.v;
        }
    }
}

/// The primitive blocking each lane's shadow ray, the first found, or
/// [`NO_PRIM`] while none is.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Blockers(pub [u32; LANES]);

impl Blockers {
    /// No blocker yet.
    pub fn new() -> Blockers {
        Blockers([NO_PRIM; LANES])
    }

    /// The lanes with a blocker.
    pub fn found(&self) -> Mask {
        found(&self.0)
    }
}

impl LaneHits for Blockers {
    type Query = AnyHit;

    #[inline(always)]
    fn limit<'a>(&'a self, p: &'a RayPacket) -> &'a [f32; LANES] {
        &p.t_max.0
    }

    #[inline(always)]
    fn far<'a>(&'a self, p: &'a RayPacket) -> &'a [f32; LANES] {
        &p.t_max.0
    }

    #[inline(always)]
    fn best(&self, _: usize) -> Option<Hit> {
        None
    }

    #[inline(always)]
    fn take(&mut self, i: usize, h: Hit) {
        self.0[i] = h.prim;
    }
}

/// The lanes whose primitive is not [`NO_PRIM`].
fn found(prim: &[u32; LANES]) -> Mask {
    (0..LANES).filter(|&i| prim[i] != NO_PRIM).fold(0, |m, i| m | 1 << i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;
    use proptest::prelude::*;

    #[test]
    fn lanes_and_masks() {
        let rays = (0..5).map(|i| (Ray::new(Vec3A::new(i as f32, 0.0, 0.0), Vec3A::Z), 0.0, f32::INFINITY));
        let p = RayPacket::new(rays);
        assert_eq!((p.active, p.len(), p.shared_k), (0b11111, 5, Some([0, 1, 2])));
        let mut q = p.clone();
        q.set(5, RayQuery::new(Ray::new(Vec3A::ZERO, Vec3A::X), 0.0), 1.0);
        assert_eq!(q.shared_k, None);
    }

    /// A permutation set in a lane reads back, without touching the other
    /// lanes', and lanes share one exactly when they were given the same.
    #[test]
    fn permutations_set_read_back_and_share() {
        let mut k = Permutations::default();
        for (i, perm) in PERMUTATIONS.iter().cycle().take(LANES).enumerate() {
            k.set(i, *perm);
        }
        for (i, perm) in PERMUTATIONS.iter().cycle().take(LANES).enumerate() {
            assert_eq!(k.lane(i), *perm, "lane {i}");
        }
        // Lanes 0, 6 and 12 hold the first permutation; 1 the second.
        assert_eq!(k.shared(1 | 1 << 6 | 1 << 12), Some(PERMUTATIONS[0]));
        assert_eq!(k.shared(0b11), None);
        assert_eq!(k.shared(0), None);
    }

    crate::simd::dispatch! {
        /// [`LaneHits::take_lanes`] of [`PacketHits`] with `isa`'s vectors.
        fn take_lanes_with(isa: Isa, hits: &mut PacketHits, found: Mask, id: u32, t: &Lanes, u: &Lanes, v: &Lanes) {
            |s| hits.take_lanes(s, found, id, t, u, v)
        }
    }

    proptest! {
        /// Hits taken a vector at a time are those taken lane by lane: a
        /// nearer one replaces a lane's hit, an equally near one only from a
        /// lower id, and lanes outside `found` keep theirs whatever their
        /// distances say.
        #[test]
        fn hits_taken_a_vector_at_a_time_are_those_taken_lane_by_lane(
            start in prop::collection::vec((any::<bool>(), 0usize..4, 0u32..6), LANES),
            new in prop::collection::vec((0usize..5, any::<f32>(), any::<f32>()), LANES),
            found in any::<u16>(),
            id in 0u32..6,
        ) {
            // Few distances, so that ties are common.
            let ts = [0.5f32, 1.0, 2.0, 3.0, 4.0];
            let p = RayPacket::new((0..LANES).map(|_| (Ray::new(Vec3A::ZERO, Vec3A::Z), 0.0, 10.0)));
            let mut base = PacketHits::new(&p);
            for (i, &(has, k, prim)) in start.iter().enumerate() {
                if has {
                    base.take(i, Hit { t: ts[k], prim, u: 0.25, v: 0.5 });
                }
            }
            let (mut t, mut u, mut v) = (Lanes::ZERO, Lanes::ZERO, Lanes::ZERO);
            let mut found = u32::from(found);
            for (i, &(k, ui, vi)) in new.iter().enumerate() {
                (t.0[i], u.0[i], v.0[i]) = (ts[k], ui, vi);
                // The kernels report only roots below the lane's limit.
                if ts[k] >= base.limit.0[i] {
                    found &= !(1 << i);
                }
            }
            let mut want = base.clone();
            for_lanes(found, |i| want.take(i, Hit { t: t.0[i], prim: id, u: u.0[i], v: v.0[i] }));
            let bits = |l: &Lanes| l.0.map(f32::to_bits);
            for isa in crate::simd::Isa::available() {
                let mut got = base.clone();
                take_lanes_with(isa, &mut got, found, id, &t, &u, &v);
                prop_assert_eq!(got.prim, want.prim, "{}", isa);
                prop_assert_eq!(bits(&got.t), bits(&want.t), "{}", isa);
                prop_assert_eq!(bits(&got.limit), bits(&want.limit), "{}", isa);
                prop_assert_eq!(bits(&got.u), bits(&want.u), "{}", isa);
                prop_assert_eq!(bits(&got.v), bits(&want.v), "{}", isa);
            }
        }

        #[test]
        fn packets_built_from_rays_hold_the_queries_of_the_rays(
            rays in prop::collection::vec((prop::array::uniform3(-5.0f32..5.0), prop::array::uniform3(-1.0f32..1.0), 0.0f32..1.0), 1..=LANES),
            axis in 0usize..4,
        ) {
            // Some directions along an axis, with negative zeros beside.
            let rays: Vec<(Ray, f32, f32)> = rays
                .iter()
                .enumerate()
                .filter_map(|(i, &(o, d, t_min))| {
                    let mut d = Vec3A::from(d);
                    if i % 3 == 0 && axis < 3 {
                        d = Vec3A::from(std::array::from_fn::<f32, 3, _>(|a| if a == axis { -1.0 } else { -0.0 }));
                    }
                    (d.length() > 1e-3).then(|| (Ray::new(Vec3A::from(o), d), t_min, 10.0))
                })
                .collect();
            let p = RayPacket::new(rays.iter().copied());
            prop_assert_eq!(p.len(), rays.len());
            let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
            for (i, &(ray, t_min, t_max)) in rays.iter().enumerate() {
                let (got, want) = (p.query(i), RayQuery::new(ray, t_min));
                prop_assert_eq!(bits(got.inv_d), bits(want.inv_d));
                prop_assert_eq!(bits(got.shear), bits(want.shear));
                prop_assert_eq!((got.neg, got.k, got.t_min.to_bits()), (want.neg, want.k, want.t_min.to_bits()));
                prop_assert_eq!((bits(got.ray.o), bits(got.ray.d)), (bits(want.ray.o), bits(want.ray.d)));
                prop_assert_eq!(p.t_max.0[i], t_max);
            }
            let ks: Vec<_> = rays.iter().map(|&(r, t, _)| RayQuery::new(r, t).k).collect();
            prop_assert_eq!(p.shared_k, ks.iter().all(|k| *k == ks[0]).then_some(ks[0]));
        }
    }
}
