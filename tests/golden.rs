//! Golden-image regression: every case of `scenes/catalogue.toml` renders,
//! identically on one and two threads, and matches its golden image. On a
//! mismatch the actual, expected and difference images are written under
//! `target/golden/` and named in the message.
//!
//! Regenerate goldens after an intended change with
//! `cargo run --release --bin golden -- update [NAME...]`.

use nffkit_formats::image_io::RgbImage;
use nffkit_tools::qa::golden::{
    self, check_case, compare, load_catalogue, render_case, write_failure_images,
};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    golden::find_scenes_dir(Path::new(env!("CARGO_MANIFEST_DIR")), "").unwrap()
}

fn shown(p: &Option<PathBuf>) -> String {
    p.as_ref().map_or("(none)".into(), |p| p.display().to_string())
}

fn out_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target/golden"))
}

#[test]
fn every_case_matches_its_golden_image() {
    let scenes = scenes_dir();
    let catalogue = load_catalogue(&scenes).unwrap();
    let mut failures = Vec::new();
    for case in &catalogue.case {
        let checked = check_case(case, &scenes, 2)
            .unwrap_or_else(|e| panic!("case {} failed to render: {e:#}", case.name));
        if let Some(why) = &checked.failure {
            let images = write_failure_images(&checked, &out_dir()).unwrap();
            failures.push(format!(
                "{}: {why}\n  actual:     {}\n  expected:   {}\n  difference: {}\n  FLIP error: {}",
                case.name,
                images.actual.display(),
                shown(&images.expected),
                shown(&images.diff),
                shown(&images.flip)
            ));
        }
    }
    assert!(failures.is_empty(), "{} golden cases failed:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn every_case_renders_identically_on_one_and_two_threads() {
    let scenes = scenes_dir();
    for case in &load_catalogue(&scenes).unwrap().case {
        let one = render_case(case, &scenes, 1).unwrap();
        let two = render_case(case, &scenes, 2).unwrap();
        assert!(one == two, "case {} depends on the thread count", case.name);
    }
}

#[test]
fn every_golden_is_used_and_none_is_missing() {
    let scenes = scenes_dir();
    let used: BTreeSet<String> =
        load_catalogue(&scenes).unwrap().case.iter().map(|c| format!("{}.png", c.golden_name())).collect();
    let present: BTreeSet<String> = std::fs::read_dir(scenes.join("golden"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let missing: Vec<_> = used.difference(&present).collect();
    let orphans: Vec<_> = present.difference(&used).collect();
    assert!(missing.is_empty(), "goldens missing: {missing:?}");
    assert!(orphans.is_empty(), "goldens no case uses: {orphans:?}");
}

fn shifted(img: &RgbImage) -> RgbImage {
    let mut out = img.clone();
    for y in 0..img.height {
        for x in 1..img.width {
            out.pixels[(y * img.width + x) as usize] = img.pixels[(y * img.width + x - 1) as usize];
        }
    }
    out
}

fn case_named(name: &str) -> golden::Case {
    load_catalogue(&scenes_dir()).unwrap().case.into_iter().find(|c| c.name == name).unwrap()
}

#[test]
fn the_comparator_passes_identical_and_fails_perturbed_images() {
    let scenes = scenes_dir();
    let case = case_named("balls2-bvh");
    let img = render_case(&case, &scenes, 2).unwrap();
    let (same, _) = compare(&img, &img);
    assert_eq!((same.bad, same.flip), (0.0, 0.0));
    assert!(same.failure(&case).is_none());
    // Shifted one pixel to the right: edges move, the check must fail.
    let (d, _) = compare(&shifted(&img), &img);
    assert!(d.failure(&case).is_some(), "one-pixel shift passed: {d:?}");
    // The sphere material 5% darker: the check must fail, and on FLIP
    // alone (few pixels move by more than 8/255).
    let dir = tempfile_dir();
    let mut scene = golden::scene_of(&case, &scenes).unwrap();
    let last = scene.materials.len() - 1;
    scene.materials[last].color *= 0.95;
    let path = dir.join("darker.nff");
    std::fs::write(&path, nffkit_formats::nff::write(&scene, Vec::new()).unwrap()).unwrap();
    let darker_case =
        golden::Case { source: golden::Source::File(path.to_string_lossy().into_owned()), ..case.clone() };
    let darker = render_case(&darker_case, &scenes, 2).unwrap();
    let (d, _) = compare(&darker, &img);
    assert!(d.failure(&case).is_some(), "5% colour change passed: {d:?}");
    let flip_only = golden::Case { max_bad: Some(1.0), ..case.clone() };
    assert!(d.failure(&flip_only).is_some(), "FLIP alone missed a 5% colour change: {d:?}");
}

fn tempfile_dir() -> PathBuf {
    let dir = out_dir().join("perturbed");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
