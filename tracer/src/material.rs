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
