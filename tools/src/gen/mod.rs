//! The scene generators, from their own crate ([`nffkit_gen`]) so the
//! browser playground builds the same scenes.

pub use nffkit_gen::{default_scene, planegen, sphereflake};
