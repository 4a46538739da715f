//! Axis-aligned bounding boxes and the slab ray-box test (Kay and Kajiya).

use crate::math::RayQuery;
use glam::Vec3A;

/// An axis-aligned box; empty when `min > max` on any axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3A,
    /// Upper corner.
    pub max: Vec3A,
}

/// Widening of the exit distance that makes the f32 slab test conservative:
/// 1 + 2γ₃ with γₙ = nε/(1−nε) (pbrt-v4, section 6.8.2), so a box is never
/// missed because of rounding and every accelerator finds the same hits.
pub const SLAB_WIDEN: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// How far past a ray's best hit (or its end) a box's computed entry may
/// lie and the box still be entered. When the hit lies on the box's face
/// the entry and the hit are two roundings of one distance, so a box holding
/// a primitive tied with the best hit (two polygons meeting at an edge) or
/// blocking a shadow ray at its very end may come out a few ulps beyond;
/// culling only past this margin lets every accelerator find what brute
/// force finds.
pub const ENTRY_SLACK: f32 = SLAB_WIDEN * SLAB_WIDEN;

impl Aabb {
    /// The empty box: a union with it changes nothing.
    pub const EMPTY: Aabb = Aabb { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };

    /// A box from two corners.
    pub fn new(min: Vec3A, max: Vec3A) -> Aabb {
        Aabb { min, max }
    }

    /// Smallest box holding both.
    #[inline]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Smallest box holding this one and a point.
    #[inline]
    pub fn grow(self, p: Vec3A) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// Edge lengths (zero or negative for empty boxes).
    #[inline]
    pub fn size(&self) -> Vec3A {
        self.max - self.min
    }

    /// Half the surface area (the SAH only compares areas); 0 when empty.
    #[inline]
    pub fn half_area(&self) -> f32 {
        let d = self.size().max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// Entry and exit distances of the ray within `[t_min, t_max]`, or `None`.
    ///
    /// Robust for rays parallel to a slab (1/d is clamped, never NaN) and for
    /// boxes of zero thickness (axis-aligned polygons): entry equals exit and
    /// the box still counts as hit.
    #[inline]
    pub fn hit(&self, q: &RayQuery, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        let t1 = (self.min - q.ray.o) * q.inv_d;
        let t2 = (self.max - q.ray.o) * q.inv_d;
        let near = t1.min(t2).max_element().max(t_min);
        let far = (t1.max(t2).min_element() * SLAB_WIDEN).min(t_max);
        (near <= far).then_some((near, far))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;

    fn q(o: [f32; 3], d: [f32; 3]) -> RayQuery {
        RayQuery::new(Ray::new(Vec3A::from(o), Vec3A::from(d)), 0.0)
    }

    fn unit() -> Aabb {
        Aabb::new(Vec3A::ZERO, Vec3A::ONE)
    }

    #[test]
    fn entry_and_exit_distances() {
        let (a, b) = unit().hit(&q([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]), 0.0, f32::INFINITY).unwrap();
        assert!((a - 1.0).abs() < 1e-6 && (b - 2.0).abs() < 1e-5);
    }

    #[test]
    fn parallel_rays_inside_and_outside_a_slab() {
        assert!(unit().hit(&q([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]), 0.0, 10.0).is_some());
        assert!(unit().hit(&q([-1.0, 1.5, 0.5], [1.0, 0.0, 0.0]), 0.0, 10.0).is_none());
    }

    #[test]
    fn flat_box_is_hit() {
        let flat = Aabb::new(Vec3A::new(0.0, 0.0, 0.0), Vec3A::new(1.0, 1.0, 0.0));
        let (a, b) = flat.hit(&q([0.5, 0.5, 1.0], [0.0, 0.0, -1.0]), 0.0, 10.0).unwrap();
        assert!((a - 1.0).abs() < 1e-6 && (b - 1.0).abs() < 1e-5);
        assert!(flat.hit(&q([0.5, 0.5, 1.0], [0.0, 0.0, 1.0]), 0.0, 10.0).is_none());
    }

    #[test]
    fn respects_the_interval() {
        assert!(unit().hit(&q([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]), 0.0, 0.5).is_none());
        assert!(unit().hit(&q([-1.0, 0.5, 0.5], [-1.0, 0.0, 0.0]), 0.0, 10.0).is_none());
    }

    #[test]
    fn empty_box() {
        assert!(Aabb::EMPTY.size().cmplt(Vec3A::ZERO).all(), "holds no point");
        assert_eq!(Aabb::EMPTY.union(unit()), unit());
        assert_eq!(Aabb::EMPTY.half_area(), 0.0);
    }
}
