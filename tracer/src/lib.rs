//! nffkit's tracer: a Whitted ray tracer for NFF scenes.
//!
//! Data flows one way: a [`nffkit_formats::Scene`] is turned by
//! [`prepare::prepare`] into a [`prepare::RenderScene`] (camera, lights,
//! materials, flat primitive arrays and an accelerator), which
//! [`render::render`] turns into a [`film::Film`].
//!
//! The hot loop (traversal and primitive tests) works on plain arrays indexed
//! by `u32`; there is no trait object per primitive and no allocation per ray.
#![deny(missing_docs)]
// Unsafe code is refused except where `simd::dispatch!` calls kernels
// compiled for an instruction set the processor was checked to have.
#![deny(unsafe_code)]

pub mod aabb;
pub mod accel;
pub mod bounce_lanes;
pub mod camera;
#[cfg(feature = "clap")]
mod cli;
pub mod film;
pub mod filter;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod packet;
pub mod prepare;
pub mod render;
pub mod sampling;
pub mod shadow_cache;
pub mod shadow_lanes;
pub mod simd;
pub mod stats;
pub mod surface_lanes;
pub mod triangulate;

pub use glam::Vec3A;
