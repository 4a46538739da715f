//! The shadow rays of a packet's hit points toward one light, set up
//! lane-wise: the light direction and N·L of each point, the robust
//! origin and end offsets of [`crate::math::shadow_ray`], and the per-ray
//! constants of [`crate::math::RayQuery`], written straight into a
//! [`RayPacket`]. Operation for operation the scalar code of
//! `Whitted::light_ray`, `shadow_ray`, `offset_ray_origin` and
//! `RayQuery::new` (with [`crate::simd::vec3`]), so every lane gets the
//! bits a ray set up alone gets, and images do not depend on packets.

use crate::packet::{Lanes, Mask, Permutations, RayPacket, LANES};
use crate::simd::vec3::{div3, dot, load3, neg3, normalize, offset, select3, sub3};
use crate::simd::vector::{group_active, group_bits, F32s};

/// Hit points of a packet in structure-of-arrays form: position, geometric
/// and shading normals (both facing the incoming ray).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub struct PointLanes {
    /// Positions.
    pub p: [Lanes; 3],
    /// Geometric normals.
    pub ng: [Lanes; 3],
    /// Shading normals.
    pub ns: [Lanes; 3],
}

impl Default for PointLanes {
    fn default() -> Self {
        let zero = [Lanes([0.0; LANES]); 3];
        PointLanes { p: zero, ng: zero, ns: zero }
    }
}

/// What shading needs of each lane's light: the unit direction to it and
/// N·L (shading normal).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub struct LightLanes {
    /// Direction to the light.
    pub l: [Lanes; 3],
    /// Shading normal · `l`.
    pub n_dot_l: Lanes,
}

impl Default for LightLanes {
    fn default() -> Self {
        LightLanes { l: [Lanes([0.0; LANES]); 3], n_dot_l: Lanes([0.0; LANES]) }
    }
}

/// Which lanes came how far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadowLanes {
    /// Lanes whose light faces the point: a shadow ray is counted.
    pub counted: Mask,
    /// Lanes with a shadow ray in the packet (the segment is not empty).
    pub rays: Mask,
}

crate::dispatch! {
    /// Shadow rays from the points of `valid` lanes toward `light[i]`,
    /// written to `out` (its other lanes emptied), with each lane's light
    /// direction and N·L in `dirs`.
    pub fn shadow_rays(
        isa: Isa,
        at: &PointLanes,
        light: &[Lanes; 3],
        valid: Mask,
        out: &mut RayPacket,
        dirs: &mut LightLanes,
    ) -> ShadowLanes {
        shadow_rays_body::<V>(at, light, valid, out, dirs)
    }
}

#[inline(always)]
fn shadow_rays_body<V: F32s>(
    at: &PointLanes,
    light: &[Lanes; 3],
    valid: Mask,
    out: &mut RayPacket,
    dirs: &mut LightLanes,
) -> ShadowLanes {
    let zero = V::splat(0.0);
    let (mut counted, mut rays) = (0, 0);
    let mut perm = Permutations::default();
    out.clear();
    for g in 0..LANES / V::W {
        if !group_active::<V>(valid, g) {
            continue;
        }
        let (p, pos) = (load3::<V>(&at.p, g), load3::<V>(light, g));
        let (ng, ns) = (load3::<V>(&at.ng, g), load3::<V>(&at.ns, g));
        let to_light = sub3(pos, p);
        let dist = dot(to_light, to_light).sqrt();
        let l = div3(to_light, dist);
        let n_dot_l = dot(ns, l);
        // Counted unless dist == 0 or N·L <= 0 (NaN goes on, as in scalar).
        let stop = V::bits(V::or(dist.eq(zero), n_dot_l.le(zero)));
        let group = V::bits(zero.eq(zero));
        counted |= (!stop & group) << (g * V::W);
        let front = zero.le(dot(ng, l));
        let side = select3(front, ng, neg3(ng));
        let origin = offset(p, side);
        let d = normalize(sub3(pos, origin));
        let end = offset(pos, neg3(d));
        let max = dot(sub3(end, origin), d);
        rays |= group_bits::<V>(zero.lt(max), g);
        for a in 0..3 {
            l[a].store(&mut dirs.l[a].0, g);
            origin[a].store(&mut out.o[a].0, g);
            d[a].store(&mut out.d[a].0, g);
        }
        n_dot_l.store(&mut dirs.n_dot_l.0, g);
        zero.store(&mut out.t_min.0, g);
        max.store(&mut out.t_max.0, g);
        perm.add::<V>(out, d, g);
    }
    let counted = counted & valid;
    let rays = rays & counted;
    perm.finish(out);
    out.activate(rays);
    ShadowLanes { counted, rays }
}
