//! The surface records of a packet's hits, lane-wise: each hit's point and
//! normals, turned to face the incoming ray, written straight into the
//! [`PointLanes`] that shading, the shadow rays and the bounces read.
//!
//! A sphere's or a flat triangle's record is computed for a whole vector
//! of lanes at once (its divisions and square roots would otherwise be a
//! dependent chain per hit), operation for operation as
//! [`Geometry::surface`] and `Whitted::shade_point` compute it. Cones,
//! planes and patches (interpolated normals) go through
//! [`Geometry::surface`] lane by lane.

use super::{PacketHits, RayPacket};
use crate::geometry::{Geometry, Kind};
use crate::simd::lanes::{for_lanes, set_lane, Lanes, Mask, LANES};
use crate::simd::vec3::{add3, cross, div3, dot, load3, neg3, normalize, scale3, select3, store3, sub3};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};
use crate::simd::Isa;

/// Hit points of a packet in structure-of-arrays form: position, geometric
/// and shading normals (both facing the incoming ray).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct PointLanes {
    /// Positions.
    pub p: [Lanes; 3],
    /// Geometric normals.
    pub ng: [Lanes; 3],
    /// Shading normals.
    pub ns: [Lanes; 3],
}

impl Default for PointLanes {
    fn default() -> Self {
        PointLanes { p: [Lanes::ZERO; 3], ng: [Lanes::ZERO; 3], ns: [Lanes::ZERO; 3] }
    }
}

/// The hit primitives' data, gathered into lanes for the kernel.
#[repr(C, align(64))]
struct Gathered {
    /// Sphere centre, or a triangle's first vertex.
    a: [Lanes; 3],
    /// A triangle's second vertex.
    b: [Lanes; 3],
    /// A triangle's third vertex.
    c: [Lanes; 3],
    /// Sphere radius.
    radius: Lanes,
    /// What each lane hit: [`SPHERE`], [`TRIANGLE`], or 0 (its record is
    /// already in the output, made by [`Geometry::surface`]).
    kind: Lanes,
}

const SPHERE: f32 = 1.0;
const TRIANGLE: f32 = 2.0;

impl Gathered {
    fn new() -> Gathered {
        let zero = Lanes::ZERO;
        Gathered { a: [zero; 3], b: [zero; 3], c: [zero; 3], radius: zero, kind: zero }
    }
}

/// Fill `out` with the point and the facing normals of every lane of `hit`
/// (lanes of `p` with a hit in `hits`) and return the lanes whose ray
/// enters its surface (hits the side the geometric normal points to),
/// with the kernel built for `isa` (see [`crate::simd`]).
pub(crate) fn surfaces(
    isa: Isa,
    geom: &Geometry,
    p: &RayPacket,
    hits: &PacketHits,
    hit: Mask,
    out: &mut PointLanes,
) -> Mask {
    let mut g = Gathered::new();
    for_lanes(hit, |i| {
        let id = hits.prim[i];
        match geom.locate(id) {
            (Kind::Sphere, k) => {
                let s = &geom.spheres[k];
                set_lane(&mut g.a, i, s.center());
                g.radius.0[i] = s.radius();
                g.kind.0[i] = SPHERE;
            }
            (Kind::Triangle, k) if geom.info[id as usize].patch().is_none() => {
                let [a, b, c] = geom.triangles[k].v;
                set_lane(&mut g.a, i, a);
                set_lane(&mut g.b, i, b);
                set_lane(&mut g.c, i, c);
                g.kind.0[i] = TRIANGLE;
            }
            _ => {
                let Some(h) = hits.get(i) else { return };
                let s = geom.surface(&h, &p.query(i));
                set_lane(&mut out.p, i, s.p);
                set_lane(&mut out.ng, i, s.ng);
                set_lane(&mut out.ns, i, s.ns);
            }
        }
    });
    surface_kernel(isa, p, hits, &g, hit, out)
}

crate::simd::dispatch! {
    /// The kernel of [`surfaces`], compiled for `isa`.
    fn surface_kernel(
        isa: Isa,
        p: &RayPacket,
        hits: &PacketHits,
        g: &Gathered,
        hit: Mask,
        out: &mut PointLanes,
    ) -> Mask {
        |s| surface_body(s, p, hits, g, hit, out)
    }
}

/// `a w + b u + c v` on one axis, summed in that order.
#[inline(always)]
fn barycentric<V: F32s>(a: V, b: V, c: V, [w, u, v]: [V; 3]) -> V {
    a.mul(w).add(b.mul(u)).add(c.mul(v))
}

/// `math::normal_or_facing` lane by lane.
#[inline(always)]
fn or_facing<V: F32s>(s: Simd<V>, n: [V; 3], d: [V; 3]) -> [V; 3] {
    select3(s.splat(0.5).lt(dot(n, n)), n, neg3(d))
}

#[inline(always)]
fn surface_body<V: F32s>(
    s: Simd<V>,
    p: &RayPacket,
    hits: &PacketHits,
    g: &Gathered,
    hit: Mask,
    out: &mut PointLanes,
) -> Mask {
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let mut entering = 0;
    for k in 0..LANES / V::W {
        if !group_active::<V>(hit, k) {
            continue;
        }
        let (o, d) = (load3(s, &p.o, k), load3(s, &p.d, k));
        let (t, u, v) = (s.load(&hits.t.0, k), s.load(&hits.u.0, k), s.load(&hits.v.0, k));
        let a = load3(s, &g.a, k);
        // Sphere: p = o + d t, n = ((p - c) / r).normalize().
        // (Products commute bit for bit: t d is d t.)
        let at = add3(o, scale3(t, d));
        let sphere_n = or_facing(s, normalize(div3(sub3(at, a), s.load(&g.radius.0, k))), d);
        // Flat triangle: p from the barycentrics, n = (b - a) × (c - a).
        let (b, c) = (load3(s, &g.b, k), load3(s, &g.c, k));
        let w = one.sub(u).sub(v);
        let weights = [w, u, v];
        let tri_p = [
            barycentric(a[0], b[0], c[0], weights),
            barycentric(a[1], b[1], c[1], weights),
            barycentric(a[2], b[2], c[2], weights),
        ];
        let tri_n = or_facing(s, normalize(cross(sub3(b, a), sub3(c, a))), d);
        let kind = s.load(&g.kind.0, k);
        let (is_sphere, is_tri) = (kind.eq(s.splat(SPHERE)), kind.eq(s.splat(TRIANGLE)));
        let pos = select3(is_sphere, at, select3(is_tri, tri_p, load3(s, &out.p, k)));
        let ng = select3(is_sphere, sphere_n, select3(is_tri, tri_n, load3(s, &out.ng, k)));
        let ns = select3(is_sphere, sphere_n, select3(is_tri, tri_n, load3(s, &out.ns, k)));
        // `shade_point`: normals turned to face the ray (times ±1, exact).
        let enters = dot(ng, d).lt(zero);
        let flip = V::select(enters, one, one.neg());
        store3(pos, &mut out.p, k);
        store3(scale3(flip, ng), &mut out.ng, k);
        store3(scale3(flip, ns), &mut out.ns, k);
        entering |= group_bits::<V>(enters, k);
    }
    entering & hit
}

#[cfg(test)]
mod tests {
    use crate::accel::Bvh;
    use crate::simd::lanes::LANES;
    use crate::simd::Isa;
    use crate::testing::{check_surfaces, random_scene, rays};

    #[test]
    fn surfaces_of_many_hits_of_every_kind_equal_the_single_ray_records() {
        // Packets aimed into a dense scene, so that every kind is hit often.
        let g = random_scene(7, 3000, false);
        let bvh = Bvh::build(&g);
        let mut kinds = [0; 3];
        for k in 0..300 {
            let a = k as f32 * 0.37;
            let origin = [(a * 1.7).sin() * 3.0, (a * 2.3).cos() * 3.0, (a * 0.7).sin() * 3.0];
            let dir = [a.sin(), a.cos(), (a * 1.3).cos()];
            let jitter: Vec<[f32; 6]> = (0..LANES)
                .map(|i| [0.0, 0.0, 0.0, (i % 4) as f32 - 1.5, (i / 4) as f32 - 1.5, 0.5])
                .collect();
            let p = rays(&g, &bvh, (origin, dir), 0.5, &jitter, 0xffff);
            for isa in Isa::available() {
                let found = check_surfaces(&g, &bvh, &p, isa);
                if isa == Isa::Portable {
                    (0..3).for_each(|j| kinds[j] += found[j]);
                }
            }
        }
        assert!(
            kinds.iter().all(|&n| n > 200),
            "too few hits of some kind (sphere, triangle, other): {kinds:?}"
        );
    }
}
