//! The course extensions (`pl`, `aabb`), and diagnostics that hide nothing:
//! every unknown entity in a stretch skipped after an error, every error of a
//! view block, the missing view beside other errors, a byte-order mark, a DOS
//! end-of-file byte and a cone wider at its apex.

use glam::DVec3;
use nffkit_formats::nff::{self, Diagnostic, ParseOptions, Severity};
use nffkit_formats::Shape;

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";

fn all(src: &[u8], opts: &ParseOptions) -> Vec<Diagnostic> {
    match nff::parse(src, opts) {
        Ok(p) => p.diagnostics,
        Err(e) => e.diagnostics,
    }
}

fn at(d: &[Diagnostic], severity: Severity, needle: &str) -> Vec<(u32, u32)> {
    d.iter()
        .filter(|d| d.severity == severity && d.message.contains(needle))
        .map(|d| (d.line, d.column))
        .collect()
}

#[test]
fn pl_and_aabb_are_read_noted_written_back_and_refused_when_strict() {
    let src = format!("{VIEW}l 1 1 1\npl 0 0 0 1 0 0 0 0 -1\nf 1 0 0 1 0 1 0 1\naabb 1 2 3 -1 5 6\n");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
    let s = &parsed.scene;
    assert_eq!(s.primitives[0].shape, Shape::plane([DVec3::ZERO, DVec3::X, DVec3::NEG_Z]));
    // Corners given out of order are taken as opposite corners, with a warning.
    assert_eq!(s.primitives[1].shape, Shape::aabb(DVec3::new(-1.0, 2.0, 3.0), DVec3::new(1.0, 5.0, 6.0)));
    assert_eq!(s.primitives[1].material, Some(0));
    assert_eq!(s.counts(), [0, 0, 0, 0, 1, 1]);
    assert_eq!(at(&parsed.diagnostics, Severity::Note, "extension"), [(9, 1), (11, 1)]);
    assert_eq!(at(&parsed.diagnostics, Severity::Warning, "opposite corners"), [(11, 1)]);
    // The plane has no bounds; the box has.
    assert_eq!(s.bounds(), Some((DVec3::new(-1.0, 2.0, 3.0), DVec3::new(1.0, 5.0, 6.0))));
    let text = nff::write(s, Vec::new()).unwrap();
    let again = nff::parse(&text, &ParseOptions::default()).unwrap().scene;
    assert_eq!(&again, s, "{}", String::from_utf8_lossy(&text));
    let strict = ParseOptions { strict: true, ..Default::default() };
    let d = all(src.as_bytes(), &strict);
    assert_eq!(at(&d, Severity::Error, "not NFF (--strict)"), [(9, 1), (11, 1)]);
}

#[test]
fn a_plane_through_collinear_points_is_an_error() {
    let d = all(format!("{VIEW}pl 0 0 0 1 1 1 2 2 2\n").as_bytes(), &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "lie on one line"), [(8, 1)]);
}

#[test]
fn recovery_reports_every_unknown_entity_in_a_skipped_stretch() {
    // The broken sphere starts a skip; `la` and `fp` lines inside it are
    // still reported, at their own positions.
    let src = format!("{VIEW}s 0 0 x 1\n1 2 3\nla 1 2 3\nfp 4\n  zz 1\ns 0 0 0 1\n");
    let d = all(src.as_bytes(), &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "expected a sphere centre"), [(8, 7)]);
    assert_eq!(at(&d, Severity::Error, "unknown entity"), [(10, 1), (11, 1), (12, 3)]);
    let lenient = all(src.as_bytes(), &ParseOptions { lenient: true, ..Default::default() });
    assert_eq!(at(&lenient, Severity::Warning, "unknown entity"), [(10, 1), (11, 1), (12, 3)]);
}

#[test]
fn the_missing_view_is_reported_beside_other_errors() {
    let d = all(b"b 1 2 x\ns 0 0 0 1\n", &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "colour component"), [(1, 7)]);
    assert_eq!(at(&d, Severity::Error, "no view"), [(2, 10)]);
    // A view with errors is not also "missing".
    let d = all(
        b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\nhither 1\nresolution 8 8\n",
        &ParseOptions::default(),
    );
    assert!(at(&d, Severity::Error, "no view").is_empty());
}

#[test]
fn every_error_of_a_view_is_reported_where_it_is() {
    let src = "v\nfrom 0 0 5\nat 0 0 zz\nup 0 1 0\nangle 200\nhither 1\nresolution 8 0\n";
    let d = all(src.as_bytes(), &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "`at` coordinate"), [(3, 8)]);
    assert_eq!(at(&d, Severity::Error, "between 0 and 180"), [(5, 1)]);
    assert_eq!(at(&d, Severity::Error, "resolution in pixels"), [(7, 14)]);
}

#[test]
fn a_missing_view_line_is_reported_at_the_line_found_instead() {
    let d = all(b"v\nfrom 0 0 5\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n", &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "expected the view's `at` line, found `up`"), [(3, 1)]);
    let d =
        all(b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\ns 0 0 0 1\n", &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "expected the view's `resolution` line, found `s`"), [(7, 1)]);
    let d = all(b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\n", &ParseOptions::default());
    assert_eq!(at(&d, Severity::Error, "end of file: expected the view's `resolution`"), [(5, 9)]);
}

#[test]
fn a_byte_order_mark_is_accepted_with_a_warning() {
    let src = format!("\u{feff}b 0 0 0\n{VIEW}");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
    assert_eq!(at(&parsed.diagnostics, Severity::Warning, "byte-order mark"), [(1, 1)]);
    assert_eq!(parsed.scene.background, Some(DVec3::ZERO));
}

#[test]
fn a_dos_end_of_file_byte_is_accepted() {
    for tail in ["\x1a", "\x1a\r\n", "\x1a\x1a\x1a"] {
        let src = format!("{VIEW}s 0 0 0 1\n{tail}");
        let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        assert_eq!(parsed.scene.primitives.len(), 1);
    }
    // Elsewhere it is still an unknown token.
    assert!(nff::parse(format!("{VIEW}\x1a s 0 0 0 1\n").as_bytes(), &ParseOptions::default()).is_err());
}

#[test]
fn a_cone_wider_at_its_apex_warns() {
    let parsed = nff::parse(
        format!("{VIEW}c 0 0 0 0.5 0 1 0 1\nc 0 0 0 1 0 1 0 0.5\n").as_bytes(),
        &ParseOptions::default(),
    )
    .unwrap();
    assert_eq!(
        at(&parsed.diagnostics, Severity::Warning, "apex radius 1 exceeds its base radius 0.5"),
        [(8, 1)]
    );
}
