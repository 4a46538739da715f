//! What the commands do with the user's files: outputs checked before any
//! work, inputs never overwritten, no debris on interruption, no write
//! through a planted link, closed pipes and full disks.

use std::path::Path;
use std::process::{Command, Output, Stdio};

const RENDER: &str = env!("CARGO_BIN_EXE_render");
const PLANEGEN: &str = env!("CARGO_BIN_EXE_planegen");
const SPHEREFLAKE: &str = env!("CARGO_BIN_EXE_sphereflake");
const NFFMERGE: &str = env!("CARGO_BIN_EXE_nffmerge");
const AADEMO: &str = env!("CARGO_BIN_EXE_aademo");
const NFFBENCH: &str = env!("CARGO_BIN_EXE_nffbench");

fn run_in(dir: &Path, bin: &str, args: &[&str]) -> Output {
    Command::new(bin).args(args).current_dir(dir).stdin(Stdio::null()).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A small scene in a fresh folder.
fn folder_with_scene() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{}/../scenes/spd/balls_s2.nff", env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(scene, dir.path().join("s.nff")).unwrap();
    dir
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn outputs_are_checked_before_any_work() {
    let dir = folder_with_scene();
    let d = dir.path();
    // 4096x4096 at 64 spp would take minutes: the error comes first.
    let big = ["s.nff", "--width", "4096", "--height", "4096", "--spp", "64"];
    let t = std::time::Instant::now();
    let o = run_in(d, RENDER, &[&big[..], &["-o", "nodir/x.png"]].concat());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("-o nodir/x.png: folder nodir does not exist"), "{}", stderr(&o));
    let o = run_in(d, RENDER, &[&big[..], &["-o", "x.png", "--aov-cost", "nodir/c.png"]].concat());
    assert!(stderr(&o).contains("--aov-cost nodir/c.png"), "{}", stderr(&o));
    assert!(t.elapsed().as_secs() < 20, "the checks came after rendering");
    assert_eq!(names(d), ["s.nff"], "nothing written");

    std::fs::write(d.join("taken"), b"a file").unwrap();
    let o = run_in(d, AADEMO, &["--out", "taken", "--size", "16"]);
    assert!(stderr(&o).contains("--out taken: it is a file, not a folder"), "{}", stderr(&o));
    std::fs::create_dir(d.join("empty")).unwrap();
    let o = run_in(d, NFFBENCH, &["--shared", "empty", "--size", "16", "--runs", "1"]);
    assert!(stderr(&o).contains("bench/embree-rays not found"), "{}", stderr(&o));
}

#[test]
fn no_input_is_overwritten_and_no_output_is_named_twice() {
    let dir = folder_with_scene();
    let d = dir.path();
    let before = std::fs::read(d.join("s.nff")).unwrap();
    let o = run_in(d, PLANEGEN, &["--append-to", "s.nff", "-o", "s.nff"]);
    assert!(stderr(&o).contains("would overwrite the input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.join("s.nff")).unwrap(), before);
    // --in-place is the way to mean it.
    assert!(run_in(d, PLANEGEN, &["--append-to", "s.nff", "--in-place", "--z", "-3"]).status.success());
    assert_ne!(std::fs::read(d.join("s.nff")).unwrap(), before);

    let o = run_in(d, RENDER, &["s.nff", "--width", "16", "--height", "32", "-o", "p.exr", "--tile", "0/2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run_in(d, RENDER, &["s.nff", "--width", "16", "--height", "32", "-o", "q.exr", "--tile", "1/2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let part = std::fs::read(d.join("p.exr")).unwrap();
    let o = run_in(d, NFFMERGE, &["-o", "p.exr", "p.exr", "q.exr"]);
    assert!(stderr(&o).contains("-o p.exr would overwrite the input"), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.join("p.exr")).unwrap(), part);

    let o = run_in(
        d,
        RENDER,
        &["s.nff", "--width", "16", "--height", "16", "-o", "same.png", "--aov-cost", "same.png"],
    );
    assert!(stderr(&o).contains("-o and --aov-cost both name same.png"), "{}", stderr(&o));
    // A scene named like an image, rendered to its default output name.
    std::fs::copy(d.join("s.nff"), d.join("scene.png")).unwrap();
    let o = run_in(d, RENDER, &["scene.png", "--width", "16", "--height", "16"]);
    assert!(stderr(&o).contains("-o scene.png would overwrite the input"), "{}", stderr(&o));
    assert!(!names(d).contains(&"same.png".to_string()));
}

#[cfg(unix)]
#[test]
fn an_interrupted_writer_leaves_no_temporary_file() {
    for signal in ["INT", "TERM"] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let mut child = Command::new(SPHEREFLAKE)
            .args(["--level", "7", "-o", "f.nff"])
            .current_dir(d)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait for the temporary file, then interrupt.
        let t = std::time::Instant::now();
        while !names(d).iter().any(|n| n.ends_with(".tmp")) {
            assert!(t.elapsed().as_secs() < 30, "no temporary file appeared");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        let kill =
            Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
        assert!(kill.success());
        let status = child.wait().unwrap();
        assert!(!status.success());
        assert!(names(d).is_empty(), "SIG{signal} left {:?}", names(d));
    }
}

#[cfg(unix)]
#[test]
fn a_link_planted_at_a_temporary_name_is_not_followed() {
    let dir = folder_with_scene();
    let d = dir.path();
    std::fs::write(d.join("victim.txt"), b"precious").unwrap();
    // The old writer's name was .NAME.PID.tmp: the shell's PID is the
    // renderer's after exec.
    let script =
        format!("ln -s victim.txt .out.png.$$.tmp; exec {RENDER} s.nff --width 16 --height 16 -q -o out.png");
    let o = Command::new("sh").args(["-c", &script]).current_dir(d).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(d.join("victim.txt")).unwrap(), b"precious");
    let out = std::fs::symlink_metadata(d.join("out.png")).unwrap();
    assert!(out.file_type().is_file());
}

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error() {
    let dir = folder_with_scene();
    let d = dir.path();
    // Many files, so that the summaries outgrow any buffer.
    let files: Vec<&str> = std::iter::repeat_n("s.nff", 2000).collect();
    let cases: [Vec<&str>; 2] = [
        [&["--check"][..], &files].concat(),
        vec!["s.nff", "--width", "16", "--height", "16", "-o", "x.png", "--stats"],
    ];
    for args in &cases {
        let mut child = Command::new(RENDER)
            .args(args)
            .current_dir(d)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{:?}: {}", &args[..2], stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    }
    #[cfg(target_os = "linux")]
    {
        let full = || std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let o = Command::new(RENDER).args(&cases[1]).current_dir(d).stdout(full()).output().unwrap();
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains("writing to standard output: No space left on device"), "{}", stderr(&o));
        // A full standard error loses the messages, not the image.
        std::fs::remove_file(d.join("x.png")).unwrap();
        let o = Command::new(RENDER).args(&cases[1][..7]).current_dir(d).stderr(full()).output().unwrap();
        assert_eq!(o.status.code(), Some(0));
        assert!(d.join("x.png").is_file());
    }
}

#[cfg(target_os = "linux")]
#[test]
fn memory_is_refused_early_not_exhausted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The largest image render accepts (2^27 pixels) under a 4 GB
    // address-space limit: refused before rendering, not an abort.
    let big =
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 11585 11585\nl 1 1 5\ns 0 0 0 1\n";
    std::fs::write(d.join("big.nff"), big).unwrap();
    let script = format!("ulimit -v 4000000; exec {RENDER} big.nff -o big.exr --aov-cost c.png");
    let t = std::time::Instant::now();
    let o = Command::new("sh").args(["-c", &script]).current_dir(d).output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("a 11585x11585 image needs about 10.7 GB of memory"), "{}", stderr(&o));
    assert!(t.elapsed().as_secs() < 10);
    // Endless streams: NUL bytes end the reading at once; text fed for
    // ever stops at the stream limit. (Random bytes are blamed where the
    // first line that is not blank or a comment starts: line 1 in about 49
    // runs of 50.)
    for (dev, blame) in [("/dev/zero", "line 1,"), ("/dev/urandom", "line ")] {
        let o = run_in(d, RENDER, &[dev, "-o", "z.png"]);
        assert_eq!(o.status.code(), Some(1), "{dev}: {}", stderr(&o));
        assert!(stderr(&o).contains(&format!("{dev}: {blame}")), "{}", stderr(&o));
    }
    let script = format!("yes 's 0 0 0 1' | {RENDER} - -o z.png --stream-limit 20");
    let o = Command::new("sh").args(["-c", &script]).current_dir(d).output().unwrap();
    assert!(stderr(&o).contains("standard input passed 21 MB without ending"), "{}", stderr(&o));
    assert_eq!(names(d), ["big.nff"]);
}

const GOLDEN: &str = env!("CARGO_BIN_EXE_golden");

/// A scenes folder with a catalogue of `cases` (TOML).
fn scenes_with(cases: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir_all(scenes.join("golden")).unwrap();
    std::fs::write(scenes.join("catalogue.toml"), cases).unwrap();
    dir
}

#[test]
fn golden_checks_its_catalogue_and_reports_every_case() {
    // A name that would write outside the goldens folder.
    let dir = scenes_with("[[case]]\nname = \"../../../escaped\"\nsource = \"default\"\nrender = [\"--width\", \"8\", \"--height\", \"8\"]\n");
    let o = run_in(dir.path(), GOLDEN, &["update"]);
    assert!(stderr(&o).contains("name `../../../escaped` must be a plain file name"), "{}", stderr(&o));
    assert!(!dir.path().parent().unwrap().join("escaped.png").exists());

    // One golden unreadable, one fine: the first fails, the second is
    // still checked, and the totals and the way to accept are printed.
    let case = |n: &str| {
        format!("[[case]]\nname = \"{n}\"\nsource = \"default\"\nrender = [\"--width\", \"8\", \"--height\", \"8\"]\n")
    };
    let dir = scenes_with(&(case("broken") + &case("fine")));
    let d = dir.path();
    assert!(run_in(d, GOLDEN, &["update"]).status.success());
    std::fs::write(d.join("scenes/golden/broken.png"), b"not a png").unwrap();
    let o = run_in(d, GOLDEN, &["check"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}{}", stderr(&o));
    assert!(out.contains("broken") && out.contains("cannot read"), "{out}");
    assert!(out.contains("fine                         pass"), "{out}");
    assert!(out.contains("2 cases: 1 passed, 1 failed"), "{out}");
    assert!(out.contains("if the change is intended: golden update broken"), "{out}");
    // The report lands in the checkout (beside scenes/), failures first.
    let html = std::fs::read_to_string(d.join("target/golden/report/index.html")).unwrap();
    assert!(html.contains("2 cases: 1 passed, 1 failed"));
    assert!(html.find(">broken<").unwrap() < html.find(">fine<").unwrap());

    // Generator options past what memory holds are refused, not tried.
    let dir = scenes_with("[[case]]\nname = \"huge\"\nsource = { sphereflake = [\"--level\", \"9\"] }\n");
    let o = run_in(dir.path(), GOLDEN, &["check"]);
    assert!(stderr(&o).contains("case huge: sphereflake level 9 needs about"), "{}", stderr(&o));
}

#[test]
fn messages_name_the_right_thing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let says = |bin: &str, args: &[&str], what: &str| {
        let o = run_in(d, bin, args);
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(stderr(&o).contains(what), "{args:?}: {}", stderr(&o));
    };
    says(SPHEREFLAKE, &["--level", "12"], "the highest level is 9 (435848050 spheres)");
    says(SPHEREFLAKE, &["--checker", "0,0"], "as NX,NY");
    says(PLANEGEN, &["--z=-1e400"], "--z must be a finite number");
    says(PLANEGEN, &["--nx", "-3"], "invalid value '-3' for '--nx <NX>'");
    says(env!("CARGO_BIN_EXE_raybench"), &["--runs", "0", "x.nff"], "0 is not in 1..=1000");
    says(NFFBENCH, &[], "pass --spd-dir DIR");
    says(NFFMERGE, &["missing.exr", "-o", "x.png"], "parts are the .exr files");
    let o =
        Command::new(PLANEGEN).args(["--nx", "1", "--ny", "1"]).env("NFFKIT_SIMD", "sse9").output().unwrap();
    assert!(stderr(&o).contains("NFFKIT_SIMD=sse9 names no instruction set"), "{}", stderr(&o));
    // The OS error once, not twice.
    let o = run_in(d, NFFMERGE, &["missing.exr", "-o", "x.png"]);
    assert_eq!(stderr(&o).matches("os error 2").count(), 1, "{}", stderr(&o));
}
