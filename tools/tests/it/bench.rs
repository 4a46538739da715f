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
        "| scene | primitives | ours, Mrays/s | Embree rtcIntersect1, Mrays/s | ours / Embree |",
    ] {
        assert!(stdout.contains(row), "no `{row}` in:\n{stdout}");
    }
    // Single eye rays on the other scenes, written by the generators: each
    // row a scene of primitives, a rate and some hits of the 256 rays, and
    // no Embree.
    for scene in ["teapot_s12", "gears_s4", "sphereflake level 2"] {
        let row = stdout.lines().find(|l| l.starts_with(&format!("| {scene} |"))).unwrap_or_default();
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let primitives: u64 = cells.get(2).and_then(|c| c.parse().ok()).unwrap_or(0);
        let figures: Vec<f64> =
            cells.get(3).map_or(vec![], |c| c.split([' ', '(']).filter_map(|w| w.parse().ok()).collect());
        assert!(primitives > 50 && cells.get(4..6) == Some(&["-", "-"][..]), "{row}");
        assert!(figures.len() == 2 && figures[0] > 0.0 && figures[1] > 0.0 && figures[1] <= 256.0, "{row}");
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

/// With `--shared`, nffbench runs the folder's `bench/embree-rays` in turn
/// with its own measurements, round by round, and each ratio is ours over
/// Embree's. Here a stand-in script reports fixed rates and build times,
/// and logs its calls.
#[test]
fn embree_runs_in_turn_with_ours() {
    use std::os::unix::fs::PermissionsExt;
    let shared = tempfile::tempdir().unwrap();
    let bench = shared.path().join("bench");
    std::fs::create_dir(&bench).unwrap();
    let log = shared.path().join("calls.log");
    let script = bench.join("embree-rays");
    std::fs::write(
        &script,
        format!(
            r#"#!/bin/sh
echo "$*" >> '{}'
case " $* " in
  *" --packet 8 "*) r=8.0 ;;
  *" --packet 16 "*) r=16.0 ;;
  *" --shadow "*) r=3.0 ;;
  *) r=2.0 ;;
esac
echo "build: first 4.00 ms (includes one-off start-up); 5 rebuilds: median 2.00 ms [1.90-2.10]"
echo "RESULT stand-in: primary, single, 1 spp, 1 thread, 16x16, quality medium: $r Mrays/s median [$r-$r] of 3"
"#,
            log.display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nffbench"))
        .args(["--size", "16", "--runs", "3", "--flake-level", "2", "--shared"])
        .arg(shared.path())
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("nffbench runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}\n{}", stdout, String::from_utf8_lossy(&out.stderr));
    // The cells of the row whose label starts with `label`.
    let cells = |label: &str| -> Vec<String> {
        let line = stdout.lines().find(|l| l.starts_with(&format!("| {label}"))).unwrap_or_default();
        line.split('|').skip(2).map(|c| c.trim().to_string()).filter(|c| !c.is_empty()).collect()
    };
    assert_eq!(cells("Embree rtcIntersect1, Mrays/s"), ["2.00", "2.00"], "{stdout}");
    assert_eq!(cells("Embree rtcIntersect16"), ["16.00", "16.00"], "{stdout}");
    assert_eq!(cells("Embree eye+shadow (single)"), ["3.00", "3.00"], "{stdout}");
    // Embree's rate is the same every round, so the median ratio is our
    // median rate over it, and the printed median rates give it back (to
    // the printing's rounding: half a hundredth on each figure).
    let first = |c: &str| c.split([' ', 'x']).next().unwrap().parse::<f64>().unwrap();
    let ours = cells("eye rays, single, Mrays/s per thread");
    let ratios = cells("eye rays: our single / Embree single");
    for (o, r) in ours.iter().zip(&ratios) {
        assert!((first(o) / 2.0 - first(r)).abs() < 0.008, "{o} against {r}:\n{stdout}");
        assert!(r.contains('(') && r.contains('-'), "three rounds show their range: {r}");
    }
    let packets = cells("eye rays, packets of 4x4");
    let best = cells("eye rays: our packets / Embree's best packets");
    for (o, r) in packets.iter().zip(&best) {
        assert!((first(o) / 16.0 - first(r)).abs() < 0.008, "{o} against {r}:\n{stdout}");
    }
    // The other scenes' single rays: Embree's rate each round, ours over it.
    for scene in ["teapot_s12", "gears_s4", "sphereflake level 2"] {
        let row = cells(&format!("{scene} |"));
        assert!(row.len() == 4 && row[2] == "2.00", "{scene}: {row:?}\n{stdout}");
        assert!((first(&row[1]) / 2.0 - first(&row[3])).abs() < 0.008, "{row:?}");
        assert!(row[3].contains('('), "three rounds show their range: {row:?}");
    }
    let build = cells("our time / Embree's rebuild time, run by run");
    assert!(build.len() == 1 && first(&build[0]) > 0.0, "{stdout}");
    assert!(stdout.contains("| Embree, median of 5 rebuilds, median | 2.0 |"), "{stdout}");
    // Per scene three rounds of three runs and one shadow run; three
    // builds; three rounds of single rays on each of the other scenes.
    let calls = std::fs::read_to_string(&log).unwrap();
    assert_eq!(calls.lines().count(), 2 * (3 * 3 + 1) + 3 + 3 * 3, "{calls}");
    assert_eq!(calls.lines().filter(|l| l.contains("--verbose")).count(), 3, "{calls}");
}
