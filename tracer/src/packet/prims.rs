//! The lane-wise primitive tests: a sphere, or a triangle when the lanes
//! share the triangle test's axis permutation, tested against a vector of
//! lanes at once, repeating [`crate::geometry`]'s single-ray tests
//! operation for operation, so a lane finds bit for bit the hit its ray
//! finds alone (and the tie rule, nearest then lowest id, is the same).
//! Where the single-ray test takes a rare slow path (the triangle test's
//! double-precision edge case), and for the other shapes, the lane falls
//! back to it.

use super::{Blockers, LaneHits, RayPacket};
use crate::geometry::{Cull, Geometry, Kind, Sphere, Triangle};
use crate::math::gamma;
use crate::simd::lanes::{for_lanes, Lanes, Mask, LANES};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};
use crate::stats::Counters;

/// Test primitive `id` on the lanes of `mask`, below each lane's
/// [`LaneHits::limit`], and take what is found into `hits`; returns the
/// lanes that found a hit. Spheres and, when the lanes share the axis
/// permutation, triangles are tested lane-wise with vectors `V`; the rest
/// ray by ray.
#[inline(always)]
pub(crate) fn test_prim<V: F32s, H: LaneHits>(
    s: Simd<V>,
    geom: &Geometry,
    id: u32,
    p: &RayPacket,
    mask: Mask,
    hits: &mut H,
    c: &mut Counters,
) -> Mask {
    let (kind, index) = geom.locate(id);
    c.tests[kind] += u64::from(mask.count_ones());
    let cull = if geom.any_cull { geom.info[id as usize].cull } else { Cull::None };
    match kind {
        Kind::Sphere => {
            let mut t = Lanes::ZERO;
            let found = mask & sphere_lanes(s, &geom.spheres[index], p, mask, hits.limit(p), cull, &mut t.0);
            hits.take_lanes(s, found, id, &t, &Lanes::ZERO, &Lanes::ZERO);
            found
        }
        Kind::Triangle if p.shared_k.is_some() => {
            let mut out = TriangleLanes::default();
            triangle_lanes(s, &geom.triangles[index], p, mask, hits.limit(p), cull, &mut out);
            let found = mask & out.found;
            hits.take_lanes(s, found, id, &out.t, &out.u, &out.v);
            found | by_ray(geom, id, p, mask & out.slow, hits)
        }
        _ => by_ray(geom, id, p, mask, hits),
    }
}

/// The lanes of `mask` tested ray by ray with the single-ray test, as
/// [`test_prim`] takes them.
#[inline(always)]
fn by_ray<H: LaneHits>(geom: &Geometry, id: u32, p: &RayPacket, mask: Mask, hits: &mut H) -> Mask {
    let mut found = 0;
    for_lanes(mask, |i| {
        if let Some(h) = geom.intersect(id, &p.query(i), hits.limit(p)[i]) {
            hits.take(i, h);
            found |= 1 << i;
        }
    });
    found
}

crate::simd::dispatch! {
    /// The lanes of `mask` that primitive `id` blocks within their
    /// `(t_min, t_max)` (the shadow cache's test of a packet).
    pub(crate) fn occludes(isa: Isa, geom: &Geometry, id: u32, p: &RayPacket, mask: Mask, c: &mut Counters) -> Mask {
        |s| test_prim(s, geom, id, p, mask, &mut Blockers::new(), c)
    }
}

/// [`crate::geometry::intersect_sphere`] on the lanes of `mask` (in vector
/// groups: other lanes of a group are computed and ignored): the lanes with
/// a root in `(t_min, limit)`, that root written to `t`.
#[inline(always)]
fn sphere_lanes<V: F32s>(
    s: Simd<V>,
    sphere: &Sphere,
    p: &RayPacket,
    mask: Mask,
    limit: &[f32; LANES],
    cull: Cull,
    t: &mut [f32; LANES],
) -> Mask {
    let c = sphere.center();
    let (cx, cy, cz) = (s.splat(c.x), s.splat(c.y), s.splat(c.z));
    let r2 = s.splat(sphere.radius() * sphere.radius());
    let zero = s.splat(0.0);
    let mut found: Mask = 0;
    for g in 0..LANES / V::W {
        if !group_active::<V>(mask, g) {
            continue;
        }
        let (dx, dy, dz) = (s.load(&p.d[0].0, g), s.load(&p.d[1].0, g), s.load(&p.d[2].0, g));
        let fx = s.load(&p.o[0].0, g).sub(cx);
        let fy = s.load(&p.o[1].0, g).sub(cy);
        let fz = s.load(&p.o[2].0, g).sub(cz);
        let b = fx.mul(dx).add(fy.mul(dy)).add(fz.mul(dz)).neg();
        let (lx, ly, lz) = (fx.add(b.mul(dx)), fy.add(b.mul(dy)), fz.add(b.mul(dz)));
        let disc = r2.sub(lx.mul(lx).add(ly.mul(ly)).add(lz.mul(lz)));
        // disc < 0 misses; a NaN disc gives NaN roots, which `ok` rejects.
        let reach = group_bits::<V>(zero.le(disc), g) & mask;
        if reach == 0 {
            // No lane of the group meets the sphere: its roots (a square
            // root and a division) are not needed.
            continue;
        }
        let cc = fx.mul(fx).add(fy.mul(fy)).add(fz.mul(fz)).sub(r2);
        let qq = b.add(disc.sqrt().copysign(b));
        let is_zero = qq.eq(zero);
        let a0 = V::select(is_zero, zero, cc.div(qq));
        let a1 = V::select(is_zero, zero, qq);
        let swap = a1.lt(a0);
        let (t0, t1) = (V::select(swap, a1, a0), V::select(swap, a0, a1));
        let (lo, hi) = (s.load(&p.t_min.0, g), s.load(limit, g));
        let ok0 = V::and(lo.lt(t0), t0.lt(hi));
        let ok1 = V::and(lo.lt(t1), t1.lt(hi));
        let (hit, tg) = match cull {
            Cull::None => (V::or(ok0, ok1), V::select(ok0, t0, t1)),
            Cull::Back => (ok0, t0),
            Cull::Front => (ok1, t1),
        };
        tg.store(t, g);
        found |= group_bits::<V>(hit, g) & reach;
    }
    found
}

/// [`crate::math::triangle_t_error`] on vectors of lanes, operation for
/// operation.
#[inline(always)]
fn triangle_t_error_lanes<V: F32s>(s: Simd<V>, max_x: V, max_y: V, max_z: V, max_e: V, inv_det: V) -> V {
    let delta_z = s.splat(gamma(3)).mul(max_z);
    let delta_x = s.splat(gamma(5)).mul(max_x.add(max_z));
    let delta_y = s.splat(gamma(5)).mul(max_y.add(max_z));
    let delta_e = s
        .splat(2.0)
        .mul(s.splat(gamma(2)).mul(max_x).mul(max_y).add(delta_y.mul(max_x)).add(delta_x.mul(max_y)));
    let sum = s.splat(gamma(3)).mul(max_e).mul(max_z).add(delta_e.mul(max_z)).add(delta_z.mul(max_e));
    s.splat(3.0).mul(sum).mul(inv_det.copysign(s.splat(0.0)))
}

/// Lane-wise results of [`triangle_lanes`].
#[derive(Default)]
struct TriangleLanes {
    /// Lanes with a hit in `(t_min, limit)`.
    found: Mask,
    /// Lanes on an edge in single precision, which need the single-ray
    /// test's double-precision path.
    slow: Mask,
    t: Lanes,
    u: Lanes,
    v: Lanes,
}

/// [`crate::geometry::intersect_triangle`] on every lane, for a packet whose
/// lanes share the axis permutation.
#[inline(always)]
fn triangle_lanes<V: F32s>(
    s: Simd<V>,
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
    let zero = s.splat(0.0);
    for g in 0..LANES / V::W {
        if !group_active::<V>(mask, g) {
            continue;
        }
        let (ox, oy, oz) = (s.load(okx, g), s.load(oky, g), s.load(okz, g));
        let (sx, sy, sz) = (s.load(&p.shear[0].0, g), s.load(&p.shear[1].0, g), s.load(&p.shear[2].0, g));
        // (Plain code, no closure: a closure is compiled without the
        // instruction set, and the intrinsics in it would not inline.)
        let (a_x, a_y, a_z) =
            (s.splat(vtx[0][kx]).sub(ox), s.splat(vtx[0][ky]).sub(oy), s.splat(vtx[0][kz]).sub(oz));
        let (b_x, b_y, b_z) =
            (s.splat(vtx[1][kx]).sub(ox), s.splat(vtx[1][ky]).sub(oy), s.splat(vtx[1][kz]).sub(oz));
        let (c_x, c_y, c_z) =
            (s.splat(vtx[2][kx]).sub(ox), s.splat(vtx[2][ky]).sub(oy), s.splat(vtx[2][kz]).sub(oz));
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
        out.slow |= group_bits::<V>(edge, g);
        // Accepted: inside all edges (or outside all, seen from the back),
        // det != 0 (NaN t then fails `inside`), not culled, t in range.
        let facing = match cull {
            Cull::None => u32::MAX,
            Cull::Back => !V::bits(det.lt(zero)),
            Cull::Front => !V::bits(zero.lt(det)),
        };
        let nonzero = !V::bits(det.eq(zero));
        // (The group's own lanes only: the negations set the bits above.)
        let group = (1 << V::W) - 1;
        let within = !V::bits(V::and(any_neg, any_pos)) & nonzero & facing & !V::bits(edge) & group;
        if (within << (g * V::W)) & mask == 0 {
            // No lane of the group inside the edges: its distance and
            // barycentrics (two divisions) are not needed.
            continue;
        }
        let t = u.mul(sz.mul(a_z)).add(v.mul(sz.mul(b_z))).add(w.mul(sz.mul(c_z))).div(det);
        let inside = V::and(s.load(&p.t_min.0, g).lt(t), t.lt(s.load(limit, g)));
        let inv = s.splat(1.0).div(det);
        t.store(&mut out.t.0, g);
        v.mul(inv).store(&mut out.u.0, g);
        w.mul(inv).store(&mut out.v.0, g);
        let mut bits = V::bits(inside) & within;
        if bits != 0 {
            // [`crate::math::triangle_t_error`], lane-wise: t beyond its
            // rounding error. (Only for groups with a candidate hit.)
            let (az, bz, cz) = (sz.mul(a_z), sz.mul(b_z), sz.mul(c_z));
            let max_x = ax.copysign(zero).max(bx.copysign(zero)).max(cx.copysign(zero));
            let max_y = ay.copysign(zero).max(by.copysign(zero)).max(cy.copysign(zero));
            let max_z = az.copysign(zero).max(bz.copysign(zero)).max(cz.copysign(zero));
            let max_e = u.copysign(zero).max(v.copysign(zero)).max(w.copysign(zero));
            let delta_t = triangle_t_error_lanes(s, max_x, max_y, max_z, max_e, inv);
            bits &= !V::bits(t.le(delta_t));
        }
        out.found |= bits << (g * V::W);
    }
}
