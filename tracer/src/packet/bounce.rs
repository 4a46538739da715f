//! The mirror and refracted rays of a packet's hits, lane-wise: for each
//! lane, the mirror direction (about the shading normal, or about the
//! geometric one where that would dive below the surface), the refracted
//! direction (Snell's law with the lane's ratio of indices) and whether it
//! exists, and both rays' robust origins.
//!
//! The geometry is computed for a vector of lanes at once (ray by ray it
//! is a chain of dependent square roots and divisions per hit), operation
//! for operation as `Whitted::mirror`, [`crate::math::reflect`],
//! [`crate::math::refract`] and [`crate::math::offset_ray_origin`] compute
//! it; which rays a hit spawns (by material and weight) is decided lane by
//! lane, by the same code as for single rays.

use super::PointLanes;
use crate::simd::lanes::{Lanes, Mask, LANES};
use crate::simd::vec3::{add3, dot, load3, neg3, normalize, offset, scale3, select3, store3, sub3};
use crate::simd::vector::{group_active, group_bits, F32s, Simd};

/// The secondary rays' geometry at each lane's hit.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct BounceLanes {
    /// Mirror ray origins (off the surface on the side the ray came from).
    pub mirror_o: [Lanes; 3],
    /// Mirror ray directions.
    pub mirror_d: [Lanes; 3],
    /// Refracted ray origins (off the surface on the far side).
    pub refract_o: [Lanes; 3],
    /// Refracted ray directions (meaningful in the lanes of `refracts`).
    pub refract_d: [Lanes; 3],
    /// Lanes whose ray refracts: no total internal reflection, and the
    /// refracted direction leaves through the surface.
    pub refracts: Mask,
}

impl Default for BounceLanes {
    fn default() -> Self {
        let zero = [Lanes::ZERO; 3];
        BounceLanes { mirror_o: zero, mirror_d: zero, refract_o: zero, refract_d: zero, refracts: 0 }
    }
}

crate::simd::dispatch! {
    /// The bounces of the hits at `at` (normals facing the rays) of rays
    /// with directions `d`, for the lanes of `want`; `eta` is each lane's
    /// ratio of indices of refraction (incident over transmitted).
    pub(crate) fn bounces(
        isa: Isa,
        at: &PointLanes,
        d: &[Lanes; 3],
        eta: &Lanes,
        want: Mask,
        out: &mut BounceLanes,
    ) {
        |s| bounces_body(s, at, d, eta, want, out)
    }
}

/// [`crate::math::reflect`]: `d - 2 (d · n) n`.
#[inline(always)]
fn reflect<V: F32s>(s: Simd<V>, d: [V; 3], n: [V; 3]) -> [V; 3] {
    sub3(d, scale3(s.splat(2.0).mul(dot(d, n)), n))
}

#[inline(always)]
fn bounces_body<V: F32s>(
    s: Simd<V>,
    at: &PointLanes,
    d: &[Lanes; 3],
    eta: &Lanes,
    want: Mask,
    out: &mut BounceLanes,
) {
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let mut refracts = 0;
    for g in 0..LANES / V::W {
        if !group_active::<V>(want, g) {
            continue;
        }
        let (p, ng, ns, d) = (load3(s, &at.p, g), load3(s, &at.ng, g), load3(s, &at.ns, g), load3(s, d, g));
        // `Whitted::mirror`: about ns, unless that leaves below the surface.
        let (about_ns, about_ng) = (reflect(s, d, ns), reflect(s, d, ng));
        let mirror = select3(zero.lt(dot(about_ns, ng)), about_ns, about_ng);
        store3(offset(p, ng), &mut out.mirror_o, g);
        store3(mirror, &mut out.mirror_d, g);
        // `refract(d, ns, eta)`, kept where it leaves through the surface.
        let eta = s.load(&eta.0, g);
        let cos_i = dot(d, ns).neg();
        let k = one.sub(eta.mul(eta).mul(one.sub(cos_i.mul(cos_i))));
        let t = normalize(add3(scale3(eta, d), scale3(eta.mul(cos_i).sub(k.sqrt()), ns)));
        let leaves = V::and(zero.le(k), dot(t, ng).lt(zero));
        refracts |= group_bits::<V>(leaves, g);
        store3(offset(p, neg3(ng)), &mut out.refract_o, g);
        store3(t, &mut out.refract_d, g);
    }
    out.refracts = refracts & want;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{offset_ray_origin, reflect, refract};
    use crate::simd::lanes::lane;
    use crate::simd::Isa;
    use glam::Vec3A;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// The mirror and refracted rays set up lane-wise are the rays
        /// `Whitted::spawn` sets up alone, bit for bit: directions (the
        /// mirror about the shading normal unless it dives below the
        /// surface), which lanes refract, and both origins.
        #[test]
        fn bounces_set_up_lane_wise_equal_the_scalar_setup(
            hits in prop::collection::vec((prop::array::uniform3(-3.0f32..3.0), prop::array::uniform3(-1.0f32..1.0), prop::array::uniform3(-0.3f32..0.3), prop::array::uniform3(-1.0f32..1.0), 0.4f32..2.5), LANES),
            tiny in any::<bool>(),
            want in any::<u16>(),
        ) {
            let mut at = PointLanes::default();
            let (mut d, mut eta) = ([Lanes::ZERO; 3], Lanes::ZERO);
            let mut scalar = Vec::new();
            for (i, &(p, ng, tilt, dir, e)) in hits.iter().enumerate() {
                // Points near the origin (the offsets' float branch) too; the
                // normals face the ray, the shading normal tilted off the
                // geometric one as a patch's is.
                let p = Vec3A::from(p) * if tiny { 1e-3 } else { 1.0 };
                let ng = Vec3A::from(ng).normalize_or(Vec3A::Z);
                let ns = (ng + Vec3A::from(tilt)).normalize_or(ng);
                let mut dir = Vec3A::from(dir).normalize_or(-Vec3A::Z);
                if dir.dot(ng) > 0.0 { dir = -dir; }
                for a in 0..3 {
                    (at.p[a].0[i], at.ng[a].0[i], at.ns[a].0[i], d[a].0[i]) = (p[a], ng[a], ns[a], dir[a]);
                }
                eta.0[i] = e;
                let r = reflect(dir, ns);
                let mirror = if r.dot(ng) > 0.0 { r } else { reflect(dir, ng) };
                let refracted = refract(dir, ns, e).filter(|t| t.dot(ng) < 0.0);
                scalar.push((offset_ray_origin(p, ng), mirror, offset_ray_origin(p, -ng), refracted));
            }
            let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
            let want = u32::from(want);
            for isa in Isa::available() {
                let mut b = BounceLanes::default();
                bounces(isa, &at, &d, &eta, want, &mut b);
                prop_assert_eq!(b.refracts & !want, 0);
                for (i, (mo, md, ro, t)) in scalar.iter().enumerate().filter(|(i, _)| want >> i & 1 != 0) {
                    prop_assert_eq!(bits(lane(&b.mirror_o, i)), bits(*mo), "{} lane {} mirror origin", isa, i);
                    prop_assert_eq!(bits(lane(&b.mirror_d, i)), bits(*md), "{} lane {} mirror", isa, i);
                    prop_assert_eq!(b.refracts >> i & 1 != 0, t.is_some(), "{} lane {} refracts", isa, i);
                    if let Some(t) = t {
                        prop_assert_eq!(bits(lane(&b.refract_o, i)), bits(*ro), "{} lane {} refracted origin", isa, i);
                        prop_assert_eq!(bits(lane(&b.refract_d, i)), bits(*t), "{} lane {} refracted", isa, i);
                    }
                }
            }
        }
    }
}
