//! glTF 2.0 (`.gltf` with external or data-URI buffers, `.glb`) through the
//! `gltf` crate.
//!
//! The default scene (else the first, else every root node) is walked with
//! each node's world transform (parent × local, accumulated from the root);
//! a mesh used by several nodes is emitted once per instance; normals go
//! through the inverse transpose; a mirroring transform (negative
//! determinant) reverses the winding so faces keep facing out.
//!
//! Material rule ([`whitted_terms`]), which never turns a lit, coloured
//! surface black: colour = baseColorFactor; the mirror share
//! s = (0.04 + 0.96·metallic)·(1 − roughness) (smooth metals are mirrors,
//! rough surfaces are not); Ks = s·(1 − 0.2·metallic);
//! Kd = 0.8·(1 − s) + 0.2·metallic·s (the rest is diffuse in the base
//! colour, and a metal keeps a fifth of its mirror share as diffuse colour,
//! since NFF reflections cannot be tinted). The glTF defaults (metallic 1,
//! roughness 1, white) give Kd 0.8, Ks 0: light grey diffuse. Shine = 2/α² − 2
//! with α = roughness² (the Blinn-Phong exponent matching that GGX width),
//! clamped to [1, 10000]; T = KHR_materials_transmission's factor; index of
//! refraction = KHR_materials_ior (1.5 when transmissive and unspecified).

use super::{Corner, Face, Mesh, MeshError};
use crate::scene::Material;
use ::gltf::mesh::Mode;
use ::gltf::Gltf;
use glam::{DMat3, DMat4, DVec3};
use std::collections::HashMap;
use std::path::Path;

/// Required extensions that change geometry, which this importer cannot read.
const GEOMETRY_EXTENSIONS: [&str; 3] =
    ["KHR_draco_mesh_compression", "KHR_mesh_quantization", "EXT_meshopt_compression"];

/// Import a glTF or GLB file.
pub fn load(path: &Path) -> Result<Mesh, MeshError> {
    let bytes =
        std::fs::read(path).map_err(|error| MeshError::Io { path: path.display().to_string(), error })?;
    let raw = Gltf::from_slice_without_validation(&bytes).map_err(|e| {
        let why = if is_gltf_1(&bytes) {
            "glTF 1.0 is not supported (only glTF 2.0; convert it first)".to_string()
        } else {
            format!("not a readable glTF file: {e}")
        };
        MeshError::invalid(path, why)
    })?;
    for ext in raw.extensions_required() {
        if GEOMETRY_EXTENSIONS.contains(&ext) {
            return Err(MeshError::invalid(
                path,
                format!("requires the extension {ext}, which changes how geometry is stored; it is not supported (decompress the file first)"),
            ));
        }
    }
    let mut warnings = Vec::new();
    let gltf = validated(raw, &bytes, path, &mut warnings)?;
    let base = path.parent();
    check_buffer_files(&gltf.document, base, path)?;
    let buffers = ::gltf::import_buffers(&gltf.document, base, gltf.blob.clone())
        .map_err(|e| MeshError::invalid(path, format!("cannot load its buffers: {e}")))?;
    let doc = &gltf.document;
    let mut mesh = Mesh { materials: vec![Material::default()], warnings, ..Default::default() };
    mesh.materials.extend(doc.materials().map(convert_material));
    if doc.materials().any(|m| m.pbr_metallic_roughness().base_color_texture().is_some())
        || doc.textures().count() > 0
    {
        mesh.warnings.push("textures are ignored".into());
    }
    let roots: Vec<::gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> =
                doc.nodes().flat_map(|n| n.children().map(|c| c.index())).collect();
            doc.nodes().filter(|n| !children.contains(&n.index())).collect()
        }
    };
    let mut state = State { path, buffers: &buffers, skipped_modes: HashMap::new(), degenerate: 0 };
    for node in roots {
        state.walk(&mut mesh, &node, DMat4::IDENTITY, 0)?;
    }
    for (mode, n) in state.skipped_modes {
        mesh.warnings.push(format!("{n} primitives of mode {mode} (points or lines) skipped"));
    }
    if state.degenerate > 0 {
        mesh.warnings.push(format!(
            "{} degenerate triangles dropped (strip stitching or repeated indices)",
            state.degenerate
        ));
    }
    Ok(mesh)
}

/// Whether the bytes are a glTF 1.0 file: a GLB of version 1, or JSON whose
/// asset version starts with "1".
fn is_gltf_1(bytes: &[u8]) -> bool {
    if bytes.len() >= 8 && &bytes[..4] == b"glTF" {
        return u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]) == 1;
    }
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    text.find("\"version\"").is_some_and(|i| {
        let rest = text[i + 9..].trim_start_matches(|c: char| c.is_whitespace() || c == ':');
        rest.starts_with("\"1")
    })
}

/// The document, validated; the spec breaches that do not stop reading the
/// geometry become warnings: accessors without `min`/`max` (nothing here
/// needs them) and required extensions that do not change geometry
/// (texture transforms, material extensions).
fn validated(raw: Gltf, bytes: &[u8], path: &Path, warnings: &mut Vec<String>) -> Result<Gltf, MeshError> {
    use ::gltf::json::validation::Error as V;
    let errors = match Gltf::from_slice(bytes) {
        Ok(g) => return Ok(g),
        Err(::gltf::Error::Validation(errors)) => errors,
        Err(e) => return Err(MeshError::invalid(path, e.to_string())),
    };
    let mut fatal = Vec::new();
    let mut no_bounds = 0;
    for (where_, e) in &errors {
        let at = where_.to_string();
        match e {
            V::Missing if at.ends_with(".min") || at.ends_with(".max") => no_bounds += 1,
            V::Unsupported if at.starts_with("extensionsRequired") => warnings.push(format!(
                "{at}: not supported, but it does not change geometry; ignored (the look may differ)"
            )),
            _ => fatal.push(format!("{at}: {e}")),
        }
    }
    if !fatal.is_empty() {
        return Err(MeshError::invalid(path, format!("invalid glTF: {}", fatal.join("; "))));
    }
    if no_bounds > 0 {
        warnings.push(format!(
            "{} accessor bounds (`min`/`max`, required by the spec for positions) missing; computed from the data",
            no_bounds
        ));
    }
    Ok(raw)
}

/// Every external buffer file exists, or an error naming it.
fn check_buffer_files(doc: &::gltf::Document, base: Option<&Path>, path: &Path) -> Result<(), MeshError> {
    for b in doc.buffers() {
        if let ::gltf::buffer::Source::Uri(uri) = b.source() {
            if uri.starts_with("data:") {
                continue;
            }
            let file = base.unwrap_or(Path::new(".")).join(uri);
            if !file.is_file() {
                return Err(MeshError::invalid(
                    path,
                    format!(
                        "buffer {} is the file `{uri}`, which is missing (looked for {})",
                        b.index(),
                        file.display()
                    ),
                ));
            }
        }
    }
    Ok(())
}

struct State<'a> {
    path: &'a Path,
    buffers: &'a [::gltf::buffer::Data],
    skipped_modes: HashMap<&'static str, usize>,
    degenerate: usize,
}

impl State<'_> {
    fn walk(
        &mut self,
        mesh: &mut Mesh,
        node: &::gltf::Node,
        parent: DMat4,
        depth: usize,
    ) -> Result<(), MeshError> {
        if depth > 256 {
            return Err(MeshError::invalid(self.path, "node hierarchy deeper than 256 (a cycle?)"));
        }
        let local = node.transform().matrix().map(|c| c.map(f64::from));
        let world = parent * DMat4::from_cols_array_2d(&local);
        if let Some(m) = node.mesh() {
            for prim in m.primitives() {
                self.primitive(mesh, &prim, &world)?;
            }
        }
        for child in node.children() {
            self.walk(mesh, &child, world, depth + 1)?;
        }
        Ok(())
    }

    fn primitive(
        &mut self,
        mesh: &mut Mesh,
        prim: &::gltf::Primitive,
        world: &DMat4,
    ) -> Result<(), MeshError> {
        let mode = prim.mode();
        let name = match mode {
            Mode::Points => Some("POINTS"),
            Mode::Lines => Some("LINES"),
            Mode::LineLoop => Some("LINE_LOOP"),
            Mode::LineStrip => Some("LINE_STRIP"),
            _ => None,
        };
        if let Some(name) = name {
            *self.skipped_modes.entry(name).or_default() += 1;
            return Ok(());
        }
        let buffers = self.buffers;
        let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let accessor = prim.get(&::gltf::Semantic::Positions).map(|a| a.index());
        if let Some(a) = prim.get(&::gltf::Semantic::Positions) {
            if a.data_type() != ::gltf::accessor::DataType::F32 {
                return Err(MeshError::invalid(
                    self.path,
                    format!(
                        "POSITION accessor {} holds {:?} integers (quantized, KHR_mesh_quantization), which this importer does not read",
                        a.index(),
                        a.data_type()
                    ),
                ));
            }
        }
        let Some(positions) = reader.read_positions() else {
            return Err(MeshError::invalid(self.path, "a primitive has no POSITION attribute"));
        };
        let base = mesh.positions.len() as u32;
        for p in positions {
            let p = world.transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
            if !p.is_finite() {
                return Err(MeshError::invalid(
                    self.path,
                    format!(
                        "accessor {} holds a position that is not a finite number",
                        accessor.unwrap_or(0)
                    ),
                ));
            }
            mesh.positions.push(p);
        }
        let count = mesh.positions.len() as u32 - base;
        let normal_matrix = DMat3::from_mat4(*world).inverse().transpose();
        let normals: Option<Vec<DVec3>> = reader.read_normals().map(|it| {
            it.map(|n| {
                (normal_matrix * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)).normalize_or_zero()
            })
            .collect()
        });
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..count).collect(),
        };
        if let Some(bad) = indices.iter().find(|&&i| i >= count) {
            return Err(MeshError::invalid(
                self.path,
                format!("index {bad} is out of range for a primitive with {count} vertices"),
            ));
        }
        let mirrored = DMat3::from_mat4(*world).determinant() < 0.0;
        let material = prim.material().index().map_or(0, |i| i as u32 + 1);
        for mut t in triangles(mode, &indices) {
            if mirrored {
                t.swap(1, 2);
            }
            let p = t.map(|i| mesh.positions[(base + i) as usize]);
            if t[0] == t[1]
                || t[1] == t[2]
                || t[0] == t[2]
                || (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0
            {
                self.degenerate += 1;
                continue;
            }
            let first = mesh.corners.len() as u32;
            for i in t {
                let normal = normals.as_ref().and_then(|n| n.get(i as usize).copied());
                mesh.corners.push(Corner { position: base + i, normal });
            }
            mesh.faces.push(Face { first, count: 3, material });
        }
        Ok(())
    }
}

/// Triangles of a primitive as index triples, wound counter-clockwise.
fn triangles(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::Triangles => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        // Odd strip triangles are wound the other way; swap to keep CCW.
        Mode::TriangleStrip => {
            (0..idx.len().saturating_sub(2))
                .map(|i| {
                    if i % 2 == 0 {
                        [idx[i], idx[i + 1], idx[i + 2]]
                    } else {
                        [idx[i + 1], idx[i], idx[i + 2]]
                    }
                })
                .collect()
        }
        Mode::TriangleFan => (1..idx.len().saturating_sub(1)).map(|i| [idx[0], idx[i], idx[i + 1]]).collect(),
        _ => Vec::new(),
    }
}

fn convert_material(m: ::gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let metallic = pbr.metallic_factor().clamp(0.0, 1.0) as f64;
    let roughness = pbr.roughness_factor().clamp(0.0, 1.0) as f64;
    let alpha = (roughness * roughness).max(1e-3);
    let t = m.transmission().map_or(0.0, |t| t.transmission_factor() as f64);
    let ior = m.ior().map(f64::from).unwrap_or(if t > 0.0 { 1.5 } else { 1.0 });
    let (kd, ks) = whitted_terms(metallic, roughness);
    Material {
        color: DVec3::new(r as f64, g as f64, b as f64),
        kd,
        ks,
        shine: (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 10000.0),
        t,
        ior,
    }
}

/// NFF's (Kd, Ks) for glTF's metallic and roughness factors (module doc).
pub fn whitted_terms(metallic: f64, roughness: f64) -> (f64, f64) {
    let mirror = (0.04 + 0.96 * metallic) * (1.0 - roughness);
    (0.8 * (1.0 - mirror) + 0.2 * metallic * mirror, mirror * (1.0 - 0.2 * metallic))
}

#[cfg(test)]
mod tests {
    use super::whitted_terms;

    #[test]
    fn no_combination_is_black_and_the_extremes_are_as_documented() {
        assert_eq!(whitted_terms(1.0, 1.0), (0.8, 0.0), "glTF defaults: light grey diffuse");
        let (kd, ks) = whitted_terms(1.0, 0.0);
        assert!((kd - 0.2).abs() < 1e-12 && (ks - 0.8).abs() < 1e-12, "smooth metal: a mirror");
        assert_eq!(whitted_terms(0.0, 1.0), (0.8, 0.0), "rough dielectric: diffuse");
        for i in 0..=10 {
            for j in 0..=10 {
                let (kd, ks) = whitted_terms(i as f64 / 10.0, j as f64 / 10.0);
                assert!(kd >= 0.2 - 1e-12 && kd + ks <= 1.0 + 1e-12, "{i} {j}: {kd} {ks}");
            }
        }
    }
}
