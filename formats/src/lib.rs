//! nffkit's file layer: the [`Scene`] data model, the NFF (and P3F) reader
//! and writer ([`nff`], [`dialect`] between the two), OBJ and glTF import ([`mesh`]), and image files ([`image_io`]).
//!
//! This crate knows nothing about ray tracing. It turns bytes into plain
//! records (with the source line each came from) and back; the `tracer` crate
//! builds cameras, shapes and accelerators from those records.
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod atomic;
pub mod dialect;
#[doc(hidden)]
pub mod fuzzing;
pub mod image_io;
pub mod mesh;
pub mod nff;
pub mod polygon;
pub mod scene;

/// The plural ending for `n` things in messages: "" for one, "s" otherwise.
pub fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

pub use scene::{
    box_faces, AxisBox, Color, Cone, Dialect, Directives, Lens, Light, LightArea, Material, Patch, Primitive,
    Scene, Shape, ShapeKind, SourceLine, View, SPD_SKY,
};
