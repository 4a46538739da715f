//! Wavefront OBJ (with MTL materials) through the `tobj` crate.
//!
//! Material mapping: colour = Kd / max(Kd) (the brightest channel becomes 1),
//! NFF Kd = max(Kd), Ks = max(Ks), Shine = Ns, T = 1 − d (or `Tr`), index of
//! refraction = Ni. A missing or broken `.mtl` is a warning and the default
//! material.

use super::{Corner, Face, Mesh, MeshError};
use crate::scene::Material;
use glam::DVec3;
use std::io::BufReader;
use std::path::Path;

fn options() -> tobj::LoadOptions {
    tobj::LoadOptions { single_index: false, triangulate: false, ignore_points: true, ignore_lines: true }
}

/// Drop the texture and normal references of every face line (`f 1/2/3` →
/// `f 1`), for files whose faces name attributes that do not exist.
fn strip_face_attributes(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("f ") || t.starts_with("f\t") {
            out.push('f');
            for v in t[1..].split_whitespace() {
                out.push(' ');
                out.push_str(v.split('/').next().unwrap_or(v));
            }
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

/// Drop lines tobj refuses although exporters write them (`usemtl` with no
/// name, from Blender), with a warning each, and the `l` (polyline) and `p`
/// (point) elements, which tobj would read as faces and NFF cannot show,
/// with one warning counting them. Lines stay in place (as blanks) so line
/// numbers in later messages are the file's.
fn sanitize(text: &str, warnings: &mut Vec<String>) -> String {
    let mut out = String::with_capacity(text.len());
    let (mut lines, mut points) = (0, 0);
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("usemtl") if words.next().is_none() => {
                warnings.push(format!("line {}: `usemtl` without a name ignored", i + 1));
            }
            Some("l") => lines += 1,
            Some("p") => points += 1,
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    if lines + points > 0 {
        warnings.push(format!(
            "{lines} polyline (`l`) and {points} point (`p`) element{} skipped: NFF has no lines or points",
            if lines + points == 1 { "" } else { "s" }
        ));
    }
    out
}

/// The first face that names a vertex not defined before it (OBJ counts
/// `v` lines so far; negative indices count back), as a message.
fn bad_vertex_index(text: &str) -> Option<String> {
    let mut defined: i64 = 0;
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => defined += 1,
            Some("f") => {
                for w in words {
                    let Ok(k) = w.split('/').next().unwrap_or("").parse::<i64>() else { continue };
                    if k == 0 || k > defined || -k > defined {
                        return Some(format!(
                            "line {}: `{}` names vertex {k}, but {defined} vertices are defined before it",
                            i + 1,
                            line.trim()
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// For tobj's errors, which carry no position: the first line that cannot be
/// read as the failing kind of statement.
fn locate(text: &str, e: &tobj::LoadError) -> Option<String> {
    let keyword = match e {
        tobj::LoadError::PositionParseError => "v",
        tobj::LoadError::NormalParseError => "vn",
        tobj::LoadError::TexcoordParseError => "vt",
        tobj::LoadError::FaceParseError => "f",
        _ => return None,
    };
    text.lines().enumerate().find_map(|(i, line)| {
        let mut words = line.split_whitespace();
        if words.next() != Some(keyword) {
            return None;
        }
        let ok = if keyword == "f" {
            words.all(|w| w.split('/').all(|p| p.is_empty() || p.parse::<i64>().is_ok()))
        } else {
            words.all(|w| w.parse::<f64>().is_ok())
        };
        (!ok).then(|| format!("line {}: `{}`", i + 1, line.trim()))
    })
}

/// Import an OBJ file.
pub fn load(path: &Path) -> Result<Mesh, MeshError> {
    let bytes =
        std::fs::read(path).map_err(|error| MeshError::Io { path: path.display().to_string(), error })?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load_bytes(&bytes, path, &dir)
}

/// Import OBJ text read elsewhere (standard input): `name` is how messages
/// call it, `dir` where its material libraries are looked for.
pub fn load_bytes(bytes: &[u8], name: &Path, dir: &Path) -> Result<Mesh, MeshError> {
    let path = name;
    if bytes.starts_with(&[0xFE, 0xFF]) || bytes.starts_with(&[0xFF, 0xFE]) {
        return Err(MeshError::invalid(
            path,
            "the file is UTF-16 text; OBJ is read as UTF-8 (convert it first)",
        ));
    }
    let mut warnings = Vec::new();
    let text = sanitize(&String::from_utf8_lossy(bytes), &mut warnings);
    let mtl_warning = std::cell::RefCell::new(Vec::<String>::new());
    let loader = |p: &Path| {
        let full = dir.join(p);
        let r = tobj::load_mtl(&full);
        if let Err(e) = &r {
            mtl_warning
                .borrow_mut()
                .push(format!("material library {}: {e}; using the default material", full.display()));
        }
        r
    };
    let parse = |t: &str| tobj::load_obj_buf(&mut BufReader::new(t.as_bytes()), &options(), loader);
    let (models, materials) = match parse(&text) {
        Ok(r) => r,
        Err(tobj::LoadError::FaceNormalOutOfBounds | tobj::LoadError::FaceTexCoordOutOfBounds) => {
            warnings.push(
                "faces name texture or normal indices that do not exist: those attributes are dropped, the faces kept"
                    .to_string(),
            );
            parse(&strip_face_attributes(&text)).map_err(|e| MeshError::invalid(path, describe(&text, e)))?
        }
        Err(e) => return Err(MeshError::invalid(path, describe(&text, e))),
    };
    warnings.extend(mtl_warning.into_inner());
    let materials = materials.unwrap_or_default();
    let mut mesh = Mesh { materials: vec![Material::default()], warnings, ..Default::default() };
    mesh.materials.extend(materials.iter().map(convert_material));
    if materials.iter().any(|m| m.diffuse_texture.is_some()) {
        mesh.warnings.push("textures are ignored".into());
    }
    for model in &models {
        add_model(&mut mesh, &model.mesh, &model.name);
    }
    Ok(mesh)
}

fn describe(text: &str, e: tobj::LoadError) -> String {
    let at = locate(text, &e).map(|l| format!(" at {l}")).unwrap_or_default();
    match e {
        tobj::LoadError::FaceVertexOutOfBounds => {
            bad_vertex_index(text).unwrap_or_else(|| "a face names a vertex that does not exist".into())
        }
        other => format!("not a readable OBJ file: {other}{at}"),
    }
}

fn add_model(mesh: &mut Mesh, m: &tobj::Mesh, name: &str) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(m.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
    let has_normals = !m.normal_indices.is_empty() && m.normal_indices.len() == m.indices.len();
    if !m.normal_indices.is_empty() && !has_normals {
        mesh.warnings.push(format!("object {name}: only some faces have normals; normals dropped"));
    }
    let material = m.material_id.map_or(0, |i| i as u32 + 1);
    let material = if (material as usize) < mesh.materials.len() { material } else { 0 };
    // face_arities is empty when every face is a triangle.
    let arities: Box<dyn Iterator<Item = u32>> = if m.face_arities.is_empty() {
        Box::new(std::iter::repeat_n(3, m.indices.len() / 3))
    } else {
        Box::new(m.face_arities.iter().copied())
    };
    let mut k = 0usize;
    for n in arities {
        let first = mesh.corners.len() as u32;
        for j in k..k + n as usize {
            let normal = has_normals.then(|| {
                let i = m.normal_indices[j] as usize * 3;
                DVec3::new(m.normals[i], m.normals[i + 1], m.normals[i + 2])
            });
            mesh.corners.push(Corner { position: base + m.indices[j], normal });
        }
        k += n as usize;
        if n >= 3 {
            mesh.faces.push(Face { first, count: n, material });
        }
    }
}

fn convert_material(m: &tobj::Material) -> Material {
    let kd = m.diffuse.unwrap_or([0.8; 3]);
    let ks = m.specular.unwrap_or([0.0; 3]);
    let kd_w = kd.iter().copied().fold(0.0, f64::max);
    let color = if kd_w > 0.0 { DVec3::from_array(kd) / kd_w } else { DVec3::ONE };
    let t = match (m.dissolve, m.unknown_param.get("Tr").and_then(|t| t.trim().parse::<f64>().ok())) {
        (Some(d), _) => 1.0 - d,
        (None, Some(tr)) => tr,
        _ => 0.0,
    };
    Material {
        color,
        kd: kd_w,
        ks: ks.iter().copied().fold(0.0, f64::max),
        shine: m.shininess.unwrap_or(1.0).max(1.0),
        t: t.clamp(0.0, 1.0),
        ior: m.optical_density.unwrap_or(1.0),
    }
}
