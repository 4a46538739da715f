//! P3F, the P3D course's language: every entity and directive read into
//! the scene model, malformed ones refused at their exact line and column,
//! students' extensions warned about (refused with --strict), and NFF and
//! P3F told apart.

use glam::DVec3;
use nffkit_formats::dialect::{sniff, to_nff, to_p3f};
use nffkit_formats::nff::{self, Diagnostic, ParseOptions, Parsed, Severity};
use nffkit_formats::{Dialect, Directives, Lens, LightArea, Shape};

/// The course's view block, lens included.
const VIEW: &str =
    "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 6\naperture 12\nfocal 1.5\n";

fn p3f() -> ParseOptions {
    ParseOptions { dialect: Dialect::P3f, ..ParseOptions::default() }
}

fn read(src: &str) -> Parsed {
    nff::parse(src.as_bytes(), &p3f()).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn first_error(src: &str, opts: &ParseOptions) -> Diagnostic {
    match nff::parse(src.as_bytes(), opts) {
        Ok(_) => panic!("accepted:\n{src}"),
        Err(e) => e.first_error().clone(),
    }
}

fn expect(src: &str, line: u32, column: u32, needle: &str) {
    let d = first_error(src, &p3f());
    assert_eq!((d.line, d.column), (line, column), "{d}\n--- source ---\n{src}");
    let text = format!("{} {}", d.message, d.note.clone().unwrap_or_default());
    assert!(text.contains(needle), "`{needle}` not in `{text}`");
}

fn warnings(p: &Parsed) -> Vec<&Diagnostic> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Warning).collect()
}

#[test]
fn every_entity_and_directive_is_read() {
    let src = format!(
        "# the course's dof.p3f, shortened\naccel 2\nspp 4\nbclr 0.078 0.361 0.753\nenv skybox\n{VIEW}\
         l 4 3 4 0.5 0.5 0.5\nal 0 10 0  0 0 0  2 1  1 1 1\n\
         f 0.9 0.1 0.1 0.8  0.5 0.6 0.7 0.3  50 0 1\ns 0 1 0 1\nbox -1 -1 -1 1 1 1\npl 0 0 0 1 0 0 0 0 -1\n\
         f 1 1 1 0  1 1 1 0.1  100 0.9 1.5\np 3\n0 0 0\n1 0 0\n0 1 0\nc 0 0 0 1 0 1 0 0.5\n\
         mesh 4 2\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 2 3\n-4 -2 -1\n"
    );
    let p = read(&src);
    assert!(warnings(&p).is_empty(), "{:?}", p.diagnostics);
    let s = &p.scene;
    assert_eq!(s.dialect, Dialect::P3f);
    assert_eq!(s.directives, Directives { spp: Some(4), accel: Some(2) });
    assert_eq!(s.background, Some(DVec3::new(0.078, 0.361, 0.753)));
    assert_eq!(s.environment.as_deref(), Some("skybox"));
    let v = s.view.as_ref().unwrap();
    assert_eq!(v.lens, Some(Lens { aperture: 12.0, focal: 1.5 }));
    assert_eq!(v.resolution, [8, 6]);
    assert_eq!(s.lights[0].color, Some(DVec3::splat(0.5)));
    assert_eq!(s.lights[0].area, None);
    assert_eq!(s.lights[1].area, Some(LightArea { facing: DVec3::ZERO, size: [2.0, 1.0] }));
    assert_eq!(s.lights[1].position, DVec3::new(0.0, 10.0, 0.0));
    let m = &s.materials[0];
    assert_eq!(
        (m.color, m.kd, m.specular, m.ks),
        (DVec3::new(0.9, 0.1, 0.1), 0.8, DVec3::new(0.5, 0.6, 0.7), 0.3)
    );
    assert_eq!((m.shine, m.t, m.ior), (50.0, 0.0, 1.0));
    assert_eq!((s.materials[1].t, s.materials[1].ior), (0.9, 1.5));
    let kinds: Vec<_> = s.primitives.iter().map(|p| p.shape.kind().name()).collect();
    assert_eq!(kinds, ["sphere", "box", "plane", "polygon", "cone", "polygon", "polygon"]);
    // 1-based indices, then negative ones counting back from the end.
    let tri = |i: usize| match &s.primitives[i].shape {
        Shape::Polygon { vertices } => vertices.clone(),
        _ => unreachable!(),
    };
    let v = |x, y| DVec3::new(x, y, 0.0);
    assert_eq!(tri(5), [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)]);
    assert_eq!(tri(6), [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]);
    assert_eq!(s.primitives[6].line.0, 33, "a triangle's line is its indices'");
    assert_eq!(s.primitives[5].material, Some(1));
}

#[test]
fn mesh_triangles_keep_the_line_of_their_indices() {
    let p = read(&format!("{VIEW}mesh 3 1\n0 0 0\n1 0 0\n0 1 0\n3 1 2\n"));
    assert_eq!(p.scene.primitives[0].line.0, 14);
}

#[test]
fn malformed_entities_name_their_line_and_column() {
    // A vertex index past the mesh, 0, and one that is no whole number.
    expect(
        &format!("{VIEW}mesh 3 1\n0 0 0\n1 0 0\n0 1 0\n1 2 4\n"),
        14,
        5,
        "vertex index 4 is past the mesh's 3",
    );
    expect(&format!("{VIEW}mesh 3 1\n0 0 0\n1 0 0\n0 1 0\n0 1 2\n"), 14, 1, "count from 1");
    expect(
        &format!("{VIEW}mesh 3 1\n0 0 0\n1 0 0\n0 1 0\n1 2.5 3\n"),
        14,
        3,
        "(a whole number), found `2.5`",
    );
    expect(&format!("{VIEW}mesh 3 2\n0 0 0\n1 0 0\n0 1 0\n1 2 3\n"), 14, 6, "mesh triangle 2 of 2");
    // An `f` cut short says what P3F's takes.
    expect(&format!("{VIEW}f 1 1 1 1 1 1 1 1 1\ns 0 0 0 1\n"), 11, 1, "a P3F `f` takes 11 numbers");
    expect(&format!("{VIEW}f 1 1 1 1 1 1 1 1 1 1\ns 0 0 0 1\n"), 11, 1, "index of refraction");
    // An area light with a negative size, or facing its own centre.
    expect(&format!("{VIEW}al 0 1 0 0 0 0 -2 1 1 1 1\n"), 10, 16, "width must not be negative");
    expect(&format!("{VIEW}al 0 1 0 0 1 0 2 1 1 1 1\n"), 10, 1, "faces its own centre");
    // `env` with no folder on its line.
    expect(&format!("{VIEW}env\ns 0 0 0 1\n"), 11, 1, "expected the folder of the cube map's six images");
    // The lens: negative aperture, zero focal ratio.
    let view = VIEW.replace("aperture 12", "aperture -1");
    expect(&view, 8, 1, "`aperture` must not be negative");
    let view = VIEW.replace("focal 1.5", "focal 0");
    expect(&view, 9, 1, "`focal` must be greater than 0");
    expect(&VIEW.replace("focal 1.5", "focal x"), 9, 7, "expected the focal distance");
    // Directives: a sample count past the most, a word.
    expect(&format!("spp 70000\n{VIEW}"), 1, 5, "a sample count must be 0 to 65536, found 70000");
    expect(&format!("accel bvh\n{VIEW}"), 1, 7, "expected an accelerator number (a whole number)");
}

#[test]
fn extensions_are_warned_about_and_refused_when_strict() {
    let src = format!("{VIEW}f 1 0 0 1  1 1 1 0.5  20 0 1  0.1 0.2 0.3\nglow 1 2 3\ns 0 0 0 1\naccel 7\n");
    let p = read(&src);
    let w = warnings(&p);
    assert_eq!(w.len(), 3, "{:?}", p.diagnostics);
    assert_eq!((w[0].line, w[0].column), (10, 31));
    assert!(w[0].message.contains("3 values after the course's") && w[0].message.contains("`0.1 0.2 0.3`"));
    assert_eq!((w[1].line, w[1].column), (11, 1));
    assert!(w[1].message.contains("unknown entity `glow`"));
    assert!(w[2].message.contains("`accel 7` names none"));
    assert_eq!(p.scene.primitives.len(), 1, "the sphere after the unknown entity is read");
    assert_eq!(p.scene.materials[0].ior, 1.0);
    let strict = ParseOptions { strict: true, ..p3f() };
    let d = first_error(&src, &strict);
    assert_eq!((d.line, d.column), (10, 31), "{d}");
    let d = first_error(&format!("{VIEW}glow 1 2 3\n"), &strict);
    assert!(d.message.contains("unknown entity `glow`"), "{d}");
}

#[test]
fn a_view_without_its_lens_is_a_pinhole_with_a_warning() {
    let view = VIEW.replace("aperture 12\nfocal 1.5\n", "");
    let p = read(&format!("{view}s 0 0 0 1\n"));
    assert_eq!(p.scene.view.as_ref().unwrap().lens, None);
    assert!(warnings(&p)[0].message.contains("no `aperture` and `focal` lines"));
    let p = read(&format!("l 0 5 0\n{VIEW}"));
    assert_eq!(p.scene.lights[0].color, Some(DVec3::ONE));
    assert!(warnings(&p)[0].message.contains("using white"));
}

#[test]
fn nff_names_p3f_words_and_points_to_the_dialect() {
    let nff_view = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";
    let d = first_error(&format!("bclr 0 0 0\n{nff_view}"), &ParseOptions::default());
    assert_eq!((d.line, d.column), (1, 1));
    assert!(d.note.unwrap().contains("--dialect p3f"));
    let d = first_error(VIEW, &ParseOptions::default());
    assert!(d.message.contains("unknown entity `aperture`"), "{d}");
    assert_eq!(sniff(VIEW.as_bytes()), Dialect::P3f);
    assert_eq!(sniff(nff_view.as_bytes()), Dialect::Nff);
}

#[test]
fn big_p3f_files_are_read_in_parallel_exactly() {
    let mut src = format!("accel 1\nspp 2\n{VIEW}f 1 1 1 1 1 1 1 0 10 0 1\n");
    let n = 40_000;
    src += &format!("mesh {} {}\n", n + 2, n);
    for i in 0..n + 2 {
        src += &format!("{} {} {}\n", i % 97, i / 97, ((i % 7) * (i % 7)) as f64 * 0.25);
    }
    for i in 0..n {
        src += &format!("{} {} -{}\n", i + 1, i + 2, n + 2 - i - 2);
    }
    for i in 0..20_000 {
        src += &format!("s {} 0 0 0.5\n", i);
    }
    assert!(src.len() > 1 << 20);
    let whole = nff::parse_sequential(src.as_bytes(), &p3f()).unwrap();
    assert!(whole.diagnostics.is_empty(), "{:?}", &whole.diagnostics[..1]);
    let chunked = nff::parse_chunked(src.as_bytes(), &p3f(), 4).expect("a quiet P3F file is read in chunks");
    assert_eq!(chunked.scene, whole.scene);
    assert_eq!(chunked.scene.primitives.len(), n + 20_000);
    assert_eq!(chunked.scene.directives, Directives { spp: Some(2), accel: Some(1) });
}

#[test]
fn p3f_converts_to_the_closest_nff_saying_what_is_lost() {
    let src = format!(
        "spp 4\nbclr 0 0 0\nenv sky\n{VIEW}al 0 10 0 0 0 0 2 1 1 1 1\nf 1 0 0 1 0.5 0.5 0.5 0.6 20 0.5 1.5\ns 0 0 0 1\n"
    );
    let scene = read(&src).scene;
    let (nff_scene, lost) = to_nff(&scene);
    assert_eq!(nff_scene.dialect, Dialect::Nff);
    let all = lost.join("\n");
    for needle in ["--aperture", "specular colour", "Fresnel", "--light-size 2", "env sky", "--spp 4"] {
        assert!(all.contains(needle), "`{needle}` not in:\n{all}");
    }
    assert!((nff_scene.materials[0].ks - 0.3).abs() < 1e-12);
    assert_eq!(nff_scene.lights[0].area, None);
    let text = String::from_utf8(nff::write(&nff_scene, Vec::new()).unwrap()).unwrap();
    let back =
        nff::parse(text.as_bytes(), &ParseOptions::default()).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(back.scene, nff_scene);
    // And back to P3F: the angle returns, within rounding.
    let (again, _) = to_p3f(&back.scene);
    let a = again.view.unwrap().angle;
    assert!((a - 45.0).abs() < 1e-9, "{a}");
    assert_eq!(again.dialect, Dialect::P3f);
}
