//! P3F through the binaries: rendered as the course meant (its camera,
//! directives, cube map, area lights, lens), checked by `render --check`,
//! recognised on standard input, and converted by `nffconvert`.

use std::path::Path;
use std::process::{Command, Output};

const RENDER: &str = env!("CARGO_BIN_EXE_render");
const CONVERT: &str = env!("CARGO_BIN_EXE_nffconvert");

fn run(bin: &str, args: &[&str], stdin: Option<&[u8]>) -> Output {
    use std::io::Write;
    let mut child = Command::new(bin)
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = child.stdin.take().unwrap();
    if let Some(input) = stdin {
        pipe.write_all(input).unwrap();
    }
    drop(pipe);
    child.wait_with_output().unwrap()
}

fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err
}

fn render(dir: &Path, scene: &str, name: &str, args: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec![scene, "-o", out.to_str().unwrap(), "-q"];
    all.extend(args);
    ok(&run(RENDER, &all, None));
    std::fs::read(out).unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Six one-colour faces, 4x4 texels, face `i` (in the course's order:
/// right, left, top, bottom, front, back) of red `40 i + 20`, green 100.
fn skybox(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    for (i, face) in ["right", "left", "top", "bottom", "front", "back"].iter().enumerate() {
        let img = image::RgbImage::from_pixel(4, 4, image::Rgb([40 * i as u8 + 20, 100, 0]));
        img.save(dir.join(format!("{face}.png"))).unwrap();
    }
}

fn rgb(png: &[u8]) -> image::RgbImage {
    image::load_from_memory(png).unwrap().to_rgb8()
}

/// A course scene with nothing P3F alone has: white specular colours, no
/// transmitter, point lights, a pinhole; a mesh, a box and a plane.
const PLAIN_P3F: &str = "bclr 0.1 0.2 0.3
v
from 3 2.5 4
at 0 0.3 0
up 0 1 0
angle 40
hither 0.01
resolution 40 30
aperture 0
focal 1
l 4 6 2 0.7 0.7 0.7
l -3 5 4 0.5 0.4 0.3
f 0.8 0.3 0.2 0.7 1 1 1 0.3 30 0 1
s 0 0.5 0 0.5
box 0.8 0 -0.6 1.4 0.6 0
f 0.4 0.4 0.45 0.9 1 1 1 0 1 0 1
pl 0 0 0 0 0 -1 1 0 0
mesh 4 2
-1.5 0 1
-0.5 0 1
-0.5 1 1
-1.5 1 1
1 2 3
-4 -2 -1
";

/// [`PLAIN_P3F`] converted by hand: NFF's `angle` spans the outer pixel
/// centres of the smaller side, P3F's the height edge to edge.
fn hand_converted() -> String {
    let angle = 2.0 * (29.0f64 / 30.0 * 20f64.to_radians().tan()).atan().to_degrees();
    format!(
        "b 0.1 0.2 0.3
v
from 3 2.5 4
at 0 0.3 0
up 0 1 0
angle {angle}
hither 0.01
resolution 40 30
l 4 6 2 0.7 0.7 0.7
l -3 5 4 0.5 0.4 0.3
f 0.8 0.3 0.2 0.7 0.3 30 0 1
s 0 0.5 0 0.5
aabb 0.8 0 -0.6 1.4 0.6 0
f 0.4 0.4 0.45 0.9 0 1 0 1
pl 0 0 0 0 0 -1 1 0 0
p 3
-1.5 0 1
-0.5 0 1
-0.5 1 1
p 3
-1.5 0 1
-0.5 1 1
-1.5 1 1
"
    )
}

#[test]
fn a_p3f_scene_and_its_hand_converted_nff_render_byte_identically() {
    let dir = tempfile::tempdir().unwrap();
    let p3f = write(dir.path(), "plain.p3f", PLAIN_P3F);
    let nff = write(dir.path(), "plain.nff", &hand_converted());
    for args in [&["--spp", "4"][..], &["--spp", "1", "--no-packets"]] {
        let a = render(dir.path(), &p3f, "a", args);
        let b = render(dir.path(), &nff, "b", args);
        assert!(a == b, "{args:?}: the P3F and its NFF differ");
    }
    // And nffconvert writes an equivalent NFF itself.
    let converted = dir.path().join("converted.nff");
    ok(&run(CONVERT, &[&p3f, "-o", converted.to_str().unwrap()], None));
    let c = render(dir.path(), converted.to_str().unwrap(), "c", &["--spp", "4"]);
    assert!(c == render(dir.path(), &p3f, "a", &["--spp", "4"]));
}

#[test]
fn the_files_spp_and_accel_are_defaults_the_flags_override() {
    let dir = tempfile::tempdir().unwrap();
    let bare = write(dir.path(), "bare.p3f", PLAIN_P3F);
    let with = write(dir.path(), "with.p3f", &format!("spp 4\naccel 1\n{PLAIN_P3F}"));
    let stats = |scene: &str, args: &[&str]| {
        let out = dir.path().join("s.png");
        let mut all = vec![scene, "-o", out.to_str().unwrap(), "--stats"];
        all.extend(args);
        let o = run(RENDER, &all, None);
        ok(&o);
        (String::from_utf8_lossy(&o.stdout).into_owned(), std::fs::read(out).unwrap())
    };
    let (file, image) = stats(&with, &[]);
    assert!(file.contains("4 spp") && file.contains("grid"), "{file}");
    assert_eq!(image, render(dir.path(), &bare, "b", &["--spp", "4"]));
    let (flags, image) = stats(&with, &["--spp", "1", "--accel", "bvh"]);
    assert!(flags.contains("1 ray through each pixel centre") && flags.contains("BVH"), "{flags}");
    assert_eq!(image, render(dir.path(), &bare, "c", &[]));
    // `accel 0`, the course template's "none", keeps the BVH, and says so.
    let zero = write(dir.path(), "zero.p3f", &format!("accel 0\nspp 0\n{PLAIN_P3F}"));
    let o = run(RENDER, &[&zero, "-o", dir.path().join("z.png").to_str().unwrap(), "--stats"], None);
    assert!(ok(&o).contains("`accel 0`") && String::from_utf8_lossy(&o.stdout).contains("BVH"));
}

/// Looking along +z from the centre of a mirror ball's room: the eye
/// rays that miss see the front face, the ball's centre shows the back.
const SKY: &str = "env sky
v
from 0 0 -4
at 0 0 0
up 0 1 0
angle 30
hither 0.01
resolution 9 9
aperture 0
focal 1
f 1 1 1 0 1 1 1 1 1 0 1
s 0 0 0 0.4
";

#[test]
fn escaping_rays_see_the_cube_map_eye_and_reflected() {
    let dir = tempfile::tempdir().unwrap();
    skybox(&dir.path().join("sky"));
    let scene = write(dir.path(), "sky.p3f", SKY);
    for args in [&[][..], &["--no-packets"]] {
        let img = rgb(&render(dir.path(), &scene, "sky", args));
        assert_eq!(img.get_pixel(0, 0).0, [40 * 4 + 20, 100, 0], "the corner sees the front");
        assert_eq!(img.get_pixel(4, 4).0, [40 * 5 + 20, 100, 0], "the mirror's centre sees the back");
    }
}

#[test]
fn a_missing_face_or_a_folder_outside_the_scenes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    skybox(&scenes.join("sky"));
    std::fs::remove_file(scenes.join("sky/top.png")).unwrap();
    let scene = write(&scenes, "sky.p3f", SKY);
    let out = dir.path().join("out.png");
    let o = run(RENDER, &[&scene, "-o", out.to_str().unwrap()], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("no `top` image") && err.contains("sky/top.png"), "{err}");
    assert!(!out.exists(), "nothing is written");
    // A cube map through a link that leaves the scene's folder.
    skybox(&dir.path().join("elsewhere"));
    std::fs::remove_dir_all(scenes.join("sky")).unwrap();
    std::os::unix::fs::symlink(dir.path().join("elsewhere"), scenes.join("sky")).unwrap();
    let o = run(RENDER, &[&scene, "-o", out.to_str().unwrap()], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--allow-outside-paths"), "{err}");
    ok(&run(RENDER, &[&scene, "-o", out.to_str().unwrap(), "--allow-outside-paths", "-q"], None));
    // `env ../x` says so before any link is followed.
    let up = write(&scenes, "up.p3f", &SKY.replace("env sky", "env ../elsewhere"));
    let o = run(RENDER, &[&up, "-o", out.to_str().unwrap()], None);
    assert!(String::from_utf8_lossy(&o.stderr).contains("leaves"), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn standard_input_is_recognised_as_p3f() {
    let dir = tempfile::tempdir().unwrap();
    let file = render(dir.path(), &write(dir.path(), "plain.p3f", PLAIN_P3F), "f", &[]);
    let out = dir.path().join("stdin.png");
    ok(&run(RENDER, &["-", "-o", out.to_str().unwrap(), "-q"], Some(PLAIN_P3F.as_bytes())));
    assert_eq!(std::fs::read(out).unwrap(), file);
    // Told it is NFF, the same text is refused, naming the first P3F word.
    let o = run(RENDER, &["-", "--dialect", "nff", "-o", "x.png"], Some(PLAIN_P3F.as_bytes()));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("<stdin>:1:1") && err.contains("--dialect p3f"), "{err}");
}

#[test]
fn check_knows_p3f_its_extensions_and_its_errors() {
    let dir = tempfile::tempdir().unwrap();
    let extended =
        PLAIN_P3F.replace("f 0.8 0.3 0.2 0.7 1 1 1 0.3 30 0 1", "f 0.8 0.3 0.2 0.7 1 1 1 0.3 30 0 1 0 0 0");
    let scene = write(dir.path(), "ext.p3f", &extended);
    let o = run(RENDER, &["--check", &scene], None);
    let err = ok(&o);
    assert!(err.contains("ext.p3f:13:36") && err.contains("3 values after the course's"), "{err}");
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains("ext.p3f: ok, P3F, view 40x30"), "{summary}");
    let all = everything(dir.path());
    let o = run(RENDER, &["--check", &all], None);
    ok(&o);
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains("P3F (env sky, lens, 1 area light, spp 4)"), "{summary}");
    let strict = run(RENDER, &["--check", "--strict", &scene], None);
    assert!(!strict.status.success());
    let broken = write(dir.path(), "broken.p3f", &PLAIN_P3F.replace("1 2 3\n", "1 2 9\n"));
    let o = run(RENDER, &["--check", &broken], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("broken.p3f:23:5") && err.contains("past the mesh's 4"),
        "{err}"
    );
}

/// Glass, a coloured metal, an area light, a lens and a cube map at once.
fn everything(dir: &Path) -> String {
    skybox(&dir.join("sky"));
    write(
        dir,
        "all.p3f",
        "spp 4
env sky
v
from 0 1.5 -4
at 0 0.5 0
up 0 1 0
angle 40
hither 0.01
resolution 24 20
aperture 20
focal 0.8
al 0 4 0  0 0 0  1.5 0.8  1 1 1
f 1 1 1 0.1 1 1 1 0.2 50 0.9 1.5
s -0.6 0.5 0 0.5
f 0.5 0.4 0.5 0.1 1.0 0.71 0.29 0.9 200 0 1
s 0.7 0.5 0.3 0.5
f 0.6 0.6 0.6 0.8 1 1 1 0 1 0 1
p 4
-4 0 -4
-4 0 4
4 0 4
4 0 -4
",
    )
}

#[test]
fn p3f_images_do_not_depend_on_packets_threads_or_accelerator() {
    let dir = tempfile::tempdir().unwrap();
    let scene = everything(dir.path());
    let base = render(dir.path(), &scene, "a", &[]);
    for args in [
        &["--no-packets"][..],
        &["--threads", "1"],
        &["--accel", "grid"],
        &["--accel", "none", "--threads", "2"],
    ] {
        assert!(base == render(dir.path(), &scene, "b", args), "{args:?} changed the image");
    }
}

#[test]
fn area_lights_lens_and_fresnel_each_change_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let scene = everything(dir.path());
    let text = std::fs::read_to_string(&scene).unwrap();
    let base = render(dir.path(), &scene, "a", &[]);
    for (what, from, to) in [
        ("the area light", "al 0 4 0  0 0 0  1.5 0.8  1 1 1", "l 0 4 0 1 1 1"),
        ("the lens", "aperture 20", "aperture 0"),
        ("the specular colour", "1.0 0.71 0.29 0.9", "1 1 1 0.9"),
    ] {
        let other = write(dir.path(), "other.p3f", &text.replace(from, to));
        assert!(base != render(dir.path(), &other, "b", &[]), "{what} changed nothing");
    }
    // The lens given on the command line overrides the file's.
    let pinhole = write(dir.path(), "pin.p3f", &text.replace("aperture 20", "aperture 0"));
    assert!(render(dir.path(), &scene, "c", &["--aperture", "0"]) == render(dir.path(), &pinhole, "d", &[]));
    // NFF glass keeps its classic weights unless --fresnel.
    let nff = dir.path().join("all.nff");
    ok(&run(CONVERT, &[&scene, "-o", nff.to_str().unwrap(), "-q"], None));
    let nff = nff.to_str().unwrap();
    assert!(render(dir.path(), nff, "e", &[]) != render(dir.path(), nff, "f", &["--fresnel"]));
}

#[test]
fn nffconvert_says_what_nff_cannot_hold_and_guards_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let scene = everything(dir.path());
    let out = dir.path().join("all.nff");
    let err = ok(&run(CONVERT, &[&scene, "-o", out.to_str().unwrap()], None));
    for needle in
        ["the lens", "render --aperture", "specular colour", "Fresnel", "area light", "env sky", "--spp 4"]
    {
        assert!(err.contains(needle), "`{needle}` not in:\n{err}");
    }
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("v\n") && !text.contains("bclr") && !text.contains("al "), "{text}");
    // Back to P3F on standard output.
    let o = run(CONVERT, &[out.to_str().unwrap(), "--to", "p3f"], None);
    let back = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(ok(&o).contains("classic weighting") && back.contains("angle 40\n"), "{back}");
    // Refusals: the input as output, no language, standard output unnamed.
    let o = run(CONVERT, &[&scene, "-o", &scene], None);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("input"));
    let o = run(CONVERT, &[&scene, "-o", dir.path().join("x.txt").to_str().unwrap()], None);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--to"));
    assert!(!dir.path().join("x.txt").exists());
    let o = run(CONVERT, &[&scene], None);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--to"));
}

#[test]
fn the_documented_course_scene_and_its_cube_map_are_reproduced() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().join("scenes/p3f");
    // make-sky.sh, run on a copy, renders the committed faces bit for bit.
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root.join("make-sky.sh"), dir.path().join("make-sky.sh")).unwrap();
    let o = Command::new("bash")
        .arg(dir.path().join("make-sky.sh"))
        .arg("64")
        .env("RENDER", RENDER)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for face in ["right", "left", "top", "bottom", "front", "back"] {
        let made = rgb(&std::fs::read(dir.path().join(format!("sky/{face}.png"))).unwrap());
        let kept = image::open(root.join(format!("sky/{face}.png"))).unwrap().to_rgb8();
        let kept = image::imageops::resize(&kept, 64, 64, image::imageops::FilterType::Triangle);
        let diff: f64 =
            made.pixels().zip(kept.pixels()).map(|(a, b)| (a[0] as f64 - b[0] as f64).abs()).sum();
        assert!(diff / 4096.0 < 12.0, "{face}: the committed face is not this scene's ({})", diff / 4096.0);
    }
    // The course scene renders with its sky above the floor.
    let scene = root.join("course.p3f");
    let img = rgb(&render(
        dir.path(),
        scene.to_str().unwrap(),
        "course",
        &["--width", "64", "--height", "48", "--spp", "1"],
    ));
    let sky = *img.get_pixel(2, 0);
    assert_eq!(sky, image::Rgb([115, 158, 235]), "the cube map's sky, not the scene's bclr 0.1 0.1 0.1");
}
