//! Reading a file in parallel chunks gives the same scene (with the same
//! source lines and material numbering) and the same diagnostics as reading
//! it in one piece.

use nffkit_formats::nff::{self, parse_chunked, parse_sequential, ParseOptions};

/// A scene of every entity kind, with material changes and lines of every
/// shape, `n` groups long.
fn big_scene(n: usize) -> String {
    let mut s = String::from(
        "# a test scene\nb 0.1 0.2 0.3\nv\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.1\nresolution 64 64\n\
         l 1 2 3\nl -1 2 3 0.5 0.5 0.5\n",
    );
    for i in 0..n {
        let x = i as f64 * 0.01;
        if i % 7 == 3 {
            s += &format!("f {} 0.5 0.5 0.8 0.2 10 0 1\n", (i % 10) as f64 / 10.0);
        }
        s += &format!("s {x} 0 0 0.5\n");
        s += &format!("p 3\n{x} 0 0\n{} 0 0\n{x} 1 0\n", x + 1.0);
        if i % 5 == 0 {
            s += &format!("pp 3\n{x} 0 1 0 0 1\n{} 0 1 0 0 1\n{x} 1 1 0 0 1\n", x + 1.0);
            s += &format!("c\n{x} 0 0 1\n{x} 2 0 0.5\n");
        }
        if i % 50 == 0 {
            s += &format!("pl 0 -1 0 1 -1 0 0 -1 -1\naabb {x} 0 0 {} 1 1\n", x + 1.0);
        }
    }
    s
}

#[test]
fn chunks_give_the_sequential_scene_exactly() {
    let src = big_scene(3000);
    let opts = ParseOptions::default();
    let one = parse_sequential(src.as_bytes(), &opts).unwrap();
    // Notes about pl/aabb make the chunked reader defer; without them it joins.
    let plain = big_scene(3000).replace("pl 0 -1 0 1 -1 0 0 -1 -1\n", "").replace("aabb", "# aabb");
    let one_plain = parse_sequential(plain.as_bytes(), &opts).unwrap();
    assert!(one_plain.diagnostics.is_empty(), "{:?}", one_plain.diagnostics.first());
    for chunks in [2, 3, 5, 8] {
        let many = parse_chunked(plain.as_bytes(), &opts, chunks).expect("a quiet file joins");
        // Debug output includes every source line, which `==` ignores.
        assert_eq!(format!("{:?}", many.scene), format!("{:?}", one_plain.scene), "{chunks} chunks");
        assert!(
            parse_chunked(src.as_bytes(), &opts, chunks).is_none(),
            "notes defer to the sequential reader"
        );
    }
    assert!(!one.diagnostics.is_empty());
}

/// Chunks count their lines as the lexer does: through CR LF and lone CR
/// line ends, comments and blank lines, the joined scene's source lines
/// are the sequential reader's.
#[test]
fn chunks_count_every_kind_of_line_end() {
    let plain = big_scene(3000).replace("pl 0 -1 0 1 -1 0 0 -1 -1\n", "").replace("aabb", "# aabb");
    let mut src = String::new();
    for (i, line) in plain.lines().enumerate() {
        src += line;
        src += ["\n", "\r\n", "\r", "  # a comment\n", "\n\n", "\t\r\n\r"][i % 6];
    }
    let opts = ParseOptions::default();
    let one = parse_sequential(src.as_bytes(), &opts).unwrap();
    assert!(one.diagnostics.is_empty(), "{:?}", one.diagnostics.first());
    let last = one.scene.primitives.last().map(|p| p.line.0);
    assert!(last > Some(plain.lines().count() as u32), "blank lines counted: {last:?}");
    for chunks in [2, 3, 5, 8] {
        let many = parse_chunked(src.as_bytes(), &opts, chunks).expect("a quiet file joins");
        assert_eq!(format!("{:?}", many.scene), format!("{:?}", one.scene), "{chunks} chunks");
    }
}

#[test]
fn a_large_file_with_errors_reports_what_the_sequential_reader_does() {
    // Over the parallel threshold, with a light after objects (a warning that
    // depends on earlier chunks) and an error near the end.
    let mut src = big_scene(60000);
    assert!(src.len() > 4 << 20, "{} bytes", src.len());
    src += "l 0 0 0\ns 1 2 x 4\n";
    let opts = ParseOptions::default();
    let (a, b) = (nff::parse(src.as_bytes(), &opts), parse_sequential(src.as_bytes(), &opts));
    let (a, b) = (a.unwrap_err(), b.unwrap_err());
    assert_eq!(a.diagnostics, b.diagnostics);
    // Without the error, the big file is read in parallel and still equal.
    let quiet = big_scene(60000).replace("pl 0 -1 0 1 -1 0 0 -1 -1\n", "").replace("aabb", "# aabb");
    let (a, b) =
        (nff::parse(quiet.as_bytes(), &opts).unwrap(), parse_sequential(quiet.as_bytes(), &opts).unwrap());
    assert_eq!(format!("{:?}", a.scene), format!("{:?}", b.scene));
    assert!(parse_chunked(quiet.as_bytes(), &opts, 2).is_some());
}
