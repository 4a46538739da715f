//! `render --device gpu` against the CPU, through the binary: every SPD
//! scene at 1 and 16 spp, soft shadows, the lens, every sampler and filter,
//! a P3F scene with its cube map, and parts of the image, each agreeing
//! within floating-point differences (mean FLIP at most 0.005, at most 0.1%
//! of pixels off by more than 2/255). CI runs these on lavapipe, Mesa's
//! software Vulkan driver, which `scripts/install-test-tools.sh` installs;
//! with NFFKIT_TEST_TOOLS=required a missing driver fails them.

use nffkit_tools::qa::golden::read_png;
use nffkit_tools::qa::metrics::agreement;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const RENDER: &str = env!("CARGO_BIN_EXE_render");

fn scenes(dir: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes").join(dir)
}

/// Whether a GPU adapter (lavapipe will do) answers; a missing one fails
/// when NFFKIT_TEST_TOOLS=required, else skips the test, saying so.
fn gpu_available() -> bool {
    static AVAILABLE: OnceLock<bool> = OnceLock::new();
    *AVAILABLE.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("probe.png");
        let o = Command::new(RENDER)
            .args(["--device", "gpu", "--width", "8", "--height", "8", "-q", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        if o.status.success() {
            return true;
        }
        assert!(stderr.contains("no GPU adapter"), "render --device gpu failed: {stderr}");
        let required = std::env::var("NFFKIT_TEST_TOOLS").is_ok_and(|v| v == "required");
        assert!(!required, "no GPU adapter (scripts/install-test-tools.sh installs lavapipe): {stderr}");
        eprintln!("skipped: no GPU adapter (scripts/install-test-tools.sh installs lavapipe)");
        false
    })
}

/// Render `scene` with `args` on `device` to a PNG in `dir`.
fn render(dir: &Path, scene: &Path, device: &str, args: &[&str]) -> nffkit_formats::image_io::RgbImage {
    let out = dir.join(format!("{device}.png"));
    let o = Command::new(RENDER)
        .arg(scene)
        .args(["--device", device, "-q", "-o"])
        .arg(&out)
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{} {args:?} on the {device}: {}",
        scene.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    read_png(&out).unwrap()
}

/// The GPU's render of `scene` agrees with the CPU's within float.
fn agrees(scene: &Path, args: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let cpu = render(dir.path(), scene, "cpu", args);
    let gpu = render(dir.path(), scene, "gpu", args);
    let a = agreement(&cpu, &gpu);
    eprintln!("{} {args:?}: {a}", scene.display());
    assert!(a.within_float(), "{} {args:?}: {a}", scene.display());
}

#[test]
fn every_spd_scene_renders_on_the_gpu_as_on_the_cpu() {
    if !gpu_available() {
        return;
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes("spd"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "nff"))
        .collect();
    files.sort();
    assert!(files.len() >= 14, "the SPD scenes: {files:?}");
    // 16 spp smaller: lavapipe traces on the CPU, one pixel per workgroup.
    for file in &files {
        agrees(file, &["--width", "64", "--height", "64", "--spp", "1"]);
        agrees(file, &["--width", "32", "--height", "32", "--spp", "16"]);
    }
}

#[test]
fn soft_shadows_lens_samplers_and_filters_agree() {
    if !gpu_available() {
        return;
    }
    let balls = scenes("spd").join("balls_s2.nff");
    let size = ["--width", "48", "--height", "48"];
    let settings: &[&[&str]] = &[
        &["--spp", "4", "--light-size", "0.4"],
        &["--spp", "4", "--light-size", "0.4", "--light-shape", "disk"],
        &["--spp", "4", "--aperture", "0.05", "--focus", "2.5"],
        &["--spp", "1", "--light-size", "0.4", "--depth", "2", "--min-weight", "0.3"],
        &["--spp", "4", "--sampler", "random", "--filter", "gaussian"],
        &["--spp", "4", "--sampler", "regular", "--filter", "tent"],
        &["--spp", "4", "--sampler", "jittered", "--filter", "mitchell"],
        &["--spp", "5", "--sampler", "n-rooks"],
        &["--spp", "9", "--sampler", "cmj", "--seed", "7"],
        &["--spp", "4", "--sampler", "hammersley"],
        &["--spp", "6", "--sampler", "sobol", "--fresnel"],
    ];
    for s in settings {
        agrees(&balls, &[&size[..], s].concat());
    }
}

#[test]
fn a_p3f_scene_with_its_cube_map_and_area_light_agrees() {
    if !gpu_available() {
        return;
    }
    agrees(&scenes("p3f").join("course.p3f"), &["--width", "48", "--height", "36", "--spp", "4"]);
}

#[test]
fn a_part_of_the_image_is_those_pixels_of_the_whole() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes("spd").join("mount_s1.nff");
    let size = ["--width", "40", "--height", "40", "--spp", "4"];
    let whole = render(dir.path(), &scene, "gpu", &size);
    let part = render(dir.path(), &scene, "gpu", &[&size[..], &["--pixel-bounds", "8,30,5,21"]].concat());
    assert_eq!((part.width, part.height), (22, 16));
    for y in 0..16 {
        for x in 0..22 {
            let p = part.pixels[(y * 22 + x) as usize];
            let w = whole.pixels[((y + 5) * 40 + x + 8) as usize];
            assert_eq!(p, w, "pixel {x},{y} of the part");
        }
    }
}

#[test]
fn what_the_gpu_does_not_do_is_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    for (flags, says) in [(&["--aov-cost", "c.png"][..], "--aov-cost"), (&["--spd-stats"][..], "--spd-stats")]
    {
        let o = Command::new(RENDER)
            .current_dir(dir.path())
            .args(["--device", "gpu", "-o"])
            .arg(&out)
            .args(flags)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && stderr.contains(says) && stderr.contains("--device gpu"), "{stderr}");
        assert!(!out.exists());
    }
}

#[test]
fn the_benchmark_measures_the_gpu_beside_the_cpu() {
    if !gpu_available() {
        return;
    }
    let out = Command::new(env!("CARGO_BIN_EXE_nffbench"))
        .args(["--size", "16", "--runs", "1", "--flake-level", "2", "--device", "gpu"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    for label in
        ["| GPU eye rays, Mrays/s (", "| GPU Whitted 16 spp, s (Mrays/s) |", "| GPU 16 spp against the CPU's"]
    {
        let row = stdout
            .lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("no `{label}` in:\n{stdout}"));
        // Two scenes, each with a positive figure.
        let figures: Vec<f64> = row
            .split('|')
            .skip(2)
            .filter_map(|c| c.trim().split([' ', 'x']).next().and_then(|v| v.parse().ok()))
            .collect();
        assert!(figures.len() == 2 && figures.iter().all(|&v| v > 0.0), "{row}");
    }
}
