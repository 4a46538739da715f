//! A pixel's eye rays set up lane-wise: [`Camera::ray`] for up to
//! [`LANES`] raster points (and lens points, for a thin lens), operation
//! for operation, with each ray's per-ray constants, written straight
//! into a [`RayPacket`].

use super::{RayConstants, RayPacket};
use crate::camera::Camera;
use crate::math::Ray;
use crate::simd::lanes::{Lanes, Mask, LANES};
use crate::simd::vec3::{add3, dot, normalize, scale3, store3, sub3};
use crate::simd::vector::{group_active, F32s, Simd};
use glam::{Vec2, Vec3A};

/// Where each lane's eye ray is aimed: its raster position (`x`, `y`, as
/// [`Camera::ray`] takes them) and its point on the unit lens disc
/// (ignored by a pinhole).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct EyeLanes {
    pub x: Lanes,
    pub y: Lanes,
    pub lens: [Lanes; 2],
}

impl Default for EyeLanes {
    fn default() -> Self {
        EyeLanes { x: Lanes::ZERO, y: Lanes::ZERO, lens: [Lanes::ZERO; 2] }
    }
}

impl EyeLanes {
    /// Aim lane `i` at raster point `raster` through `lens`.
    #[inline]
    pub fn set(&mut self, i: usize, raster: Vec2, lens: Vec2) {
        (self.x.0[i], self.y.0[i], self.lens[0].0[i], self.lens[1].0[i]) =
            (raster.x, raster.y, lens.x, lens.y);
    }

    /// Lane `i`'s eye ray and its hither distance, ray by ray
    /// ([`Camera::ray`], which [`eye_rays`] repeats lane-wise).
    #[inline]
    pub fn ray(&self, i: usize, camera: &Camera) -> (Ray, f32) {
        camera.ray(self.x.0[i], self.y.0[i], Vec2::new(self.lens[0].0[i], self.lens[1].0[i]))
    }
}

crate::simd::dispatch! {
    /// The eye rays of `camera` through the points of the lanes of `mask`
    /// in `at`, from their hither distance on without end, into `out`
    /// (its other lanes emptied).
    pub(crate) fn eye_rays(isa: Isa, camera: &Camera, at: &EyeLanes, mask: Mask, out: &mut RayPacket) {
        |s| eye_rays_body(s, camera, at, mask, out)
    }
}

#[inline(always)]
fn eye_rays_body<V: F32s>(s: Simd<V>, camera: &Camera, at: &EyeLanes, mask: Mask, out: &mut RayPacket) {
    let (forward, right, up, pixel) = camera.frame();
    let (eye, forward) = (splat3(s, camera.eye), splat3(s, forward));
    let (right, up) = (splat3(s, right), splat3(s, up));
    let (width, height) = camera.resolution();
    let (half_w, half_h) = (s.splat(width as f32 * 0.5), s.splat(height as f32 * 0.5));
    let (pixel, hither) = (s.splat(pixel), s.splat(camera.hither));
    let mut constants = RayConstants::default();
    out.clear();
    for g in 0..LANES / V::W {
        if !group_active::<V>(mask, g) {
            continue;
        }
        let sx = s.load(&at.x.0, g).sub(half_w).mul(pixel);
        let sy = half_h.sub(s.load(&at.y.0, g)).mul(pixel);
        // forward + right * sx + up * sy, summed left to right.
        let dir = normalize(add3(add3(forward, scale3(sx, right)), scale3(sy, up)));
        let cos = dot(dir, forward);
        let (o, d, t_min) = if camera.aperture <= 0.0 {
            (eye, dir, hither.div(cos))
        } else {
            let focus_point = add3(eye, scale3(s.splat(camera.focus).div(cos), dir));
            let (lx, ly) = (s.load(&at.lens[0].0, g), s.load(&at.lens[1].0, g));
            let on_lens = scale3(s.splat(camera.aperture), add3(scale3(lx, right), scale3(ly, up)));
            let lens_point = add3(eye, on_lens);
            let d = normalize(sub3(focus_point, lens_point));
            (lens_point, d, hither.div(dot(d, forward)))
        };
        store3(o, &mut out.o, g);
        store3(d, &mut out.d, g);
        t_min.store(&mut out.t_min.0, g);
        s.splat(f32::INFINITY).store(&mut out.t_max.0, g);
        constants.add(s, out, d, g);
    }
    constants.finish(out, mask);
}

/// `v` in every lane.
#[inline(always)]
fn splat3<V: F32s>(s: Simd<V>, v: Vec3A) -> [V; 3] {
    [s.splat(v.x), s.splat(v.y), s.splat(v.z)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::lanes::lane;
    use crate::simd::Isa;
    use glam::DVec3;
    use nffkit_formats::View;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

        /// Every lane's ray, its constants and its hither distance are the
        /// bits `Camera::ray` and `RayQuery::new` give, for pinholes and
        /// thin lenses, every instruction set.
        #[test]
        fn eye_rays_set_up_lane_wise_equal_the_camera_rays(
            from in prop::array::uniform3(-5.0f64..5.0),
            at in prop::array::uniform3(-5.0f64..5.0),
            angle in 10.0f64..120.0,
            (w, h) in (2u32..700, 2u32..700),
            points in prop::collection::vec(prop::array::uniform4(0.0f32..1.0), LANES),
            aperture in prop::sample::select(vec![0.0f32, 0.05, 0.7]),
            mask in any::<u16>(),
        ) {
            let view = View {
                lens: None,
                from: DVec3::from(from),
                at: DVec3::from(at) + DVec3::new(0.0, 0.0, 0.5),
                up: DVec3::new(0.1, 0.2, 1.0),
                angle,
                hither: 0.01,
                resolution: [w, h],
            };
            let camera = Camera::new(&view, w, h).with_lens(aperture, None);
            let mut eye = EyeLanes::default();
            for (i, p) in points.iter().enumerate() {
                eye.set(i, Vec2::new(p[0] * w as f32, p[1] * h as f32), Vec2::new(p[2] * 2.0 - 1.0, p[3] * 2.0 - 1.0));
            }
            let mask = u32::from(mask) | 1;
            for isa in Isa::available() {
                let mut packet = RayPacket::empty();
                eye_rays(isa, &camera, &eye, mask, &mut packet);
                prop_assert_eq!(packet.active, mask);
                for i in (0..LANES).filter(|i| mask >> i & 1 != 0) {
                    let (ray, t_min) = camera.ray(eye.x.0[i], eye.y.0[i], Vec2::new(eye.lens[0].0[i], eye.lens[1].0[i]));
                    let want = crate::math::RayQuery::new(ray, t_min);
                    let got = packet.query(i);
                    let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
                    prop_assert_eq!(bits(got.ray.o), bits(want.ray.o), "{} lane {} origin", isa, i);
                    prop_assert_eq!(bits(lane(&packet.d, i)), bits(want.ray.d), "{} lane {} direction", isa, i);
                    prop_assert_eq!(bits(got.inv_d), bits(want.inv_d));
                    prop_assert_eq!(bits(got.shear), bits(want.shear));
                    prop_assert_eq!((got.neg, got.k), (want.neg, want.k));
                    prop_assert_eq!(got.t_min.to_bits(), want.t_min.to_bits(), "{} lane {} hither", isa, i);
                    prop_assert_eq!(packet.t_max.0[i], f32::INFINITY);
                }
            }
        }
    }
}
