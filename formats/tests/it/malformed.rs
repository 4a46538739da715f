//! Malformed input: each case names the exact line and column of the first
//! error and what the message must say.

use nffkit_formats::nff::{self, ParseOptions, Severity};

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";

fn first_error(src: &str) -> nff::Diagnostic {
    match nff::parse(src.as_bytes(), &ParseOptions::default()) {
        Ok(_) => panic!("accepted:\n{src}"),
        Err(e) => e.first_error().clone(),
    }
}

fn expect(src: &str, line: u32, column: u32, needle: &str) {
    let d = first_error(src);
    assert_eq!((d.line, d.column), (line, column), "{d}\n--- source ---\n{src}");
    let text = format!("{} {}", d.message, d.note.clone().unwrap_or_default());
    assert!(text.contains(needle), "`{needle}` not in `{text}`");
}

#[test]
fn glued_numbers() {
    expect("b 0.0780.3610.753\n", 1, 3, "expected a colour component, found `0.0780.3610.753`");
}

#[test]
fn truncated_polygon_names_its_first_line() {
    let src = format!("{VIEW}p 4\n0 0 0\n1 0 0\n1 1 0\n");
    expect(&src, 11, 6, "the `p` that starts on line 8");
}

#[test]
fn polygon_cut_short_by_the_next_entity() {
    let src = format!("{VIEW}p 4\n0 0 0\n1 0 0\n1 1 0\ns 0 0 0 1\n");
    expect(&src, 12, 1, "expected a coordinate of vertex 4 of 4, found `s`");
}

#[test]
fn absurd_vertex_count_is_refused_without_allocating() {
    let src = format!("{VIEW}p 4000000000\n0 0 0\n");
    expect(&src, 8, 3, "vertex count must be 3 to");
}

#[test]
fn negative_and_small_counts() {
    expect(&format!("{VIEW}p -3\n"), 8, 3, "expected a vertex count (a whole number), found `-3`");
    expect(&format!("{VIEW}p 2\n0 0 0\n1 1 1\n"), 8, 3, "found 2");
}

#[test]
fn non_finite_numbers() {
    expect(&format!("{VIEW}s 0 0 nan 1\n"), 8, 7, "finite");
    expect(&format!("{VIEW}s 0 inf 0 1\n"), 8, 5, "finite");
}

#[test]
fn view_errors_point_at_the_offending_line() {
    expect("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 0 8\n", 7, 12, "resolution");
    expect(
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 180\nhither 1\nresolution 8 8\n",
        5,
        1,
        "between 0 and 180",
    );
    expect(
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\nhither 1\nresolution 8 8\n",
        5,
        1,
        "between 0 and 180",
    );
    expect("v\nfrom 1 2 3\nat 1 2 3\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n", 3, 1, "same point");
    expect("v\nfrom 0 0 5\nat 0 0 0\nup 0 0 2\nangle 45\nhither 1\nresolution 8 8\n", 4, 1, "parallel");
    expect(
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nhither 1\nresolution 8 8\n",
        5,
        1,
        "expected the view's `angle` line, found `hither`",
    );
}

#[test]
fn short_material() {
    let src = format!("{VIEW}f 1 0 0 0.5 0.5 3\ns 0 0 0 1\n");
    expect(&src, 9, 1, "has 6");
}

#[test]
fn unknown_keyword_is_an_error_unless_lenient() {
    let src = format!("{VIEW}la 1 2 3\ns 0 0 0 1\n");
    expect(&src, 8, 1, "unknown entity `la`");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions { lenient: true, ..Default::default() }).unwrap();
    assert_eq!(parsed.scene.primitives.len(), 1);
    assert_eq!(parsed.diagnostics[0].severity, Severity::Warning);
    assert_eq!(parsed.diagnostics[0].line, 8);
}

#[test]
fn lenient_skips_mail_headers_and_dialect_lines() {
    let src = format!(
        "From: someone@example.com\nSubject: a scene\n\n{VIEW}tess 3\ndod 1 2\ng 0 0 0 1 1 1\nfp 0 0 0\nQ 4\ns 0 0 0 1\n"
    );
    let parsed = nff::parse(src.as_bytes(), &ParseOptions { lenient: true, ..Default::default() }).unwrap();
    assert_eq!(parsed.scene.primitives.len(), 1);
    assert!(parsed.scene.view.is_some());
}

#[test]
fn missing_view_is_an_error_except_for_fragments() {
    expect("s 0 0 0 1\n", 1, 10, "no view");
    let frag = nff::parse(b"s 0 0 0 1\n", &ParseOptions { fragment: true, ..Default::default() });
    assert_eq!(frag.unwrap().scene.primitives.len(), 1);
}

#[test]
fn sense8_nff_is_recognised() {
    expect("nff\nversion 2.0\ncube\n8\n", 1, 1, "Sense8");
}

#[test]
fn cone_errors() {
    expect(&format!("{VIEW}c\n0 0 0 1\n0 0 0 0.5\n"), 8, 1, "same point");
    expect(&format!("{VIEW}c\n0 0 0 1\n0 0 1 -0.5\n"), 8, 1, "differ in sign");
}

#[test]
fn every_error_is_reported_not_just_the_first() {
    let src = format!("{VIEW}s 0 0 x 1\ns 0 0 0 1\ns y 0 0 1\n");
    let err = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap_err();
    let lines: Vec<u32> =
        err.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| d.line).collect();
    assert_eq!(lines, vec![8, 10]);
}

#[test]
fn crlf_tabs_and_comments_anywhere() {
    let src = "b 0 0 0 # sky\r\nv\r\nfrom\t0 0 5\r\nat 0 0 0 #look\r\nup 0 1 0\r\nangle 45\r\nhither 1\r\nresolution 8 8\r\n\
               c 0 0 0 .5 0 0 1 -0   # one-line cone\r\ns 1.11022e-16 -0 .5 +2\r\n";
    let scene = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap().scene;
    assert_eq!(scene.primitives.len(), 2);
    assert_eq!(scene.primitives[1].line.0, 10);
}

#[test]
fn suspicious_geometry_is_a_warning_with_its_line() {
    let src = format!("{VIEW}p 4\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
    let w = &parsed.diagnostics[0];
    assert_eq!((w.severity, w.line), (Severity::Warning, 8));
    assert!(w.message.contains("crosses itself"), "{w}");
}

#[test]
fn light_after_objects_warns() {
    let src = format!("{VIEW}s 0 0 0 1\nl 1 1 1\n");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
    assert!(parsed.diagnostics.iter().any(|d| d.line == 9 && d.message.contains("spec requires")));
}

#[test]
fn diagnostics_render_like_a_compiler() {
    let src = "b 0.0780.3610.753\n";
    let d = first_error(src);
    let text = d.render("scene.nff", src.as_bytes());
    assert!(text.contains("--> scene.nff:1:3"), "{text}");
    assert!(text.contains("1 | b 0.0780.3610.753"), "{text}");
    assert!(text.contains("  ^^^^^^^^^^^^^^^"), "{text}");
}

#[test]
fn empty_and_comment_only_files_are_errors_not_panics() {
    for src in ["", "   \n\n", "# just a comment\n"] {
        let d = first_error(src);
        assert!(d.message.contains("no view"));
    }
}

#[test]
fn cr_only_line_endings_give_the_right_lines() {
    // Old Mac files end lines with CR alone: line 9, not line 1 column 80.
    let src = format!("{VIEW}l 0 0 5\ns 0 0 0 1 2\n").replace('\n', "\r");
    expect(&src, 9, 11, "`2`");
    let text = first_error(&src).render("mac.nff", src.as_bytes());
    assert!(text.contains("9 | s 0 0 0 1 2\n"), "{text}");
}

#[test]
fn a_short_vertex_line_is_blamed_where_it_is() {
    // Vertex 2 has two numbers: the reader runs on into the next entity.
    let src = format!("{VIEW}p 3\n0 0 0\n1 0\n0 1 0\ns 0 0 0 1\n");
    expect(&src, 10, 1, "vertex 2 of 3 has 2 numbers on line 10, not 3");
    expect(&src, 10, 1, "failed at 12:1: expected a coordinate of vertex 3 of 3, found `s`");
    // At the end of the file, and in a patch written a vertex and its
    // normal to a line.
    expect(&format!("{VIEW}p 3\n0 0\n1 0 0\n0 1 0\n"), 9, 1, "vertex 1 of 3 has 2 numbers on line 9");
    let patch = format!("{VIEW}pp 3\n0 0 0 0 0 1\n1 0 0 0 0\n0 1 0 0 0 1\ns 0 0 0 1\n");
    expect(&patch, 10, 1, "vertex 2 of 3 has 5 numbers on line 10, not 6");
    // Lines that all hold whole vertices: the polygon is cut short, and
    // the error is where the reader stopped.
    expect(&format!("{VIEW}p 4\n0 0 0\n1 0 0\n1 1 0\ns 0 0 0 1\n"), 12, 1, "vertex 4 of 4");
}

#[test]
fn a_value_too_many_is_extra_not_an_unknown_entity() {
    let src = format!("{VIEW}s 0 0 0 1 2\n");
    expect(&src, 8, 11, "extra value `2` after the `s` on line 8");
    expect(&src, 8, 11, "a sphere takes 4 numbers");
    // In a polygon, the line with a number too many is blamed.
    let src = format!("{VIEW}p 3\n0 0 0 5\n1 0 0\n0 1 0\n");
    expect(&src, 9, 1, "vertex 1 of 3 has 4 numbers on line 9, not 3");
    expect(&src, 9, 1, "ended before `0` at 11:5");
    // Lenient: a warning, and the scene is read.
    let lenient = ParseOptions { lenient: true, ..Default::default() };
    let parsed = nff::parse(format!("{VIEW}s 0 0 0 1 2\ns 0 0 0 1\n").as_bytes(), &lenient).unwrap();
    assert_eq!(parsed.scene.primitives.len(), 2);
    assert!(parsed.diagnostics[0].message.contains("extra value `2`"));
}

#[test]
fn utf16_files_are_named_as_such() {
    let text = format!("{VIEW}s 0 0 0 1\n");
    let le: Vec<u8> = text.encode_utf16().flat_map(u16::to_le_bytes).collect();
    let be: Vec<u8> = text.encode_utf16().flat_map(u16::to_be_bytes).collect();
    let le_bom = [&[0xFF, 0xFE][..], &le].concat();
    for (bytes, encoding) in [(le, "UTF-16LE"), (be, "UTF-16BE"), (le_bom, "UTF-16LE")] {
        let d = nff::parse(&bytes, &ParseOptions::default()).unwrap_err().first_error().clone();
        assert_eq!((d.line, d.column), (1, 1));
        assert!(d.message.contains(&format!("the file is {encoding} text")), "{d}");
        assert!(d.note.unwrap().contains("iconv"));
    }
}

#[test]
fn view_errors_name_what_overflows_or_underflows() {
    let view = |from: &str, at: &str, up: &str| {
        format!("v\nfrom {from}\nat {at}\nup {up}\nangle 45\nhither 1\nresolution 8 8\ns 0 0 0 1\n")
    };
    expect(&view("1e300 -5 0", "0 0 0", "0 1 0"), 2, 1, "`from` coordinate 1e300 is beyond");
    expect(&view("0 0 5", "0 0 0", "0 0 1e-300"), 4, 1, "`up` is too short");
    expect(&view("0 0 5", "0 0 0", "0 0 0"), 4, 1, "`up` is zero");
    expect(&view("0 0 1e-300", "0 0 0", "0 1 0"), 3, 1, "`at` is only 1e-300 from `from`");
    // Short but not too short: read.
    let fine = view("0 0 5", "0 0 0", "0 1e-150 0");
    assert!(nff::parse(fine.as_bytes(), &ParseOptions::default()).is_ok());
}

#[test]
fn shapes_and_lights_beyond_single_precision_are_warned_about() {
    let src = format!("{VIEW}l 1e30 0 0\ns 0 0 0 1\nc\n0 0 0 1\n5e80 0 0 0\n");
    let parsed = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap();
    let at = |line: u32| parsed.diagnostics.iter().find(|d| d.line == line);
    assert!(at(8).is_some_and(|d| d.message.contains("light's position has a coordinate of 1e30")));
    assert!(at(9).is_none(), "{:?}", parsed.diagnostics);
    let cone = at(10).expect("the cone is warned about");
    assert!(cone.message.contains("cone is 5e80, beyond what single-precision"), "{cone}");
}
