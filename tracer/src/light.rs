//! Lights as the shader sees them: NFF's positional lights with their
//! intensity resolved (a light without a colour gets SPD's 1/sqrt(n)), and
//! the area `--light-size` gives each for soft shadows (P3D report §2.2);
//! P3F's `al` lights bring their own rectangle, sampled the same way.

use crate::math::basis;
use crate::sampling::concentric_disk;
use glam::{Vec2, Vec3A};
use strum::{Display, IntoStaticStr, VariantArray};

/// A light as the shader sees it.
#[derive(Debug, Clone, Copy)]
pub struct PointLight {
    /// Position.
    pub position: Vec3A,
    /// RGB intensity.
    pub intensity: Vec3A,
    /// A P3F area light's rectangle (then `--light-size` does not apply).
    pub rect: Option<LightRect>,
}

/// A rectangle of light centred on the light's position: its two edges,
/// full length (`width · a` and `height · b` for unit axes `a`, `b`
/// across the direction it faces).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightRect {
    /// The edge along the width.
    pub u: Vec3A,
    /// The edge along the height.
    pub v: Vec3A,
}

impl LightRect {
    /// The rectangle `width` by `height` facing direction `n` (unit): its
    /// width runs level (across world up, y), its height up the face; a
    /// light facing straight up or down has its width along x and its
    /// height along z.
    pub fn facing(n: Vec3A, width: f32, height: f32) -> LightRect {
        let level = Vec3A::Y.cross(n);
        let a = if level.length_squared() > 1e-12 { level.normalize() } else { Vec3A::X };
        let b = n.cross(a).normalize_or_zero();
        LightRect { u: a * width, v: b * height }
    }
}

/// Shape of the area that `--light-size` gives each point light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum LightShape {
    /// A square of side `size`, facing the shaded point.
    #[default]
    Square,
    /// A disc of diameter `size`, facing the shaded point.
    Disk,
}

impl PointLight {
    /// Where the light is seen from `p` when it is given an area of `size`
    /// (side of a square or diameter of a disc) and `shape`, facing `p`:
    /// the point of that area at `u` in the unit square (one light sample;
    /// the caller draws `u` from the light's own sample dimension). With no
    /// area, or from the light's very position, its position. A light with
    /// its own rectangle is seen at the rectangle's point `u`.
    #[inline]
    pub(crate) fn seen_from(&self, p: Vec3A, size: f32, shape: LightShape, u: Vec2) -> Vec3A {
        let center = self.position;
        if let Some(r) = self.rect {
            return center + r.u * (u.x - 0.5) + r.v * (u.y - 0.5);
        }
        let offset = match shape {
            LightShape::Square => (u - Vec2::splat(0.5)) * size,
            LightShape::Disk => concentric_disk(u) * (0.5 * size),
        };
        let w = (p - center).normalize_or_zero();
        if w == Vec3A::ZERO {
            return center;
        }
        let (a, b) = basis(w);
        center + a * offset.x + b * offset.y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangles_face_their_direction_with_the_width_level() {
        let r = LightRect::facing(Vec3A::NEG_Y, 2.0, 1.0);
        assert_eq!((r.u, r.v.abs()), (Vec3A::X * 2.0, Vec3A::Z));
        let n = Vec3A::new(1.0, -1.0, 0.0).normalize();
        let r = LightRect::facing(n, 3.0, 0.5);
        assert!(r.u.dot(n).abs() < 1e-6 && r.v.dot(n).abs() < 1e-6);
        assert!(r.u.y.abs() < 1e-6, "the width is level");
        assert!((r.u.length() - 3.0).abs() < 1e-6 && (r.v.length() - 0.5).abs() < 1e-6);
        let light = PointLight { position: Vec3A::ONE, intensity: Vec3A::ONE, rect: Some(r) };
        let corner = light.seen_from(Vec3A::ZERO, 0.0, LightShape::Square, Vec2::ZERO);
        assert!((corner - (Vec3A::ONE - r.u * 0.5 - r.v * 0.5)).length() < 1e-6);
    }
}
