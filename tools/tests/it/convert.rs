//! `nffconvert` out of NFF: real programs read what it writes. POV-Ray
//! renders the export of SPD databases with `render`'s silhouettes and
//! brightness, Mitsuba 3 with its silhouettes; the Khronos glTF-Validator
//! finds no error in any glTF;
//! `mesh2nff` (through tobj and gltf) reads the OBJ and glTF back to the
//! same triangles.

use crate::common::program;
use glam::DVec3;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Shape;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const RENDER: &str = env!("CARGO_BIN_EXE_render");
const CONVERT: &str = env!("CARGO_BIN_EXE_nffconvert");
const MESH2NFF: &str = env!("CARGO_BIN_EXE_mesh2nff");

fn run(bin: &str, args: &[&str]) -> Output {
    Command::new(bin).args(args).output().unwrap()
}

fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}{}", String::from_utf8_lossy(&o.stdout));
    err
}

fn spd(name: &str) -> String {
    format!("{}/../scenes/spd/{name}.nff", env!("CARGO_MANIFEST_DIR"))
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Per-pixel agreement of the foreground (not the background colour, to
/// within 3/255) of two images, and the ratio of their mean brightness
/// over the pixels both cover.
fn compare(a: &image::RgbImage, b: &image::RgbImage, bg: [u8; 3]) -> (f64, f64) {
    let fg = |p: &image::Rgb<u8>| p.0.iter().zip(bg).any(|(c, g)| c.abs_diff(g) > 3);
    let (mut agree, mut sum_a, mut sum_b) = (0usize, 0f64, 0f64);
    for (pa, pb) in a.pixels().zip(b.pixels()) {
        let (fa, fb) = (fg(pa), fg(pb));
        agree += (fa == fb) as usize;
        if fa && fb {
            sum_a += pa.0.iter().map(|&c| c as f64).sum::<f64>();
            sum_b += pb.0.iter().map(|&c| c as f64).sum::<f64>();
        }
    }
    (agree as f64 / a.pixels().len() as f64, sum_b / sum_a.max(1.0))
}

/// `src` with every material white, matte and opaque, on black: its
/// image is its silhouette.
fn silhouette_scene(src: &str) -> String {
    src.lines()
        .map(|l| match l.split_whitespace().next() {
            Some("f") => "f 1 1 1 1 0 1 0 1".to_string(),
            Some("b") => "b 0 0 0".to_string(),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `scene` rendered by `render` and by POV-Ray from nffconvert's export, at
/// 128x128: the two images.
fn both(povray: &Path, dir: &Path, name: &str, src: &str) -> (image::RgbImage, image::RgbImage) {
    let nff = dir.join(format!("{name}.nff"));
    std::fs::write(&nff, src).unwrap();
    let pov = dir.join(format!("{name}.pov"));
    let (ours, theirs) = (dir.join(format!("{name}.png")), dir.join(format!("{name}-pov.png")));
    ok(&run(CONVERT, &[path(&nff), "-o", path(&pov), "-q"]));
    ok(&run(RENDER, &[path(&nff), "-o", path(&ours), "--width", "128", "--height", "128", "-q"]));
    let o = Command::new(povray)
        .args([&format!("+I{}", path(&pov)), &format!("+O{}", path(&theirs))])
        .args(["+W128", "+H128", "-D", "+FN", "-A", "File_Gamma=1.0", "-GA", "+WT2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
    (image::open(&ours).unwrap().to_rgb8(), image::open(&theirs).unwrap().to_rgb8())
}

#[test]
fn povray_renders_the_export_with_renders_silhouettes_and_brightness() {
    let Some(povray) = program("povray") else { return };
    let dir = tempfile::tempdir().unwrap();
    for scene in
        ["balls_s1", "mount_s5", "gears_s1", "tree_s1", "rings_s1", "teapot_s1", "jacks_s1", "lattice_s1"]
    {
        let src = std::fs::read_to_string(spd(scene)).unwrap();
        let (a, b) = both(&povray, dir.path(), &format!("{scene}-flat"), &silhouette_scene(&src));
        let (agreement, _) = compare(&a, &b, [0, 0, 0]);
        let (a, b) = both(&povray, dir.path(), scene, &src);
        let (_, brightness) = compare(&a, &b, [20, 92, 192]);
        eprintln!("{scene}: foreground agreement {agreement:.4}, brightness POV-Ray/render {brightness:.3}");
        assert!(agreement >= 0.98, "{scene}: foreground agreement {agreement}");
        assert!((0.9..=1.1).contains(&brightness), "{scene}: brightness ratio {brightness}");
    }
}

#[test]
fn mitsuba_renders_the_export_with_renders_silhouettes() {
    let Some(python) = program("python") else { return };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/support/mitsuba-coverage.py");
    let dir = tempfile::tempdir().unwrap();
    for scene in ["mount_s5", "gears_s1", "tree_s1", "rings_s1", "teapot_s1", "jacks_s1", "lattice_s1"] {
        let src = std::fs::read_to_string(spd(scene)).unwrap();
        let flat = silhouette_scene(&src)
            .lines()
            .map(|l| if l.starts_with("resolution") { "resolution 128 128" } else { l })
            .collect::<Vec<_>>()
            .join("\n");
        let nff = dir.path().join(format!("{scene}.nff"));
        std::fs::write(&nff, flat).unwrap();
        let (xml, pgm, ours) = (
            dir.path().join(format!("{scene}.xml")),
            dir.path().join(format!("{scene}.pgm")),
            dir.path().join(format!("{scene}.png")),
        );
        ok(&run(CONVERT, &[path(&nff), "-o", path(&xml), "-q"]));
        let o = Command::new(&python).arg(&script).arg(&xml).arg(&pgm).output().unwrap();
        if !o.status.success() && String::from_utf8_lossy(&o.stderr).contains("No module named 'mitsuba'") {
            let required = std::env::var("NFFKIT_TEST_TOOLS").is_ok_and(|v| v == "required");
            assert!(!required, "mitsuba is missing (scripts/install-test-tools.sh installs it)");
            eprintln!("skipped: mitsuba is not installed");
            return;
        }
        assert!(o.status.success(), "{scene}: {}", String::from_utf8_lossy(&o.stderr));
        // Coverage, ours: white under ambient 1 on black, 16 samples.
        ok(&run(RENDER, &[path(&nff), "-o", path(&ours), "--ambient", "1", "--spp", "16", "-q"]));
        let a = image::open(&ours).unwrap().to_luma8();
        let b = image::open(&pgm).unwrap().to_luma8();
        assert_eq!(a.dimensions(), b.dimensions(), "{scene}");
        let agree = a.pixels().zip(b.pixels()).filter(|(p, q)| (p.0[0] > 127) == (q.0[0] > 127)).count();
        let agreement = agree as f64 / a.pixels().len() as f64;
        eprintln!("{scene}: Mitsuba foreground agreement {agreement:.4}");
        assert!(agreement >= 0.98, "{scene}: Mitsuba foreground agreement {agreement}");
    }
}

#[test]
fn the_glb_and_gltf_exports_pass_the_khronos_validator() {
    let Some(node) = program("node") else { return };
    let validator =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/test-tools/npm/node_modules/gltf-validator");
    if !validator.is_dir() {
        let required = std::env::var("NFFKIT_TEST_TOOLS").is_ok_and(|v| v == "required");
        assert!(!required, "gltf-validator is missing (scripts/install-test-tools.sh installs it)");
        eprintln!("skipped: gltf-validator is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut files: Vec<PathBuf> = Vec::new();
    for scene in ["balls_s1", "gears_s1", "tree_s1", "teapot_s1", "mount_s1"] {
        for ext in ["gltf", "glb"] {
            let out = dir.path().join(format!("{scene}.{ext}"));
            ok(&run(CONVERT, &[&spd(scene), "-o", path(&out), "-q"]));
            files.push(out);
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/support/gltf-validate.js");
    let o = Command::new(node).arg(script).arg(&validator).args(&files).output().unwrap();
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{report}{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(report.matches(": 0 errors").count(), files.len(), "{report}");
}

/// The triangles of a scene's polygons, patches and boxes, corners
/// rounded to `digits` decimals (from its smallest corner), sorted.
fn triangles(text: &[u8], digits: i32) -> Vec<[[i64; 3]; 3]> {
    let scene = nff::parse(text, &ParseOptions { fragment: true, ..Default::default() }).unwrap().scene;
    let round = |v: DVec3| v.to_array().map(|x| (x * 10f64.powi(digits)).round() as i64);
    let mut out: Vec<[[i64; 3]; 3]> = Vec::new();
    let mut polygons: Vec<Vec<DVec3>> = Vec::new();
    for p in &scene.primitives {
        match &p.shape {
            Shape::Polygon { vertices } => polygons.push(vertices.clone()),
            Shape::Patch(patch) => polygons.push(patch.vertices.clone()),
            // A box's six faces, each a quadrilateral.
            Shape::Box(aabb) => {
                let nffkit_formats::AxisBox { min, max } = &**aabb;
                let c = |x: bool, y: bool, z: bool| {
                    DVec3::new(
                        if x { max.x } else { min.x },
                        if y { max.y } else { min.y },
                        if z { max.z } else { min.z },
                    )
                };
                let (f, t) = (false, true);
                polygons.extend([
                    vec![c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)],
                    vec![c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)],
                    vec![c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)],
                    vec![c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)],
                    vec![c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)],
                    vec![c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)],
                ]);
            }
            _ => {}
        }
    }
    for vertices in &polygons {
        for t in nffkit_formats::polygon::triangulate(vertices) {
            let mut corners = t.map(|i| round(vertices[i as usize]));
            // The same triangle from any starting corner.
            let first = (0..3).min_by_key(|&k| corners[k]).unwrap();
            corners.rotate_left(first);
            out.push(corners);
        }
    }
    out.sort();
    out
}

#[test]
fn obj_and_gltf_exports_read_back_through_mesh2nff_to_the_same_triangles() {
    let dir = tempfile::tempdir().unwrap();
    // A scene of polygons, patches and a box: the triangles are exact.
    let scene = format!("{}/../scenes/spd/mount_s5.nff", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read(&scene).unwrap();
    let mut src = String::from_utf8(text).unwrap();
    src = src.lines().filter(|l| !l.starts_with("s ")).collect::<Vec<_>>().join("\n");
    src += "\naabb 0 0 0 1 2 3\npp 3\n0 0 1 0 0 1\n1 0 1 0 0 1\n0 1 1 0.1 0 1\n";
    let nff_path = dir.path().join("m.nff");
    std::fs::write(&nff_path, &src).unwrap();
    let expected = triangles(src.as_bytes(), 3);
    assert!(expected.len() > 100);
    for ext in ["obj", "gltf", "glb"] {
        let out = dir.path().join(format!("m.{ext}"));
        ok(&run(CONVERT, &[path(&nff_path), "-o", path(&out), "-q"]));
        let back = dir.path().join(format!("m-{ext}.nff"));
        ok(&run(MESH2NFF, &[path(&out), "-o", path(&back), "-q"]));
        let got = triangles(&std::fs::read(&back).unwrap(), 3);
        assert_eq!(got.len(), expected.len(), "{ext}");
        // glTF holds single precision: a corner may round the other way.
        let off = got.iter().zip(&expected).filter(|(a, b)| a != b).count();
        let allowed = if ext == "obj" { 0 } else { expected.len() / 100 };
        eprintln!("{ext}: {off} of {} triangles differ at 1e-3", expected.len());
        assert!(off <= allowed, "{ext}: {off} of {} triangles differ", expected.len());
        // Materials: colour x Kd, Ks and the index come back.
        let back = nff::parse(&std::fs::read(&back).unwrap(), &ParseOptions::default()).unwrap().scene;
        let orig = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap().scene;
        let m0 = &orig.materials[orig.primitives[0].material.unwrap() as usize];
        let b0 = &back.materials[back.primitives[0].material.unwrap() as usize];
        let (a, b) = (m0.color * m0.kd, b0.color * b0.kd);
        assert!((a - b).abs().max_element() < 1e-3, "{ext}: colour x Kd {a} came back {b}");
        assert!((m0.ks - b0.ks).abs() < 1e-3, "{ext}: Ks {} came back {}", m0.ks, b0.ks);
    }
}

#[test]
fn nffconvert_guards_its_input_and_its_second_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.nff");
    std::fs::copy(spd("balls_s1"), &scene).unwrap();
    let o = run(CONVERT, &[path(&scene), "--to", "obj"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("give -o FILE"));
    // An OBJ whose .mtl would be the input: refused before anything is written.
    let mtl_input = dir.path().join("x.mtl");
    std::fs::copy(spd("balls_s1"), &mtl_input).unwrap();
    let o = run(CONVERT, &[path(&mtl_input), "--dialect", "nff", "-o", path(&dir.path().join("x.obj"))]);
    assert!(!o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!dir.path().join("x.obj").exists());
    // POV-Ray and glb go to standard output.
    let o = run(CONVERT, &[path(&scene), "--to", "pov"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("#version 3.7;"));
    let o = run(CONVERT, &[path(&scene), "--to", "glb", "-q"]);
    assert!(ok(&o).is_empty() && o.stdout.starts_with(b"glTF"));
    // The soft-shadow and depth-of-field settings reach POV-Ray.
    let o = run(
        CONVERT,
        &[path(&scene), "--to", "pov", "--area-light", "0.5", "--aperture", "0.1", "--focus", "3"],
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("area_light <0.5, 0, 0>, <0, 0, 0.5>, 4, 4 jitter orient adaptive 0"), "{text}");
    assert!(text.contains("aperture 0.2") && text.contains("blur_samples 16"), "{text}");
}

#[test]
fn every_benchmark_setting_renders_in_povray() {
    let Some(povray) = program("povray") else { return };
    let dir = tempfile::tempdir().unwrap();
    let nff = PathBuf::from(spd("balls_s1"));
    let scene = nff::parse(&std::fs::read(&nff).unwrap(), &ParseOptions::default()).unwrap().scene;
    let runner = nffkit_tools::bench::povray::Runner {
        povray,
        render: PathBuf::from(RENDER),
        size: 24,
        runs: 1,
        dir: dir.path().to_path_buf(),
    };
    let settings = nffkit_tools::bench::povray::settings(0.5, 0.05);
    assert_eq!(settings.len(), 5);
    for setting in &settings {
        let t = runner.compare(&nff, &scene, setting).unwrap();
        assert!(t.a > 0.0 && t.b > 0.0 && t.ratio == t.a / t.b && t.rounds == 1, "{}", setting.label);
        let text = std::fs::read_to_string(dir.path().join("scene.pov")).unwrap();
        if setting.label.starts_with("soft") {
            assert!(text.contains("area_light <0.5, 0, 0>, <0, 0, 0.5>, 4, 4 jitter orient adaptive 0"));
        }
        if setting.label.starts_with("depth") {
            assert!(text.contains("aperture 0.1") && text.contains("blur_samples 16"));
        }
    }
}
