//! Meshes imported from OBJ ([`obj`]) and glTF 2.0 ([`gltf`]): polygons in
//! world space with optional per-corner normals and NFF materials, in a
//! compact layout (a million triangles is a few tens of megabytes), plus
//! what the file says about each face's look (texture and vertex colours
//! averaged per face, [`texture`]; emission) and its cameras.

pub mod gltf;
mod gltf_checks;
pub mod obj;
pub mod resource;
pub mod texture;

pub use resource::ImportOptions;

use crate::scene::Material;
use glam::DVec3;
use std::path::Path;
use thiserror::Error;

/// One corner of a face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// Index into [`Mesh::positions`] (shared between faces, for smoothing).
    pub position: u32,
    /// The normal the file gives this corner, if any.
    pub normal: Option<DVec3>,
}

/// A face: `count` consecutive corners starting at `first`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    /// First corner.
    pub first: u32,
    /// Number of corners (3 or more).
    pub count: u32,
    /// Index into [`Mesh::materials`].
    pub material: u32,
    /// The face's own colour, replacing its material's: the base colour
    /// times the texture and vertex colours averaged over the face.
    pub color: Option<[f32; 3]>,
    /// The light the face emits (linear RGB, unbounded); `None` when dark.
    pub emission: Option<[f32; 3]>,
}

impl Face {
    /// A face in its material's colour, emitting nothing.
    pub fn plain(first: u32, count: u32, material: u32) -> Face {
        Face { first, count, material, color: None, emission: None }
    }

    /// Set the face's emission; one that is black in every channel is none.
    pub(crate) fn set_emission(&mut self, e: DVec3) {
        self.emission = (e.max_element() > 0.0).then(|| e.as_vec3().to_array());
    }
}

/// A light of the file (glTF KHR_lights_punctual), in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshLight {
    /// "point", "spot" or "directional".
    pub kind: &'static str,
    /// Where it is (point and spot lights).
    pub position: DVec3,
    /// Where it shines (spot and directional lights: the node's -z).
    pub direction: DVec3,
    /// Linear RGB colour times intensity (candela, or lux when directional).
    pub power: DVec3,
}

/// A perspective camera of the file, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshCamera {
    /// The camera's name in the file, if any.
    pub name: Option<String>,
    /// Eye position.
    pub from: DVec3,
    /// Viewing direction (unit).
    pub direction: DVec3,
    /// Up direction (unit, perpendicular to `direction`).
    pub up: DVec3,
    /// Vertical field of view between the image's top and bottom edges, radians.
    pub yfov: f64,
    /// Width over height, when the file fixes it.
    pub aspect: Option<f64>,
    /// Near clipping distance.
    pub znear: f64,
}

/// An imported mesh.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// World-space positions.
    pub positions: Vec<DVec3>,
    /// Face corners.
    pub corners: Vec<Corner>,
    /// Faces, counter-clockwise seen from the front.
    pub faces: Vec<Face>,
    /// Materials; faces without one use index 0, the default.
    pub materials: Vec<Material>,
    /// The perspective cameras of the file's scene, in the order met.
    pub cameras: Vec<MeshCamera>,
    /// Things that were dropped or approximated, for the user.
    pub warnings: Vec<String>,
    /// The file's lights.
    pub lights: Vec<MeshLight>,
    /// Degenerate triangles the importer dropped (strip stitching,
    /// repeated indices), which are not among `faces`.
    pub dropped_degenerate: usize,
}

impl Mesh {
    /// The corners of a face.
    pub fn corners_of(&self, f: &Face) -> &[Corner] {
        &self.corners[f.first as usize..(f.first + f.count) as usize]
    }
}

/// Why a mesh could not be imported.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{path}: {error}")]
    Io {
        /// The file.
        path: String,
        /// The cause (not a `source()`: the message already says it).
        error: std::io::Error,
    },
    /// The file is broken; the message says where.
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong (with the line, accessor or buffer where known).
        message: String,
    },
}

impl MeshError {
    pub(crate) fn invalid(path: &Path, message: impl Into<String>) -> MeshError {
        MeshError::Invalid { path: path.display().to_string(), message: message.into() }
    }
}

/// Import by extension: `.obj`, `.gltf` or `.glb`, with the default options.
pub fn load(path: &Path) -> Result<Mesh, MeshError> {
    load_with(path, &ImportOptions::default())
}

/// Import by extension: `.obj`, `.gltf` or `.glb`.
pub fn load_with(path: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let mesh = match ext.as_deref() {
        Some("obj") => obj::load(path, opts)?,
        Some("gltf") | Some("glb") => gltf::load(path, opts)?,
        _ => {
            return Err(MeshError::invalid(
                path,
                "not a mesh file this tool reads (use .obj, .gltf or .glb)",
            ));
        }
    };
    validate(path, mesh)
}

/// Import OBJ text from elsewhere (standard input): `name` is how messages
/// call it, `dir` where material libraries are looked for.
pub fn load_obj_bytes(
    bytes: &[u8],
    name: &Path,
    dir: &Path,
    opts: &ImportOptions,
) -> Result<Mesh, MeshError> {
    validate(name, obj::load_bytes(bytes, name, dir, opts)?)
}

/// Import glTF or GLB bytes read elsewhere: `name` is how messages call
/// the file, and the files it refers to are looked for beside it.
pub fn load_gltf_bytes(bytes: &[u8], name: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    validate(name, gltf::load_bytes(bytes, name, opts)?)
}

/// What every importer's mesh must satisfy: finite positions, some faces.
fn validate(path: &Path, mesh: Mesh) -> Result<Mesh, MeshError> {
    if let Some((i, _)) = mesh.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(MeshError::invalid(path, format!("position {i} is not a finite number")));
    }
    if mesh.faces.is_empty() {
        let why =
            if mesh.warnings.is_empty() { String::new() } else { format!(" ({})", mesh.warnings.join("; ")) };
        return Err(MeshError::invalid(path, format!("the mesh has no faces{why}")));
    }
    Ok(mesh)
}
