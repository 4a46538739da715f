//! glTF 2.0: the scene's triangles ([`super::triangles`]) as one mesh, a
//! primitive per material, the view as a perspective camera and the lights
//! as `KHR_lights_punctual` point lights; `.gltf` with its `.bin` beside it,
//! or one `.glb`.
//!
//! Materials, metallic-roughness from the Whitted terms, chosen so that
//! `mesh2nff` (which reads them back with `whitted_terms`) finds the same
//! Ks and Shine, and the same colour x Kd where that stays within [0, 1]:
//! roughness = (2 / (Shine + 2))^(1/4), the inverse of mesh2nff's Shine =
//! 2/alpha^2 - 2 with alpha = roughness^2 (1 where Ks = 0: no highlight);
//! metallic solved for Ks (a Ks below 0.04 (1 - roughness), a dielectric's
//! least, comes back as that);
//! base colour = colour x Kd over the Kd those give. A transmitter gets
//! `KHR_materials_transmission` (T) and `KHR_materials_ior`. Every material
//! is double-sided, as `render` shades. glTF point lights fall off with
//! the square of the distance, NFF's do not: each intensity is scaled by
//! its distance to the scene's centre squared, so they agree there.

use super::triangles::{groups, Group};
use super::{falloff_scale, ExportOptions, Frame};
use glam::{DMat3, DQuat, DVec3};
use nffkit_formats::mesh::gltf::whitted_terms;
use nffkit_formats::{Material, Scene};
use nffkit_tracer::prepare::{point_lights, Ambient};
use serde_json::{json, Value};

/// The document and its binary buffer, and what glTF cannot hold.
pub struct Gltf {
    /// The JSON document (its buffer's `uri` set for .gltf, absent for .glb).
    pub json: Value,
    /// The buffer's bytes.
    pub bin: Vec<u8>,
    /// What was lost.
    pub lost: Vec<String>,
}

/// The scene as glTF; `bin_uri` names the buffer file (`None`: a .glb).
pub fn build(scene: &Scene, opts: &ExportOptions, bin_uri: Option<&str>) -> Gltf {
    let (groups, mut lost) = groups(scene, opts.tessellate);
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut primitives = Vec::new();
    let mut materials = Vec::new();
    for g in &groups {
        let position = push_vec3(&mut bin, &mut views, &mut accessors, &g.positions, true);
        let normals: Vec<DVec3> = g
            .normals
            .iter()
            .map(|n| if n.length_squared() > 0.0 { n.normalize() } else { DVec3::Z })
            .collect();
        let normal = push_vec3(&mut bin, &mut views, &mut accessors, &normals, false);
        let indices = push_indices(&mut bin, &mut views, &mut accessors, g);
        let m = super::material(scene, g.material);
        primitives.push(json!({
            "attributes": { "POSITION": position, "NORMAL": normal },
            "indices": indices,
            "material": materials.len(),
            "mode": 4
        }));
        materials.push(material(g.material, &m));
    }
    let mut nodes = vec![json!({ "name": "scene", "mesh": 0 })];
    let mut cameras = Vec::new();
    if let Some(v) = &scene.view {
        let f = Frame::of(v, scene);
        let rotation = DQuat::from_mat3(&DMat3::from_cols(f.right, f.up, -f.forward)).normalize();
        cameras.push(json!({
            "type": "perspective",
            "perspective": {
                "yfov": f.vertical_fov(),
                "aspectRatio": f.width as f64 / f.height as f64,
                "znear": f.near
            }
        }));
        nodes.push(json!({
            "name": "view",
            "camera": 0,
            "translation": v.from.to_array(),
            "rotation": rotation.to_array()
        }));
    }
    let (resolved, _) = point_lights(&scene.lights, Ambient::Value(0.0));
    let mut lights = Vec::new();
    for (l, file) in resolved.iter().zip(&scene.lights) {
        let i = l.intensity * falloff_scale(scene, file.position) as f32;
        let peak = i.max_element().max(f32::MIN_POSITIVE);
        lights.push(json!({
            "type": "point",
            "color": [i.x / peak, i.y / peak, i.z / peak],
            "intensity": peak
        }));
        nodes.push(json!({
            "name": format!("light {}", lights.len()),
            "translation": file.position.to_array(),
            "extensions": { "KHR_lights_punctual": { "light": lights.len() - 1 } }
        }));
    }
    let mut buffer = json!({ "byteLength": bin.len() });
    if let Some(uri) = bin_uri {
        buffer["uri"] = json!(uri);
    }
    let mut used = Vec::new();
    if materials.iter().any(|m| m["extensions"].get("KHR_materials_transmission").is_some()) {
        used.extend(["KHR_materials_transmission", "KHR_materials_ior"]);
    }
    if !lights.is_empty() {
        used.push("KHR_lights_punctual");
    }
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "nffkit nffconvert" },
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": [{ "name": "scene", "primitives": primitives }],
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [buffer]
    });
    if !cameras.is_empty() {
        doc["cameras"] = json!(cameras);
    }
    if !lights.is_empty() {
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
    }
    if !used.is_empty() {
        doc["extensionsUsed"] = json!(used);
    }
    if groups.is_empty() {
        // A mesh needs a primitive: a scene of no shapes has no mesh.
        doc.as_object_mut().map(|d| d.remove("meshes"));
        doc["nodes"][0] = json!({ "name": "scene" });
    }
    if scene.background.is_some() {
        lost.push("the background colour".into());
    }
    if !scene.lights.is_empty() {
        lost.push(
            "lights without falloff: glTF's fall off with the distance squared (they match NFF's at the \
             scene's centre)"
                .into(),
        );
    }
    Gltf { json: doc, bin, lost }
}

impl Gltf {
    /// The `.glb` file: header, JSON chunk, BIN chunk.
    pub fn glb(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.json).unwrap_or_default();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend(b"glTF");
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(json);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }
}

/// Append `v` as a VEC3 float accessor (with its bounds when `bounds`);
/// returns its index.
fn push_vec3(
    bin: &mut Vec<u8>,
    views: &mut Vec<Value>,
    accessors: &mut Vec<Value>,
    v: &[DVec3],
    bounds: bool,
) -> usize {
    let offset = bin.len();
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in v {
        let f = p.as_vec3().to_array();
        for k in 0..3 {
            lo[k] = lo[k].min(f[k]);
            hi[k] = hi[k].max(f[k]);
            bin.extend(f[k].to_le_bytes());
        }
    }
    views.push(
        json!({ "buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset, "target": 34962 }),
    );
    let mut a =
        json!({ "bufferView": views.len() - 1, "componentType": 5126, "count": v.len(), "type": "VEC3" });
    if bounds {
        a["min"] = json!(lo);
        a["max"] = json!(hi);
    }
    accessors.push(a);
    accessors.len() - 1
}

/// Append a group's triangle indices as an unsigned-int accessor.
fn push_indices(bin: &mut Vec<u8>, views: &mut Vec<Value>, accessors: &mut Vec<Value>, g: &Group) -> usize {
    let offset = bin.len();
    for t in &g.triangles {
        for i in t {
            bin.extend(i.to_le_bytes());
        }
    }
    views.push(
        json!({ "buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset, "target": 34963 }),
    );
    accessors.push(json!({
        "bufferView": views.len() - 1, "componentType": 5125, "count": g.triangles.len() * 3, "type": "SCALAR"
    }));
    accessors.len() - 1
}

/// Material `m` (index `i` of the scene's, 0 the default) as glTF.
fn material(i: usize, m: &Material) -> Value {
    // Without a highlight Shine means nothing, and only roughness 1 gives
    // Ks 0 back.
    let roughness = if m.ks > 0.0 { (2.0 / (m.shine.max(1.0) + 2.0)).powf(0.25) } else { 1.0 };
    let metallic = solve_metallic(m.ks, roughness);
    let kd = whitted_terms(metallic, roughness).0.max(1e-6);
    let base = (m.color * m.kd / kd).clamp(DVec3::ZERO, DVec3::ONE);
    let mut out = json!({
        "name": format!("m{i}"),
        "doubleSided": true,
        "pbrMetallicRoughness": {
            "baseColorFactor": [base.x, base.y, base.z, 1.0],
            "metallicFactor": metallic,
            "roughnessFactor": roughness
        }
    });
    if m.t > 0.0 {
        out["extensions"] = json!({
            "KHR_materials_transmission": { "transmissionFactor": m.t.min(1.0) },
            "KHR_materials_ior": { "ior": m.ior.max(1.0) }
        });
    }
    out
}

/// The metallic factor that gives Ks `ks` at `roughness` under
/// `whitted_terms` (increasing in metallic), clamped to [0, 1].
fn solve_metallic(ks: f64, roughness: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if whitted_terms(mid, roughness).1 < ks {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
