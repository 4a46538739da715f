//! The scene generators: the checkerboard plane of the P3D report
//! ([`planegen`]), the SPD sphereflake ([`sphereflake`]), and the built-in
//! default scene made of both ([`default_scene`]). Each generator's
//! options are one struct deriving `clap::Args`, which its binary and the
//! golden catalogue both parse. A crate of its own, apart from the command
//! line tools, so the browser playground (WebAssembly) builds the same
//! scenes as `planegen` and `sphereflake`.

pub mod default_scene;
pub mod options;
pub mod planegen;
pub mod sphereflake;
