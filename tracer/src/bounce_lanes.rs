//! The mirror and refracted rays of a packet's hits, lane-wise: for each
//! lane, the mirror direction (about the shading normal, or about the
//! geometric one where that would dive below the surface), the refracted
//! direction (Snell's law with the lane's ratio of indices) and whether it
//! exists, and both rays' robust origins.
//!
//! Ray by ray, `Whitted::spawn` was a chain of dependent square roots and
//! divisions per hit (12% of a 16 spp render of mount_s7, after the
//! surface records went lane-wise). Here the geometry is computed for a
//! vector of lanes at once, operation for operation as `Whitted::mirror`,
//! [`crate::math::reflect`], [`crate::math::refract`] and
//! [`crate::math::offset_ray_origin`] compute it (see
//! [`crate::simd::vec3`]), so every lane gets the bits its ray gets alone;
//! which rays a hit spawns (by material and weight) is still decided lane
//! by lane, by the same code as for single rays.

use crate::packet::{Lanes, Mask, LANES};
use crate::shadow_lanes::PointLanes;
use crate::simd::vec3::{add3, dot, load3, neg3, normalize, offset, scale3, select3, store3, sub3};
use crate::simd::vector::{group_active, group_bits, F32s};

/// The secondary rays' geometry at each lane's hit.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub struct BounceLanes {
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
    /// The lanes set up (the rest hold nothing).
    pub want: Mask,
}

impl Default for BounceLanes {
    fn default() -> Self {
        let zero = [Lanes([0.0; LANES]); 3];
        BounceLanes { mirror_o: zero, mirror_d: zero, refract_o: zero, refract_d: zero, refracts: 0, want: 0 }
    }
}

crate::dispatch! {
    /// The bounces of the hits at `at` (normals facing the rays) of rays
    /// with directions `d`, for the lanes of `want`; `eta` is each lane's
    /// ratio of indices of refraction (incident over transmitted).
    pub fn bounces(
        isa: Isa,
        at: &PointLanes,
        d: &[Lanes; 3],
        eta: &Lanes,
        want: Mask,
        out: &mut BounceLanes,
    ) {
        bounces_body::<V>(at, d, eta, want, out)
    }
}

/// [`crate::math::reflect`]: `d - 2 (d · n) n`.
#[inline(always)]
fn reflect<V: F32s>(d: [V; 3], n: [V; 3]) -> [V; 3] {
    sub3(d, scale3(V::splat(2.0).mul(dot(d, n)), n))
}

#[inline(always)]
fn bounces_body<V: F32s>(at: &PointLanes, d: &[Lanes; 3], eta: &Lanes, want: Mask, out: &mut BounceLanes) {
    let (zero, one) = (V::splat(0.0), V::splat(1.0));
    let mut refracts = 0;
    for g in 0..LANES / V::W {
        if !group_active::<V>(want, g) {
            continue;
        }
        let (p, ng, ns, d) =
            (load3::<V>(&at.p, g), load3::<V>(&at.ng, g), load3::<V>(&at.ns, g), load3::<V>(d, g));
        // `Whitted::mirror`: about ns, unless that leaves below the surface.
        let (about_ns, about_ng) = (reflect(d, ns), reflect(d, ng));
        let mirror = select3(zero.lt(dot(about_ns, ng)), about_ns, about_ng);
        store3(offset(p, ng), &mut out.mirror_o, g);
        store3(mirror, &mut out.mirror_d, g);
        // `refract(d, ns, eta)`, kept where it leaves through the surface.
        let eta = V::load(&eta.0, g);
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
