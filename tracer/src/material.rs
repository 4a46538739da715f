//! The surface description the shader uses: NFF's fill material (colour,
//! Kd, Ks, Shine, T, index of refraction), named apart from the file's own
//! `nffkit_formats::Material` (double precision, as written).

use glam::Vec3A;

/// An NFF `f` line as the Whitted shader reads it, in single precision.
#[derive(Debug, Clone, Copy)]
pub struct WhittedMaterial {
    /// Surface colour.
    pub color: Vec3A,
    /// Diffuse weight.
    pub kd: f32,
    /// Specular weight.
    pub ks: f32,
    /// Phong exponent.
    pub shine: f32,
    /// Transmittance.
    pub t: f32,
    /// Index of refraction.
    pub ior: f32,
}

impl From<&nffkit_formats::Material> for WhittedMaterial {
    fn from(m: &nffkit_formats::Material) -> WhittedMaterial {
        let c = m.color;
        WhittedMaterial {
            color: Vec3A::new(c.x as f32, c.y as f32, c.z as f32),
            kd: m.kd as f32,
            ks: m.ks as f32,
            shine: m.shine as f32,
            t: m.t as f32,
            ior: m.ior as f32,
        }
    }
}

impl WhittedMaterial {
    /// Whether a hit on it may spawn rays: it reflects or transmits.
    #[inline]
    pub(crate) fn spawns_rays(&self) -> bool {
        self.ks > 0.0 || self.t > 0.0
    }

    /// The ratio of indices of refraction across its surface, incident over
    /// transmitted, for a ray `entering` it or leaving.
    #[inline]
    pub(crate) fn eta(&self, entering: bool) -> f32 {
        if entering {
            1.0 / self.ior
        } else {
            self.ior
        }
    }
}
