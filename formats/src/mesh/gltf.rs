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
//!
//! Per face: colour = baseColorFactor × the base-colour texture averaged
//! over the face ([`super::texture`]) × the mean of its corners'
//! `COLOR_0`; emission = emissiveFactor × KHR_materials_emissive_strength ×
//! the emissive texture's mean. Images come from the GLB chunk, a data URI
//! or a file beside the model ([`super::resource`]); one that cannot be read
//! is a warning naming it, and the factor alone is used.
//!
//! Cameras: each node with a perspective camera in the scene walked, in the
//! order met, with its world position, direction (−Z) and up (+Y).

use super::resource::{read_uri, resolve, ImportOptions};
use super::texture::{Texture, Wrap};
use super::{Corner, Face, Mesh, MeshCamera, MeshError, MeshLight};
use crate::scene::Material;
use ::gltf::mesh::Mode;
use ::gltf::Gltf;
use glam::{DMat3, DMat4, DVec2, DVec3};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

/// Required extensions that change geometry, which this importer cannot read.
const GEOMETRY_EXTENSIONS: [&str; 3] =
    ["KHR_draco_mesh_compression", "KHR_mesh_quantization", "EXT_meshopt_compression"];

/// Extensions gltf-json calls unsupported that this importer reads.
const HANDLED_EXTENSIONS: [&str; 1] = ["EXT_mesh_gpu_instancing"];

/// Import a glTF or GLB file.
pub fn load(path: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    let bytes =
        std::fs::read(path).map_err(|error| MeshError::Io { path: path.display().to_string(), error })?;
    load_bytes(&bytes, path, opts)
}

/// Import glTF or GLB bytes read from `path` (which names the file in
/// messages; the files it refers to are looked for beside it).
pub fn load_bytes(bytes: &[u8], path: &Path, opts: &ImportOptions) -> Result<Mesh, MeshError> {
    let raw = match Gltf::from_slice_without_validation(bytes) {
        Ok(raw) => raw,
        // gltf-json 1.4.1 cannot read an animation channel without a node
        // (KHR_animation_pointer); animations are not converted anyway.
        Err(e) if e.to_string().contains("missing field `node`") => match without_animations(bytes) {
            Some(stripped) => {
                let mut mesh = load_bytes(&stripped, path, opts)?;
                mesh.warnings.push("animations skipped (NFF has none; some target no node)".into());
                return Ok(mesh);
            }
            None => return Err(unreadable(bytes, path, e)),
        },
        Err(e) => return Err(unreadable(bytes, path, e)),
    };
    for ext in raw.extensions_required() {
        if GEOMETRY_EXTENSIONS.contains(&ext) {
            return Err(MeshError::invalid(
                path,
                format!("requires the extension {ext}, which changes how geometry is stored; it is not supported (decompress the file first)"),
            ));
        }
    }
    let mut warnings = Vec::new();
    let gltf = validated(raw, path, opts, &mut warnings)?;
    let base = path.parent();
    check_buffer_files(&gltf.document, base, path, opts)?;
    let buffers = ::gltf::import_buffers(&gltf.document, base, gltf.blob.clone())
        .map_err(|e| MeshError::invalid(path, format!("cannot load its buffers: {e}")))?;
    let doc = &gltf.document;
    let mut mesh = Mesh { materials: vec![Material::default()], warnings, ..Default::default() };
    mesh.materials.extend(doc.materials().map(convert_material));
    if !opts.textures && doc.textures().count() > 0 {
        mesh.warnings.push("textures are ignored (--no-textures)".into());
    }
    let mut images = Images {
        dir: base.unwrap_or(Path::new(".")),
        buffers: &buffers,
        opts,
        decoded: vec![None; doc.textures().count()],
        images: vec![None; doc.images().count()],
        total: 0,
    };
    let mut looks = vec![Look::default_material()];
    for m in doc.materials() {
        looks.push(Look::of(&m, &mut images, &mut mesh.warnings));
    }
    let roots: Vec<::gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> =
                doc.nodes().flat_map(|n| n.children().map(|c| c.index())).collect();
            doc.nodes().filter(|n| !children.contains(&n.index())).collect()
        }
    };
    let mut state = State {
        path,
        doc,
        buffers: &buffers,
        looks: &looks,
        skipped_modes: HashMap::new(),
        degenerate: 0,
        compression: GEOMETRY_EXTENSIONS.into_iter().find(|e| doc.extensions_used().any(|u| u == *e)),
        orthographic: 0,
    };
    for node in roots {
        state.walk(&mut mesh, &node, DMat4::IDENTITY, 0)?;
    }
    for (mode, n) in state.skipped_modes {
        mesh.warnings.push(format!("{n} primitives of mode {mode} (points or lines) skipped"));
    }
    if state.orthographic > 0 {
        mesh.warnings.push(format!(
            "{} orthographic camera{} skipped: NFF views are perspective",
            state.orthographic,
            crate::plural(state.orthographic)
        ));
    }
    mesh.dropped_degenerate = state.degenerate;
    if state.degenerate > 0 {
        mesh.warnings.push(format!(
            "{} degenerate triangles dropped (strip stitching or repeated indices)",
            state.degenerate
        ));
    }
    Ok(mesh)
}

/// Why the bytes are no glTF this importer reads.
fn unreadable(bytes: &[u8], path: &Path, e: ::gltf::Error) -> MeshError {
    let why = if is_gltf_1(bytes) {
        "glTF 1.0 is not supported (only glTF 2.0; convert it first)".to_string()
    } else if e.to_string().contains("missing field `nodes`") {
        // Valid glTF (a scene's nodes are optional), which gltf-json
        // 1.4.1 cannot read; it has nothing to convert either way.
        "the scene has no nodes: nothing to convert".to_string()
    } else {
        format!("not a readable glTF file: {e}")
    };
    MeshError::invalid(path, why)
}

/// The file without its `animations` (JSON, or a GLB rebuilt around its
/// new JSON chunk); `None` when its JSON cannot be read or has none.
fn without_animations(bytes: &[u8]) -> Option<Vec<u8>> {
    let strip = |json: &[u8]| -> Option<Vec<u8>> {
        let mut v: serde_json::Value = serde_json::from_slice(json).ok()?;
        v.as_object_mut()?.remove("animations")?;
        serde_json::to_vec(&v).ok()
    };
    if !bytes.starts_with(b"glTF") {
        return strip(bytes);
    }
    let glb = ::gltf::Glb::from_slice(bytes).ok()?;
    let mut json = strip(&glb.json)?;
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut bin = glb.bin.map(|b| b.into_owned());
    if let Some(b) = &mut bin {
        while b.len() % 4 != 0 {
            b.push(0);
        }
    }
    let length = 12 + 8 + json.len() + bin.as_ref().map_or(0, |b| 8 + b.len());
    let mut out = Vec::with_capacity(length);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&u32::try_from(length).ok()?.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if let Some(b) = bin {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    Some(out)
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
fn validated(
    raw: Gltf,
    path: &Path,
    opts: &ImportOptions,
    warnings: &mut Vec<String>,
) -> Result<Gltf, MeshError> {
    use ::gltf::json::validation::{Error as V, Validate};
    // Files gltf would panic on, or that would expand past the bounds,
    // are refused here first.
    let missing = super::gltf_checks::problems(raw.document.as_json(), opts);
    if !missing.is_empty() {
        return Err(MeshError::invalid(path, format!("invalid glTF: {}", missing.join("; "))));
    }
    // The document read once, validated as gltf's own `from_slice` would.
    let mut errors = Vec::new();
    let json = raw.document.as_json();
    json.validate(json, ::gltf::json::Path::new, &mut |at, e| errors.push((at(), e)));
    if errors.is_empty() {
        return Ok(raw);
    }
    let mut fatal = Vec::new();
    let mut no_bounds = 0;
    for (where_, e) in &errors {
        let at = where_.to_string();
        match e {
            V::Missing if at.ends_with(".min") || at.ends_with(".max") => no_bounds += 1,
            V::Unsupported if at.starts_with("extensionsRequired") => {
                let index = at.trim_start_matches("extensionsRequired[").trim_end_matches(']').parse().ok();
                let name = index.and_then(|i: usize| raw.extensions_required().nth(i));
                if !name.is_some_and(|n| HANDLED_EXTENSIONS.contains(&n)) {
                    warnings.push(format!(
                        "{at}{}: not supported, but it does not change geometry; ignored (the look may differ)",
                        name.map(|n| format!(" ({n})")).unwrap_or_default()
                    ));
                }
            }
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

/// Every external buffer file is inside the model's folder (unless allowed)
/// and exists, or an error naming it.
fn check_buffer_files(
    doc: &::gltf::Document,
    base: Option<&Path>,
    path: &Path,
    opts: &ImportOptions,
) -> Result<(), MeshError> {
    for b in doc.buffers() {
        if let ::gltf::buffer::Source::Uri(uri) = b.source() {
            if uri.starts_with("data:") {
                continue;
            }
            let file = resolve(base.unwrap_or(Path::new(".")), &super::resource::percent_decode(uri), opts)
                .map_err(|why| MeshError::invalid(path, format!("buffer {}: {why}", b.index())))?;
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

/// The textures of the document, each decoded once, on first use.
struct Images<'a> {
    dir: &'a Path,
    buffers: &'a [::gltf::buffer::Data],
    opts: &'a ImportOptions,
    /// Per texture: not yet tried, or the outcome.
    decoded: Vec<Option<Option<Rc<Texture>>>>,
    /// Per image: not yet tried, or the outcome (the decoded texels, which
    /// every texture of the image shares, or why not).
    images: Vec<Option<Result<Texture, String>>>,
    /// Bytes of texels decoded so far, at most `opts.max_texture_bytes`.
    total: u64,
}

impl Images<'_> {
    /// The texture, or `None` with a warning naming the image.
    fn get(&mut self, texture: &::gltf::Texture, warnings: &mut Vec<String>) -> Option<Rc<Texture>> {
        if !self.opts.textures {
            return None;
        }
        if let Some(done) = &self.decoded[texture.index()] {
            return done.clone();
        }
        let Some(image) = texture.source() else {
            // Only in an extension's form (KHR_texture_basisu, EXT_texture_webp).
            warnings.push(format!(
                "texture {} has its image only in an extension's format, which mesh2nff cannot decode; \
                 using the factor alone",
                texture.index()
            ));
            self.decoded[texture.index()] = Some(None);
            return None;
        };
        let (name, decoded) = self.image(&image);
        let decoded = decoded
            .map(|mut t| {
                let sampler = texture.sampler();
                t.wrap = [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())];
                Rc::new(t)
            })
            .map_err(|why| warnings.push(format!("texture {name}: {why}; using the factor alone")))
            .ok();
        self.decoded[texture.index()] = Some(decoded.clone());
        decoded
    }

    /// The image's name for messages and its texels (shared), decoded on
    /// first use within the total bound.
    fn image(&mut self, image: &::gltf::Image) -> (String, Result<Texture, String>) {
        let name = match image.source() {
            ::gltf::image::Source::View { view, .. } => {
                format!("image {} (buffer view {})", image.index(), view.index())
            }
            ::gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
                format!("image {} (a data: URI)", image.index())
            }
            ::gltf::image::Source::Uri { uri, .. } => format!("image {} (`{uri}`)", image.index()),
        };
        if let Some(done) = &self.images[image.index()] {
            return (name, done.clone());
        }
        // Bytes in a GLB chunk or buffer are borrowed; only files and data
        // URIs are read into a new vector.
        let bytes: Result<Cow<[u8]>, String> = match image.source() {
            ::gltf::image::Source::View { view, .. } => self
                .buffers
                .get(view.buffer().index())
                .and_then(|b| b.0.get(view.offset()..view.offset().checked_add(view.length())?))
                .map(Cow::Borrowed)
                .ok_or_else(|| "the buffer view lies outside its buffer".to_string()),
            ::gltf::image::Source::Uri { uri, .. } => read_uri(self.dir, uri, self.opts).map(Cow::Owned),
        };
        let max = self.opts.max_texture_bytes;
        let decoded = bytes.and_then(|b| Texture::decode(&b)).and_then(|t| {
            if self.total + t.bytes() > max {
                Err(format!("decoding it would take the textures past {max} bytes in all"))
            } else {
                self.total += t.bytes();
                Ok(t)
            }
        });
        self.images[image.index()] = Some(decoded.clone());
        (name, decoded)
    }
}

fn wrap(mode: ::gltf::texture::WrappingMode) -> Wrap {
    match mode {
        ::gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
        ::gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
        ::gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// A texture and the UV set it reads.
struct Mapped {
    texture: Rc<Texture>,
    set: u32,
}

/// What a material contributes per face.
struct Look {
    factor: DVec3,
    base: Option<Mapped>,
    emission: Option<DVec3>,
    emissive: Option<Mapped>,
}

impl Look {
    /// glTF's default material: white, not emitting.
    fn default_material() -> Look {
        Look { factor: DVec3::ONE, base: None, emission: None, emissive: None }
    }

    fn of(m: &::gltf::Material, images: &mut Images, warnings: &mut Vec<String>) -> Look {
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let mut mapped = |info: Option<::gltf::texture::Info>| {
            let info = info?;
            Some(Mapped { texture: images.get(&info.texture(), warnings)?, set: info.tex_coord() })
        };
        let base = mapped(pbr.base_color_texture());
        let strength = m.emissive_strength().unwrap_or(1.0) as f64;
        let emission = DVec3::from_array(m.emissive_factor().map(f64::from)) * strength;
        let emission = (emission.max_element() > 0.0).then_some(emission);
        let emissive = if emission.is_some() { mapped(m.emissive_texture()) } else { None };
        Look { factor: DVec3::new(r as f64, g as f64, b as f64), base, emission, emissive }
    }
}

struct State<'a> {
    path: &'a Path,
    doc: &'a ::gltf::Document,
    buffers: &'a [::gltf::buffer::Data],
    looks: &'a [Look],
    skipped_modes: HashMap<&'static str, usize>,
    degenerate: usize,
    /// A geometry-compression extension the file uses (not requires).
    compression: Option<&'static str>,
    orthographic: usize,
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
        if let Some(camera) = node.camera() {
            match camera.projection() {
                ::gltf::camera::Projection::Perspective(p) => match world_camera(&world, &p, camera.name()) {
                    Some(c) => mesh.cameras.push(c),
                    None => mesh.warnings.push(format!(
                        "camera {} skipped: its field of view or placement is degenerate",
                        camera.index()
                    )),
                },
                ::gltf::camera::Projection::Orthographic(_) => self.orthographic += 1,
            }
        }
        if let Some(light) = node.light() {
            use ::gltf::khr_lights_punctual::Kind;
            let kind = match light.kind() {
                Kind::Point => "point",
                Kind::Spot { .. } => "spot",
                Kind::Directional => "directional",
            };
            let power = DVec3::from(light.color().map(f64::from)) * light.intensity() as f64;
            let direction = world.transform_vector3(-DVec3::Z).normalize_or(-DVec3::Z);
            mesh.lights.push(MeshLight {
                kind,
                position: world.transform_point3(DVec3::ZERO),
                direction,
                power,
            });
        }
        if let Some(m) = node.mesh() {
            for placed in self.instances(node, &world)? {
                for prim in m.primitives() {
                    self.primitive(mesh, &prim, &placed)?;
                }
            }
        }
        for child in node.children() {
            self.walk(mesh, &child, world, depth + 1)?;
        }
        Ok(())
    }

    /// Where the node's mesh goes: at `world`, or once per instance of
    /// EXT_mesh_gpu_instancing (TRANSLATION, ROTATION, SCALE accessors of
    /// floats, each instance's T R S applied before the node's transform;
    /// the count is bounded by the size check).
    fn instances(&self, node: &::gltf::Node, world: &DMat4) -> Result<Vec<DMat4>, MeshError> {
        let Some(ext) = node.extension_value("EXT_mesh_gpu_instancing") else { return Ok(vec![*world]) };
        let attribute = |name: &str| {
            let index = ext.get("attributes")?.get(name)?.as_u64()?;
            self.doc.accessors().nth(index as usize)
        };
        let data = |b: ::gltf::Buffer| self.buffers.get(b.index()).map(|d| &d.0[..]);
        let bad = |name: &str| {
            MeshError::invalid(
                self.path,
                format!(
                    "node {}: EXT_mesh_gpu_instancing {name} is not a readable accessor of floats",
                    node.index()
                ),
            )
        };
        let read3 = |name: &str| -> Result<Option<Vec<[f32; 3]>>, MeshError> {
            let Some(a) = attribute(name) else { return Ok(None) };
            let ok = a.data_type() == ::gltf::accessor::DataType::F32
                && a.dimensions() == ::gltf::accessor::Dimensions::Vec3;
            ok.then(|| ::gltf::accessor::Iter::<[f32; 3]>::new(a, data).map(|i| i.collect()))
                .flatten()
                .map(Some)
                .ok_or_else(|| bad(name))
        };
        let rotations: Option<Vec<[f32; 4]>> = match attribute("ROTATION") {
            None => None,
            Some(a) => {
                let ok = a.data_type() == ::gltf::accessor::DataType::F32
                    && a.dimensions() == ::gltf::accessor::Dimensions::Vec4;
                Some(
                    ok.then(|| ::gltf::accessor::Iter::<[f32; 4]>::new(a, data).map(|i| i.collect()))
                        .flatten()
                        .ok_or_else(|| bad("ROTATION"))?,
                )
            }
        };
        let (translations, scales) = (read3("TRANSLATION")?, read3("SCALE")?);
        let n = [
            translations.as_ref().map(Vec::len),
            rotations.as_ref().map(Vec::len),
            scales.as_ref().map(Vec::len),
        ]
        .into_iter()
        .flatten()
        .max()
        .unwrap_or(0);
        Ok((0..n)
            .map(|i| {
                let t = translations
                    .as_ref()
                    .and_then(|v| v.get(i))
                    .map_or(glam::DVec3::ZERO, |t| t.map(f64::from).into());
                let r = rotations
                    .as_ref()
                    .and_then(|v| v.get(i))
                    .map_or(glam::DQuat::IDENTITY, |q| glam::DQuat::from_array(q.map(f64::from)).normalize());
                let s = scales
                    .as_ref()
                    .and_then(|v| v.get(i))
                    .map_or(glam::DVec3::ONE, |s| s.map(f64::from).into());
                *world * DMat4::from_scale_rotation_translation(s, r, t)
            })
            .collect())
    }

    /// Why a primitive's positions cannot be read: it has none, they are
    /// compressed by an extension, or they lie outside their buffer.
    fn unreadable_positions(&self, prim: &::gltf::Primitive) -> String {
        let Some(a) = prim.get(&::gltf::Semantic::Positions) else {
            return "a primitive has no POSITION attribute".into();
        };
        if let Some(ext) = self.compression {
            return format!("its geometry is compressed with {ext}, which mesh2nff cannot decode (decompress the file first)");
        }
        match a.view() {
            None => format!("POSITION accessor {} has no buffer view (and no sparse values to read)", a.index()),
            Some(view) => format!(
                "POSITION accessor {} ({} elements from byte {} of buffer view {}, {} bytes long, of buffer {} of {} bytes) lies outside its data",
                a.index(),
                a.count(),
                a.offset(),
                view.index(),
                view.length(),
                view.buffer().index(),
                self.buffers.get(view.buffer().index()).map_or(0, |b| b.0.len())
            ),
        }
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
            return Err(MeshError::invalid(self.path, self.unreadable_positions(prim)));
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
        let look = self.looks.get(material as usize).unwrap_or(&self.looks[0]);
        let uv_set = |m: &Option<Mapped>| -> Option<(Rc<Texture>, Vec<DVec2>)> {
            let m = m.as_ref()?;
            let uvs: Vec<DVec2> = reader
                .read_tex_coords(m.set)?
                .into_f32()
                .map(|[u, v]| DVec2::new(u as f64, v as f64))
                .collect();
            (uvs.len() == count as usize).then(|| (m.texture.clone(), uvs))
        };
        let base_map = uv_set(&look.base);
        let emissive_map = uv_set(&look.emissive);
        let colors: Option<Vec<DVec3>> = reader
            .read_colors(0)
            .map(|c| c.into_rgb_f32().map(|c| DVec3::from_array(c.map(f64::from))).collect())
            .filter(|c: &Vec<DVec3>| c.len() == count as usize);
        let face_mean = |map: &Option<(Rc<Texture>, Vec<DVec2>)>, t: [u32; 3]| {
            map.as_ref().map(|(tex, uvs)| tex.mean_over_triangle(t.map(|i| uvs[i as usize])))
        };
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
            let mut face = Face::plain(first, 3, material);
            let textured = face_mean(&base_map, t);
            let vertex = colors.as_ref().map(|c| t.iter().map(|&i| c[i as usize]).sum::<DVec3>() / 3.0);
            if textured.is_some() || vertex.is_some() {
                let c = look.factor * textured.unwrap_or(DVec3::ONE) * vertex.unwrap_or(DVec3::ONE);
                face.color = Some(c.as_vec3().to_array());
            }
            if let Some(e) = look.emission {
                face.set_emission(e * face_mean(&emissive_map, t).unwrap_or(DVec3::ONE));
            }
            mesh.faces.push(face);
        }
        Ok(())
    }
}

/// A perspective camera placed by its node's world transform: glTF cameras
/// look down their local −Z with +Y up. `None` when the field of view is not
/// in (0°, 180°) or the transform flattens the camera.
fn world_camera(world: &DMat4, p: &::gltf::camera::Perspective, name: Option<&str>) -> Option<MeshCamera> {
    let direction = world.transform_vector3(-DVec3::Z).normalize_or_zero();
    let up = world.transform_vector3(DVec3::Y);
    let up = (up - direction * up.dot(direction)).normalize_or_zero();
    let yfov = p.yfov() as f64;
    let from = world.transform_point3(DVec3::ZERO);
    if !(yfov > 0.0 && yfov < std::f64::consts::PI)
        || direction == DVec3::ZERO
        || up == DVec3::ZERO
        || !from.is_finite()
    {
        return None;
    }
    Some(MeshCamera {
        name: name.map(str::to_string),
        from,
        direction,
        up,
        yfov,
        aspect: p.aspect_ratio().map(f64::from),
        znear: (p.znear() as f64).max(0.0),
    })
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
        specular: DVec3::ONE,
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
