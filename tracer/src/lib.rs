//! nffkit's tracer: a Whitted ray tracer for NFF scenes.
//!
//! Data flows one way: a [`nffkit_formats::Scene`] is turned by
//! [`prepare::prepare`] into a [`prepare::RenderScene`] (camera, lights,
//! materials, flat primitive arrays and an accelerator), which
//! [`render::render`] turns into a [`film::Film`].
//!
//! The public modules are what a user of the library chooses and reads:
//! settings, the prepared scene, the image and the counters. The core
//! (primitives, accelerators, packets and their kernels, shading) is
//! private, so its invariants (a lane computes the bits its ray computes
//! alone, vectors exist only where their instructions do) hold by
//! construction; the benchmarks reach it through [`bench`].
//!
//! The hot loop (traversal and primitive tests) works on plain arrays indexed
//! by `u32`; there is no trait object per primitive and no allocation per ray.
#![deny(missing_docs)]
// Unsafe code is refused except in `simd`, where vectors are made under a
// proof that the processor has their instructions.
#![deny(unsafe_code)]

pub mod accel;
#[doc(hidden)]
pub mod bench;
pub mod camera;
pub mod environment;
pub mod film;
pub mod filter;
#[doc(hidden)]
pub mod fuzzing;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod light;
pub mod prepare;
pub mod probe;
pub mod progressive;
pub mod render;
pub mod sampling;
pub mod simd;
pub mod stats;
pub mod stopwatch;

mod aabb;
#[cfg(feature = "clap")]
mod cli;
mod geometry;
mod integrator;
mod material;
mod math;
mod packet;
mod query;
mod shadow_cache;
#[cfg(test)]
mod testing;

pub use glam::Vec3A;
