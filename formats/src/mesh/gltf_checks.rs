//! What is refused in a glTF document before gltf reads it: anything
//! gltf 1.4.1 would panic on (it indexes some references unchecked and
//! has `unreachable!()` for types the spec forbids), and anything that
//! would expand past the import's bounds: a node graph that is not a
//! forest (a node with two parents, reachable twice, can double the
//! instances at every level: 2^40 from a 3 KB file), an accessor with
//! more elements than the bound, or more triangles in all than
//! `ImportOptions::max_triangles`. Each problem is one message with the
//! JSON path at fault.

use super::resource::ImportOptions;
use ::gltf::json::Root;

/// Every problem of `json`, one message each; empty when it may be read.
pub(super) fn problems(json: &Root, opts: &ImportOptions) -> Vec<String> {
    let mut found = unreadable_accessors(json);
    found.extend(node_forest(json));
    found.extend(missing_lights(json));
    if found.is_empty() {
        found.extend(sizes(json, opts.max_triangles));
    }
    found
}

/// What gltf would panic on reading, one message each: an attribute or
/// index list naming an accessor past the last (gltf-json's validation
/// indexes it unchecked), or of a component type its reader does not
/// expect (`unreachable!` in gltf's `read_indices`, `read_tex_coords`,
/// `read_colors`). The spec allows only these types, so such a file is
/// invalid anyway.
fn unreadable_accessors(json: &Root) -> Vec<String> {
    use ::gltf::json::accessor::ComponentType as C;
    use ::gltf::json::accessor::Type as T;
    use ::gltf::json::mesh::Semantic as S;
    use ::gltf::json::validation::Checked;
    const ANY: &[C] = &[C::I8, C::U8, C::I16, C::U16, C::U32, C::F32];
    let count = json.accessors.len();
    let mut found = Vec::new();
    let mut check = |at: String, index: usize, allowed: &[C], what: &str, shapes: &[T]| {
        let Some(accessor) = json.accessors.get(index) else {
            found.push(format!("{at}: accessor {index} does not exist (the file has {count})"));
            return;
        };
        if let Checked::Valid(t) = &accessor.component_type {
            if !allowed.contains(&t.0) {
                found.push(format!("{at}: accessor {index} has component type {:?}; {what}", t.0));
            }
        }
        if let Checked::Valid(t) = &accessor.type_ {
            if !shapes.is_empty() && !shapes.contains(t) {
                found.push(format!("{at}: accessor {index} is {t:?}; it must be one of {shapes:?}"));
            }
        }
    };
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let at = format!("meshes[{m}].primitives[{p}]");
            for (semantic, index) in &primitive.attributes {
                let shapes: &[T] = match semantic {
                    Checked::Valid(S::Positions | S::Normals) => &[T::Vec3],
                    Checked::Valid(S::Tangents) => &[T::Vec4],
                    Checked::Valid(S::TexCoords(_)) => &[T::Vec2],
                    Checked::Valid(S::Colors(_)) => &[T::Vec3, T::Vec4],
                    _ => &[],
                };
                let (name, allowed, what): (String, &[C], &str) = match semantic {
                    Checked::Valid(s @ (S::TexCoords(_) | S::Colors(_))) => {
                        (s.to_string(), &[C::F32, C::U8, C::U16], "it must be F32, U8 or U16")
                    }
                    Checked::Valid(s @ (S::Positions | S::Normals | S::Tangents)) => (
                        s.to_string(),
                        &[C::F32],
                        "it must be F32 (other types need KHR_mesh_quantization, not supported)",
                    ),
                    Checked::Valid(s) => (s.to_string(), ANY, ""),
                    Checked::Invalid => ("(unknown)".to_string(), ANY, ""),
                };
                check(format!("{at}.attributes.{name}"), index.value(), allowed, what, shapes);
            }
            if let Some(index) = &primitive.indices {
                check(
                    format!("{at}.indices"),
                    index.value(),
                    &[C::U8, C::U16, C::U32],
                    "indices must be U8, U16 or U32",
                    &[T::Scalar],
                );
            }
        }
    }
    for (i, image) in json.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view, &image.mime_type) {
            (Some(_), None, _) | (None, Some(_), Some(_)) => {}
            (None, Some(_), None) => {
                found.push(format!("images[{i}]: an image in a bufferView needs a mimeType"))
            }
            _ => found.push(format!("images[{i}]: an image needs a uri or a bufferView, and not both")),
        }
    }
    for (i, buffer) in json.buffers.iter().enumerate() {
        let Some(uri) = buffer.uri.as_deref().filter(|u| !u.starts_with("data:")) else { continue };
        if std::str::from_utf8(&super::resource::percent_bytes(uri)).is_err() {
            found.push(format!("buffers[{i}].uri `{uri}` decodes to bytes that are not UTF-8"));
        }
    }
    found
}

/// Nodes naming a KHR_lights_punctual light the file lacks (gltf unwraps
/// the lookup).
fn missing_lights(json: &Root) -> Vec<String> {
    let count =
        json.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map_or(0, |l| l.lights.len());
    json.nodes
        .iter()
        .enumerate()
        .filter_map(|(i, n)| {
            let light = n.extensions.as_ref()?.khr_lights_punctual.as_ref()?.light.value();
            (light >= count).then(|| {
                format!("nodes[{i}].extensions.KHR_lights_punctual.light: light {light} does not exist (the file has {count})")
            })
        })
        .collect()
}

/// The spec's node graph: every node the child of at most one node, no
/// cycle, and a scene's nodes roots.
fn node_forest(json: &Root) -> Vec<String> {
    let n = json.nodes.len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    let mut found = Vec::new();
    for (p, node) in json.nodes.iter().enumerate() {
        for child in node.children.iter().flatten() {
            let c = child.value();
            if c >= n {
                found.push(format!("nodes[{p}].children: node {c} does not exist (the file has {n})"));
                continue;
            }
            match parent[c] {
                Some(q) => found.push(format!(
                    "nodes[{c}] is a child of nodes[{q}] and of nodes[{p}]; the spec allows one parent \
                     (a node reachable twice can double the model at every level)"
                )),
                None => parent[c] = Some(p),
            }
        }
    }
    if !found.is_empty() {
        return found;
    }
    // One parent each: a cycle is a walk up that comes back.
    for start in 0..n {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parent[at] {
            at = p;
            steps += 1;
            if at == start || steps > n {
                return vec![format!("nodes[{start}] is its own ancestor (a cycle in the node graph)")];
            }
        }
    }
    for (s, scene) in json.scenes.iter().enumerate() {
        let mut seen = std::collections::HashSet::new();
        for node in &scene.nodes {
            let i = node.value();
            if i >= n {
                found.push(format!("scenes[{s}].nodes: node {i} does not exist (the file has {n})"));
            } else if let Some(p) = parent[i] {
                found.push(format!(
                    "scenes[{s}].nodes lists nodes[{i}], a child of nodes[{p}]; a scene lists roots"
                ));
            } else if !seen.insert(i) {
                found.push(format!("scenes[{s}].nodes lists nodes[{i}] twice"));
            }
        }
    }
    found
}

/// Accessors with more elements than `max_triangles` allows (three
/// vertices a triangle), and a model of more triangles than that in all
/// (each mesh's primitives once per node that places it; a forest, so
/// each node once).
fn sizes(json: &Root, max_triangles: u64) -> Vec<String> {
    let raise = "--max-triangles raises the bound";
    let max_elements = max_triangles.saturating_mul(3);
    let mut found = Vec::new();
    for (i, a) in json.accessors.iter().enumerate() {
        let count = a.count.0;
        if count > max_elements {
            found.push(format!(
                "accessors[{i}] has {count} elements, more than the {max_elements} a model of \
                 {max_triangles} triangles needs ({raise})"
            ));
        }
    }
    if !found.is_empty() {
        return found;
    }
    let count_of = |i: usize| json.accessors.get(i).map_or(0, |a| a.count.0);
    let triangles_of_mesh = |m: usize| -> u64 {
        json.meshes.get(m).map_or(0, |mesh| {
            mesh.primitives
                .iter()
                .map(|p| {
                    use ::gltf::json::mesh::{Mode, Semantic};
                    use ::gltf::json::validation::Checked;
                    let positions = p.attributes.iter().find_map(|(s, a)| {
                        matches!(s, Checked::Valid(Semantic::Positions)).then(|| count_of(a.value()))
                    });
                    let vertices = p.indices.as_ref().map(|i| count_of(i.value())).or(positions).unwrap_or(0);
                    match p.mode {
                        Checked::Valid(Mode::Triangles) => vertices / 3,
                        Checked::Valid(Mode::TriangleStrip | Mode::TriangleFan) => vertices.saturating_sub(2),
                        // Points and lines are skipped; an invalid mode is refused.
                        _ => 0,
                    }
                })
                .sum()
        })
    };
    // EXT_mesh_gpu_instancing places a node's mesh once per element of
    // its attributes.
    let instances = |n: &::gltf::json::Node| -> u64 {
        let attributes = n
            .extensions
            .as_ref()
            .and_then(|e| e.others.get("EXT_mesh_gpu_instancing"))
            .and_then(|v| v.get("attributes"));
        attributes
            .and_then(|a| a.as_object())
            .map(|a| a.values().filter_map(|i| i.as_u64()).map(|i| count_of(i as usize)).max().unwrap_or(0))
            .unwrap_or(1)
    };
    let total: u64 = json
        .nodes
        .iter()
        .filter_map(|n| n.mesh.as_ref().map(|m| triangles_of_mesh(m.value()).saturating_mul(instances(n))))
        .fold(0u64, u64::saturating_add);
    if total > max_triangles {
        found.push(format!("the model has up to {total} triangles, more than {max_triangles} ({raise})"));
    }
    found
}
