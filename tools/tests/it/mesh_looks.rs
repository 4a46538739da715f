//! mesh2nff on models that bring their own looks, all written by the tests:
//! textures (data URI, GLB chunk, external file, OBJ map_Kd), vertex
//! colours, emission turned into lights, glTF cameras, the lights added for
//! what the camera sees, and the folder rule for referenced files.

use crate::common::glb;
use base64::Engine;
use glam::{DVec3, Vec3A};
use nffkit_formats::mesh::{load_with, ImportOptions, Mesh};
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{Scene, Shape};
use nffkit_tools::mesh2nff::{write, Lights, Options, Summary};
use std::path::{Path, PathBuf};

fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
    let mut out = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png).unwrap();
    out
}

/// Left texel red, right texel blue.
fn red_blue() -> Vec<u8> {
    png(2, 1, |x, _| if x == 0 { [255, 0, 0] } else { [0, 0, 255] })
}

fn b64(data: &[u8]) -> String {
    base64::engine::general_purpose::STANDARD.encode(data)
}

fn write_file(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A glTF document with one buffer holding `parts` (each becomes a buffer
/// view and accessor, in order), written as JSON with the buffer embedded.
struct Doc {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Doc {
    fn new() -> Doc {
        Doc { bin: Vec::new(), views: Vec::new(), accessors: Vec::new() }
    }

    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend(bytes);
        self.views.len() - 1
    }

    /// Floats in groups of `ty` ("VEC2", "VEC3"); positions get min/max.
    fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let n = if ty == "VEC2" { 2 } else { 3 };
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let v = self.view(&bytes);
        let bounds = if ty == "VEC3" {
            let c =
                |k: usize, f: fn(f32, f32) -> f32| data.iter().skip(k).step_by(3).copied().reduce(f).unwrap();
            format!(
                r#","min":[{},{},{}],"max":[{},{},{}]"#,
                c(0, f32::min),
                c(1, f32::min),
                c(2, f32::min),
                c(0, f32::max),
                c(1, f32::max),
                c(2, f32::max)
            )
        } else {
            String::new()
        };
        self.accessors.push(format!(
            r#"{{"bufferView":{v},"componentType":5126,"count":{},"type":"{ty}"{bounds}}}"#,
            data.len() / n
        ));
        self.accessors.len() - 1
    }

    fn indices(&mut self, ix: &[u16]) -> usize {
        let bytes: Vec<u8> = ix.iter().flat_map(|i| i.to_le_bytes()).collect();
        let v = self.view(&bytes);
        self.accessors.push(format!(
            r#"{{"bufferView":{v},"componentType":5123,"count":{},"type":"SCALAR"}}"#,
            ix.len()
        ));
        self.accessors.len() - 1
    }

    /// The document: `primitives` and `rest` (materials, images, ...) are
    /// JSON; `nodes` the node list (the scene holds them all).
    fn json(&self, primitives: &str, nodes: &str, rest: &str) -> String {
        let n = nodes.matches('{').count();
        let roots: Vec<String> = (0..n).map(|i| i.to_string()).collect();
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":{nodes},
"meshes":[{{"primitives":{primitives}}}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
"bufferViews":[{}],"accessors":[{}]{rest}}}"#,
            roots.join(","),
            self.bin.len(),
            b64(&self.bin),
            self.views.join(","),
            self.accessors.join(",")
        )
    }
}

/// A unit quad in z = 0 (two triangles, counter-clockwise seen from +z) with
/// UVs u = x, v = 1 − y; returns (positions, uvs, indices) accessors.
fn quad(doc: &mut Doc) -> (usize, usize, usize) {
    let p = doc.floats(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.], "VEC3");
    let uv = doc.floats(&[0., 1., 1., 1., 1., 0., 0., 0.], "VEC2");
    let ix = doc.indices(&[0, 1, 2, 0, 2, 3]);
    (p, uv, ix)
}

fn load(path: &Path, opts: &ImportOptions) -> Mesh {
    load_with(path, opts).unwrap_or_else(|e| panic!("{e}"))
}

fn convert(mesh: &Mesh, opts: &Options) -> (Scene, Summary) {
    let (text, summary) = write(mesh, opts, Vec::new()).unwrap();
    let parsed = nff::parse(&text, &ParseOptions { fragment: !opts.view, ..Default::default() })
        .unwrap_or_else(|e| panic!("{e}\n{}", String::from_utf8_lossy(&text)));
    (parsed.scene, summary)
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

/// The colour of each primitive, in the order written.
fn colours(scene: &Scene) -> Vec<DVec3> {
    scene.primitives.iter().map(|p| scene.material_of(p).color).collect()
}

/// The two triangles of `quad` over the red|blue texture: the first lies
/// mostly right of u = 1/2 (3/4 of it blue), the second mostly left.
fn assert_red_blue_faces(scene: &Scene) {
    let c = colours(scene);
    assert_eq!(c.len(), 2);
    let blueish = DVec3::new(0.25, 0.0, 0.75);
    let reddish = DVec3::new(0.75, 0.0, 0.25);
    // Sampled at 64 points each: within a few percent of the exact shares.
    assert!(close(c[0], blueish, 0.05) && close(c[1], reddish, 0.05), "{c:?}");
}

const TEXTURED_PRIMITIVE: &str = r#"[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]"#;
const PLAIN_MATERIAL: &str = r#""materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":1}}],
"textures":[{"source":0}]"#;

#[test]
fn a_gltf_texture_colours_each_face_from_a_data_uri_a_file_or_the_glb_chunk() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    quad(&mut doc);
    let data_uri =
        format!(r#","images":[{{"uri":"data:image/png;base64,{}"}}],{PLAIN_MATERIAL}"#, b64(&red_blue()));
    let p = write_file(dir.path(), "data.gltf", doc.json(TEXTURED_PRIMITIVE, r#"[{"mesh":0}]"#, &data_uri));
    let (scene, summary) = convert(&load(&p, &ImportOptions::default()), &Options::default());
    assert_red_blue_faces(&scene);
    assert_eq!(summary.materials, 2, "one `f` line per colour");

    write_file(dir.path(), "rb.png", red_blue());
    let file = format!(r#","images":[{{"uri":"rb.png"}}],{PLAIN_MATERIAL}"#);
    let p = write_file(dir.path(), "file.gltf", doc.json(TEXTURED_PRIMITIVE, r#"[{"mesh":0}]"#, &file));
    assert_red_blue_faces(&convert(&load(&p, &ImportOptions::default()), &Options::default()).0);

    // GLB: the image in the binary chunk, through a buffer view.
    let mut glb_doc = Doc::new();
    quad(&mut glb_doc);
    let image_view = glb_doc.view(&red_blue());
    let json = glb_doc
        .json(
            TEXTURED_PRIMITIVE,
            r#"[{"mesh":0}]"#,
            &format!(r#","images":[{{"bufferView":{image_view},"mimeType":"image/png"}}],{PLAIN_MATERIAL}"#),
        )
        .replace(
            &format!(r#""uri":"data:application/octet-stream;base64,{}""#, b64(&glb_doc.bin)),
            "\"x\":0",
        );
    let p = write_file(dir.path(), "t.glb", glb(&json, &glb_doc.bin));
    assert_red_blue_faces(&convert(&load(&p, &ImportOptions::default()), &Options::default()).0);

    // --no-textures: the factor (white) alone, and a warning saying so.
    let mesh = load(&p, &ImportOptions { textures: false, ..Default::default() });
    assert!(mesh.warnings.iter().any(|w| w.contains("--no-textures")), "{:?}", mesh.warnings);
    assert!(colours(&convert(&mesh, &Options::default()).0).iter().all(|c| *c == DVec3::ONE));
}

#[test]
fn a_missing_undecodable_or_outside_texture_is_a_warning_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    quad(&mut doc);
    write_file(dir.path(), "broken.png", b"not a png");
    for (uri, says) in [
        ("gone.png", "gone.png"),
        ("broken.png", "broken.png"),
        ("../outside.png", "leaves the model's folder"),
        ("/etc/hostname", "leaves the model's folder"),
    ] {
        let rest = format!(r#","images":[{{"uri":"{uri}"}}],{PLAIN_MATERIAL}"#);
        let p = write_file(dir.path(), "m.gltf", doc.json(TEXTURED_PRIMITIVE, r#"[{"mesh":0}]"#, &rest));
        let mesh = load(&p, &ImportOptions::default());
        let w = mesh.warnings.join("\n");
        assert!(w.contains(says) && w.contains("using the factor alone"), "{uri}: {w}");
        assert!(colours(&convert(&mesh, &Options::default()).0).iter().all(|c| *c == DVec3::ONE));
    }
    // --allow-outside-paths reads a texture beside the folder.
    let inner = dir.path().join("model");
    std::fs::create_dir(&inner).unwrap();
    write_file(dir.path(), "outside.png", red_blue());
    let rest = format!(r#","images":[{{"uri":"../outside.png"}}],{PLAIN_MATERIAL}"#);
    let p = write_file(&inner, "m.gltf", doc.json(TEXTURED_PRIMITIVE, r#"[{"mesh":0}]"#, &rest));
    let mesh = load(&p, &ImportOptions { allow_outside_paths: true, ..Default::default() });
    assert_red_blue_faces(&convert(&mesh, &Options::default()).0);
}

#[test]
fn a_buffer_outside_the_model_folder_is_refused_unless_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("model");
    std::fs::create_dir(&inner).unwrap();
    let bin: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|f| f.to_le_bytes()).collect();
    write_file(dir.path(), "tri.bin", &bin);
    let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":36,"uri":"../tri.bin"}],
"bufferViews":[{"buffer":0,"byteLength":36}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]}"#;
    let p = write_file(&inner, "m.gltf", json);
    let e = load_with(&p, &ImportOptions::default()).unwrap_err().to_string();
    assert!(e.contains("m.gltf") && e.contains("buffer 0") && e.contains("`../tri.bin` leaves"), "{e}");
    let mesh = load(&p, &ImportOptions { allow_outside_paths: true, ..Default::default() });
    assert_eq!(mesh.faces.len(), 1);
}

#[test]
fn obj_map_kd_and_vertex_colours_colour_the_faces() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    write_file(&dir.path().join("tex"), "rb.png", red_blue());
    // Options before the name, and a Windows separator, as exporters write.
    write_file(dir.path(), "m.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd -s 1 1 1 tex\\rb.png\n");
    // OBJ's v runs up: vt (u, v) = (x, y) is the same mapping as the glTF quad.
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
               usemtl tex\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
    let p = write_file(dir.path(), "m.obj", obj);
    assert_red_blue_faces(&convert(&load(&p, &ImportOptions::default()), &Options::default()).0);

    // Vertex colours on some vertices only: faces with none keep the
    // material colour, the others average the corners that have one.
    let obj = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
               f 1 2 3\nf 2 5 6\nf 1 3 4\n";
    let p = write_file(dir.path(), "vc.obj", obj);
    let mesh = load(&p, &ImportOptions::default());
    let (scene, _) = convert(&mesh, &Options::default());
    let by_x = |x: f64| {
        scene.primitives.iter().find(|p| match &p.shape {
            Shape::Polygon { vertices } => vertices.iter().any(|v| v.x == x),
            _ => false,
        })
    };
    let c = |x: f64| scene.material_of(by_x(x).unwrap()).color;
    assert!(close(c(2.0), DVec3::new(0.0, 1.0, 0.0), 0.01), "only vertex 2 coloured: {}", c(2.0));
    let first = scene.material_of(&scene.primitives[0]).color;
    assert!(close(first, DVec3::splat(1.0 / 3.0), 0.01), "mean of red, green, blue: {first}");
    let third = colours(&scene)[2];
    assert!(close(third, DVec3::new(0.5, 0.0, 0.5), 0.01), "mean of red and blue: {third}");
}

#[test]
fn gltf_vertex_colours_are_averaged_per_face_times_the_factor() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let (_, _, _) = quad(&mut doc);
    let col = doc.floats(&[1., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.], "VEC3");
    let prim = format!(r#"[{{"attributes":{{"POSITION":0,"COLOR_0":{col}}},"indices":2,"material":0}}]"#);
    let rest =
        r#","materials":[{"pbrMetallicRoughness":{"baseColorFactor":[1,1,0.5,1],"metallicFactor":0}}]"#;
    let p = write_file(dir.path(), "vc.gltf", doc.json(&prim, r#"[{"mesh":0}]"#, rest));
    let (scene, _) = convert(&load(&p, &ImportOptions::default()), &Options::default());
    let c = colours(&scene);
    // Triangle (0, 1, 2): red, red, green; triangle (0, 2, 3): red, green, blue.
    assert!(close(c[0], DVec3::new(2.0 / 3.0, 1.0 / 3.0, 0.0), 0.01), "{c:?}");
    assert!(close(c[1], DVec3::new(1.0 / 3.0, 1.0 / 3.0, 0.5 / 3.0), 0.01), "{c:?}");
}

#[test]
fn an_emissive_quad_becomes_lights_keeping_the_total_and_shows_its_colour() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    quad(&mut doc);
    let prim = r#"[{"attributes":{"POSITION":0},"indices":2,"material":0}]"#;
    let rest = r#","materials":[{"emissiveFactor":[1,0.5,0.25],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}]"#;
    let p = write_file(dir.path(), "e.gltf", doc.json(prim, r#"[{"mesh":0}]"#, rest));
    let mesh = load(&p, &ImportOptions::default());
    assert_eq!(mesh.faces[0].emission, Some([4.0, 2.0, 1.0]));
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.emission_lights >= 2, "two large triangles: a few lights each");
    assert_eq!(scene.lights.len(), summary.emission_lights, "nothing else lights a self-lit model");
    let total: DVec3 = scene.lights.iter().map(|l| l.color.unwrap()).sum();
    assert!(
        close(total, DVec3::new(1.0, 0.5, 0.25), 1e-6),
        "the total keeps the hue, brightest channel 1: {total}"
    );
    for l in &scene.lights {
        let p = l.position;
        assert!(p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0 && p.z > 0.0, "in front of the quad: {p}");
    }
    // It renders in its emission clamped to 1: white (the written colour
    // makes up for the lights' hue), not a dim orange.
    let (_, mean) = model_pixels(&render(&scene));
    assert!(mean.min_element() > 0.75 && mean.max_element() - mean.min_element() < 0.05, "white: {mean}");

    // OBJ Ke: the same, through the material library.
    write_file(dir.path(), "k.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 2 2 2\n");
    let obj = "mtllib k.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 -1\nv 1 0 -1\nv 1 1 -1\n\
               f 5 6 7\nusemtl lamp\nf 1 2 3 4\n";
    let mesh = load(&write_file(dir.path(), "k.obj", obj), &ImportOptions::default());
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.emission_lights >= 1);
    // The emission lights come first (an eye light may follow).
    let total: DVec3 = scene.lights[..summary.emission_lights].iter().map(|l| l.color.unwrap()).sum();
    assert!(close(total, DVec3::ONE, 1e-6), "{total}");
}

/// The Cornell-style box of the issue: walls, a block, a `Ke` panel under
/// the ceiling; open at +z.
const CORNELL_MTL: &str = "newmtl white\nKd 0.75 0.75 0.75\nnewmtl red\nKd 0.63 0.06 0.05\n\
newmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\n";
const CORNELL_OBJ: &str = "mtllib c.mtl\n\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
v 0.4 0.998 0.4\nv 0.6 0.998 0.4\nv 0.6 0.998 0.6\nv 0.4 0.998 0.6\n\
v 0.3 0 0.3\nv 0.5 0 0.3\nv 0.5 0.3 0.3\nv 0.3 0.3 0.3\n\
usemtl white\nf 1 5 6 2\nf 4 3 7 8\nf 1 2 3 4\nf 2 6 7 3\n\
usemtl red\nf 1 4 8 5\n\
usemtl white\nf 13 14 15 16\n\
usemtl light\nf 9 10 11 12\n";

/// The pixels that are not the background: how many, and their mean
/// (each clamped to 1, as an image shows it).
fn model_pixels(film: &nffkit_tracer::film::Film) -> (usize, Vec3A) {
    let background = nffkit_formats::SPD_SKY.as_vec3a();
    let seen: Vec<Vec3A> = (0..film.width * film.height)
        .map(|i| film.get(i % film.width, i / film.width))
        .filter(|c| (*c - background).abs().max_element() > 1e-3)
        .collect();
    (seen.len(), seen.iter().map(|c| c.min(Vec3A::ONE)).sum::<Vec3A>() / seen.len().max(1) as f32)
}

fn render(scene: &Scene) -> nffkit_tracer::film::Film {
    let opts =
        nffkit_tracer::prepare::PrepareOptions { width: Some(64), height: Some(64), ..Default::default() };
    let prepared = nffkit_tracer::prepare::prepare(scene, &opts).unwrap();
    nffkit_tracer::render::render(&prepared, &Default::default(), &|_, _| {}).film
}

#[test]
fn a_cornell_box_is_lit_by_its_panel_and_seen_through_its_opening() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "c.mtl", CORNELL_MTL);
    let mesh = load(&write_file(dir.path(), "c.obj", CORNELL_OBJ), &ImportOptions::default());
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.emission_lights > 0 && scene.lights.iter().all(|l| l.color.is_some()));
    for l in &scene.lights {
        assert!(
            l.position.y < 0.998 && l.position.y > 0.9,
            "below the panel, inside the box: {}",
            l.position
        );
    }
    let v = scene.view.as_ref().unwrap();
    assert!(
        v.from.z > 1.0 && (v.from.x - 0.5).abs() < 0.3,
        "looking in through the open front: {:?}",
        v.from
    );
    // The centre of the image is the lit back wall, warm like the panel.
    let film = render(&scene);
    let c = film.get(32, 32);
    assert!(c.x > 0.2 && c.x > c.z, "back wall lit by the panel: {c}");
}

/// An OBJ cube of side `side` at `at` (its faces wound outward), each face
/// with the material of the `usemtl` line before it.
fn obj_cube(first_vertex: usize, at: DVec3, side: f64) -> String {
    let mut s = String::new();
    for i in 0..8 {
        let c = |bit: usize| if i >> bit & 1 == 1 { side / 2.0 } else { -side / 2.0 };
        s += &format!("v {} {} {}\n", at.x + c(0), at.y + c(1), at.z + c(2));
    }
    for f in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
        let f = f.map(|k| (k + first_vertex).to_string());
        s += &format!("f {}\n", f.join(" "));
    }
    s
}

/// An emitter that is all the model, closed (every face on its bounding
/// box): its lights sit outside it, and it renders in its emission.
#[test]
fn a_closed_emitter_shines_outward_and_shows_its_emission() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "e.mtl", "newmtl glow\nKd 0.5 0.5 0.5\nKe 0.8 0.4 0.2\n");
    let obj = format!("mtllib e.mtl\nusemtl glow\n{}", obj_cube(1, DVec3::ZERO, 1.0));
    let mesh = load(&write_file(dir.path(), "e.obj", obj), &ImportOptions::default());
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.emission_lights >= 6, "{summary:?}");
    for l in &scene.lights[..summary.emission_lights] {
        assert!(l.position.abs().max_element() > 0.5, "outside the cube: {}", l.position);
    }
    let (count, mean) = model_pixels(&render(&scene));
    assert!(
        count > 500 && close(mean.as_dvec3(), DVec3::new(0.8, 0.4, 0.2), 0.12),
        "in its emission: {mean}"
    );
    // Beside a floor, the floor around it is lit by it.
    let obj = format!(
        "mtllib e.mtl\nv -3 -0.6 -3\nv 3 -0.6 -3\nv 3 -0.6 3\nv -3 -0.6 3\nf 4 3 2 1\nusemtl glow\n{}",
        obj_cube(5, DVec3::ZERO, 1.0)
    );
    let mesh = load(&write_file(dir.path(), "f.obj", obj), &ImportOptions::default());
    let (scene, summary) = convert(&mesh, &Options { lights: Lights::None, ..Default::default() });
    assert!(summary.emission_lights > 0 && scene.lights.len() == summary.emission_lights);
    let film = render(&scene);
    // Below the cube's image, a column of floor: lit, and not sky.
    let floor = (38..46)
        .map(|y| film.get(32, y))
        .filter(|c| (*c - nffkit_formats::SPD_SKY.as_vec3a()).abs().max_element() > 1e-3);
    let brightest = floor.fold(Vec3A::ZERO, |a, c| a.max(c));
    assert!(brightest.x > 0.05 && brightest.x > brightest.z, "the floor in front is lit: {brightest}");
}

/// A small emitter (a label on a model) does not switch the framing lights
/// off: the model renders lit as one without it would, the label in its
/// emission.
#[test]
fn a_small_emitter_keeps_the_framing_lights() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "l.mtl", "newmtl white\nKd 0.8 0.8 0.8\nnewmtl label\nKd 0.5 0.5 0.5\nKe 0 1 0\n");
    let label = "v -0.1 -0.05 0.51\nv 0.1 -0.05 0.51\nv 0.1 0.05 0.51\nv -0.1 0.05 0.51\nf 9 10 11 12\n";
    let obj = format!("mtllib l.mtl\nusemtl white\n{}usemtl label\n{label}", obj_cube(1, DVec3::ZERO, 1.0));
    let mesh = load(&write_file(dir.path(), "l.obj", obj), &ImportOptions::default());
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.notes.iter().any(|n| n.contains("beside the framing lights")), "{:?}", summary.notes);
    // The framing lights as strong as alone: 1/sqrt(2), not 1/sqrt(10).
    let white =
        |l: &&nffkit_formats::Light| l.color.is_some_and(|c| close(c, DVec3::splat(0.5f64.sqrt()), 1e-12));
    assert_eq!(scene.lights.iter().filter(white).count(), 2, "{:?}", scene.lights);
    let emitted: DVec3 = scene.lights.iter().filter(|l| !white(l)).filter_map(|l| l.color).sum();
    assert!(emitted.max_element() < 0.1, "the label's lights are weak: {emitted}");
    let film = render(&scene);
    let mean =
        (0..64 * 64).map(|i| film.get(i % 64, i / 64).min(Vec3A::ONE).element_sum() / 3.0).sum::<f32>()
            / 4096.0;
    let (without, _) = convert(
        &load(
            &write_file(dir.path(), "w.obj", format!("usemtl white\n{}", obj_cube(1, DVec3::ZERO, 1.0))),
            &ImportOptions::default(),
        ),
        &Options::default(),
    );
    let film_without = render(&without);
    let mean_without = (0..64 * 64)
        .map(|i| film_without.get(i % 64, i / 64).min(Vec3A::ONE).element_sum() / 3.0)
        .sum::<f32>()
        / 4096.0;
    assert!(mean > 0.8 * mean_without, "lit as without the label: {mean} against {mean_without}");
}

/// Lights go to the side the face's normals point to: the file's normals
/// when it gives them, else its winding.
#[test]
fn emission_lights_go_where_the_normals_point() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "n.mtl", "newmtl lamp\nKe 1 1 1\n");
    let quad = "mtllib n.mtl\nusemtl lamp\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 -1\n";
    for (faces, front) in [("f 1 2 3 4\n", 1.0), ("f 1//1 2//1 3//1 4//1\n", -1.0), ("f 4 3 2 1\n", -1.0)] {
        let mesh =
            load(&write_file(dir.path(), "n.obj", format!("{quad}{faces}")), &ImportOptions::default());
        let (scene, summary) = convert(&mesh, &Options::default());
        for l in &scene.lights[..summary.emission_lights] {
            assert!(l.position.z * front > 0.0, "{faces}: {}", l.position);
        }
    }
}

/// A closed cube of side 2 around the origin with a camera inside, no lights
/// of its own: the framing lights outside cannot reach in.
#[test]
fn a_closed_box_around_the_camera_renders_lit_by_a_light_at_the_eye() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    let p: Vec<f32> = (0..8)
        .flat_map(|i| {
            [(i & 1) as f32 * 2.0 - 1.0, (i >> 1 & 1) as f32 * 2.0 - 1.0, (i >> 2) as f32 * 2.0 - 1.0]
        })
        .collect();
    doc.floats(&p, "VEC3");
    doc.indices(&[
        0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1,
        7, 5,
    ]);
    let prim = r#"[{"attributes":{"POSITION":0},"indices":1}]"#;
    let nodes = r#"[{"mesh":0},{"camera":0,"translation":[0,0,0.5]}]"#;
    let rest = r#","cameras":[{"type":"perspective","perspective":{"yfov":1.0,"znear":0.01}}]"#;
    let path = write_file(dir.path(), "room.gltf", doc.json(prim, nodes, rest));
    let mesh = load(&path, &ImportOptions::default());
    assert_eq!(mesh.cameras.len(), 1);
    let (scene, summary) = convert(&mesh, &Options::default());
    assert!(summary.notes.iter().any(|n| n.contains("light at the eye")), "{:?}", summary.notes);
    assert!(scene.lights.iter().any(|l| l.position == DVec3::new(0.0, 0.0, 0.5)));
    let film = render(&scene);
    assert!(film.get(32, 32).min_element() > 0.3, "the far wall is lit: {}", film.get(32, 32));
    // --lights none: only the model's own (none here), so it renders black.
    let (dark, _) = convert(&mesh, &Options { lights: Lights::None, ..Default::default() });
    assert!(dark.lights.is_empty());
}

#[test]
fn a_gltf_camera_becomes_the_view() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Doc::new();
    quad(&mut doc);
    let prim = r#"[{"attributes":{"POSITION":0},"indices":2}]"#;
    // Camera 0 at (0.5, 0.5, 3) looking down −Z; camera 1 turned 90° about Y
    // (looking down −X) at (4, 0.5, 0.5), with a 2:1 aspect.
    let nodes = r#"[{"mesh":0},{"camera":0,"translation":[0.5,0.5,3]},
{"camera":1,"translation":[4,0.5,0.5],"rotation":[0,0.7071067811865476,0,0.7071067811865476]}]"#;
    let rest = r#","cameras":[{"type":"perspective","name":"front","perspective":{"yfov":0.5,"znear":0.1}},
{"type":"perspective","perspective":{"yfov":0.8,"aspectRatio":2.0,"znear":0.05}}]"#;
    let mesh =
        load(&write_file(dir.path(), "cams.gltf", doc.json(prim, nodes, rest)), &ImportOptions::default());
    assert_eq!(mesh.cameras.len(), 2);
    let (scene, summary) = convert(&mesh, &Options { camera: Some(0), ..Default::default() });
    let v = scene.view.unwrap();
    assert!(
        close(v.from, DVec3::new(0.5, 0.5, 3.0), 1e-6) && close((v.at - v.from).normalize(), -DVec3::Z, 1e-6)
    );
    assert!(close(v.up, DVec3::Y, 1e-6) && v.resolution == [512, 512]);
    let expect = 2.0 * (0.25f64.tan() * 511.0 / 512.0).atan();
    assert!((v.angle - expect.to_degrees()).abs() < 1e-6, "{} vs {}", v.angle, expect.to_degrees());
    assert!((v.hither - 0.1).abs() < 1e-6);
    assert!(summary.notes.iter().any(|n| n.contains("camera 0 `front`")), "{:?}", summary.notes);

    let (scene, _) = convert(&mesh, &Options { camera: Some(1), scale: 2.0, ..Default::default() });
    let v = scene.view.unwrap();
    assert!(close(v.from, DVec3::new(8.0, 1.0, 1.0), 1e-6), "placed like the positions: {:?}", v.from);
    assert!(close((v.at - v.from).normalize(), -DVec3::X, 1e-6));
    assert_eq!(v.resolution, [512, 256], "512 wide at the camera's aspect ratio");
    let expect = 2.0 * (0.4f64.tan() * 255.0 / 256.0).atan();
    assert!((v.angle - expect.to_degrees()).abs() < 1e-6);
    assert!((v.hither - 0.1).abs() < 1e-6, "znear 0.05 scaled by 2: {}", v.hither);
    // --fit places the camera like the positions: the quad (side 1) is
    // centred, so (4, 0.5, 0.5) − (0.5, 0.5, 0) = (3.5, 0, 0.5), mirrored
    // by the negative scale (the probe renders of that view once tripped
    // an overflow on −0 in the ray offset).
    let (scene, _) =
        convert(&mesh, &Options { camera: Some(1), fit: true, scale: -1.0, ..Default::default() });
    let v = scene.view.unwrap();
    assert!(close(v.from, -DVec3::new(3.5, 0.0, 0.5), 1e-6), "{:?}", v.from);
    assert!(close((v.at - v.from).normalize(), DVec3::X, 1e-6) && close(v.up, -DVec3::Y, 1e-6), "mirrored");

    // With several cameras and none asked for, the framing view.
    let (scene, _) = convert(&mesh, &Options::default());
    assert!(scene.view.unwrap().from.z < 3.0);
    let e = write(&mesh, &Options { camera: Some(2), ..Default::default() }, Vec::new()).unwrap_err();
    assert!(e.to_string().contains("--camera 2: the model has 2 perspective cameras"), "{e}");
}

fn mesh2nff(args: &[&str], dir: &Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_mesh2nff")).args(args).current_dir(dir).output().unwrap()
}

#[test]
fn the_command_line_takes_lights_camera_and_path_options_and_check_finds_it_lit() {
    let dir = tempfile::tempdir().unwrap();
    write_file(dir.path(), "c.mtl", CORNELL_MTL);
    write_file(dir.path(), "c.obj", CORNELL_OBJ);
    let out = mesh2nff(&["c.obj", "-o", "c.nff"], dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("lights from emitting faces"), "{err}");
    let check = std::process::Command::new(env!("CARGO_BIN_EXE_render"))
        .args(["--check", "c.nff"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&check.stderr);
    assert!(check.status.success() && !said.contains("no lights"), "{said}");

    let out = mesh2nff(&["c.obj", "--lights", "eye"], dir.path());
    let text = String::from_utf8_lossy(&out.stdout);
    let eye_line = text.lines().find(|l| l.starts_with("from ")).unwrap().replace("from ", "l ");
    assert!(text.lines().any(|l| l.starts_with(&eye_line)), "a light at the eye:\n{text}");

    let out = mesh2nff(&["c.obj", "--camera", "0"], dir.path());
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--camera 0: c.obj has 0 perspective cameras"));

    write_file(dir.path(), "far.mtl", "newmtl m\nKd 1 0 0\n");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    write_file(
        &dir.path().join("sub"),
        "m.obj",
        "mtllib ../far.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
    );
    let out = mesh2nff(&["sub/m.obj"], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.contains("`../far.mtl` leaves the model's folder"), "{err}");
    let out = mesh2nff(&["sub/m.obj", "--allow-outside-paths"], dir.path());
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("f 1 0 0"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
