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

use glam::DVec3;
use nffkit_formats::{Material, Scene, View};
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

/// A view's camera as the writers need it: the unit frame `render`'s
/// camera uses (right = forward x up), the pixel size at unit distance in
/// the scene's dialect, the image size and a near distance.
pub(crate) struct Frame {
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    /// One pixel's side on an image plane at unit distance.
    pub pixel: f64,
    pub width: u32,
    pub height: u32,
    /// The hither distance, or a thousandth of the view distance where it
    /// is 0 (glTF and Mitsuba need a positive one).
    pub near: f64,
}

impl Frame {
    pub fn of(v: &View, scene: &Scene) -> Frame {
        let [width, height] = v.resolution;
        let forward = (v.at - v.from).normalize();
        let right = forward.cross(v.up.normalize()).normalize();
        Frame {
            forward,
            right,
            up: right.cross(forward),
            pixel: v.pixel_size(scene.dialect, width, height),
            width,
            height,
            near: if v.hither > 0.0 { v.hither } else { 1e-3 * (v.at - v.from).length() },
        }
    }

    /// The vertical field of view, edge to edge, in radians.
    pub fn vertical_fov(&self) -> f64 {
        2.0 * (self.pixel * self.height as f64 * 0.5).atan()
    }
}

/// Material `i` as the writers number them: 0 the default (before any
/// `f`), `i + 1` the scene's `i`-th.
pub(crate) fn material(scene: &Scene, i: usize) -> Material {
    i.checked_sub(1).map_or_else(Material::default, |i| scene.materials[i].clone())
}

/// What a light's intensity is multiplied by where lights fall off with
/// the square of the distance (glTF, Mitsuba): that distance to the
/// scene's centre, squared, so that the light there is NFF's (which does
/// not fall off).
pub(crate) fn falloff_scale(scene: &Scene, light: DVec3) -> f64 {
    let centre = scene.bounds().map_or(DVec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
    (light - centre).length_squared().max(1e-12)
}
