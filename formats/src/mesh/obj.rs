//! Wavefront OBJ (with MTL materials) through the `tobj` crate.
//!
//! Material mapping: colour = Kd / max(Kd) (the brightest channel becomes 1),
//! NFF Kd = max(Kd), Ks = max(Ks), Shine = Ns, T = 1 − d (or `Tr`), index of
//! refraction = Ni. A missing or broken `.mtl` is a warning and the default
//! material.
//!
//! Per face: the diffuse texture (`map_Kd`, v pointing up as OBJ has it)
//! averaged over the face times that colour, and vertex colours
//! (`v x y z r g b`) averaged over the face's corners that carry one (so a
//! file where only some vertices are coloured keeps the material colour on
//! faces without any); emission is `Ke` times `map_Ke`'s mean. A texture
//! that is missing, undecodable or outside the model's folder is a warning
//! naming it, and the colour alone is used.

use super::resource::{resolve, ImportOptions};
use super::texture::Texture;
use super::{Corner, Face, Mesh, MeshError};
use crate::scene::Material;
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::io::BufReader;
use std::path::{Path, PathBuf};

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

/// Vertex colours by position (the bits of x, y, z as tobj reads them), so
/// that they survive tobj's renumbering of each object's vertices.
type VertexColors = HashMap<[u64; 3], DVec3>;

/// A `v x y z r g b` line's position and colour.
fn colored_vertex(words: &[&str]) -> Option<([u64; 3], DVec3)> {
    let n: Vec<f64> = words.iter().map(|w| w.parse().ok()).collect::<Option<_>>()?;
    (n.len() == 6).then(|| ([n[0].to_bits(), n[1].to_bits(), n[2].to_bits()], DVec3::new(n[3], n[4], n[5])))
}

/// Drop lines tobj refuses although exporters write them (`usemtl` with no
/// name, from Blender), with a warning each, and the `l` (polyline) and `p`
/// (point) elements, which tobj would read as faces and NFF cannot show,
/// with one warning counting them. Vertex colours are taken out into
/// `colors` (tobj misnumbers them when only some vertices have one). A
/// line ending in `\` goes on on the next; a comment may follow data on a
/// line; a vertex's fourth number (w, for rational curves) is dropped, as
/// tinyobjloader and assimp do for polygons. Whether each face (of three
/// corners or more, in file order) names normals goes to `face_normals`:
/// tobj gives a face without them another face's; `faces` counts the
/// triangles they make and finds the largest. Lines stay in place (as
/// blanks) so line numbers in later messages are the file's.
/// The most corners one face may have.
pub const MAX_FACE_CORNERS: usize = 1 << 20;

/// What [`sanitize`] counts of the faces.
#[derive(Debug, Default)]
struct FaceCounts {
    /// Triangles the faces make, corners − 2 each.
    triangles: u64,
    /// The most corners of a face, and its line.
    largest: (usize, usize),
}

fn sanitize(
    text: &str,
    warnings: &mut Vec<String>,
    colors: &mut VertexColors,
    face_normals: &mut Vec<bool>,
    faces: &mut FaceCounts,
) -> String {
    let mut out = String::with_capacity(text.len());
    let (mut lines, mut points, mut bad_colors) = (0, 0, 0);
    let raw: Vec<&str> = text.lines().collect();
    let mut i = 0;
    while i < raw.len() {
        let start = i;
        let mut line = std::borrow::Cow::Borrowed(raw[i]);
        while line.trim_end().ends_with('\\') && i + 1 < raw.len() {
            let kept = line.trim_end().trim_end_matches('\\').to_string();
            i += 1;
            line = std::borrow::Cow::Owned(format!("{kept} {}", raw[i]));
        }
        // The keywords this pass acts on, without copying the line.
        let first = line.split_whitespace().next();
        let keyword = ["usemtl", "l", "p", "v", "vt", "vn", "f"].into_iter().find(|k| first == Some(*k));
        let data = matches!(keyword, Some("v" | "vt" | "vn" | "f" | "l" | "p"));
        // A comment starts at a `#` after a space: `1.#IND` (MSVC's NaN)
        // is a word, not a number followed by a comment.
        let comment =
            line.match_indices('#').map(|(i, _)| i).find(|&i| line[..i].ends_with(char::is_whitespace));
        if let (true, Some(hash)) = (data, comment) {
            line = std::borrow::Cow::Owned(line[..hash].to_string());
        }
        let mut words = line.split_whitespace().skip(1);
        match keyword {
            Some("usemtl") if words.next().is_none() => {
                warnings.push(format!("line {}: `usemtl` without a name ignored", start + 1));
            }
            Some("l") => lines += 1,
            Some("p") => points += 1,
            Some("v") => {
                let rest: Vec<&str> = words.collect();
                match colored_vertex(&rest) {
                    Some((key, color)) => {
                        if color.is_finite() {
                            colors.entry(key).or_insert(color);
                        } else {
                            bad_colors += 1;
                        }
                        out.push_str(&format!("v {} {} {}", rest[0], rest[1], rest[2]));
                    }
                    None if rest.len() == 4 => {
                        out.push_str(&format!("v {} {} {}", rest[0], rest[1], rest[2]))
                    }
                    None => out.push_str(&line),
                }
            }
            Some("f") => {
                let (mut corners, mut with_normals) = (0, 0);
                for c in words {
                    corners += 1;
                    with_normals += c.split('/').nth(2).is_some_and(|n| !n.is_empty()) as usize;
                }
                if corners >= 3 {
                    face_normals.push(with_normals == corners);
                    faces.triangles += corners as u64 - 2;
                    if corners > faces.largest.0 {
                        faces.largest = (corners, start + 1);
                    }
                }
                out.push_str(&line);
            }
            _ => out.push_str(&line),
        }
        out.push('\n');
        for _ in start..i {
            out.push('\n');
        }
        i += 1;
    }
    if bad_colors > 0 {
        warnings.push(format!(
            "{bad_colors} vertex colour{} not a number (NaN or infinite); those colours are ignored",
            if bad_colors == 1 { " is" } else { "s are" }
        ));
    }
    if lines + points > 0 {
        warnings.push(format!(
            "{lines} polyline (`l`) and {points} point (`p`) element{} skipped: NFF has no lines or points",
            crate::plural(lines + points)
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
    // The keyword and how many numbers tobj needs after it.
    let (keyword, least) = match e {
        tobj::LoadError::PositionParseError => ("v", 3),
        tobj::LoadError::NormalParseError => ("vn", 3),
        tobj::LoadError::TexcoordParseError => ("vt", 2),
        tobj::LoadError::FaceParseError => ("f", 3),
        _ => return None,
    };
    text.lines().enumerate().find_map(|(i, line)| {
        let rest = line.trim_start().strip_prefix(keyword)?;
        if !rest.starts_with(char::is_whitespace) && !rest.is_empty() {
            return None;
        }
        let ok = |w: &str| {
            if keyword == "f" {
                w.split('/').all(|p| p.is_empty() || p.parse::<i64>().is_ok())
            } else {
                w.parse::<f64>().is_ok()
            }
        };
        let words: Vec<&str> = rest.split_whitespace().take_while(|w| !w.starts_with('#')).collect();
        let shown = line.trim();
        if let Some(bad) = words.iter().find(|w| !ok(w)) {
            // The column of the word, counting from 1 in characters.
            let offset = bad.as_ptr() as usize - line.as_ptr() as usize;
            let column = line[..offset].chars().count() + 1;
            return Some(format!("line {}, column {column}: `{bad}` is not a number in `{shown}`", i + 1));
        }
        (words.len() < least).then(|| {
            format!("line {}: `{shown}` has {} numbers, `{keyword}` needs {least}", i + 1, words.len())
        })
    })
}

/// Import an OBJ file.
pub fn load(path: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    let bytes =
        std::fs::read(path).map_err(|error| MeshError::Io { path: path.display().to_string(), error })?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load_bytes(&bytes, path, &dir, opts)
}

/// Import OBJ text read elsewhere (standard input): `name` is how messages
/// call it, `dir` where its material libraries are looked for.
pub fn load_bytes(bytes: &[u8], name: &Path, dir: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    let path = name;
    if bytes.starts_with(&[0xFE, 0xFF]) || bytes.starts_with(&[0xFF, 0xFE]) {
        return Err(MeshError::invalid(
            path,
            "the file is UTF-16 text; OBJ is read as UTF-8 (convert it first)",
        ));
    }
    let mut warnings = Vec::new();
    let mut colors = VertexColors::new();
    let mut face_normals = Vec::new();
    let mut faces = FaceCounts::default();
    let text =
        sanitize(&String::from_utf8_lossy(bytes), &mut warnings, &mut colors, &mut face_normals, &mut faces);
    if faces.triangles > opts.max_triangles {
        return Err(MeshError::invalid(
            path,
            format!(
                "the faces make {} triangles, more than {} (--max-triangles raises the bound)",
                faces.triangles, opts.max_triangles
            ),
        ));
    }
    if faces.largest.0 > MAX_FACE_CORNERS {
        return Err(MeshError::invalid(
            path,
            format!(
                "line {}: a face of {} corners; at most {MAX_FACE_CORNERS} are read (a real model's largest \
                 faces have thousands)",
                faces.largest.1, faces.largest.0
            ),
        ));
    }
    let mtl_warning = std::cell::RefCell::new(Vec::<String>::new());
    // Textures are named relative to their library's folder.
    let mtl_dir = std::cell::RefCell::new(dir.to_path_buf());
    let loader = |p: &Path| {
        let full = match resolve(dir, &p.to_string_lossy(), opts) {
            Ok(full) => full,
            Err(why) => {
                mtl_warning.borrow_mut().push(format!("material library {why}; using the default material"));
                return Err(tobj::LoadError::OpenFileFailed);
            }
        };
        let r = tobj::load_mtl(&full);
        match &r {
            Ok(_) => *mtl_dir.borrow_mut() = full.parent().map(Path::to_path_buf).unwrap_or_default(),
            Err(e) => mtl_warning
                .borrow_mut()
                .push(format!("material library {}: {e}; using the default material", full.display())),
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
    let mut textures = Textures { dir: mtl_dir.into_inner(), opts, cache: HashMap::new(), total: 0 };
    let plain = Look { color: Material::default().color, ..Look::default() };
    let looks: Vec<Look> = std::iter::once(plain)
        .chain(
            materials
                .iter()
                .zip(&mesh.materials[1..])
                .map(|(m, nff)| Look::of(m, nff.color, &mut textures, &mut mesh.warnings)),
        )
        .collect();
    if !opts.textures
        && materials.iter().any(|m| m.diffuse_texture.is_some() || m.unknown_param.contains_key("map_Ke"))
    {
        mesh.warnings.push("textures are ignored (--no-textures)".into());
    }
    // tobj keeps faces in file order, model after model; if its count of
    // faces differs, the flags cannot be matched and every face keeps what
    // tobj gave it.
    let faces: usize = models.iter().map(|m| face_count(&m.mesh)).sum();
    let mut face_normals = (faces == face_normals.len()).then_some(face_normals.into_iter());
    for model in &models {
        add_model(&mut mesh, &model.mesh, &model.name, &looks, &colors, face_normals.as_mut());
    }
    Ok(mesh)
}

/// Textures named by the material library, each read once.
struct Textures<'a> {
    dir: PathBuf,
    opts: &'a ImportOptions,
    cache: HashMap<String, Option<std::rc::Rc<Texture>>>,
    /// Bytes of texels decoded so far, at most `opts.max_texture_bytes`.
    total: u64,
}

impl Textures<'_> {
    /// The texture a `map_*` statement names (options such as `-s 1 1 1`
    /// before the file name are skipped), or `None` with a warning.
    fn get(&mut self, statement: &str, warnings: &mut Vec<String>) -> Option<std::rc::Rc<Texture>> {
        if !self.opts.textures {
            return None;
        }
        let statement = statement.trim();
        let name = if statement.starts_with('-') {
            statement.split_whitespace().last().unwrap_or(statement)
        } else {
            statement
        };
        // Exporters on Windows write `textures\wood.png`.
        let name = &name.replace('\\', "/");
        if let Some(t) = self.cache.get(name) {
            return t.clone();
        }
        let loaded = resolve(&self.dir, name, self.opts)
            .and_then(|p| {
                let bytes = std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))?;
                let t = Texture::decode(&bytes).map_err(|e| format!("{}: {e}", p.display()))?;
                let max = self.opts.max_texture_bytes;
                if self.total + t.bytes() > max {
                    return Err(format!(
                        "{}: decoding it would take the textures past {max} bytes in all",
                        p.display()
                    ));
                }
                self.total += t.bytes();
                Ok(t)
            })
            .map_err(|why| warnings.push(format!("texture {why}; using the material colour alone")))
            .ok()
            .map(std::rc::Rc::new);
        self.cache.insert(name.clone(), loaded.clone());
        loaded
    }
}

/// What a material adds per face: textures and emission.
#[derive(Default)]
struct Look {
    diffuse: Option<std::rc::Rc<Texture>>,
    emission: Option<DVec3>,
    emission_texture: Option<std::rc::Rc<Texture>>,
    /// The material's NFF colour (Kd normalised), which textures multiply.
    color: DVec3,
}

impl Look {
    /// `color` is the material's NFF colour (from [`convert_material`]).
    fn of(m: &tobj::Material, color: DVec3, textures: &mut Textures, warnings: &mut Vec<String>) -> Look {
        let emission = m.emissive.map(DVec3::from_array).filter(|e| e.max_element() > 0.0);
        Look {
            diffuse: m.diffuse_texture.as_deref().and_then(|t| textures.get(t, warnings)),
            emission_texture: emission
                .and(m.unknown_param.get("map_Ke"))
                .and_then(|t| textures.get(t, warnings)),
            emission,
            color,
        }
    }
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

/// How many faces of three corners or more tobj read into `m`.
fn face_count(m: &tobj::Mesh) -> usize {
    if m.face_arities.is_empty() {
        m.indices.len() / 3
    } else {
        m.face_arities.iter().filter(|&&n| n >= 3).count()
    }
}

fn add_model(
    mesh: &mut Mesh,
    m: &tobj::Mesh,
    name: &str,
    looks: &[Look],
    colors: &VertexColors,
    mut face_normals: Option<&mut std::vec::IntoIter<bool>>,
) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(m.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
    let has_normals = !m.normal_indices.is_empty() && m.normal_indices.len() == m.indices.len();
    if !m.normal_indices.is_empty() && !has_normals {
        mesh.warnings.push(format!("object {name}: only some faces have normals; normals dropped"));
    }
    let material = m.material_id.map_or(0, |i| i as u32 + 1);
    let material = if (material as usize) < mesh.materials.len() { material } else { 0 };
    let look = &looks[material as usize];
    let has_uvs = m.texcoord_indices.len() == m.indices.len() && !m.texcoords.is_empty();
    // OBJ's v runs up the image; the texture's rows run down.
    let uv = |j: usize| {
        let i = m.texcoord_indices[j] as usize * 2;
        DVec2::new(m.texcoords[i], 1.0 - m.texcoords[i + 1])
    };
    let mut uvs = Vec::new();
    let color_of = |j: usize| {
        let p = &m.positions[m.indices[j] as usize * 3..][..3];
        colors.get(&[p[0].to_bits(), p[1].to_bits(), p[2].to_bits()]).copied()
    };
    // face_arities is empty when every face is a triangle.
    let arities: Box<dyn Iterator<Item = u32>> = if m.face_arities.is_empty() {
        Box::new(std::iter::repeat_n(3, m.indices.len() / 3))
    } else {
        Box::new(m.face_arities.iter().copied())
    };
    let mut k = 0usize;
    for n in arities {
        let first = mesh.corners.len() as u32;
        // A face the file gave no normals gets none (its geometric normal).
        let named = n < 3 || face_normals.as_mut().and_then(|f| f.next()).unwrap_or(true);
        for j in k..k + n as usize {
            let normal = (has_normals && named).then(|| {
                let i = m.normal_indices[j] as usize * 3;
                DVec3::new(m.normals[i], m.normals[i + 1], m.normals[i + 2])
            });
            mesh.corners.push(Corner { position: base + m.indices[j], normal });
        }
        let range = k..k + n as usize;
        k += n as usize;
        if n < 3 {
            continue;
        }
        let mut face = Face::plain(first, n, material);
        uvs.clear();
        if has_uvs {
            uvs.extend(range.clone().map(uv));
        }
        let mut color = None;
        if let (Some(t), true) = (&look.diffuse, has_uvs) {
            color = Some(look.color * t.mean_over_face(&uvs));
        }
        if !colors.is_empty() {
            let (sum, count) =
                range.clone().filter_map(color_of).fold((DVec3::ZERO, 0), |(s, n), c| (s + c, n + 1));
            if count > 0 {
                color = Some(color.unwrap_or(look.color) * sum / count as f64);
            }
        }
        face.color = color.map(|c| c.as_vec3().to_array());
        if let Some(e) = look.emission {
            let tex = match (&look.emission_texture, has_uvs) {
                (Some(t), true) => t.mean_over_face(&uvs),
                _ => DVec3::ONE,
            };
            face.set_emission(e * tex);
        }
        mesh.faces.push(face);
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
        specular: DVec3::ONE,
        kd: kd_w,
        ks: ks.iter().copied().fold(0.0, f64::max),
        shine: m.shininess.unwrap_or(1.0).max(1.0),
        t: t.clamp(0.0, 1.0),
        ior: m.optical_density.unwrap_or(1.0),
    }
}
