//! `nffconvert`: a scene out of NFF (or P3F) into another renderer's
//! language, so the same scene can be rendered elsewhere and compared.
//!
//! Each writer lives in its own file: `pov.rs` (POV-Ray 3.7 SDL), `obj.rs`
//! (Wavefront OBJ + MTL), `gltf.rs` (glTF 2.0, .gltf + .bin or .glb),
//! `mitsuba.rs` (Mitsuba 3 XML + PLY).
//! `triangles.rs` turns any scene into triangle lists by material, for the
//! formats that hold nothing else. Every writer returns what the target
//! cannot hold, one note a line; the binary writes the files atomically.

pub mod gltf;
pub mod mitsuba;
pub mod obj;
pub mod pov;
pub mod triangles;

use nffkit_formats::Dialect;
use std::path::Path;

/// The languages `nffconvert` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// NFF.
    Nff,
    /// The P3D course's P3F.
    P3f,
    /// POV-Ray 3.7 scene description (.pov).
    Pov,
    /// Wavefront OBJ with its MTL beside it (.obj).
    Obj,
    /// glTF 2.0, JSON with its .bin beside it (.gltf).
    Gltf,
    /// glTF 2.0, binary (.glb).
    Glb,
    /// Mitsuba 3 scene XML, with PLY files beside it (.xml).
    Mitsuba,
}

impl Format {
    /// The format an output's extension names.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "nff" => Format::Nff,
            "p3f" => Format::P3f,
            "pov" => Format::Pov,
            "obj" => Format::Obj,
            "gltf" => Format::Gltf,
            "glb" => Format::Glb,
            "xml" => Format::Mitsuba,
            _ => return None,
        })
    }

    /// The scene language, for NFF and P3F.
    pub fn dialect(self) -> Option<Dialect> {
        match self {
            Format::Nff => Some(Dialect::Nff),
            Format::P3f => Some(Dialect::P3f),
            _ => None,
        }
    }
}

/// How to render the exported scene, where the target language holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportOptions {
    /// Recursion limit, counting the eye ray as 1 (`render --depth`).
    pub depth: u32,
    /// Give each point light a square area of this side (`render
    /// --light-size`), 4x4 jittered in POV-Ray.
    pub area_light: Option<f64>,
    /// Lens radius (`render --aperture`).
    pub aperture: Option<f64>,
    /// Distance in focus (`render --focus`; default the from-at distance).
    pub focus: Option<f64>,
    /// Tessellation of spheres and cones for triangle-only formats: a
    /// sphere is six faces of N x N quadrilaterals, a cone 4N sides.
    pub tessellate: u32,
    /// Rays whose weight falls below this are not traced (`render
    /// --min-weight`; POV-Ray's `adc_bailout`).
    pub min_weight: f64,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            depth: 6,
            area_light: None,
            aperture: None,
            focus: None,
            tessellate: 8,
            min_weight: 0.0,
        }
    }
}

/// A number as the writers print it: the shortest text that reads back
/// to the same double.
pub(crate) fn num(x: f64) -> String {
    nffkit_formats::nff::format_number(x)
}

/// A vector as `x, y, z`.
pub(crate) fn vec3(v: glam::DVec3) -> String {
    format!("{}, {}, {}", num(v.x), num(v.y), num(v.z))
}
