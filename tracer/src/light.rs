//! Lights as the shader sees them: NFF's positional lights with their
//! intensity resolved (a light without a colour gets SPD's 1/sqrt(n)), and
//! the area `--light-size` gives each for soft shadows (P3D report §2.2).

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
    /// area, or from the light's very position, its position.
    #[inline]
    pub(crate) fn seen_from(&self, p: Vec3A, size: f32, shape: LightShape, u: Vec2) -> Vec3A {
        let center = self.position;
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
