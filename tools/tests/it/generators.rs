//! sphereflake matches the SPD's own output; planegen's board and append
//! mode behave as documented. Outputs parse with zero diagnostics.

use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::Shape;
use nffkit_tools::gen::planegen::Board;
use nffkit_tools::gen::sphereflake::{Floor, Sphereflake};

fn fixture(name: &str) -> nffkit_formats::Scene {
    let p = format!("{}/../scenes/spd/{name}", env!("CARGO_MANIFEST_DIR"));
    nff::parse(&std::fs::read(p).unwrap(), &ParseOptions::default()).unwrap().scene
}

#[test]
fn sphereflake_matches_the_spd_sphere_for_sphere() {
    for level in 1..=4 {
        let text = Sphereflake { level, ..Default::default() }.write(Vec::new()).unwrap();
        let parsed = nff::parse(&text, &ParseOptions::default()).unwrap();
        assert!(parsed.diagnostics.is_empty());
        let ours = parsed.scene;
        let spd = fixture(&format!("balls_s{level}.nff"));
        assert_eq!(ours.view, spd.view);
        assert_eq!(ours.lights, spd.lights);
        assert_eq!(ours.materials, spd.materials);
        assert_eq!(ours.background, spd.background);
        assert_eq!(ours.primitives.len(), spd.primitives.len(), "level {level}");
        for (i, (a, b)) in ours.primitives.iter().zip(&spd.primitives).enumerate() {
            match (&a.shape, &b.shape) {
                (Shape::Sphere { center: c1, radius: r1 }, Shape::Sphere { center: c2, radius: r2 }) => {
                    assert!((*c1 - *c2).abs().max_element() < 1e-6, "level {level} sphere {i}: {c1} vs {c2}");
                    assert!((r1 - r2).abs() < 1e-6);
                }
                (x, y) => assert_eq!(x, y, "level {level} primitive {i}"),
            }
        }
    }
}

#[test]
fn sphereflake_options() {
    let s = Sphereflake { resolution: [64, 32], ..Sphereflake::at(1, Floor::None) }.scene();
    assert_eq!(s.primitives.len(), 10);
    assert_eq!(s.view.unwrap().resolution, [64, 32]);
    let s = Sphereflake::at(1, Floor::Checker(4, 4)).scene();
    assert_eq!(s.primitives.len(), 10 + 16);
}

#[test]
fn planegen_append_keeps_the_original_first() {
    let base = fixture("balls_s1.nff");
    let mut scene = base.clone();
    Board { nx: 2, ny: 2, ..Default::default() }.add_to(&mut scene);
    let text = nff::write(&scene, Vec::new()).unwrap();
    let back = nff::parse(&text, &ParseOptions::default()).unwrap();
    assert!(back.diagnostics.is_empty());
    let back = back.scene;
    assert_eq!(back.view, base.view);
    assert_eq!(back.lights, base.lights);
    assert_eq!(&back.primitives[..base.primitives.len()], &base.primitives[..]);
    assert_eq!(back.primitives.len(), base.primitives.len() + 4);
    // The text keeps the spec's order: lights, then materials and objects.
    let text = String::from_utf8(text).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let last_light = lines.iter().rposition(|l| l.starts_with("l ")).unwrap();
    let first_f = lines.iter().position(|l| l.starts_with("f ")).unwrap();
    assert!(last_light < first_f);
}
