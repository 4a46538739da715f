//! Render parts: any crop, pixel range or tile equals the same pixels of the
//! full render, for every sampler, filter, light size and aperture; tiles
//! rendered by concurrent processes merge to the full render's bytes; merge
//! refuses parts that do not belong together.

use crate::common::program;
use nffkit_tools::render::args::{render_config_from, PartSpec};
use nffkit_tracer::film::Film;
use nffkit_tracer::prepare::prepare;
use nffkit_tracer::render::{render, PixelWindow};
use std::path::Path;
use std::process::{Command, Output};

const RENDER: &str = env!("CARGO_BIN_EXE_render");
const NFFMERGE: &str = env!("CARGO_BIN_EXE_nffmerge");

/// Every primitive kind (sphere, cone, polygon, patch), a mirror and glass,
/// two lights.
const SCENE: &str = "\
v
from 0 -6 2
at 0 0 0.5
up 0 0 1
angle 40
hither 0.01
resolution 48 40
b 0.1 0.2 0.4
l 4 -4 6
l -3 -2 5 0.6 0.6 0.5
f 0.9 0.8 0.6 0.7 0.3 20 0 1
p 4
-4 -4 0
4 -4 0
4 4 0
-4 4 0
f 1 0.3 0.2 0.6 0.4 30 0 1
s -1 0 1 0.8
f 0.8 0.9 1 0.1 0.2 50 0.8 1.5
s 1.2 -0.5 0.8 0.6
f 0.3 0.9 0.3 0.8 0.1 10 0 1
c 0 1.5 0 0.5 0 1.5 2 0.1
pp 3
-2 2 0.1 0 0 1
-1 2 1.5 0 -0.5 1
-3 2 1.5 0 -0.5 1
";

fn scene() -> nffkit_formats::Scene {
    nffkit_formats::nff::parse(SCENE.as_bytes(), &Default::default()).unwrap().scene
}

/// Render `args` in-process; `window` restricts it to a part.
fn film(args: &[&str], part: Option<PartSpec>) -> (Film, Option<PixelWindow>) {
    let cfg = render_config_from(args.iter().copied()).unwrap();
    let prepared = prepare(&scene(), &cfg.prepare).unwrap();
    let (w, h) = prepared.camera.resolution();
    let mut settings = cfg.settings.clone();
    settings.window = part.map(|p| p.window(w, h).unwrap());
    (render(&prepared, &settings, &|_, _| {}).film, settings.window)
}

fn assert_part_matches(full: &Film, part: &Film, win: PixelWindow, what: &str) {
    assert_eq!((part.width, part.height), (win.width(), win.height()), "{what}");
    for y in win.y0..win.y1 {
        for x in win.x0..win.x1 {
            let (a, b) = (full.get(x, y), part.get(x - win.x0, y - win.y0));
            assert!(a.to_array() == b.to_array(), "{what}: pixel ({x}, {y}) {a} vs {b}");
        }
    }
}

#[test]
fn every_part_equals_the_same_pixels_of_the_full_render() {
    let settings: [&[&str]; 5] = [
        &["--spp", "16", "--light-size", "0.5", "--aperture", "0.1", "--focus", "5"],
        &["--spp", "4", "--sampler", "random", "--filter", "mitchell"],
        &[
            "--spp",
            "4",
            "--sampler",
            "sobol",
            "--filter",
            "gaussian",
            "--light-shape",
            "disk",
            "--light-size",
            "1",
        ],
        &["--spp", "9", "--sampler", "n-rooks", "--filter", "tent"],
        &[],
    ];
    let parts = [
        PartSpec::Tile { k: 0, n: 3 },
        PartSpec::Tile { k: 2, n: 3 },
        PartSpec::Crop([0.1, 0.65, 0.3, 0.9]),
        PartSpec::Pixels([17, 18, 23, 24]),
        PartSpec::Pixels([0, 48, 39, 40]),
    ];
    for args in settings {
        let (full, _) = film(args, None);
        for part in parts {
            let (p, win) = film(args, Some(part));
            assert_part_matches(&full, &p, win.unwrap(), &format!("{args:?} {part:?}"));
        }
    }
}

#[test]
fn tiles_cover_the_image_once_evenly_or_not() {
    for n in [1, 3, 4, 7] {
        let (w, h) = (48, 120);
        let mut covered = vec![0u32; h as usize];
        for k in 0..n {
            let win = PartSpec::Tile { k, n }.window(w, h).unwrap();
            assert_eq!((win.x0, win.x1), (0, w));
            assert!(win.y0.is_multiple_of(16), "tiles are whole bands of 16 rows");
            for y in win.y0..win.y1 {
                covered[y as usize] += 1;
            }
        }
        assert!(covered.iter().all(|&c| c == 1), "{n} tiles: {covered:?}");
    }
    let e = PartSpec::Tile { k: 0, n: 9 }.window(48, 120).unwrap_err().to_string();
    assert!(e.contains("only 8 bands"), "{e}");
    let e = PartSpec::Pixels([0, 49, 0, 1]).window(48, 40).unwrap_err().to_string();
    assert!(e.contains("reaches past the 48x40 image"), "{e}");
}

fn run(bin: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(bin).args(args).current_dir(dir).output().unwrap()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    assert!(!o.status.success(), "expected a failure");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const SETTINGS: [&str; 7] = ["--spp", "16", "--light-size", "0.5", "--aperture", "0.1", "-q"];

#[test]
fn tiles_from_concurrent_processes_merge_to_the_full_render_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    // Four render processes at once, as a farm would run them.
    let children: Vec<_> = (0..4)
        .map(|k| {
            let (tile, out) = (format!("{k}/4"), format!("t{k}.exr"));
            let args =
                [&["s.nff", "--tile", &tile, "-o", &out, "--width", "64", "--height", "64"][..], &SETTINGS]
                    .concat();
            Command::new(RENDER).args(args).current_dir(d).spawn().unwrap()
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    // A part rendered again is the same file, header included.
    let again =
        [&["s.nff", "--tile", "0/4", "-o", "again.exr", "--width", "64", "--height", "64"][..], &SETTINGS]
            .concat();
    ok(&run(RENDER, d, &again));
    let (t0, again) = (std::fs::read(d.join("t0.exr")).unwrap(), std::fs::read(d.join("again.exr")).unwrap());
    assert!(t0 == again, "the same part rendered twice gave different files");
    for ext in ["png", "exr"] {
        let full = format!("full.{ext}");
        let merged = format!("merged.{ext}");
        ok(&run(
            RENDER,
            d,
            &[&["s.nff", "-o", &full, "--width", "64", "--height", "64"][..], &SETTINGS].concat(),
        ));
        let stats =
            ok(&run(NFFMERGE, d, &["t0.exr", "t1.exr", "t2.exr", "t3.exr", "-o", &merged, "--stats"]));
        assert!(stats.contains("eye 65536 ("), "16 spp x 64 x 64 eye rays summed: {stats}");
        let (a, b) = (std::fs::read(d.join(&full)).unwrap(), std::fs::read(d.join(&merged)).unwrap());
        assert!(a == b, "merged {ext} differs from the full render");
    }
}

#[test]
fn merge_refuses_parts_that_do_not_belong_together() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    // The same scene reformatted (comments, spacing) has the same digest.
    let reformatted = format!("# reformatted\n{}", SCENE.replace(' ', "  "));
    std::fs::write(d.join("same.nff"), reformatted).unwrap();
    std::fs::write(d.join("other.nff"), SCENE.replace("s -1 0 1 0.8", "s -1 0 1 0.7")).unwrap();
    let part = |scene: &str, tile: &str, out: &str, extra: &[&str]| {
        ok(&run(RENDER, d, &[&[scene, "--tile", tile, "-o", out, "-q"][..], extra].concat()));
    };
    part("s.nff", "0/2", "a0.exr", &[]);
    part("same.nff", "1/2", "a1.exr", &[]);
    part("other.nff", "1/2", "b1.exr", &[]);
    part("s.nff", "1/2", "c1.exr", &["--spp", "4"]);
    ok(&run(NFFMERGE, d, &["a0.exr", "a1.exr", "-o", "ok.png"]));
    let e = err(&run(NFFMERGE, d, &["a0.exr", "b1.exr", "-o", "x.png"]));
    assert!(e.contains("b1.exr comes from another scene than a0.exr"), "{e}");
    let e = err(&run(NFFMERGE, d, &["a0.exr", "c1.exr", "-o", "x.png"]));
    assert!(e.contains("other settings") && e.contains("spp=4"), "{e}");
    let e = err(&run(NFFMERGE, d, &["a0.exr", "a0.exr", "a1.exr", "-o", "x.png"]));
    assert!(e.contains("overlap: both cover pixel (0, 0)"), "{e}");
    let e = err(&run(NFFMERGE, d, &["a0.exr", "-o", "x.png"]));
    assert!(e.contains("uncovered, the first at (0, 16)"), "{e}");
    std::fs::write(d.join("plain.exr"), b"not an exr").unwrap();
    let e = err(&run(NFFMERGE, d, &["plain.exr", "-o", "x.png"]));
    assert!(e.contains("plain.exr: not a readable OpenEXR file"), "{e}");
    assert!(!d.join("x.png").exists(), "a refused merge writes nothing");
}

#[test]
fn merge_refuses_parts_lit_differently() {
    // Half the image brighter must not pass: the ambient light is a
    // setting that changes pixels.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    ok(&run(RENDER, d, &["s.nff", "--tile", "0/2", "-o", "t0.exr", "-q"]));
    ok(&run(RENDER, d, &["s.nff", "--tile", "1/2", "--ambient", "0.8", "-o", "t1.exr", "-q"]));
    let e = err(&run(NFFMERGE, d, &["t0.exr", "t1.exr", "-o", "x.png"]));
    assert!(e.contains("ambient differs (t0.exr: ambient=0, t1.exr: ambient=0.8)"), "{e}");
    assert!(!d.join("x.png").exists());
    ok(&run(RENDER, d, &["s.nff", "--tile", "1/2", "--ambient", "0", "-o", "t1.exr", "-q"]));
    ok(&run(NFFMERGE, d, &["t0.exr", "t1.exr", "-o", "x.png", "-q"]));
}

#[test]
fn bad_part_options_get_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    for (args, says) in [
        (&["--tile", "4/4"][..], "K counts from 0 to N-1"),
        (&["--tile", "two"], "expected K/N"),
        (&["--tile", "0/0"], "K counts from 0"),
        (&["--crop", "0.5,0.2,0,1"], "0 <= x0 < x1 <= 1"),
        (&["--crop", "0,1,0"], "four comma-separated numbers"),
        (&["--pixel-bounds", "0,100,0,10"], "reaches past the 48x40 image"),
        (&["--tile", "0/2", "--crop", "0,1,0,1"], "cannot be used with"),
        (&["--tile", "0/9"], "only 3 bands"),
        (&["--tile", "0/2", "--spd-stats"], "--spd-stats"),
    ] {
        let e = err(&run(RENDER, d, &[&["s.nff", "-o", "x.exr"][..], args].concat()));
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(!d.join("x.exr").exists());
    }
}

#[test]
fn merge_refuses_edited_parts_bad_pixels_and_huge_windows() {
    use nffkit_formats::image_io::RgbImage;
    use nffkit_tools::render::part::encode_part;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    ok(&run(RENDER, d, &["s.nff", "--tile", "0/2", "-o", "a0.exr", "-q", "--stats"]));
    ok(&run(RENDER, d, &["s.nff", "--tile", "1/2", "-o", "a1.exr", "-q"]));
    // Counters edited in place (one digit of `eye=`): the digest tells.
    let mut bytes = std::fs::read(d.join("a1.exr")).unwrap();
    let at = bytes.windows(4).position(|w| w == b"eye=").unwrap() + 4;
    bytes[at] = if bytes[at] == b'9' { b'1' } else { bytes[at] + 1 };
    std::fs::write(d.join("edited.exr"), &bytes).unwrap();
    let e = err(&run(NFFMERGE, d, &["a0.exr", "edited.exr", "-o", "x.png"]));
    assert!(e.contains("edited.exr: the part's pixels or counters are not what render wrote"), "{e}");

    // A NaN pixel with a digest to match.
    let counters = nffkit_tracer::stats::Counters::default();
    let window = PixelWindow { x0: 0, x1: 2, y0: 0, y1: 1 };
    let nan = RgbImage { width: 2, height: 1, pixels: vec![[0.5; 3], [f32::NAN, 0.0, 0.0]] };
    let bytes = encode_part(&nan, (2, 2), window, "d", "s", &counters).unwrap();
    std::fs::write(d.join("nan.exr"), bytes).unwrap();
    let e = err(&run(NFFMERGE, d, &["nan.exr", "-o", "x.png"]));
    assert!(e.contains("nan.exr: pixel (1, 0) is [NaN, 0.0, 0.0], not a finite non-negative colour"), "{e}");
    // A window past what render makes, refused from the header.
    let one = RgbImage { width: 1, height: 1, pixels: vec![[0.5; 3]] };
    let window = PixelWindow { x0: 0, x1: 1, y0: 0, y1: 1 };
    let bytes = encode_part(&one, (46000, 46000), window, "d", "s", &counters).unwrap();
    std::fs::write(d.join("huge.exr"), bytes).unwrap();
    let e = err(&run(NFFMERGE, d, &["huge.exr", "-o", "x.png"]));
    assert!(e.contains("huge.exr: a 46000x46000 image is larger than nffkit renders"), "{e}");
    // A PNG given as a part says what parts are.
    ok(&run(RENDER, d, &["s.nff", "-o", "p.png", "-q"]));
    let e = err(&run(NFFMERGE, d, &["p.png", "-o", "x.png"]));
    assert!(e.contains("parts are the .exr files `render --tile`"), "{e}");
    assert!(!d.join("x.png").exists());
}

fn examples() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

/// PATH with the project's binaries first, as the recipes expect them.
fn path_with_binaries() -> String {
    let bin = Path::new(RENDER).parent().unwrap().to_string_lossy().into_owned();
    format!("{bin}:{}", std::env::var("PATH").unwrap_or_default())
}

/// The bytes of a full render of `s.nff` in `d` at 64x64, as `name`.
fn full_render(d: &Path, name: &str) -> Vec<u8> {
    ok(&run(RENDER, d, &["s.nff", "-o", name, "--width", "64", "--height", "64", "-q"]));
    std::fs::read(d.join(name)).unwrap()
}

#[test]
fn the_parallel_script_holds() {
    let Some(_) = program("parallel") else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    ok(&run(RENDER, d, &["s.nff", "-o", "full.png", "--width", "16", "--height", "256", "-q"]));
    let full = std::fs::read(d.join("full.png")).unwrap();
    // N left out, the binaries by relative paths (the script changes folder).
    std::fs::create_dir(d.join("sub")).unwrap();
    std::os::unix::fs::symlink(Path::new(RENDER).parent().unwrap(), d.join("sub/bin")).unwrap();
    let rel = |b: &str| format!("bin/{b}");
    let script = examples().join("render-parallel.sh");
    let o = Command::new("bash")
        .arg(&script)
        .args(["../s.nff", "out.png", "--width", "16", "--height", "256"])
        .env("RENDER", rel("render"))
        .env("NFFMERGE", rel("nffmerge"))
        .current_dir(d.join("sub"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read(d.join("sub/out.png")).unwrap(), full);
    // A failed merge keeps the parts and says where.
    let o = Command::new("bash")
        .arg(&script)
        .args(["s.nff", "x.png", "4", "--width", "64", "--height", "64"])
        .env("RENDER", RENDER)
        .env("NFFMERGE", "false")
        .current_dir(d)
        .output()
        .unwrap();
    let e = err(&o);
    let kept = e.split("the parts are kept in ").nth(1).expect(&e).trim();
    let parts = std::fs::read_dir(kept)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("part-"));
    assert_eq!(parts.count(), 4, "{e}");
    std::fs::remove_dir_all(kept).unwrap();
}

#[test]
fn the_slurm_script_renders_any_evenly_stepped_array() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    let full = full_render(d, "full.png");
    let path = path_with_binaries();
    let task = |id: u32, min: u32, step: u32, max: u32| {
        Command::new("bash")
            .arg(examples().join("render-array.sbatch"))
            .args(["s.nff", "parts", "--width", "64", "--height", "64"])
            .env("PATH", &path)
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "4")
            .env("SLURM_ARRAY_TASK_MIN", min.to_string())
            .env("SLURM_ARRAY_TASK_STEP", step.to_string())
            .env("SLURM_ARRAY_TASK_MAX", max.to_string())
            .current_dir(d)
            .output()
            .unwrap()
    };
    // --array=1-7:2, four tasks: tiles 0..3.
    for id in [1, 3, 5, 7] {
        ok(&task(id, 1, 2, 7));
    }
    ok(&run(
        NFFMERGE,
        d,
        &["parts/part-0.exr", "parts/part-1.exr", "parts/part-2.exr", "parts/part-3.exr", "-o", "m.png"],
    ));
    assert_eq!(std::fs::read(d.join("m.png")).unwrap(), full);
    // --array=1,5,9,20 (four tasks, not one stepped range): refused.
    let e = err(&task(5, 1, 1, 20));
    assert!(e.contains("must be one evenly stepped range"), "{e}");
}

#[test]
fn the_openjd_template_runs_locally() {
    let Some(openjd) = program("openjd") else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.nff"), SCENE).unwrap();
    let full = full_render(d, "full.png");
    let template = examples().join("render-tiles.openjd.yaml");
    let o = Command::new(&openjd)
        .arg("run")
        .arg(&template)
        .args(["--step", "Merge", "--run-dependencies"])
        .arg("-p")
        .arg(format!("Scene={}", d.join("s.nff").display()))
        .arg("-p")
        .arg(format!("Output={}", d.join("out.png").display()))
        .arg("-p")
        .arg(format!("PartsDir={}", d.join("parts").display()))
        .args(["-p", "Tiles=4", "-p", "RenderOptions=--width 64 --height 64"])
        .env("PATH", path_with_binaries())
        .current_dir(d)
        .output()
        .unwrap();
    let log = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success() && log.contains("Session ended successfully"), "{log}");
    assert_eq!(std::fs::read_dir(d.join("parts")).unwrap().count(), 4);
    assert_eq!(std::fs::read(d.join("out.png")).unwrap(), full);
}

#[test]
fn the_kubernetes_jobs_are_valid_and_their_command_renders_each_index() {
    let Some(validate) = program("kubernetes-validate") else { return };
    let manifests = ["render-tiles.k8s.yaml", "merge-tiles.k8s.yaml"].map(|m| examples().join(m));
    let o = Command::new(&validate).arg("--strict").args(&manifests).output().unwrap();
    let log = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success() && log.matches("passed").count() == 2, "{log}");
    // The pods' shell commands, run here with each completion index in a
    // folder standing for the volume.
    let python = validate.with_file_name("python");
    let command = |m: &Path| {
        let code = "import sys, yaml; c = yaml.safe_load(open(sys.argv[1]))['spec']['template']['spec']['containers'][0]; print(c['args'][0])";
        let o = Command::new(&python).args(["-c", code]).arg(m).output().unwrap();
        String::from_utf8(o.stdout).unwrap()
    };
    let (tiles, merge) = (command(&manifests[0]), command(&manifests[1]));
    assert!(tiles.contains("$JOB_COMPLETION_INDEX/16"), "{tiles}");
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Tall enough for 16 bands of 16 rows.
    std::fs::write(d.join("scene.nff"), SCENE.replace("resolution 48 40", "resolution 24 256")).unwrap();
    let path = path_with_binaries();
    for k in 0..16 {
        let o = Command::new("sh")
            .args(["-c", &tiles])
            .env("JOB_COMPLETION_INDEX", k.to_string())
            .env("PATH", &path)
            .current_dir(d)
            .output()
            .unwrap();
        ok(&o);
    }
    ok(&Command::new("sh").args(["-c", &merge]).env("PATH", &path).current_dir(d).output().unwrap());
    ok(&run(RENDER, d, &["scene.nff", "-o", "full.png", "-q"]));
    assert_eq!(std::fs::read(d.join("render.png")).unwrap(), std::fs::read(d.join("full.png")).unwrap());
}
