//! `nffbench` runs end to end (small: 16x16 images, one run, sphereflake
//! level 2, no POV-Ray or Embree) and prints every table it promises.

use std::process::Command;

#[test]
fn benchmark_prints_its_tables() {
    let out = Command::new(env!("CARGO_BIN_EXE_nffbench"))
        .args(["--size", "16", "--runs", "1", "--flake-level", "2"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("nffbench runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}\n{}", stdout, String::from_utf8_lossy(&out.stderr));
    for row in [
        "| measure | balls_s4 | mount_s7 |",
        "| eye rays, packets of 4x4",
        "| Whitted 16 spp, s (Mrays/s per thread) |",
        "| render --check mount_s7 (2.7 MB) |",
        "| render --version |",
        "| 2 | 0.0 |",
        "| prepare ms | of which BVH build ms | BVH SAH cost |",
        "Level 2 against level 2: whole process",
    ] {
        assert!(stdout.contains(row), "no `{row}` in:\n{stdout}");
    }
    // The level-2 row gives the BVH's build time and a SAH cost of at
    // least the root's one step.
    let level2 = stdout.lines().find(|l| l.starts_with("| 2 |")).unwrap_or_default();
    let cells: Vec<&str> = level2.split('|').map(str::trim).collect();
    let sah: f64 = cells.get(6).and_then(|c| c.parse().ok()).unwrap_or(0.0);
    assert!(sah > 1.0 && sah < 100.0 && cells.get(5).is_some_and(|c| c.parse::<f64>().is_ok()), "{level2}");
    // Every row of the check table holds two times in milliseconds.
    let check = stdout.lines().find(|l| l.starts_with("| render --check")).unwrap_or_default();
    let times: Vec<f64> = check.split('|').filter_map(|c| c.trim().parse().ok()).collect();
    assert!(times.len() == 2 && times.iter().all(|&t| t > 0.0 && t < 10_000.0), "{check}");
}

/// `raybench --all` traces the same eye rays one by one and as packets:
/// both find the same number of hits, and every rate is a number.
#[test]
fn raybench_all_measures_single_rays_and_packets_alike() {
    let scene = format!("{}/../scenes/spd/balls_s1.nff", env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(env!("CARGO_BIN_EXE_raybench"))
        .args([scene.as_str(), "--size", "32", "--runs", "1", "--all"])
        .output()
        .expect("raybench runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}\n{}", stdout, String::from_utf8_lossy(&out.stderr));
    // "eye R (H hit), shadow R (N rays), eye packets R (H hit), shadow packets R"
    let figures: Vec<f64> = stdout
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter(|w| w.contains(|c: char| c.is_ascii_digit()))
        .filter_map(|w| w.parse().ok())
        .collect();
    let n = figures.len();
    assert!(n >= 7, "{stdout}");
    let [eye, hits, shadow, shadow_rays, packets, packet_hits, shadow_packets] =
        <[f64; 7]>::try_from(&figures[n - 7..]).unwrap();
    assert!(hits > 0.0 && hits == packet_hits && hits <= 1024.0, "{stdout}");
    assert!(shadow_rays > 0.0, "{stdout}");
    assert!([eye, shadow, packets, shadow_packets].iter().all(|&r| r > 0.0 && r.is_finite()), "{stdout}");
}
