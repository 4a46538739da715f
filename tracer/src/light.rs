//! Lights as the shader sees them: NFF's positional lights with their
//! intensity resolved (a light without a colour gets SPD's 1/sqrt(n)). Soft
//! shadows sample an area around each one (`integrator::LightShape`).

use glam::Vec3A;

/// A light as the shader sees it.
#[derive(Debug, Clone, Copy)]
pub struct PointLight {
    /// Position.
    pub position: Vec3A,
    /// RGB intensity.
    pub intensity: Vec3A,
}
