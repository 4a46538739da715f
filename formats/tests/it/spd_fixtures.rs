//! Every SPD database shipped in `scenes/spd/` parses with zero errors, with
//! the entity counts the file holds, and survives a write/parse round trip.

use nffkit_formats::nff::{self, ParseOptions, Severity};
use std::path::PathBuf;

fn fixture(name: &str) -> Vec<u8> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/spd").join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// (file, lights, materials, spheres, cones, polygons, patches)
const COUNTS: &[(&str, usize, usize, usize, usize, usize, usize)] = &[
    ("balls_s1.nff", 3, 2, 10, 0, 1, 0),
    ("balls_s2.nff", 3, 2, 91, 0, 1, 0),
    ("balls_s3.nff", 3, 2, 820, 0, 1, 0),
    ("balls_s4.nff", 3, 2, 7381, 0, 1, 0),
    ("gears_s1.nff", 5, 2, 0, 0, 147, 0),
    ("jacks_s1.nff", 1, 1, 6, 3, 0, 0),
    ("lattice_s1.nff", 6, 20, 8, 12, 0, 0),
    ("mount_s1.nff", 1, 2, 4, 0, 8, 0),
    ("mount_s5.nff", 1, 2, 4, 0, 2048, 0),
    ("mount_s7.nff", 1, 2, 4, 0, 32768, 0),
    ("rings_s1.nff", 3, 7, 30, 30, 1, 0),
    ("teapot_s1.nff", 2, 3, 0, 0, 1, 56),
    ("tetra_s2.nff", 1, 1, 0, 0, 16, 0),
    ("tree_s1.nff", 7, 2, 3, 3, 1, 0),
];

#[test]
fn every_spd_database_parses_with_the_right_counts() {
    for &(name, lights, materials, s, c, p, pp) in COUNTS {
        let src = fixture(name);
        let parsed = nff::parse(&src, &ParseOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(parsed.diagnostics.iter().all(|d| d.severity == Severity::Warning));
        let scene = &parsed.scene;
        assert!(scene.view.is_some(), "{name}");
        assert!(scene.background.is_some(), "{name}");
        assert_eq!(scene.lights.len(), lights, "{name} lights");
        assert_eq!(scene.materials.len(), materials, "{name} materials");
        assert_eq!(scene.counts(), [s, c, p, pp, 0, 0], "{name} primitives");
    }
}

#[test]
fn every_spd_database_round_trips_through_the_writer() {
    for &(name, ..) in COUNTS {
        let scene = nff::parse(&fixture(name), &ParseOptions::default()).unwrap().scene;
        let text = nff::write(&scene, Vec::new()).unwrap();
        let again = nff::parse(&text, &ParseOptions::default())
            .unwrap_or_else(|e| panic!("{name} rewritten: {e}"))
            .scene;
        assert_eq!(again, scene, "{name}");
    }
}

#[test]
fn primitives_remember_their_lines() {
    let scene = nff::parse(&fixture("balls_s1.nff"), &ParseOptions::default()).unwrap().scene;
    // The floor `p` is on line 13, the first sphere on line 19.
    assert_eq!(scene.primitives[0].line.0, 13);
    assert_eq!(scene.primitives[1].line.0, 19);
}

#[test]
fn spd_view_block_is_read_exactly() {
    let scene = nff::parse(&fixture("balls_s1.nff"), &ParseOptions::default()).unwrap().scene;
    let v = scene.view.unwrap();
    assert_eq!(v.from.to_array(), [2.1, 1.3, 1.7]);
    assert_eq!(v.up.to_array(), [0.0, 0.0, 1.0]);
    assert_eq!((v.angle, v.hither, v.resolution), (45.0, 0.01, [512, 512]));
    let m = &scene.materials[1];
    assert_eq!((m.kd, m.ks, m.shine, m.t, m.ior), (0.5, 0.5, 3.0827, 0.0, 1.0));
}
