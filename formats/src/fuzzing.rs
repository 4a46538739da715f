//! The fuzz targets' bodies, here so that the fuzzers (`fuzz/`, cargo-fuzz
//! on nightly) and the regular tests that replay every input a fuzzer ever
//! crashed (`formats/tests/fuzz-regressions/<target>/`) run the same code.
//! Each takes any bytes and panics only when a property is broken.

use crate::mesh::{self, ImportOptions, Mesh};
use crate::nff::{self, ParseOptions};
use std::path::{Path, PathBuf};

/// A fuzz target: the name of its fuzz binary and regression folder, and
/// its body.
pub type Target = (&'static str, fn(&[u8]));

/// Every target of this crate.
pub const TARGETS: [Target; 4] = [
    ("parse_nff", parse_nff),
    ("chunked_nff", chunked_nff),
    ("import_obj", import_obj),
    ("import_gltf", import_gltf),
];

/// The ways of reading NFF (and P3F) that the targets try.
fn nff_options() -> [ParseOptions; 5] {
    let p3f = crate::Dialect::P3f;
    [
        ParseOptions::default(),
        ParseOptions { lenient: true, fragment: true, ..Default::default() },
        ParseOptions { strict: true, ..Default::default() },
        ParseOptions { dialect: p3f, ..Default::default() },
        ParseOptions { dialect: p3f, strict: true, fragment: true, ..Default::default() },
    ]
}

/// The reader returns a scene or diagnostics; a scene it accepts survives
/// the writer; every diagnostic prints.
pub fn parse_nff(data: &[u8]) {
    for opts in nff_options() {
        match nff::parse(data, &opts) {
            Ok(parsed) => {
                let text = nff::write(&parsed.scene, Vec::new()).expect("writing to memory");
                let again = nff::parse(&text, &ParseOptions { fragment: true, ..opts })
                    .expect("the writer's text reads back");
                assert_eq!(again.scene, parsed.scene, "the scene changed through the writer");
            }
            Err(e) => {
                let mut report = nff::Report::new("fuzz.nff", data);
                for d in &e.diagnostics {
                    let _ = report.render(d);
                }
                let _ = report.held_back();
            }
        }
    }
}

/// Read in pieces, a file gives exactly what it gives read in one, lines
/// included, or it is handed back to the sequential reader.
pub fn chunked_nff(data: &[u8]) {
    for opts in nff_options() {
        let whole = nff::parse_sequential(data, &opts);
        for chunks in [2, 3, 5] {
            let Some(pieces) = nff::parse_chunked(data, &opts, chunks) else { continue };
            let whole = whole.as_ref().expect("the sequential reader accepts what the chunked one does");
            assert!(whole.diagnostics.is_empty(), "the chunked reader joined a file with diagnostics");
            assert_eq!(pieces.scene, whole.scene, "{chunks} chunks read another scene");
            let lines = |s: &crate::Scene| s.primitives.iter().map(|p| p.line.0).collect::<Vec<_>>();
            assert_eq!(lines(&pieces.scene), lines(&whole.scene), "{chunks} chunks give other lines");
        }
    }
}

/// Where imported files look for what they refer to: nowhere.
const NO_DIR: &str = "/nonexistent/nffkit-fuzz";

/// OBJ bytes import into a consistent mesh or an error.
pub fn import_obj(data: &[u8]) {
    let name = Path::new(NO_DIR).join("fuzz.obj");
    if let Ok(m) = mesh::load_obj_bytes(data, &name, Path::new(NO_DIR), &ImportOptions::default()) {
        check_mesh(&m);
    }
}

/// glTF or GLB bytes import into a consistent mesh or an error.
pub fn import_gltf(data: &[u8]) {
    let name = Path::new(NO_DIR).join("fuzz.glb");
    if let Ok(m) = mesh::load_gltf_bytes(data, &name, &ImportOptions::default()) {
        check_mesh(&m);
    }
}

/// What mesh2nff relies on: faces of three corners or more within the
/// corner list, corners within the positions, materials that exist,
/// finite numbers.
fn check_mesh(m: &Mesh) {
    assert!(!m.faces.is_empty(), "an imported mesh has faces");
    assert!(m.positions.iter().all(|p| p.is_finite()), "positions are finite");
    for f in &m.faces {
        assert!(f.count >= 3, "a face has three corners or more");
        assert!(f.first as usize + f.count as usize <= m.corners.len(), "a face's corners exist");
        assert!((f.material as usize) < m.materials.len(), "a face's material exists");
        for c in m.corners_of(f) {
            assert!((c.position as usize) < m.positions.len(), "a corner's position exists");
            assert!(c.normal.is_none_or(|n| n.is_finite()), "normals are finite");
        }
    }
}

/// Run every input under `root/<target>/` through its target (a folder
/// named after no target is an error): the inputs that still fail, and how
/// many were run. For the regression tests of this crate and the tracer.
pub fn replay(root: &Path, targets: &[Target]) -> (Vec<PathBuf>, usize) {
    let mut failed = Vec::new();
    let mut replayed = 0;
    let folders: Vec<PathBuf> =
        std::fs::read_dir(root).map(|d| d.flatten().map(|e| e.path()).collect()).unwrap_or_default();
    for folder in folders.iter().filter(|p| p.is_dir()) {
        let name = folder.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let Some((_, target)) = targets.iter().find(|(t, _)| *t == name) else {
            failed.push(folder.clone());
            continue;
        };
        let mut inputs: Vec<PathBuf> =
            std::fs::read_dir(folder).into_iter().flatten().flatten().map(|e| e.path()).collect();
        inputs.sort();
        for input in inputs {
            let data = std::fs::read(&input).unwrap_or_default();
            if std::panic::catch_unwind(|| target(&data)).is_err() {
                failed.push(input);
            }
            replayed += 1;
        }
    }
    (failed, replayed)
}
