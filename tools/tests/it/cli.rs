//! End-to-end: the binaries a user runs, on small inputs.

use nffkit_formats::image_io::to_u8;
use std::path::Path;
use std::process::{Command, Output};

fn run(bin: &str, args: &[&str], stdin: Option<&[u8]>) -> Output {
    use std::io::Write;
    let mut cmd = Command::new(bin);
    cmd.args(args).stdin(std::process::Stdio::piped()).stdout(std::process::Stdio::piped());
    cmd.stderr(std::process::Stdio::piped());
    let mut child = cmd.spawn().unwrap();
    if let Some(input) = stdin {
        child.stdin.take().unwrap().write_all(input).unwrap();
    } else {
        drop(child.stdin.take());
    }
    child.wait_with_output().unwrap()
}

const RENDER: &str = env!("CARGO_BIN_EXE_render");
const PLANEGEN: &str = env!("CARGO_BIN_EXE_planegen");
const SPHEREFLAKE: &str = env!("CARGO_BIN_EXE_sphereflake");

fn spd(name: &str) -> String {
    format!("{}/../scenes/spd/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn png(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn default_scene_renders_with_no_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d.png");
    let o = run(RENDER, &["-o", out.to_str().unwrap(), "--width", "64", "--height", "48", "-q"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = png(&out);
    assert_eq!(img.dimensions(), (64, 48));
    // A real picture: many distinct colours, not a flat fill.
    let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() > 100, "{} colours", colours.len());
}

#[test]
fn renders_a_file_and_stdin_identically() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.ppm"));
    let o = run(
        RENDER,
        &[&spd("balls_s1.nff"), "-o", a.to_str().unwrap(), "--width", "40", "--height", "40"],
        None,
    );
    assert!(o.status.success());
    let src = std::fs::read(spd("balls_s1.nff")).unwrap();
    let o = run(RENDER, &["-", "-o", b.to_str().unwrap(), "--width", "40", "--height", "40"], Some(&src));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(png(&a), png(&b));
    assert!(o.stdout.is_empty(), "nothing on stdout unless asked");
}

#[test]
fn floating_point_outputs_are_written() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["exr", "hdr"] {
        let out = dir.path().join(format!("x.{ext}"));
        let o = run(
            RENDER,
            &[&spd("tetra_s2.nff"), "-o", out.to_str().unwrap(), "--width", "16", "--height", "16"],
            None,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(std::fs::metadata(&out).unwrap().len() > 100);
    }
}

#[test]
fn eight_bit_outputs_hold_the_float_pixels_codes() {
    // PNG and PPM are written from the film's codes, EXR from its floats:
    // the two paths must agree, with and without the sRGB curve.
    let dir = tempfile::tempdir().unwrap();
    for srgb in [false, true] {
        let shot = |ext: &str| {
            let out = dir.path().join(format!("x-{srgb}.{ext}"));
            let mut args = vec![spd("balls_s1.nff"), "-o".into(), out.to_str().unwrap().into()];
            args.extend(["--width", "24", "--height", "20", "--spp", "2"].map(String::from));
            if srgb && ext != "exr" {
                args.push("--srgb".into());
            }
            let o = run(RENDER, &args.iter().map(String::as_str).collect::<Vec<_>>(), None);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            image::open(out).unwrap()
        };
        let floats = shot("exr").to_rgb32f();
        let want: Vec<u8> = floats.pixels().flat_map(|p| p.0.map(|c| to_u8(c, srgb))).collect();
        assert!(want.iter().any(|&c| c > 20), "a lit image");
        for ext in ["png", "ppm"] {
            let got = shot(ext).to_rgb8();
            assert_eq!((got.width(), got.height()), (24, 20), "{ext}");
            assert_eq!(got.into_raw(), want, "{ext}, sRGB {srgb}");
        }
    }
}

#[test]
fn stats_are_printed_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    let o = run(
        RENDER,
        &[&spd("balls_s1.nff"), "-o", out.to_str().unwrap(), "--spd-stats", "--width", "8", "--height", "8"],
        None,
    );
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("eye 81,") || text.contains("eye 81"), "{text}");
    assert!(text.contains("SPD test procedure"));
    // The report names the sampling actually used, and tests per kind by name.
    let scene = spd("balls_s1.nff");
    let plain = |extra: &[&str]| {
        let args = [&[&scene, "-o", out.to_str().unwrap(), "--stats", "--width", "8"][..], extra];
        String::from_utf8(run(RENDER, &args.concat(), None).stdout).unwrap()
    };
    let text = plain(&[]);
    assert!(text.contains("1 ray through each pixel centre"), "{text}");
    assert!(text.contains("sphere ") && text.contains("triangle ") && text.contains("cone "), "{text}");
    let text = plain(&["--spp", "4", "--sampler", "sobol"]);
    assert!(text.contains("4 spp sobol, filter box"), "{text}");
}

#[test]
fn bad_input_fails_cleanly_and_leaves_no_image() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.nff");
    std::fs::write(&bad, "b 0.0780.3610.753\n").unwrap();
    let out = dir.path().join("bad.png");
    let o = run(RENDER, &[bad.to_str().unwrap(), "-o", out.to_str().unwrap()], None);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("bad.nff:1:3"), "{err}");
    assert!(err.contains("expected a colour component, found `0.0780.3610.753`"), "{err}");
    assert!(!out.exists());
    for args in [
        vec!["--spp", "0"],
        vec!["-o", "x.jpg"],
        vec!["--width", "0"],
        vec!["--width", "65536", "--height", "65536"],
    ] {
        let o = run(RENDER, &args, None);
        assert!(!o.status.success(), "{args:?}");
    }
    let o = run(RENDER, &["/no/such/file.nff"], None);
    assert!(String::from_utf8_lossy(&o.stderr).contains("/no/such/file.nff"));
}

#[test]
fn check_summarises_and_sets_the_exit_code() {
    let o = run(RENDER, &["--check", &spd("balls_s1.nff"), &spd("gears_s1.nff")], None);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(text.lines().count(), 2);
    assert!(text.contains("147 primitives (147 polygons)"), "{text}");
    let o = run(RENDER, &["--check", "-"], Some(b"s 0 0 0 1\n"));
    assert!(!o.status.success());
    let o = run(RENDER, &["--check", "--fragment", "-"], Some(b"s 0 0 0 1\n"));
    assert!(o.status.success());
}

#[test]
fn planegen_pipes_into_render() {
    let board = run(PLANEGEN, &["--nx", "4", "--ny", "4"], None);
    assert!(board.status.success());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("board.png");
    let o = run(
        RENDER,
        &["-", "-o", out.to_str().unwrap(), "--width", "32", "--height", "32"],
        Some(&board.stdout),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(png(&out).dimensions(), (32, 32));
}

#[test]
fn planegen_refuses_bad_arguments_and_protects_its_input() {
    for args in [vec!["--nx", "0"], vec!["--sx", "-2"], vec!["--c1", "2,0,0"], vec!["--c1", "1,0"]] {
        let o = run(PLANEGEN, &args, None);
        assert!(!o.status.success(), "{args:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.nff");
    std::fs::copy(spd("balls_s1.nff"), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let o = run(PLANEGEN, &["--nx", "2", "--ny", "2", "--append-to", scene.to_str().unwrap()], None);
    assert!(o.status.success());
    assert_eq!(std::fs::read(&scene).unwrap(), before, "input untouched without --in-place");
    assert!(String::from_utf8(o.stdout).unwrap().matches("\np 4\n").count() == 5);
    let o = run(
        PLANEGEN,
        &["--nx", "2", "--ny", "2", "--append-to", scene.to_str().unwrap(), "--in-place"],
        None,
    );
    assert!(o.status.success());
    assert_ne!(std::fs::read(&scene).unwrap(), before);
    let bad = dir.path().join("bad.nff");
    std::fs::write(&bad, "v\nfrom 1\n").unwrap();
    let o = run(PLANEGEN, &["--append-to", bad.to_str().unwrap()], None);
    assert!(!o.status.success());
}

#[test]
fn sphereflake_level_2_matches_and_streams_to_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b2.nff");
    let o = run(SPHEREFLAKE, &["--level", "2", "-o", out.to_str().unwrap()], None);
    assert!(o.status.success());
    let o = run(RENDER, &["--check", out.to_str().unwrap()], None);
    assert!(String::from_utf8(o.stdout).unwrap().contains("91 spheres"));
    assert!(!run(SPHEREFLAKE, &["--level", "12"], None).status.success());
}

#[test]
fn cost_image_has_a_colour_bar_and_accelerators_agree() {
    let dir = tempfile::tempdir().unwrap();
    let mut images = Vec::new();
    for accel in ["none", "grid", "bvh"] {
        let (out, cost) =
            (dir.path().join(format!("{accel}.png")), dir.path().join(format!("{accel}-cost.png")));
        let o = run(
            RENDER,
            &[
                &spd("balls_s2.nff"),
                "-o",
                out.to_str().unwrap(),
                "--width",
                "32",
                "--height",
                "24",
                "--accel",
                accel,
                "--aov-cost",
                cost.to_str().unwrap(),
                "-q",
            ],
            None,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(png(&cost).dimensions(), (32, 24 + 16));
        images.push(png(&out));
    }
    assert_eq!(images[0], images[1]);
    assert_eq!(images[0], images[2]);
}

#[test]
fn adaptive_depth_control_prunes_rays_and_barely_changes_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    let base = [&spd("mount_s5.nff"), "--width", "64", "--height", "64", "--stats"];
    let full = run(RENDER, &[&base[..], &["-o", a.to_str().unwrap()]].concat(), None);
    let cut =
        run(RENDER, &[&base[..], &["-o", b.to_str().unwrap(), "--min-weight", "0.0039"]].concat(), None);
    let rays = |o: &Output| -> u64 {
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        let line = text.lines().find(|l| l.starts_with("rays")).unwrap().to_string();
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    assert!(rays(&cut) < rays(&full), "{} vs {}", rays(&cut), rays(&full));
    let (ia, ib) = (png(&a), png(&b));
    let worst =
        ia.pixels().zip(ib.pixels()).flat_map(|(p, q)| (0..3).map(move |i| p[i].abs_diff(q[i]))).max();
    assert!(worst.unwrap() <= 2, "{worst:?}");
    assert!(!run(RENDER, &["--min-weight", "2"], None).status.success());
}

fn run_in(bin: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(bin).args(args).current_dir(dir).stdin(std::process::Stdio::null()).output().unwrap()
}

#[test]
fn golden_finds_scenes_from_any_folder_inside_the_checkout_and_says_so_outside() {
    let golden = env!("CARGO_BIN_EXE_golden");
    // From a folder deep inside the checkout: the catalogue is found (an
    // unknown case name is the error, not a missing catalogue).
    let inside = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/bin");
    let o = run_in(golden, &inside, &["update", "no-such-case"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("no case named no-such-case"), "{err}");
    // From a folder outside any checkout: a clear error.
    let outside = tempfile::tempdir().unwrap();
    let o = run_in(golden, outside.path(), &["check"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("no scenes/catalogue.toml") && err.contains("--scenes"), "{err}");
}

#[test]
fn every_binary_has_its_own_help_and_no_build_machine_path() {
    let bins = [
        env!("CARGO_BIN_EXE_render"),
        env!("CARGO_BIN_EXE_planegen"),
        env!("CARGO_BIN_EXE_sphereflake"),
        env!("CARGO_BIN_EXE_mesh2nff"),
        env!("CARGO_BIN_EXE_golden"),
        env!("CARGO_BIN_EXE_table1"),
        env!("CARGO_BIN_EXE_aademo"),
        env!("CARGO_BIN_EXE_raybench"),
        env!("CARGO_BIN_EXE_nffmerge"),
        env!("CARGO_BIN_EXE_spd"),
        env!("CARGO_BIN_EXE_nffconvert"),
    ];
    let source_tree = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_string_lossy().into_owned();
    let mut abouts = std::collections::BTreeSet::new();
    for bin in bins {
        for flag in ["-h", "--help"] {
            let o = run(bin, &[flag], None);
            let help = String::from_utf8_lossy(&o.stdout).into_owned();
            assert!(o.status.success(), "{bin} {flag}");
            assert!(!help.contains(&source_tree), "{bin} {flag} shows the build tree:\n{help}");
            if flag == "-h" {
                abouts.insert(help.lines().next().unwrap_or_default().to_string());
            }
        }
    }
    assert_eq!(abouts.len(), bins.len(), "binaries share an about text: {abouts:?}");
}

#[test]
fn spd_stats_prints_the_published_figures_for_sphereflake_level_4() {
    let dir = tempfile::tempdir().unwrap();
    let nff = dir.path().join("balls.nff");
    let o = run(SPHEREFLAKE, &["--level", "4", "-o", nff.to_str().unwrap()], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("b.png");
    let o = run(RENDER, &[nff.to_str().unwrap(), "-o", out.to_str().unwrap(), "--spd-stats", "-q"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("SPD published figures: balls at size 4"), "{text}");
    // Every row within the Readme's 10%.
    for row in ["eye hit rays", "reflect rays", "refract rays", "shadow rays"] {
        let line =
            text.lines().find(|l| l.trim_start().starts_with(row)).unwrap_or_else(|| panic!("{row}: {text}"));
        let diff: f64 = line.split_whitespace().last().unwrap().trim_end_matches('%').parse().unwrap();
        assert!(diff.abs() < 10.0, "{line}");
    }
    assert!(text.contains("eye 263169 (263169 hit)"), "{text}");
}

#[test]
fn check_notes_course_extensions_and_warns_of_a_scene_without_lights() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("course.nff");
    std::fs::write(
        &f,
        "v\nfrom 0 2 8\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.1\nresolution 32 32\n\
         pl 0 0 0 1 0 0 0 0 -1\naabb -1 0 -1 1 1 1\n",
    )
    .unwrap();
    let path = f.to_str().unwrap();
    let o = run(RENDER, &["--check", path], None);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("note: `pl` (infinite plane through three points) is a course extension"), "{err}");
    assert!(err.contains("course.nff:9:1"), "{err}");
    assert!(err.contains("warning: the scene has no lights"), "{err}");
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains("(1 plane, 1 box)") && summary.contains("2 notes"), "{summary}");
    // --strict refuses them; rendering warns of the missing light, and
    // --ambient lights the scene.
    let o = run(RENDER, &["--check", "--strict", path], None);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("`pl` is not NFF (--strict)"));
    let out = dir.path().join("c.png");
    let o = run(RENDER, &[path, "-o", out.to_str().unwrap()], None);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no lights") && !err.contains("note:"), "{err}");
    let dark = png(&out);
    let o = run(RENDER, &[path, "-o", out.to_str().unwrap(), "--ambient", "spd"], None);
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("no lights"));
    let lit = png(&out);
    let sum = |img: &image::RgbImage| img.pixels().map(|p| p.0[0] as u64).sum::<u64>();
    assert!(sum(&lit) > sum(&dark) + 32 * 32 * 20, "ambient lights the plane and the box");
    let o = run(RENDER, &[path, "-o", out.to_str().unwrap(), "--ambient", "bright"], None);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("expected a number or `spd`"));
}

#[test]
fn packets_change_the_speed_not_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let shot = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut args =
            vec![spd("mount_s1.nff"), "-o".into(), out.to_str().unwrap().into(), "--spp".into(), "16".into()];
        args.extend(["--width", "48", "--height", "40", "--light-size", "0.2", "--stats"].map(String::from));
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(RENDER, &args, None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (png(&out), String::from_utf8_lossy(&[o.stdout, o.stderr].concat()).into_owned())
    };
    let (with, stats) = shot("p.png", &[]);
    let (without, stats_off) = shot("s.png", &["--no-packets"]);
    assert_eq!(with, without);
    assert!(stats.contains("in packets of 16, kernels for"), "{stats}");
    assert!(stats_off.contains("packets      off"), "{stats_off}");
}

/// A scene of `n` patches whose normals have length 2 (a warning each),
/// one patch per line, or all on one line.
fn patches_with_long_normals(n: usize, one_line: bool) -> String {
    let mut s =
        String::from("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 0.1 resolution 16 16\nl 0 0 5\n");
    for _ in 0..n {
        s += "pp 3 0 0 0 0 0 2 1 0 0 0 0 2 0 1 0 0 0 2";
        s.push(if one_line { ' ' } else { '\n' });
    }
    s
}

#[test]
fn repeated_warnings_are_counted_after_the_first_few() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("p.nff");
    std::fs::write(&file, patches_with_long_normals(3000, false)).unwrap();
    let f = file.to_str().unwrap();
    let out = run(RENDER, &["--check", f], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.matches("warning: patch normal").count(), 5, "{err}");
    assert!(
        err.contains("... and 2995 more like `patch normal of vertex 1 has length 2.0000, not 1`"),
        "{err}"
    );
    // The patches, all at one place, also overlap in one plane: one more.
    assert!(err.contains("overlap in one plane (and 4498499 more pairs)"), "{err}");
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(summary.contains("3001 warnings"), "{summary}");
    let all = run(RENDER, &["--check", "--all-warnings", f], None);
    assert_eq!(String::from_utf8_lossy(&all.stderr).matches("warning: patch normal").count(), 3000);
    let quiet = run(RENDER, &["--check", "-q", f], None);
    assert!(quiet.stderr.is_empty() && quiet.status.success());
    assert!(String::from_utf8_lossy(&quiet.stdout).contains("3001 warnings"));
    // A render prints the same summarised warnings, and nothing with -q.
    let png = dir.path().join("p.png");
    let r = run(RENDER, &[f, "-o", png.to_str().unwrap()], None);
    assert_eq!(String::from_utf8_lossy(&r.stderr).matches("warning: patch normal").count(), 5);
    let r = run(RENDER, &[f, "-q", "-o", png.to_str().unwrap()], None);
    assert!(r.stderr.is_empty());
}

#[test]
fn warnings_on_one_long_line_stay_small() {
    // 5,000 warnings on one 200 KB line: each shows a window of the line,
    // not the line padded out to its column.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("p.nff");
    std::fs::write(&file, patches_with_long_normals(5000, true)).unwrap();
    let out = run(RENDER, &["--check", "--all-warnings", file.to_str().unwrap()], None);
    assert_eq!(String::from_utf8_lossy(&out.stderr).matches("warning: patch normal").count(), 5000);
    assert!(out.stderr.len() < 3 << 20, "{} bytes of warnings", out.stderr.len());
}

/// A closed box seen from outside whose front wall faces inwards (away
/// from the camera), lit from a point in that wall's plane: the author
/// meant the interior, which the spec's one-sided rule shows.
const BOX_SEEN_FROM_BEHIND: &str =
    "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\nresolution 32 32\n\
    l 0 0.5 1\nf 0.8 0.8 0.8 1 0 0 0 1\n\
    p 4\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n\
    p 4\n-1 -1 1\n-1 1 1\n1 1 1\n1 -1 1\n\
    p 4\n-1 -1 -1\n-1 -1 1\n1 -1 1\n1 -1 -1\n\
    p 4\n-1 1 -1\n1 1 -1\n1 1 1\n-1 1 1\n\
    p 4\n-1 -1 -1\n-1 1 -1\n-1 1 1\n-1 -1 1\n\
    p 4\n1 -1 -1\n1 -1 1\n1 1 1\n1 1 -1\n";

#[test]
fn a_view_of_back_faces_lit_edge_on_is_warned_not_silently_black() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("box.nff");
    std::fs::write(&f, BOX_SEEN_FROM_BEHIND).unwrap();
    let path = f.to_str().unwrap();
    let in_plane = "light 1 at (0, 0.5, 1) lies in the plane of the polygon on line 15";
    let backs = "of the view is the back of opaque surfaces (the first on line 15)";
    let o = run(RENDER, &["--check", path], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains(in_plane) && err.contains(backs), "{err}");
    assert!(err.contains("box.nff:15"), "{err}");
    assert!(String::from_utf8_lossy(&o.stdout).contains("2 warnings"));
    // Rendered as it is, it is black and both are said; one-sided, the
    // interior shows and only the light in the plane is.
    let out = dir.path().join("b.png");
    let o = run(RENDER, &[path, "-o", out.to_str().unwrap()], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains(in_plane) && err.contains(backs), "{err}");
    assert!(png(&out).pixels().all(|p| p.0 == [0, 0, 0]));
    let o = run(RENDER, &[path, "-o", out.to_str().unwrap(), "--one-sided"], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains(in_plane) && !err.contains(backs), "{err}");
    assert!(png(&out).pixels().filter(|p| p.0[0] > 50).count() > 32 * 32 / 2);
}

#[test]
fn a_scene_beyond_single_precision_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let view = "v\nfrom 2 1 1.5\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\nresolution 16 16\nl -3 1 5\n";
    let warning = "spans 2.5e9 times the size of its smallest object";
    for (name, extra, warned) in
        [("fine.nff", "s 0 0 0 0.5\n", false), ("wide.nff", "s 0.4 0.3 0.4 2.8e8\n", true)]
    {
        let f = dir.path().join(name);
        std::fs::write(&f, format!("{view}s 0.3 0.4 0.4 0.0555\n{extra}")).unwrap();
        let o = run(RENDER, &["--check", f.to_str().unwrap()], None);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.contains(warning), warned, "{name}: {err}");
    }
}
