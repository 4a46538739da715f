//! mesh2nff on small meshes written by the tests: OBJ (normals, n-gons,
//! negative indices, materials) and glTF (hierarchy, mirroring, strips,
//! fans, GLB, embedded buffers, sparse accessors), checked through the
//! project's own NFF reader.

use glam::DVec3;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{Scene, Shape};
use nffkit_tools::mesh2nff::{write, Options, Summary};
use std::path::{Path, PathBuf};

fn convert(path: &Path, opts: &Options) -> (Scene, Summary, Vec<String>) {
    let mesh = nffkit_formats::mesh::load(path).unwrap_or_else(|e| panic!("{e}"));
    let (text, summary) = write(&mesh, opts, Vec::new()).unwrap();
    let parsed = nff::parse(&text, &ParseOptions { fragment: !opts.view, ..Default::default() })
        .unwrap_or_else(|e| panic!("{e}\n{}", String::from_utf8_lossy(&text)));
    (parsed.scene, summary, mesh.warnings)
}

fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn vertices(s: &Shape) -> &[DVec3] {
    s.vertices().expect("a polygon")
}

fn normal(s: &Shape) -> DVec3 {
    let v = vertices(s);
    (v[1] - v[0]).cross(v[2] - v[1]).normalize()
}

const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
// Faces counter-clockwise seen from outside.
const CUBE_FACES: &str = "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn obj_cube_without_normals_gives_outward_quads() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), "cube.obj", &format!("{CUBE}{CUBE_FACES}"));
    let (scene, summary, _) = convert(&p, &Options::default());
    assert_eq!((summary.polygons, summary.patches), (6, 0));
    let c = DVec3::splat(0.5);
    for prim in &scene.primitives {
        let v = vertices(&prim.shape);
        assert_eq!(v.len(), 4, "planar convex quads stay whole");
        assert!(normal(&prim.shape).dot(v[0] - c) > 0.0, "winding faces outwards");
    }
    let b = scene.bounds().unwrap();
    assert_eq!((b.0, b.1), (DVec3::ZERO, DVec3::ONE), "world coordinates unchanged");
    assert!(scene.view.is_some() && !scene.lights.is_empty());
}

#[test]
fn obj_with_normals_gives_patches_and_smooth_computes_them() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";
    let (scene, summary, _) = convert(&write_file(dir.path(), "t.obj", text), &Options::default());
    assert_eq!(summary.patches, 1);
    assert!(matches!(&scene.primitives[0].shape, Shape::Patch(patch) if patch.normals[0] == DVec3::Z));
    let p = write_file(dir.path(), "cube.obj", &format!("{CUBE}{CUBE_FACES}"));
    let (_, s, _) = convert(&p, &Options { smooth: true, ..Default::default() });
    assert_eq!(s.patches, 6);
    let (_, s, _) =
        convert(&write_file(dir.path(), "t2.obj", text), &Options { flat: true, ..Default::default() });
    assert_eq!((s.polygons, s.patches), (1, 0));
}

#[test]
fn obj_concave_ngon_is_ear_clipped_and_negative_indices_work() {
    let dir = tempfile::tempdir().unwrap();
    // An L-shaped hexagon, given with relative (negative) indices.
    let text = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf -6 -5 -4 -3 -2 -1\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\nf -4 -3 -2 -1\n";
    let (scene, summary, _) = convert(&write_file(dir.path(), "l.obj", text), &Options::default());
    assert_eq!(summary.triangulated, 1);
    assert_eq!(scene.primitives.len(), 4 + 1);
    for prim in &scene.primitives {
        assert!(normal(&prim.shape).z > 0.0);
    }
}

#[test]
fn obj_materials_and_missing_mtl() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "m.mtl", "newmtl red\nKd 0.8 0.2 0.1\nKs 0.5 0.5 0.5\nNs 40\nd 0.75\nNi 1.3\n");
    let text = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
    let (scene, _, _) = convert(&write_file(dir.path(), "a.obj", text), &Options::default());
    let m = scene.material_of(&scene.primitives[0]);
    assert!((m.color - DVec3::new(1.0, 0.25, 0.125)).length() < 1e-9);
    assert_eq!((m.kd, m.ks, m.shine, m.t, m.ior), (0.8, 0.5, 40.0, 0.25, 1.3));
    let text = "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (scene, _, warnings) = convert(&write_file(dir.path(), "b.obj", text), &Options::default());
    assert_eq!(scene.primitives.len(), 1);
    assert!(warnings.iter().any(|w| w.contains("nowhere.mtl")), "{warnings:?}");
}

#[test]
fn obj_missing_normal_index_keeps_the_face() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//7 3//1\n";
    let (scene, _, warnings) = convert(&write_file(dir.path(), "n.obj", text), &Options::default());
    assert_eq!(scene.primitives.len(), 1);
    assert!(warnings.iter().any(|w| w.contains("dropped")));
}

#[test]
fn bad_meshes_are_refused_with_the_file_named() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("range.obj", "v 0 0 0\nf 1 2 3\n"),
        ("empty.obj", "v 0 0 0\n"),
        ("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("x.txt", "hello"),
        ("broken.gltf", "{ not json"),
    ] {
        let p = write_file(dir.path(), name, text);
        let e = nffkit_formats::mesh::load(&p).err().unwrap_or_else(|| panic!("{name} accepted")).to_string();
        assert!(e.contains(name), "{e}");
    }
    let gltf = gltf_json(&[0.0f32; 9], None, "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"], \"extensionsUsed\": [\"KHR_draco_mesh_compression\"],", 4, "", None);
    let e = nffkit_formats::mesh::load(&write_file(dir.path(), "draco.gltf", &gltf)).unwrap_err().to_string();
    assert!(e.contains("KHR_draco_mesh_compression"), "{e}");
    let missing = r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"gone.bin","byteLength":36}]}"#;
    let e = nffkit_formats::mesh::load(&write_file(dir.path(), "m.gltf", missing)).unwrap_err().to_string();
    assert!(e.contains("m.gltf") && e.contains("`gone.bin`, which is missing"), "{e}");
}

fn base64(data: &[u8]) -> String {
    const T: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            out.push(if k <= c.len() { T[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    out
}

/// A glTF with one mesh of `positions` (and optional u16 `indices`) in one
/// embedded buffer; `nodes` is the JSON of the node list.
fn gltf_json(
    positions: &[f32],
    indices: Option<&[u16]>,
    extra: &str,
    mode: u32,
    nodes: &str,
    sparse: Option<&str>,
) -> String {
    let mut bin: Vec<u8> = positions.iter().flat_map(|f| f.to_le_bytes()).collect();
    let pos_len = bin.len();
    if let Some(ix) = indices {
        bin.extend(ix.iter().flat_map(|i| i.to_le_bytes()));
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
    }
    let n = positions.len() / 3;
    let (lo, hi) = positions.chunks(3).fold(([f32::MAX; 3], [f32::MIN; 3]), |(mut lo, mut hi), p| {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
        (lo, hi)
    });
    let idx_view = indices.map_or(String::new(), |ix| {
        format!(",{{\"buffer\":0,\"byteOffset\":{pos_len},\"byteLength\":{}}}", ix.len() * 2)
    });
    let idx_acc = indices.map_or(String::new(), |ix| {
        format!(",{{\"bufferView\":1,\"componentType\":5123,\"count\":{},\"type\":\"SCALAR\"}}", ix.len())
    });
    let indices_attr = if indices.is_some() { ",\"indices\":1" } else { "" };
    let sparse = sparse.map_or(String::new(), |s| format!(",\"sparse\":{s}"));
    let nodes = if nodes.is_empty() { r#"[{"mesh":0}]"# } else { nodes };
    format!(
        r#"{{"asset":{{"version":"2.0"}},{extra}
"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":{nodes},
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":{mode}{indices_attr}}}]}}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{pos_len}}}{idx_view}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":{n},"type":"VEC3","min":{lo:?},"max":{hi:?}{sparse}}}{idx_acc}]}}"#,
        bin.len(),
        base64(&bin)
    )
}

const TRI: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

#[test]
fn gltf_hierarchy_transforms_and_instancing() {
    let dir = tempfile::tempdir().unwrap();
    // Root translated by (10,0,0) and scaled 2; child rotated 90 degrees
    // about z and translated (0,5,0); both instance mesh 0.
    let nodes = r#"[{"mesh":0,"translation":[10,0,0],"scale":[2,2,2],"children":[1]},
                    {"mesh":0,"translation":[0,5,0],"rotation":[0,0,0.7071067811865476,0.7071067811865476]}]"#;
    let p = write_file(dir.path(), "h.gltf", &gltf_json(&TRI, None, "", 4, nodes, None));
    let (scene, _, _) = convert(&p, &Options::default());
    assert_eq!(scene.primitives.len(), 2, "one triangle per instance");
    let root = vertices(&scene.primitives[0].shape);
    assert!((root[1] - DVec3::new(12.0, 0.0, 0.0)).length() < 1e-6);
    // Child: world = T(10,0,0) S2 * T(0,5,0) Rz90: (1,0,0) -> (0,1,0) -> (0,6,0) -> (0,12,0)+(10,0,0)
    let child = vertices(&scene.primitives[1].shape);
    assert!((child[1] - DVec3::new(10.0, 12.0, 0.0)).length() < 1e-5, "{:?}", child[1]);
    for prim in &scene.primitives {
        assert!(normal(&prim.shape).z > 0.99);
    }
}

#[test]
fn gltf_mirrored_node_keeps_faces_outward() {
    let dir = tempfile::tempdir().unwrap();
    let nodes = r#"[{"mesh":0,"scale":[-1,1,1]}]"#;
    let p = write_file(dir.path(), "m.gltf", &gltf_json(&TRI, None, "", 4, nodes, None));
    let (scene, _, _) = convert(&p, &Options::default());
    assert!(normal(&scene.primitives[0].shape).z > 0.99, "winding flipped back");
}

#[test]
fn gltf_strips_fans_indices_and_degenerates() {
    let dir = tempfile::tempdir().unwrap();
    let quad = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
    // Strip 0,1,2,3 -> two triangles, both facing +z.
    let (scene, _, _) = convert(
        &write_file(dir.path(), "s.gltf", &gltf_json(&quad, None, "", 5, "", None)),
        &Options::default(),
    );
    assert_eq!(scene.primitives.len(), 2);
    assert!(scene.primitives.iter().all(|p| normal(&p.shape).z > 0.99));
    // Fan 0,1,3,2 -> two triangles.
    let (scene, _, _) = convert(
        &write_file(dir.path(), "f.gltf", &gltf_json(&quad, Some(&[0, 1, 3, 2]), "", 6, "", None)),
        &Options::default(),
    );
    assert_eq!(scene.primitives.len(), 2);
    assert!(scene.primitives.iter().all(|p| normal(&p.shape).z > 0.99));
    // Strip with a stitching repeat: degenerate triangles dropped, warned.
    let (scene, _, w) = convert(
        &write_file(dir.path(), "d.gltf", &gltf_json(&quad, Some(&[0, 1, 2, 2, 3]), "", 5, "", None)),
        &Options::default(),
    );
    assert!(scene.primitives.len() < 3);
    assert!(w.iter().any(|w| w.contains("degenerate")), "{w:?}");
}

#[test]
fn gltf_sparse_accessor_moves_a_vertex() {
    let dir = tempfile::tempdir().unwrap();
    // Sparse: vertex 1 replaced by (3,0,0). Indices and values appended as
    // a second buffer in a data URI.
    let mut extra_bin: Vec<u8> = vec![1, 0, 0, 0];
    extra_bin.extend([3.0f32, 0.0, 0.0].iter().flat_map(|f| f.to_le_bytes()));
    let json = gltf_json(
        &TRI,
        None,
        "",
        4,
        "",
        Some(r#"{"count":1,"indices":{"bufferView":1,"componentType":5125},"values":{"bufferView":2}}"#),
    );
    let json = json
        .replace(
            "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}]",
            "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":1,\"byteOffset\":0,\"byteLength\":4},{\"buffer\":1,\"byteOffset\":4,\"byteLength\":12}]",
        )
        .replace(
            "\"buffers\":[",
            &format!("\"buffers\":[{{\"byteLength\":16,\"uri\":\"data:application/octet-stream;base64,{}\"}},", base64(&extra_bin)),
        )
        .replace("\"buffer\":0,", "\"buffer\":9,")
        .replace("\"buffer\":1,", "\"buffer\":0,")
        .replace("\"buffer\":9,", "\"buffer\":1,");
    let (scene, _, _) = convert(&write_file(dir.path(), "sp.gltf", &json), &Options::default());
    let v = vertices(&scene.primitives[0].shape);
    assert!(v.iter().any(|p| (*p - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-6), "{v:?}");
}

#[test]
fn glb_loads_like_gltf() {
    let dir = tempfile::tempdir().unwrap();
    let bin: Vec<u8> = TRI.iter().flat_map(|f| f.to_le_bytes()).collect();
    let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":36}],
"bufferViews":[{"buffer":0,"byteLength":36}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]}"#;
    let glb = crate::common::glb(json, &bin);
    let p = dir.path().join("t.glb");
    std::fs::write(&p, glb).unwrap();
    let (scene, _, _) = convert(&p, &Options::default());
    assert_eq!(scene.primitives.len(), 1);
    let b = scene.bounds().unwrap();
    assert_eq!((b.0, b.1), (DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0)));
}

#[test]
fn no_view_fit_and_center() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), "cube.obj", &format!("{CUBE}{CUBE_FACES}"));
    let (scene, _, _) = convert(&p, &Options { view: false, ..Default::default() });
    assert!(scene.view.is_none() && scene.lights.is_empty());
    let (scene, _, _) = convert(&p, &Options { fit: true, scale: 2.0, ..Default::default() });
    let b = scene.bounds().unwrap();
    assert_eq!((b.0, b.1), (DVec3::splat(-1.0), DVec3::splat(1.0)));
}

#[test]
fn obj_parse_errors_name_the_line_and_nameless_usemtl_is_tolerated() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nv 3.1+e2 0 1\nf 1 2 3\n");
    let e = nffkit_formats::mesh::load(&p).unwrap_err().to_string();
    assert!(e.contains("line 3, column 3: `3.1+e2` is not a number"), "{e}");
    let p = write_file(dir.path(), "short.obj", "v 0 0 0\nv 1 0\n");
    let e = nffkit_formats::mesh::load(&p).unwrap_err().to_string();
    assert!(e.contains("line 2: `v 1 0` has 2 numbers, `v` needs 3"), "{e}");
    let p = write_file(dir.path(), "blender.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl \nf 1 2 3\n");
    let (scene, _, warnings) = convert(&p, &Options::default());
    assert_eq!(scene.primitives.len(), 1);
    assert!(warnings.iter().any(|w| w.contains("line 4")), "{warnings:?}");
    let p = dir.path().join("utf16.obj");
    std::fs::write(&p, [0xFF, 0xFE, b'v', 0]).unwrap();
    assert!(nffkit_formats::mesh::load(&p).unwrap_err().to_string().contains("UTF-16"));
}

#[test]
fn gltf_with_an_external_bin() {
    let dir = tempfile::tempdir().unwrap();
    let bin: Vec<u8> = TRI.iter().flat_map(|f| f.to_le_bytes()).collect();
    std::fs::write(dir.path().join("tri.bin"), &bin).unwrap();
    let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[0,0,2]}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":36,"uri":"tri.bin"}],
"bufferViews":[{"buffer":0,"byteLength":36}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]}"#;
    let (scene, _, _) = convert(&write_file(dir.path(), "ext.gltf", json), &Options::default());
    let b = scene.bounds().unwrap();
    assert_eq!((b.0, b.1), (DVec3::new(0.0, 0.0, 2.0), DVec3::new(1.0, 1.0, 2.0)));
}

#[test]
fn gltf_default_material_renders_light_grey_not_black() {
    let dir = tempfile::tempdir().unwrap();
    // A material with no pbrMetallicRoughness at all: glTF's defaults,
    // metallic 1, roughness 1, base colour white.
    let extra = r#""materials":[{"name":"plain"}],"#;
    let json = gltf_json(&TRI, None, extra, 4, "", None).replace(r#""mode":4"#, r#""mode":4,"material":0"#);
    let (scene, _, _) = convert(&write_file(dir.path(), "d.gltf", &json), &Options::default());
    let m = scene.material_of(&scene.primitives[0]);
    assert_eq!((m.color, m.kd, m.ks), (DVec3::ONE, 0.8, 0.0));
    let prepared = nffkit_tracer::prepare::prepare(&scene, &Default::default()).unwrap();
    let film = nffkit_tracer::render::render(&prepared, &Default::default(), &|_, _| {}).film;
    let (w, h) = (film.width, film.height);
    let centre = film.get(w / 3, h / 2).max(film.get(w / 2, h / 2));
    assert!(
        film.pixels.iter().any(|p| p.min_element() > 0.3 && (p.x - p.y).abs() < 1e-6),
        "lit grey: {centre}"
    );
}

fn mesh2nff(args: &[&str], dir: &Path, stdin: Option<&str>) -> std::process::Output {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_mesh2nff"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let input = child.stdin.take().unwrap();
    if let Some(text) = stdin {
        let mut input = input;
        input.write_all(text.as_bytes()).unwrap();
    }
    child.wait_with_output().unwrap()
}

#[test]
fn obj_polylines_and_points_are_skipped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nl 1 2 4\nl 2 4\np 4\n";
    let (scene, _, warnings) = convert(&write_file(dir.path(), "l.obj", text), &Options::default());
    assert_eq!(scene.primitives.len(), 1, "only the face");
    assert!(
        warnings.iter().any(|w| w.contains("2 polyline (`l`) and 1 point (`p`) elements skipped")),
        "{warnings:?}"
    );
}

#[test]
fn obj_messages_name_the_line_and_print_each_error_once() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\nf 1 2 9\n");
    let o = mesh2nff(&["bad.obj"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("bad.obj: line 6: `f 1 2 9` names vertex 9, but 3 vertices are defined before it"),
        "{err}"
    );
    let o = mesh2nff(&["missing.obj"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("No such file").count(), 1, "{err}");
    // Every part of the error's chain is printed, joined by colons.
    write_file(dir.path(), "tab.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n");
    let o = mesh2nff(&["tab.obj", "-o", "out.nff"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("error: cannot convert: tab.obj: not a readable OBJ file: face parse error at line 4, column 7: `x3`"),
        "{err}"
    );
    assert!(!dir.path().join("out.nff").exists());
}

#[test]
fn output_naming_the_input_is_refused_and_stdin_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    write_file(dir.path(), "t.obj", text);
    let o = mesh2nff(&["t.obj", "-o", "t.obj"], dir.path(), None);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("would overwrite the input"));
    assert_eq!(std::fs::read_to_string(dir.path().join("t.obj")).unwrap(), text, "input untouched");
    let o = mesh2nff(&["-", "--no-view"], dir.path(), Some(text));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let scene = nff::parse(&o.stdout, &ParseOptions { fragment: true, ..Default::default() }).unwrap().scene;
    assert_eq!(scene.primitives.len(), 1);
}

#[test]
fn a_mesh_of_only_degenerate_faces_is_refused_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    let o = mesh2nff(&["flat.obj", "-o", "out.nff"], dir.path(), None);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no faces with any area"));
    assert!(!dir.path().join("out.nff").exists());
}

#[test]
fn a_negative_scale_mirrors_and_keeps_faces_outward() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), "cube.obj", &format!("{CUBE}{CUBE_FACES}"));
    let (scene, _, _) = convert(&p, &Options { scale: -2.0, view: false, ..Default::default() });
    let (lo, hi) = scene.bounds().unwrap();
    assert_eq!((lo, hi), (DVec3::splat(-2.0), DVec3::ZERO));
    let centre = DVec3::splat(-1.0);
    for prim in &scene.primitives {
        let v = vertices(&prim.shape);
        let face_centre = v.iter().sum::<DVec3>() / v.len() as f64;
        assert!(normal(&prim.shape).dot(face_centre - centre) > 0.0, "a face turned inward");
    }
}

#[test]
fn gltf_leniency_where_geometry_is_readable_and_clear_refusals_where_not() {
    let dir = tempfile::tempdir().unwrap();
    let load = |name: &str, json: &str| nffkit_formats::mesh::load(&write_file(dir.path(), name, json));
    // No accessor min/max: read, with a warning.
    let plain = gltf_json(&TRI, None, "", 4, "", None);
    let no_bounds = plain.replace(r#","min":[0.0, 0.0, 0.0],"max":[1.0, 1.0, 0.0]"#, "");
    assert_ne!(no_bounds, plain, "the helper's bounds were removed");
    let m = load("nb.gltf", &no_bounds).unwrap();
    assert_eq!(m.faces.len(), 1);
    assert!(m.warnings.iter().any(|w| w.contains("min`/`max")), "{:?}", m.warnings);
    // A required extension that does not change geometry: read, with a warning.
    let ext = r#""extensionsUsed":["KHR_texture_transform"],"extensionsRequired":["KHR_texture_transform"],"#;
    let m = load("tt.gltf", &gltf_json(&TRI, None, ext, 4, "", None)).unwrap();
    assert!(m.warnings.iter().any(|w| w.contains("KHR_texture_transform")), "{:?}", m.warnings);
    // glTF 1.0, a missing buffer file and quantized positions: named refusals.
    let e = load("v1.gltf", r#"{"asset":{"version":"1.0"},"meshes":{}}"#).unwrap_err().to_string();
    assert!(e.contains("glTF 1.0 is not supported"), "{e}");
    let gone =
        plain.replace(&format!("data:application/octet-stream;base64,{}", base64(&tri_bytes())), "gone.bin");
    let e = load("gone.gltf", &gone).unwrap_err().to_string();
    assert!(e.contains("`gone.bin`, which is missing"), "{e}");
    let quantized = plain.replace(r#""componentType":5126"#, r#""componentType":5122,"normalized":true"#);
    let e = load("q.gltf", &quantized).unwrap_err().to_string();
    assert!(e.contains("KHR_mesh_quantization"), "{e}");
}

fn tri_bytes() -> Vec<u8> {
    TRI.iter().flat_map(|f| f.to_le_bytes()).collect()
}

#[test]
fn a_buffer_uri_that_decodes_to_no_text_is_refused_not_a_panic() {
    // `%FF` decodes to a byte that is not UTF-8; the lossy reading finds
    // the file named with U+FFFD, gltf's own reading panicked on it.
    let dir = tempfile::tempdir().unwrap();
    let pos: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|f| f.to_le_bytes()).collect();
    std::fs::write(dir.path().join("\u{FFFD}.bin"), &pos).unwrap();
    let gltf = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
        "buffers":[{"byteLength":36,"uri":"%FF.bin"}],"bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    write_file(dir.path(), "t.gltf", gltf);
    let o = mesh2nff(&["t.gltf", "--no-view"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("buffers[0].uri `%FF.bin` decodes to bytes that are not UTF-8"), "{err}");
}

#[test]
fn obj_faces_are_bounded_and_an_outline_running_round_is_written_once() {
    let dir = tempfile::tempdir().unwrap();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    // The triangles a file's faces make count against --max-triangles.
    write_file(dir.path(), "two.obj", &format!("{tri}f 1 2 3\nf 1 2 3 1 2 3\n"));
    let o = mesh2nff(&["two.obj", "--max-triangles", "4"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("the faces make 5 triangles, more than 4 (--max-triangles raises the bound)"),
        "{err}"
    );
    // A face of more corners than any real model has.
    let corners = " 1 2 3".repeat(350_000);
    write_file(dir.path(), "huge.obj", &format!("{tri}\nf{corners}\n"));
    let o = mesh2nff(&["huge.obj"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("line 5: a face of 1050000 corners; at most 1048576 are read"), "{err}");
    // Round the same triangle 1000 times: one triangle, not a convex
    // polygon of 3000 corners (all its turns go one way) nor 2998 copies.
    let round = " 1 2 3".repeat(1000);
    let (scene, summary, _) =
        convert(&write_file(dir.path(), "round.obj", &format!("{tri}f{round}\n")), &Options::default());
    assert_eq!(scene.primitives.len(), 1);
    assert_eq!(vertices(&scene.primitives[0].shape).len(), 3);
    assert!(summary.repeated > 2900, "{}", summary.repeated);
}

#[test]
fn gltf_graphs_and_counts_that_would_explode_are_refused_before_expanding() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, json: &str, args: &[&str]| {
        write_file(dir.path(), name, json);
        let o = mesh2nff(&[&[name, "--no-view"][..], args].concat(), dir.path(), None);
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    // 40 nodes, each listing the next twice: 2^40 instances.
    let twice: Vec<String> = (0..40)
        .map(|i| {
            if i < 39 {
                format!(r#"{{"mesh":0,"children":[{},{}]}}"#, i + 1, i + 1)
            } else {
                r#"{"mesh":0}"#.into()
            }
        })
        .collect();
    let (code, err) =
        run("twice.gltf", &gltf_json(&TRI, None, "", 4, &format!("[{}]", twice.join(",")), None), &[]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("nodes[1] is a child of nodes[0] and of nodes[0]; the spec allows one parent"),
        "{err}"
    );
    // 40 levels of two distinct nodes, both parents of the next pair.
    let pairs: Vec<String> = (0..80)
        .map(|i| {
            let next = (i / 2 + 1) * 2;
            if next < 80 {
                format!(r#"{{"mesh":0,"children":[{next},{}]}}"#, next + 1)
            } else {
                r#"{"mesh":0}"#.into()
            }
        })
        .collect();
    let (code, err) =
        run("pairs.gltf", &gltf_json(&TRI, None, "", 4, &format!("[{}]", pairs.join(",")), None), &[]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("nodes[2] is a child of nodes[0] and of nodes[1]"), "{err}");
    // A sparse accessor of two billion elements and no bufferView.
    let huge = gltf_json(&TRI, None, "", 4, "", None).replace(r#""count":3"#, r#""count":2000000000"#);
    let (code, err) = run("sparse.gltf", &huge, &[]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("accessors[0] has 2000000000 elements, more than the 60000000"), "{err}");
    // A hundred instances of a triangle, under a bound of fifty.
    let many: Vec<String> = (0..100).map(|_| r#"{"mesh":0}"#.to_string()).collect();
    let roots: Vec<String> = (0..100).map(|i| i.to_string()).collect();
    let flat = gltf_json(&TRI, None, "", 4, &format!("[{}]", many.join(",")), None)
        .replace(r#""scenes":[{"nodes":[0]}]"#, &format!(r#""scenes":[{{"nodes":[{}]}}]"#, roots.join(",")));
    let (code, err) = run("many.gltf", &flat, &["--max-triangles", "50"]);
    assert!(
        err.contains("the model has up to 100 triangles, more than 50 (--max-triangles raises the bound)"),
        "{err}"
    );
    assert_eq!(code, Some(1));
    // Exactly at the bound: a triangle list counts a triangle per three
    // vertices (it counted one a vertex, refusing models a third the size).
    let (code, err) = run("many.gltf", &flat, &["--max-triangles", "100"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, err) = run("many.gltf", &flat, &[]);
    assert_eq!(code, Some(0), "{err}");
}

#[cfg(unix)]
#[test]
fn references_through_links_out_of_the_folder_are_not_read() {
    use std::os::unix::fs::symlink;
    let root = tempfile::tempdir().unwrap();
    let (model, outside) = (root.path().join("model"), root.path().join("outside"));
    std::fs::create_dir_all(&model).unwrap();
    std::fs::create_dir_all(&outside).unwrap();
    std::fs::write(outside.join("secret.bin"), tri_bytes()).unwrap();
    symlink(outside.join("secret.bin"), model.join("inside.bin")).unwrap();
    symlink(&outside, model.join("sub")).unwrap();
    let with_uri = |uri: &str| {
        gltf_json(&TRI, None, "", 4, "", None)
            .replace(&format!("data:application/octet-stream;base64,{}", base64(&tri_bytes())), uri)
    };
    for (name, uri) in [("a.gltf", "inside.bin"), ("b.gltf", "sub/secret.bin")] {
        write_file(&model, name, &with_uri(uri));
        let o = mesh2nff(&[name, "--no-view"], &model, None);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains("leads out of the model's folder through a link"), "{name}: {err}");
    }
    // An MTL library behind a link to the outside: not read (a warning).
    std::fs::write(outside.join("lib.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
    symlink(outside.join("lib.mtl"), model.join("lib.mtl")).unwrap();
    write_file(&model, "m.obj", "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    let o = mesh2nff(&["m.obj", "--no-view"], &model, None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("leads out of the model's folder through a link"), "{err}");
    assert!(!String::from_utf8_lossy(&o.stdout).contains("f 1 0 0"), "the outside red was read");
}

#[test]
fn obj_is_read_as_the_format_means() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = |name: &str, text: &str, args: &[&str]| {
        write_file(d, name, text);
        let o = mesh2nff(&[&[name][..], args].concat(), d, None);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    // A face without normals after one with: its own (geometric) normal,
    // not the other face's `1 0 0`.
    let nff = out(
        "mixed.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 1 0 0\nf 1//1 2//1 4//1\nf 1 2 3\n",
        &["--no-view"],
    );
    assert!(nff.contains("pp 3") && nff.contains("\np 3\n0 0 0\n1 0 0\n0 1 0\n"), "{nff}");
    // w is ignored (0 was refused, 2 halved the vertex).
    let nff = out("w.obj", "v 0 0 0 1\nv 1 0 0 0\nv 0 2 0 2\nf 1 2 3\n", &["--no-view"]);
    assert!(nff.contains("p 3\n0 0 0\n1 0 0\n0 2 0\n"), "{nff}");
    // A continued line and comments after data.
    let nff =
        out("cont.obj", "v 0 0 0 # origin\nv 1 0 \\\n 0\nv 0 1 0\nf 1 2 3 # the face\n", &["--no-view"]);
    assert!(nff.contains("p 3\n0 0 0\n1 0 0\n0 1 0\n"), "{nff}");
    // `#` inside a word is not a comment: MSVC's `1.#IND` is named, not
    // read as `1.` with a comment (which tobj then refused as too short).
    write_file(dir.path(), "ind.obj", "v 0 0 0\nv 1.#IND 0 0\nv 0 1 0\nf 1 2 3\n");
    let o = mesh2nff(&["ind.obj"], dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("line 2, column 3: `1.#IND` is not a number"), "{err}");
    // A degenerate face far away does not move the framing.
    let nff = out("stray.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1000000 0 0\nf 1 2 3\nf 4 4 4\n", &[]);
    let at = nff.lines().find(|l| l.starts_with("at ")).unwrap();
    let x: f64 = at.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!(x.abs() < 1.0, "{at}");
}

#[test]
fn gltf_is_read_as_the_spec_allows() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, json: &str| {
        write_file(dir.path(), name, json);
        let o = mesh2nff(&[name, "--no-view"], dir.path(), None);
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let plain = gltf_json(&TRI, None, "", 4, "", None);
    let attrs = r#""attributes":{"POSITION":0}"#;
    // An application-specific attribute: valid, ignored.
    let (code, err) =
        run("custom.gltf", &plain.replace(attrs, r#""attributes":{"POSITION":0,"_FEATURE_ID_0":0}"#));
    assert_eq!(code, Some(0), "{err}");
    // A texture only in KHR_texture_basisu form: the factor alone, said.
    let basisu = r#""extensionsUsed":["KHR_texture_basisu"],"extensionsRequired":["KHR_texture_basisu"],
        "images":[{"uri":"t.ktx2","mimeType":"image/ktx2"}],"textures":[{"extensions":{"KHR_texture_basisu":{"source":0}}}],
        "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1],"baseColorTexture":{"index":0}}}],"#;
    let json = gltf_json(&TRI, None, basisu, 4, "", None).replace(attrs, &format!("{attrs},\"material\":0"));
    let (code, err) = run("basisu.gltf", &json);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("texture 0 has its image only in an extension's format"), "{err}");
    // An animation channel without a node (KHR_animation_pointer).
    let anim = r#""extensionsUsed":["KHR_animation_pointer"],"animations":[{"channels":[{"sampler":0,
        "target":{"path":"pointer","extensions":{"KHR_animation_pointer":{"pointer":"/nodes/0/scale"}}}}],
        "samplers":[{"input":0,"output":0}]}],"#;
    let (code, err) = run("anim.gltf", &gltf_json(&TRI, None, anim, 4, "", None));
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("animations skipped"), "{err}");
    // A scene without nodes.
    let (code, err) = run("empty.gltf", &plain.replace(r#""scenes":[{"nodes":[0]}]"#, r#""scenes":[{}]"#));
    assert_eq!(code, Some(1));
    assert!(err.contains("the scene has no nodes"), "{err}");
}

#[test]
fn an_image_used_by_many_textures_is_decoded_once_within_the_memory_bound() {
    use nffkit_formats::mesh::{load_with, resource::ImportOptions};
    let dir = tempfile::tempdir().unwrap();
    // One 64x64 PNG, twenty textures and materials using it.
    let mut png = Vec::new();
    image::RgbImage::from_pixel(64, 64, image::Rgb([200, 30, 30]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let textures: Vec<String> = (0..20).map(|_| r#"{"source":0}"#.to_string()).collect();
    let materials: Vec<String> = (0..20)
        .map(|i| format!(r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":{i}}}}}}}"#))
        .collect();
    let extra = format!(
        r#""images":[{{"uri":"data:image/png;base64,{}"}}],"textures":[{}],"materials":[{}],"#,
        base64(&png),
        textures.join(","),
        materials.join(",")
    );
    let path = write_file(dir.path(), "shared.gltf", &gltf_json(&TRI, None, &extra, 4, "", None));
    let texels = 64 * 64 * 3;
    // Room for two decodes: twenty textures of one image fit, decoded once.
    let opts = ImportOptions { max_texture_bytes: 2 * texels, ..Default::default() };
    let mesh = load_with(&path, &opts).unwrap();
    assert!(!mesh.warnings.iter().any(|w| w.contains("texture")), "{:?}", mesh.warnings);
    // Room for none: each texture keeps its factor, with a warning.
    let opts = ImportOptions { max_texture_bytes: texels - 1, ..Default::default() };
    let mesh = load_with(&path, &opts).unwrap();
    let past =
        mesh.warnings.iter().filter(|w| w.contains(&format!("past {} bytes in all", texels - 1))).count();
    assert_eq!(past, 20, "{:?}", mesh.warnings);
}

#[test]
fn messages_say_what_happened() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |args: &[&str], stdin: Option<&str>| {
        let o = mesh2nff(args, d, stdin);
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    // Degenerate triangles dropped by the importer are in the summary.
    let strip = gltf_json(&TRI, Some(&[0, 1, 2, 2, 2]), "", 5, "", None);
    write_file(d, "strip.gltf", &strip);
    let (code, err) = run(&["strip.gltf", "--no-view"], None);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("2 degenerate triangles dropped") && err.contains("2 degenerate dropped)"), "{err}");
    // Positions outside their buffer are named as such.
    let short = gltf_json(&TRI, None, "", 4, "", None).replace(r#""count":3"#, r#""count":30"#);
    write_file(d, "short.gltf", &short);
    let (code, err) = run(&["short.gltf", "--no-view"], None);
    assert_eq!(code, Some(1));
    assert!(err.contains("POSITION accessor 0") && err.contains("lies outside its data"), "{err}");
    // --camera past the cameras is an argument error.
    write_file(d, "t.gltf", &gltf_json(&TRI, None, "", 4, "", None));
    let (code, err) = run(&["t.gltf", "--camera", "3", "-o", "x.nff"], None);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("--camera 3: t.gltf has 0 perspective cameras") && !err.contains("cannot write"),
        "{err}"
    );
    // A glTF piped to standard input.
    let (code, err) = run(&["-"], Some(&gltf_json(&TRI, None, "", 4, "", None)));
    assert_eq!(code, Some(1));
    assert!(err.contains("standard input is read as OBJ text"), "{err}");
    // A NaN vertex colour: a warning, not a black face.
    write_file(d, "nan.obj", "v 0 0 0 nan 0 0\nv 1 0 0 1 0 0\nv 0 1 0 1 0 0\nf 1 2 3\n");
    let o = mesh2nff(&["nan.obj", "--no-view"], d, None);
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(err.contains("1 vertex colour is not a number"), "{err}");
    assert!(out.contains("f 1 0 0 "), "{out}");
}

#[test]
fn gpu_instancing_places_the_mesh_once_per_instance() {
    let dir = tempfile::tempdir().unwrap();
    let offsets: Vec<u8> =
        [0f32, 0., 0., 10., 0., 0., 20., 0., 0.].iter().flat_map(|f| f.to_le_bytes()).collect();
    let json = gltf_json(&TRI, None, r#""extensionsUsed":["EXT_mesh_gpu_instancing"],"extensionsRequired":["EXT_mesh_gpu_instancing"],"#, 4, r#"[{"mesh":0,"translation":[0,5,0],"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{"TRANSLATION":1}}}}]"#, None)
        .replace(
            r#""buffers":["#,
            &format!(r#""buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{}"}},"#, base64(&offsets)),
        )
        .replace(r#""buffer":0,"byteOffset":0"#, r#""buffer":1,"byteOffset":0"#)
        .replace(r#""bufferViews":["#, r#""bufferViews":[{"buffer":0,"byteLength":36},"#)
        .replace(r#""accessors":[{"bufferView":0"#, r#""accessors":[{"bufferView":1"#);
    // Accessor 0 (positions) now reads view 1 (buffer 1: the triangle);
    // accessor 1, the translations, reads view 0.
    let json = json.replace(
        r#""max":[1.0, 1.0, 0.0]}"#,
        r#""max":[1.0, 1.0, 0.0]},{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}"#,
    );
    let p = write_file(dir.path(), "inst.gltf", &json);
    let (scene, _, _) = convert(&p, &Options::default());
    assert_eq!(scene.primitives.len(), 3, "{json}");
    let xs: Vec<f64> = scene.primitives.iter().map(|p| vertices(&p.shape)[0].x).collect();
    assert_eq!(xs, [0.0, 10.0, 20.0]);
    assert!(scene.primitives.iter().all(|p| vertices(&p.shape)[0].y == 5.0));
}

#[test]
fn punctual_lights_become_nff_lights() {
    let dir = tempfile::tempdir().unwrap();
    let lights = r#""extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":{"lights":[
        {"type":"point","color":[1,0.5,0.5],"intensity":3},{"type":"directional","intensity":1}]}},"#;
    let nodes = r#"[{"mesh":0,"children":[1,2]},{"translation":[0,0,4],"extensions":{"KHR_lights_punctual":{"light":0}}},
        {"rotation":[0.7071068,0,0,0.7071068],"extensions":{"KHR_lights_punctual":{"light":1}}}]"#;
    write_file(dir.path(), "lit.gltf", &gltf_json(&TRI, None, lights, 4, nodes, None));
    let o = mesh2nff(&["lit.gltf"], dir.path(), None);
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("lights from the file's KHR_lights_punctual: 1 point, 1 directional (as a far light)"),
        "{err}"
    );
    let ls: Vec<&str> = out.lines().filter(|l| l.starts_with("l ")).collect();
    assert_eq!(ls.len(), 2, "{out}");
    // The point light where its node is, its power's share (3, 1.5, 1.5 of
    // a total of 4, 2.5, 2.5: scaled by 1/4).
    assert!(ls[0].starts_with("l 0 0 4 0.75 0.375 0.375"), "{}", ls[0]);
    // The directional light shines along its node's -z turned 90° about x
    // (down -y... toward +y from far below): far away on the -y side...
    let y: f64 = ls[1].split_whitespace().nth(2).unwrap().parse().unwrap();
    assert!(y.abs() > 100.0, "{}", ls[1]);
    // A node naming a light the file lacks: refused, not a panic.
    let bad = nodes.replace(r#""light":1"#, r#""light":7"#);
    write_file(dir.path(), "bad.gltf", &gltf_json(&TRI, None, lights, 4, &bad, None));
    let o = mesh2nff(&["bad.gltf"], dir.path(), None);
    assert!(String::from_utf8_lossy(&o.stderr).contains("light 7 does not exist (the file has 2)"));
}
