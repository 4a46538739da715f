//! Rays and the small vector helpers the tracer shares.

use glam::{Vec3A, Vec3Swizzles};
use std::ops::{Add, Mul};

/// A ray with unit direction; `t` along it is a distance.
#[derive(Debug, Clone, Copy)]
pub struct Ray {
    /// Origin.
    pub o: Vec3A,
    /// Unit direction.
    pub d: Vec3A,
}

impl Ray {
    /// A ray from `o` along `d` (normalised here).
    #[inline]
    pub fn new(o: Vec3A, d: Vec3A) -> Ray {
        Ray { o, d: d.normalize() }
    }

    /// The point at distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        self.o + self.d * t
    }
}

/// Per-ray constants shared by every box and triangle test of one traversal.
#[derive(Debug, Clone, Copy)]
pub struct RayQuery {
    /// The ray.
    pub ray: Ray,
    /// Component-wise 1/d, clamped to ±1e30 so that 0 × 1/d is never NaN.
    pub inv_d: Vec3A,
    /// Which components of 1/d are negative (which slab plane is near);
    /// taken from 1/d, not d, so that −0 is handled consistently.
    pub neg: [bool; 3],
    /// Watertight triangle test: the axis d is largest along, and the two
    /// others in an order that keeps the winding (Woop, Benthin and Wald,
    /// "Watertight Ray/Triangle Intersection", JCGT 2013).
    pub k: [usize; 3],
    /// Shear constants (Sx, Sy, Sz) of the same test.
    pub shear: Vec3A,
    /// Smallest accepted distance (the hither plane for eye rays, else 0).
    pub t_min: f32,
}

/// The axis of `v`'s largest component, the first of equals in x, y, z
/// order.
#[inline(always)]
pub fn largest_axis(v: Vec3A) -> usize {
    if v.x >= v.y && v.x >= v.z {
        0
    } else if v.y >= v.z {
        1
    } else {
        2
    }
}

impl RayQuery {
    /// Precompute everything a traversal needs for `ray`.
    #[inline]
    pub fn new(ray: Ray, t_min: f32) -> RayQuery {
        let d = ray.d;
        let inv = Vec3A::ONE / d;
        let inv_d = inv.clamp(Vec3A::splat(-1e30), Vec3A::splat(1e30));
        let kz = largest_axis(d.abs());
        // The permutation, and d permuted by it with swizzles (indexing a
        // vector by a variable goes through memory); then one vector
        // division gives the three shear constants.
        let ((kx, ky), p) = match (kz, d[kz] < 0.0) {
            (0, false) => ((1, 2), d.yzx()),
            (0, true) => ((2, 1), d.zyx()),
            (1, false) => ((2, 0), d.zxy()),
            (1, true) => ((0, 2), d.xzy()),
            (_, false) => ((0, 1), d),
            (_, true) => ((1, 0), d.yxz()),
        };
        let shear = Vec3A::new(p.x, p.y, 1.0) / Vec3A::splat(p.z);
        RayQuery {
            ray,
            inv_d,
            neg: [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0],
            k: [kx, ky, kz],
            shear,
            t_min,
        }
    }
}

/// γₙ = nε/(1 − nε), with ε half the f32 machine epsilon: the bound on the
/// relative rounding error of n floating-point operations (Higham; pbrt-v4
/// section 6.8.1).
pub(crate) const fn gamma(n: u32) -> f32 {
    let e = f32::EPSILON * 0.5;
    n as f32 * e / (1.0 - n as f32 * e)
}

/// `a > b ? a : b`: the comparison the lane-wise kernels' `max` makes, so a
/// scalar bound and its lane-wise twin agree bit for bit.
#[inline(always)]
pub(crate) fn max_of(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The bound of pbrt-v4 (section 6.8.4) on the rounding error of the
/// watertight triangle test's distance: from the largest sheared vertex
/// coordinates (`max_x`, `max_y`, and `max_z` already scaled by Sz), the
/// largest edge function `max_e`, and |1/det|. A hit nearer than this may
/// lie behind the origin: a ray leaving a large polygon from (nearly) its
/// own plane would otherwise find that polygon again. On `f32`, or lane by
/// lane on a vector of them (the same operations in the same order).
#[inline(always)]
pub(crate) fn triangle_t_error<T>(max_x: T, max_y: T, max_z: T, max_e: T, inv_det_abs: T) -> T
where
    T: Copy + Add<Output = T> + Mul<Output = T>,
    f32: Mul<T, Output = T>,
{
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det_abs
}

/// An orthonormal basis around a unit vector `n` (Duff et al., "Building an
/// Orthonormal Basis, Revisited", JCGT 2017).
#[inline]
pub fn basis(n: Vec3A) -> (Vec3A, Vec3A) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3A::new(b, sign + n.y * n.y * a, -n.y))
}

/// Mirror direction of `d` about the normal `n`.
#[inline]
pub fn reflect(d: Vec3A, n: Vec3A) -> Vec3A {
    d - 2.0 * d.dot(n) * n
}

/// Refract unit direction `d` through a surface with unit normal `n` facing
/// the incoming side, `eta` = n_incident / n_transmitted (Snell's law).
/// `None` on total internal reflection.
#[inline]
pub fn refract(d: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| (eta * d + (eta * cos_i - k.sqrt()) * n).normalize())
}

/// A unit normal `n` as computed, or `-d` (facing the ray along `d`) where
/// there was none to compute: a zero-length vector normalises to NaN (a
/// point computed exactly at a sphere's centre, far along a ray whose
/// single-precision origin is coarse) or, overflowing, to zero. The packet
/// surface records make the same choice lane by lane.
#[inline]
pub fn normal_or_facing(n: Vec3A, d: Vec3A) -> Vec3A {
    if n.dot(n) > 0.5 {
        n
    } else {
        -d
    }
}

/// Move a surface point off the surface along the normal `n` (pointing to the
/// side the new ray leaves from), by a few units in the last place of its own
/// coordinates rather than by a fixed epsilon (Wächter and Binder, "A Fast and
/// Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019).
#[inline]
pub fn offset_ray_origin(p: Vec3A, n: Vec3A) -> Vec3A {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let mut out = [0.0f32; 3];
    for i in 0..3 {
        let of_i = (INT_SCALE * n[i]) as i32;
        let bits = p[i].to_bits() as i32;
        // Wrapping: near zero (where the result is not used) a negative zero's
        // bits, i32::MIN, would overflow; where it is used it never wraps.
        let p_i = f32::from_bits(bits.wrapping_add(if p[i] < 0.0 { -of_i } else { of_i }) as u32);
        out[i] = if p[i].abs() < ORIGIN { p[i] + FLOAT_SCALE * n[i] } else { p_i };
    }
    Vec3A::from_array(out)
}

/// The shadow ray from surface point `p` to a light at `light`, leaving on
/// the side of normal `side`, and its length: the segment is shortened at
/// both ends by the same robust offset, off the surface at `p` and short of
/// the light, so a light lying in the plane of a polygon (a lamp on a wall)
/// is not shadowed by that polygon through rounding. `None` when nothing is
/// left of the segment.
#[inline]
pub fn shadow_ray(p: Vec3A, light: Vec3A, side: Vec3A) -> Option<(Ray, f32)> {
    let origin = offset_ray_origin(p, side);
    let dir = (light - origin).normalize();
    let end = offset_ray_origin(light, -dir);
    let max = (end - origin).dot(dir);
    (max > 0.0).then_some((Ray { o: origin, d: dir }, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsetting_negative_zero_does_not_overflow() {
        let p = Vec3A::new(-0.0, -0.0, 2.0);
        let o = offset_ray_origin(p, Vec3A::new(-1.0, -1.0, -1.0));
        assert!(o.x < 0.0 && o.y < 0.0 && o.z < 2.0, "{o}");
    }

    #[test]
    fn refraction_obeys_snell() {
        let n = Vec3A::Y;
        let d = Vec3A::new(1.0, -1.0, 0.0).normalize();
        let t = refract(d, n, 1.0 / 1.5).unwrap();
        let sin_i = d.x;
        let sin_t = t.x;
        assert!((sin_i / sin_t - 1.5).abs() < 1e-5);
        assert!(t.y < 0.0);
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        let n = Vec3A::Y;
        // Leaving glass (eta = 1.5) at 60 degrees: sin 60 * 1.5 > 1.
        let d = Vec3A::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
        assert!(refract(d, n, 1.5).is_none());
        // At 30 degrees it still refracts.
        let d = Vec3A::new(30f32.to_radians().sin(), -30f32.to_radians().cos(), 0.0);
        assert!(refract(d, n, 1.5).is_some());
    }

    #[test]
    fn reflection_keeps_the_tangent_component() {
        let r = reflect(Vec3A::new(1.0, -1.0, 0.0), Vec3A::Y);
        assert_eq!(r, Vec3A::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn basis_is_orthonormal() {
        for n in [Vec3A::Z, -Vec3A::Z, Vec3A::new(1.0, 2.0, -3.0).normalize()] {
            let (a, b) = basis(n);
            assert!(a.dot(b).abs() < 1e-6 && a.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6);
            assert!((a.length() - 1.0).abs() < 1e-6 && (b.length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn offset_moves_off_the_surface_relative_to_magnitude() {
        for p in [Vec3A::new(1000.0, 0.0, 0.0), Vec3A::new(0.001, 0.0, 0.0), Vec3A::new(-3.0, 2.0, 1.0)] {
            let q = offset_ray_origin(p, Vec3A::X);
            assert!(q.x > p.x, "{p} -> {q}");
            assert!((q.x - p.x) < 1e-3 * p.x.abs().max(1.0));
        }
    }
}
