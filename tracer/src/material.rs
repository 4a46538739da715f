//! The surface description the shader uses: NFF's fill material (colour,
//! Kd, Ks, Shine, T, index of refraction, and P3F's specular colour), named
//! apart from the file's own `nffkit_formats::Material` (double precision,
//! as written), with the rule its transmission follows.

use glam::Vec3A;

/// An NFF `f` line as the Whitted shader reads it, in single precision.
#[derive(Debug, Clone, Copy)]
pub struct WhittedMaterial {
    /// Surface colour.
    pub color: Vec3A,
    /// Colour of the highlight and the mirror reflection (white in NFF).
    pub specular: Vec3A,
    /// Transmitters weigh their mirror and refracted rays by Fresnel's
    /// equations (P3F, or `render --fresnel`) rather than by Ks and T.
    pub fresnel: bool,
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

impl WhittedMaterial {
    /// The file's material; `fresnel` says which rule its transmission
    /// follows.
    pub fn new(m: &nffkit_formats::Material, fresnel: bool) -> WhittedMaterial {
        let v = |c: glam::DVec3| Vec3A::new(c.x as f32, c.y as f32, c.z as f32);
        WhittedMaterial {
            color: v(m.color),
            specular: v(m.specular),
            fresnel,
            kd: m.kd as f32,
            ks: m.ks as f32,
            shine: m.shine as f32,
            t: m.t as f32,
            ior: m.ior as f32,
        }
    }

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

    /// Whether its transmission follows Fresnel's equations.
    #[inline]
    pub(crate) fn fresnel_weighted(&self) -> bool {
        self.fresnel && self.t > 0.0
    }
}

impl From<&nffkit_formats::Material> for WhittedMaterial {
    /// The classic NFF rule (no Fresnel weighting).
    fn from(m: &nffkit_formats::Material) -> WhittedMaterial {
        WhittedMaterial::new(m, false)
    }
}

/// The share of light a smooth dielectric reflects (unpolarised Fresnel
/// reflectance, the mean of the s and p terms), for a ray meeting it at
/// `cos_i` (cosine to the normal on its side) with `eta` = incident over
/// transmitted index; 1 on total internal reflection. Pharr, Jakob and
/// Humphreys, *Physically Based Rendering* (4th ed.), §9.3, `FrDielectric`.
#[inline]
pub fn fresnel_reflectance(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

#[cfg(test)]
mod tests {
    use super::fresnel_reflectance;

    #[test]
    fn fresnel_matches_the_closed_forms() {
        // Normal incidence: ((n1 - n2) / (n1 + n2))^2, from either side.
        for (n1, n2) in [(1.0f32, 1.5f32), (1.5, 1.0), (1.0, 2.4), (1.33, 1.0)] {
            let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
            assert!((fresnel_reflectance(1.0, n1 / n2) - r0).abs() < 1e-6, "{n1} -> {n2}");
        }
        // Grazing incidence reflects everything.
        assert!((fresnel_reflectance(0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
        assert!((fresnel_reflectance(1e-4, 1.0 / 1.5) - 1.0).abs() < 1e-3);
        // Past the critical angle (asin(1/1.5) = 41.8 degrees inside glass): total.
        let cos_at = |deg: f32| deg.to_radians().cos();
        assert_eq!(fresnel_reflectance(cos_at(45.0), 1.5), 1.0);
        assert!(fresnel_reflectance(cos_at(40.0), 1.5) < 1.0);
        // 45 degrees into glass, the textbook value: Rs = 0.0920, Rp = 0.0085.
        let r = fresnel_reflectance(cos_at(45.0), 1.0 / 1.5);
        assert!((r - 0.5 * (0.0920 + 0.0085)).abs() < 5e-4, "{r}");
        // An index of 1 reflects nothing.
        assert!(fresnel_reflectance(0.3, 1.0).abs() < 1e-7);
    }
}
