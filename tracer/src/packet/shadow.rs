//! The shadow rays of a packet's hit points toward one light, set up
//! lane-wise: the light direction and N·L of each point, the robust
//! origin and end offsets of [`crate::math::shadow_ray`], and the per-ray
//! constants of [`crate::math::RayQuery`], written straight into a
//! [`RayPacket`]. Operation for operation the scalar code of
//! `Whitted::light_ray`, `shadow_ray`, `offset_ray_origin` and
//! `RayQuery::new`.

use super::{PointLanes, RayConstants, RayPacket};
use crate::simd::lanes::{Lanes, Mask, LANES};
use crate::simd::vec3::{div3, dot, load3, neg3, normalize, offset, select3, sub3};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};

/// What shading needs of each lane's light: the unit direction to it and
/// N·L (shading normal).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct LightLanes {
    /// Direction to the light.
    pub l: [Lanes; 3],
    /// Shading normal · `l`.
    pub n_dot_l: Lanes,
}

impl Default for LightLanes {
    fn default() -> Self {
        LightLanes { l: [Lanes::ZERO; 3], n_dot_l: Lanes::ZERO }
    }
}

/// Which lanes came how far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ShadowLanes {
    /// Lanes whose light faces the point: a shadow ray is counted.
    pub counted: Mask,
    /// Lanes with a shadow ray in the packet (the segment is not empty).
    pub rays: Mask,
}

crate::simd::dispatch! {
    /// Shadow rays from the points of `valid` lanes toward `light[i]`,
    /// written to `out` (its other lanes emptied), with each lane's light
    /// direction and N·L in `dirs`.
    pub(crate) fn shadow_rays(
        isa: Isa,
        at: &PointLanes,
        light: &[Lanes; 3],
        valid: Mask,
        out: &mut RayPacket,
        dirs: &mut LightLanes,
    ) -> ShadowLanes {
        |s| shadow_rays_body(s, at, light, valid, out, dirs)
    }
}

#[inline(always)]
fn shadow_rays_body<V: F32s>(
    s: Simd<V>,
    at: &PointLanes,
    light: &[Lanes; 3],
    valid: Mask,
    out: &mut RayPacket,
    dirs: &mut LightLanes,
) -> ShadowLanes {
    let zero = s.splat(0.0);
    let (mut counted, mut rays) = (0, 0);
    let mut constants = RayConstants::default();
    out.clear();
    for g in 0..LANES / V::W {
        if !group_active::<V>(valid, g) {
            continue;
        }
        let (p, pos) = (load3(s, &at.p, g), load3(s, light, g));
        let (ng, ns) = (load3(s, &at.ng, g), load3(s, &at.ns, g));
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
        constants.add(s, out, d, g);
    }
    let counted = counted & valid;
    let rays = rays & counted;
    constants.finish(out, rays);
    ShadowLanes { counted, rays }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{shadow_ray, RayQuery};
    use crate::simd::lanes::lane;
    use crate::simd::Isa;
    use glam::Vec3A;
    use proptest::prelude::*;

    /// The scalar setup of a shadow ray (`Whitted::light_ray`): the light
    /// direction, N·L, and the ray's query and length, or where it stops.
    fn scalar_shadow_ray(
        p: Vec3A,
        ng: Vec3A,
        ns: Vec3A,
        pos: Vec3A,
    ) -> (bool, Option<(Vec3A, f32, RayQuery, f32)>) {
        let to_light = pos - p;
        let dist = to_light.length();
        if dist == 0.0 {
            return (false, None);
        }
        let l = to_light / dist;
        let n_dot_l = ns.dot(l);
        if n_dot_l <= 0.0 {
            return (false, None);
        }
        let side = if ng.dot(l) >= 0.0 { ng } else { -ng };
        let ray = shadow_ray(p, pos, side);
        (true, ray.map(|(ray, max)| (l, n_dot_l, RayQuery::new(ray, 0.0), max)))
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        #[test]
        fn shadow_rays_set_up_lane_wise_equal_the_scalar_setup(
            points in prop::collection::vec((prop::array::uniform3(-3.0f32..3.0), prop::array::uniform3(-1.0f32..1.0), prop::array::uniform3(-1.0f32..1.0)), LANES),
            light in prop::array::uniform3(-4.0f32..4.0),
            tiny in any::<bool>(),
            valid in any::<u16>(),
        ) {
            let mut at = PointLanes::default();
            let mut pos = [Lanes::ZERO; 3];
            let mut scalar = Vec::new();
            for (i, (p, ng, ns)) in points.iter().enumerate() {
                // Near the origin (the offsets' float branch), exactly on the
                // light, and negative zeros, besides ordinary points.
                let scale = if tiny { 1e-3 } else { 1.0 };
                let mut p = Vec3A::from(*p) * scale;
                if i == 3 { p = Vec3A::new(-0.0, 0.0, -0.0); }
                let l = if i == 5 { p } else { Vec3A::from(light) };
                let (ng, ns) = (Vec3A::from(*ng).normalize_or(Vec3A::Z), Vec3A::from(*ns).normalize_or(Vec3A::Z));
                for a in 0..3 {
                    (at.p[a].0[i], at.ng[a].0[i], at.ns[a].0[i], pos[a].0[i]) = (p[a], ng[a], ns[a], l[a]);
                }
                scalar.push(scalar_shadow_ray(p, ng, ns, l));
            }
            for isa in Isa::available() {
                let mut packet = RayPacket::empty();
                let mut dirs = LightLanes::default();
                let valid = u32::from(valid);
                let lanes = shadow_rays(isa, &at, &pos, valid, &mut packet, &mut dirs);
                for (i, (counted, ray)) in scalar.iter().enumerate() {
                    let on = valid >> i & 1 != 0;
                    prop_assert_eq!(lanes.counted >> i & 1 != 0, on && *counted, "{} lane {} counted", isa, i);
                    prop_assert_eq!(lanes.rays >> i & 1 != 0, on && ray.is_some(), "{} lane {} ray", isa, i);
                    prop_assert_eq!(packet.active, lanes.rays);
                    let (Some((l, n_dot_l, q, max)), true) = (ray, on) else { continue };
                    let got = packet.query(i);
                    let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
                    prop_assert_eq!(bits(got.ray.o), bits(q.ray.o), "{} lane {} origin", isa, i);
                    prop_assert_eq!(bits(got.ray.d), bits(q.ray.d));
                    prop_assert_eq!(bits(got.inv_d), bits(q.inv_d));
                    prop_assert_eq!(bits(got.shear), bits(q.shear));
                    prop_assert_eq!((got.neg, got.k, got.t_min), (q.neg, q.k, q.t_min));
                    prop_assert_eq!(packet.t_max.0[i].to_bits(), max.to_bits());
                    prop_assert_eq!(bits(lane(&dirs.l, i)), bits(*l));
                    prop_assert_eq!(dirs.n_dot_l.0[i].to_bits(), n_dot_l.to_bits());
                }
            }
        }
    }
}
