//! The scene generators: the checkerboard plane of the P3D report
//! ([`planegen`]), the SPD sphereflake ([`sphereflake`]), and the built-in
//! default scene made of both ([`default_scene`]). Each generator's
//! options are one struct deriving `clap::Args`, which its binary and the
//! golden catalogue both parse.

pub mod default_scene;
pub mod planegen;
pub mod sphereflake;
