//! Parts of an image for render farms, and merging them back.
//!
//! A part is an OpenEXR file whose data window is the part's pixels inside
//! the full image's display window, in linear 32-bit float, with metadata:
//! the digest of the parsed scene (SHA-256 of the scene as the writer prints
//! it, so reformatting or re-commenting the file does not matter), every
//! setting that changes pixels ([`pixel_settings`]), and the part's ray
//! counters. Because each pixel is a pure function of its coordinates and
//! the settings, the merged image is the same, byte for byte, as one full
//! render; merge refuses parts that differ in any of those settings and
//! names it.

use anyhow::{bail, Context, Result};
use exr::prelude::{
    read_first_rgba_layer_from_file, AttributeValue, IntegerBounds, LayerAttributes, Text, Vec2,
};
use nffkit_formats::image_io::{self, RgbImage};
use nffkit_formats::{nff, Scene};
use nffkit_tracer::camera::Camera;
use nffkit_tracer::prepare::PrepareOptions;
use nffkit_tracer::render::{PixelWindow, RenderSettings, ShadeSettings};
use nffkit_tracer::sampling::Sampler;
use nffkit_tracer::stats::Counters;
use sha2::{Digest, Sha256};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const DIGEST: &str = "nffkit.sceneDigest";
const SETTINGS: &str = "nffkit.settings";
const COUNTERS: &str = "nffkit.counters";
const PART_DIGEST: &str = "nffkit.partDigest";

/// SHA-256 of the scene as the NFF writer prints it, in hex.
pub fn scene_digest(scene: &Scene) -> String {
    let text = nff::write(scene, Vec::new()).unwrap_or_default();
    hex(&Sha256::digest(&text))
}

/// Every setting that changes pixels, by name (the `render` flag that sets
/// it), with its value, in a fixed order.
///
/// The settings types are destructured whole, so a new field does not
/// compile until it is listed here or said not to change pixels. Those
/// that do not: how the work is done (thread count, packets, shadow cache,
/// the accelerator: all of them find the same hit, ties broken by
/// primitive id, so none changes a pixel), what else is recorded (the cost
/// image) and which part is rendered (the window).
pub fn pixel_settings(
    settings: &RenderSettings,
    prepare: &PrepareOptions,
    camera: &Camera,
) -> Vec<(&'static str, String)> {
    let RenderSettings {
        sampler,
        centre_single_sample: _, // in `pixel-centre`, with the sample count and the lens
        filter,
        shade,
        cost: _,
        shadow_cache: _,
        packets: _,
        row_stride,
        window: _,
    } = settings;
    let ShadeSettings { max_depth, light_size, light_shape, min_weight, spd } = shade;
    // (The sampler's grid side follows from its count.)
    let Sampler { kind, spp, seed, .. } = sampler;
    let PrepareOptions {
        width: _, // in `size`, with the file's resolution
        height: _,
        one_sided,
        aperture,
        focus,
        fresnel,
        accel: _,
        ambient,
    } = prepare;
    // `None`: the scene file's lens, which its digest covers.
    let or_scene = |v: &Option<f32>| v.map_or("scene".to_string(), |v| v.to_string());
    let (w, h) = camera.resolution();
    vec![
        ("size", format!("{w}x{h}")),
        ("depth", max_depth.to_string()),
        ("spp", spp.to_string()),
        ("sampler", kind.to_string()),
        ("seed", seed.to_string()),
        ("pixel-centre", settings.pixel_centre_only(camera).to_string()),
        ("filter", filter.to_string()),
        ("light-size", light_size.to_string()),
        ("light-shape", light_shape.to_string()),
        ("min-weight", min_weight.to_string()),
        ("spd-stats", spd.to_string()),
        ("row-stride", row_stride.to_string()),
        ("aperture", or_scene(aperture)),
        ("focus", or_scene(focus)),
        ("fresnel", fresnel.to_string()),
        ("one-sided", one_sided.to_string()),
        ("ambient", ambient.to_string()),
    ]
}

/// [`pixel_settings`] as one line, `name=value` separated by spaces, as a
/// part stores it.
pub fn settings_signature(settings: &RenderSettings, prepare: &PrepareOptions, camera: &Camera) -> String {
    let pairs = pixel_settings(settings, prepare, camera);
    pairs.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(" ")
}

/// The first setting in which two signatures differ, with both values
/// (`None` for a setting one of them lacks, as from another version).
fn first_difference<'a>(a: &'a str, b: &'a str) -> Option<(&'a str, Option<&'a str>, Option<&'a str>)> {
    let pairs = |s: &'a str| -> Vec<(&'a str, &'a str)> {
        s.split_whitespace().map(|f| f.split_once('=').unwrap_or((f, ""))).collect()
    };
    let (pa, pb) = (pairs(a), pairs(b));
    let value = |p: &[(&'a str, &'a str)], k: &str| p.iter().find(|(n, _)| *n == k).map(|(_, v)| *v);
    pa.iter().chain(&pb).map(|(k, _)| *k).find_map(|k| {
        let (va, vb) = (value(&pa, k), value(&pb, k));
        (va != vb).then_some((k, va, vb))
    })
}

/// What a part file says about itself.
#[derive(Debug, Clone)]
pub struct Part {
    /// Where it was read from.
    pub path: PathBuf,
    /// The full image's size.
    pub full: (u32, u32),
    /// The part's pixels in the full image.
    pub window: PixelWindow,
    /// [`scene_digest`] of its scene.
    pub digest: String,
    /// [`settings_signature`] of its render.
    pub settings: String,
    /// Its ray counters.
    pub counters: Counters,
    /// Its pixels, row-major.
    pub pixels: Vec<[f32; 3]>,
}

fn text(s: &str) -> Result<Text> {
    Text::new_or_none(s).with_context(|| format!("`{s}` cannot be stored in an EXR attribute"))
}

fn counters_line(c: &Counters) -> String {
    let tests: Vec<String> = c.tests.iter().map(|(k, n)| format!("{}={n}", <&str>::from(k))).collect();
    format!(
        "eye={} eye_hits={} reflected={} refracted={} shadow={} visits={} mailbox={} shadow_cache={} {}",
        c.eye,
        c.eye_hits,
        c.reflected,
        c.refracted,
        c.shadow,
        c.visits,
        c.mailbox_hits,
        c.shadow_cache_hits,
        tests.join(" ")
    )
}

fn parse_counters(s: &str) -> Option<Counters> {
    let mut c = Counters::default();
    for field in s.split_whitespace() {
        let (key, value) = field.split_once('=')?;
        let value: u64 = value.parse().ok()?;
        match key {
            "eye" => c.eye = value,
            "eye_hits" => c.eye_hits = value,
            "reflected" => c.reflected = value,
            "refracted" => c.refracted = value,
            "shadow" => c.shadow = value,
            "visits" => c.visits = value,
            "mailbox" => c.mailbox_hits = value,
            "shadow_cache" => c.shadow_cache_hits = value,
            kind => {
                let k = c.tests.iter().map(|(k, _)| k).find(|k| <&str>::from(*k) == kind)?;
                c.tests[k] = value;
            }
        }
    }
    Some(c)
}

/// Encode a part as EXR bytes: `image` holds the window's pixels.
pub fn encode_part(
    image: &RgbImage,
    full: (u32, u32),
    window: PixelWindow,
    digest: &str,
    settings: &str,
    counters: &Counters,
) -> Result<Vec<u8>> {
    let mut attrs = LayerAttributes::named(text("nffkit part")?);
    attrs.layer_position = Vec2(window.x0 as i32, window.y0 as i32);
    attrs.other.insert(text(DIGEST)?, AttributeValue::Text(text(digest)?));
    attrs.other.insert(text(SETTINGS)?, AttributeValue::Text(text(settings)?));
    let counters = counters_line(counters);
    attrs
        .other
        .insert(text(PART_DIGEST)?, AttributeValue::Text(text(&part_digest(&image.pixels, &counters))?));
    attrs.other.insert(text(COUNTERS)?, AttributeValue::Text(text(&counters)?));
    let display = IntegerBounds::new(Vec2(0, 0), Vec2(full.0 as usize, full.1 as usize));
    image_io::encode_exr(image, attrs, display).context("encoding the EXR part")
}

/// Read a part written by `render --crop/--pixel-bounds/--tile -o X.exr`:
/// its header first (so a crafted window is refused before any pixel is
/// decoded), then its pixels, which must match the part's digest and be
/// finite and non-negative.
pub fn read_part(path: &Path) -> Result<Part> {
    let name = path.display();
    let unreadable = || {
        format!("{name}: not a readable OpenEXR file (parts are the .exr files `render --tile`, `--crop` or `--pixel-bounds` writes)")
    };
    let meta = exr::meta::MetaData::read_from_file(path, false).with_context(unreadable)?;
    let header = meta.headers.first().with_context(unreadable)?;
    let (full, window) = windows(
        &name.to_string(),
        header.shared_attributes.display_window,
        header.own_attributes.layer_position,
        header.layer_size,
    )?;
    let image = read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), vec![[0f32; 3]; size.area()]),
        |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * *w + pos.x()] = [r, g, b],
    )
    .with_context(unreadable)?;
    let attrs = &image.layer_data.attributes;
    let get = |key: &str| {
        match attrs.other.get(&Text::from(key)) {
        Some(AttributeValue::Text(t)) => Ok(t.to_string()),
        _ => bail!(
            "{name}: not an nffkit part (no {key} attribute); render parts with --crop, --pixel-bounds or --tile into .exr"
        ),
    }
    };
    // The decoded layer must be the one the header described.
    if windows(
        &name.to_string(),
        image.attributes.display_window,
        attrs.layer_position,
        image.layer_data.size,
    )? != (full, window)
    {
        bail!("{name}: the part's windows changed between its header and its pixels");
    }
    let pixels = image.layer_data.channel_data.pixels.1;
    let counters = get(COUNTERS)?;
    if get(PART_DIGEST)? != part_digest(&pixels, &counters) {
        bail!("{name}: the part's pixels or counters are not what render wrote (their digest differs); render it again");
    }
    if let Some(k) = pixels.iter().position(|p| p.iter().any(|c| !c.is_finite() || *c < 0.0)) {
        let (x, y) = (
            window.x0 as usize + k % window.width() as usize,
            window.y0 as usize + k / window.width() as usize,
        );
        bail!("{name}: pixel ({x}, {y}) is {:?}, not a finite non-negative colour", pixels[k]);
    }
    Ok(Part {
        path: path.to_path_buf(),
        full,
        window,
        digest: get(DIGEST)?,
        settings: get(SETTINGS)?,
        counters: parse_counters(&counters)
            .with_context(|| format!("{name}: unreadable counters `{counters}`"))?,
        pixels,
    })
}

/// The full image's size and the part's window, from a part's display
/// window and data window (position and size), checked.
fn windows(
    name: &str,
    display: IntegerBounds,
    pos: Vec2<i32>,
    size: Vec2<usize>,
) -> Result<((u32, u32), PixelWindow)> {
    if display.position != Vec2(0, 0) || pos.x() < 0 || pos.y() < 0 {
        bail!("{name}: the part's windows do not start at 0,0 as nffkit writes them");
    }
    let (fw, fh) = (display.size.width() as u64, display.size.height() as u64);
    // The same bound render sets: a merged film of at most 2^27 pixels.
    if fw == 0 || fh == 0 || fw > 65536 || fh > 65536 || fw * fh > 1 << 27 {
        bail!("{name}: a {fw}x{fh} image is larger than nffkit renders");
    }
    let (x0, y0) = (pos.x() as u64, pos.y() as u64);
    let (x1, y1) = (x0 + size.width() as u64, y0 + size.height() as u64);
    if x1 > fw || y1 > fh {
        bail!("{name}: the part's pixels reach outside its {fw}x{fh} image");
    }
    if x1 == x0 || y1 == y0 {
        bail!("{name}: the part has no pixels");
    }
    let window = PixelWindow { x0: x0 as u32, x1: x1 as u32, y0: y0 as u32, y1: y1 as u32 };
    Ok(((fw as u32, fh as u32), window))
}

/// SHA-256 of a part's pixels (their bits, row by row) and its counters
/// line, in hex: what render wrote, unedited.
fn part_digest(pixels: &[[f32; 3]], counters: &str) -> String {
    let mut h = Sha256::new();
    for p in pixels {
        for c in p {
            h.update(c.to_bits().to_le_bytes());
        }
    }
    h.update(counters.as_bytes());
    hex(&h.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// Parts merged into the full image.
pub struct Merged {
    /// The image.
    pub image: RgbImage,
    /// The parts' counters, summed.
    pub counters: Counters,
}

/// Check that `parts` come from one scene and one set of settings and cover
/// the image exactly once, then stitch them.
pub fn merge(parts: &[Part]) -> Result<Merged> {
    let Some(first) = parts.first() else { bail!("no parts to merge") };
    let (w, h) = first.full;
    for p in &parts[1..] {
        let (a, b) = (first.path.display(), p.path.display());
        if p.digest != first.digest {
            let short = |d: &str| d.chars().take(12).collect::<String>();
            bail!(
                "{b} comes from another scene than {a} (scene digests {} and {})",
                short(&p.digest),
                short(&first.digest)
            );
        }
        if p.settings != first.settings {
            let Some((name, va, vb)) = first_difference(&first.settings, &p.settings) else {
                bail!(
                    "{b} was rendered with other settings than {a}:\n  {a}: {}\n  {b}: {}",
                    first.settings,
                    p.settings
                );
            };
            let shown = |v: Option<&str>| v.map_or("(not recorded)".to_string(), |v| format!("{name}={v}"));
            bail!(
                "{b} was rendered with other settings than {a}: {name} differs ({a}: {}, {b}: {}); render every part with the same settings",
                shown(va),
                shown(vb)
            );
        }
        if p.full != first.full {
            bail!("{b} is part of a {}x{} image, {a} of a {w}x{h} one", p.full.0, p.full.1);
        }
    }
    let mut owner: Vec<u32> = vec![u32::MAX; w as usize * h as usize];
    let mut image = RgbImage { width: w, height: h, pixels: vec![[0.0; 3]; owner.len()] };
    let mut counters = Counters::default();
    for (i, p) in parts.iter().enumerate() {
        let pw = p.window.width() as usize;
        for y in p.window.y0..p.window.y1 {
            for x in p.window.x0..p.window.x1 {
                let at = y as usize * w as usize + x as usize;
                if owner[at] != u32::MAX {
                    bail!(
                        "{} and {} overlap: both cover pixel ({x}, {y})",
                        parts[owner[at] as usize].path.display(),
                        p.path.display()
                    );
                }
                owner[at] = i as u32;
                image.pixels[at] = p.pixels[(y - p.window.y0) as usize * pw + (x - p.window.x0) as usize];
            }
        }
        counters += p.counters;
    }
    let missing = owner.iter().filter(|&&o| o == u32::MAX).count();
    if missing > 0 {
        let first_gap = owner.iter().position(|&o| o == u32::MAX).unwrap_or(0);
        let rows: Vec<u32> =
            (0..h).filter(|&y| owner[(y * w) as usize..((y + 1) * w) as usize].contains(&u32::MAX)).collect();
        bail!(
            "the parts leave {missing} pixels of the {w}x{h} image uncovered, the first at ({}, {}); rows {}..={} are incomplete",
            first_gap as u32 % w,
            first_gap as u32 / w,
            rows[0],
            rows[rows.len() - 1]
        );
    }
    Ok(Merged { image, counters })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Merge the two halves of a 4x2 image, the top rendered with default
    /// settings and the bottom with `change` applied: the error, if any.
    fn merge_halves(change: impl Fn(&mut RenderSettings, &mut PrepareOptions)) -> Option<String> {
        let view = nffkit_formats::View {
            lens: None,
            from: glam::DVec3::new(0.0, -5.0, 0.0),
            at: glam::DVec3::ZERO,
            up: glam::DVec3::Z,
            angle: 40.0,
            hither: 0.0,
            resolution: [4, 2],
        };
        let dir = tempfile::tempdir().unwrap();
        let mut parts = Vec::new();
        for (k, y0) in [0, 1].into_iter().enumerate() {
            let (mut settings, mut prepare) = (RenderSettings::default(), PrepareOptions::default());
            if k == 1 {
                change(&mut settings, &mut prepare);
            }
            let size = |o: Option<u32>, d: u32| o.unwrap_or(d);
            let camera = Camera::new(&view, size(prepare.width, 4), size(prepare.height, 2));
            let signature = settings_signature(&settings, &prepare, &camera);
            let window = PixelWindow { x0: 0, x1: 4, y0, y1: y0 + 1 };
            let img = RgbImage { width: 4, height: 1, pixels: vec![[0.5; 3]; 4] };
            let bytes = encode_part(&img, (4, 2), window, "d", &signature, &Counters::default()).unwrap();
            let path = dir.path().join(format!("part{k}.exr"));
            std::fs::write(&path, bytes).unwrap();
            parts.push(read_part(&path).unwrap());
        }
        merge(&parts).err().map(|e| e.to_string())
    }

    /// One test per setting that changes pixels: parts differing in it are
    /// refused, and the message names it. `TESTED` lists them, so that
    /// [`every_pixel_setting_has_its_test`] can hold the list to the
    /// signature's.
    macro_rules! refused_when_parts_differ_in {
        ($($test:ident: $name:literal => |$s:ident, $p:ident| $change:expr;)*) => {
            mod refused_when_parts_differ_in {
                use super::*;
                $(
                    #[test]
                    #[allow(unused_variables)]
                    fn $test() {
                        let e = merge_halves(|$s, $p| $change)
                            .unwrap_or_else(|| panic!("{} differs, yet merged", $name));
                        assert!(e.contains(&format!("{} differs", $name)) && e.contains("other settings"), "{e}");
                    }
                )*
            }
            const TESTED: &[&str] = &[$($name),*];
        };
    }

    refused_when_parts_differ_in! {
        size: "size" => |s, p| p.width = Some(8);
        depth: "depth" => |s, p| s.shade.max_depth = 3;
        spp: "spp" => |s, p| s.sampler = Sampler::new(s.sampler.kind, 4, s.sampler.seed).0;
        sampler: "sampler" => |s, p| s.sampler.kind = nffkit_tracer::sampling::SamplerKind::Sobol;
        seed: "seed" => |s, p| s.sampler.seed = 9;
        pixel_centre: "pixel-centre" => |s, p| s.centre_single_sample = false;
        filter: "filter" => |s, p| s.filter = nffkit_tracer::filter::FilterKind::Tent;
        light_size: "light-size" => |s, p| s.shade.light_size = 0.5;
        light_shape: "light-shape" => |s, p| s.shade.light_shape = nffkit_tracer::light::LightShape::Disk;
        min_weight: "min-weight" => |s, p| s.shade.min_weight = 0.01;
        spd_stats: "spd-stats" => |s, p| s.shade.spd = true;
        row_stride: "row-stride" => |s, p| s.row_stride = 2;
        aperture: "aperture" => |s, p| p.aperture = Some(0.1);
        focus: "focus" => |s, p| p.focus = Some(3.0);
        fresnel: "fresnel" => |s, p| p.fresnel = true;
        one_sided: "one-sided" => |s, p| p.one_sided = true;
        ambient: "ambient" => |s, p| p.ambient = nffkit_tracer::prepare::Ambient::Value(0.8);
    }

    #[test]
    fn every_pixel_setting_has_its_test() {
        let view = nffkit_formats::View {
            lens: None,
            from: glam::DVec3::Y,
            at: glam::DVec3::ZERO,
            up: glam::DVec3::Z,
            angle: 40.0,
            hither: 0.0,
            resolution: [4, 2],
        };
        let camera = Camera::new(&view, 4, 2);
        let names: Vec<&str> =
            pixel_settings(&RenderSettings::default(), &PrepareOptions::default(), &camera)
                .into_iter()
                .map(|(name, _)| name)
                .collect();
        assert_eq!(names, TESTED);
    }

    #[test]
    fn parts_may_differ_in_how_the_work_is_done() {
        use nffkit_tracer::accel::{AccelKind, AccelOptions};
        let how = |s: &mut RenderSettings, p: &mut PrepareOptions| {
            (s.packets, s.shadow_cache, s.cost) = (false, false, true);
            p.accel = AccelOptions { kind: AccelKind::Grid, grid_m: 3.0, mailbox: false };
        };
        assert_eq!(merge_halves(how), None);
    }

    #[test]
    fn counters_round_trip_through_their_attribute() {
        let mut c = Counters {
            eye: 5,
            eye_hits: 6,
            reflected: 4,
            refracted: 3,
            shadow: 2,
            visits: 9,
            mailbox_hits: 1,
            shadow_cache_hits: 8,
            ..Default::default()
        };
        for (i, (k, _)) in Counters::default().tests.iter().enumerate() {
            c.tests[k] = 10 + i as u64;
        }
        assert_eq!(parse_counters(&counters_line(&c)), Some(c));
        assert_eq!(parse_counters("eye=1 comet=2"), None);
    }

    fn part_file(dir: &Path, name: &str, full: (u32, u32), window: PixelWindow, digest: &str) -> PathBuf {
        let img = RgbImage {
            width: window.width(),
            height: window.height(),
            pixels: vec![[0.5; 3]; (window.width() * window.height()) as usize],
        };
        let bytes = encode_part(&img, full, window, digest, "s", &Counters::default()).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }

    #[test]
    fn hostile_parts_are_refused_without_panicking() {
        let dir = tempfile::tempdir().unwrap();
        let top = PixelWindow { x0: 0, x1: 4, y0: 0, y1: 2 };
        let bottom = PixelWindow { x0: 0, x1: 4, y0: 2, y1: 4 };
        let a = read_part(&part_file(dir.path(), "a.exr", (4, 4), top, "ab")).unwrap();
        let b = read_part(&part_file(dir.path(), "b.exr", (4, 4), bottom, "c")).unwrap();
        let e = merge(&[a.clone(), b]).err().unwrap().to_string();
        assert!(e.contains("another scene") && e.contains("digests c and ab"), "{e}");
        let whole = PixelWindow { x0: 0, x1: 4, y0: 0, y1: 4 };
        assert_eq!(
            merge(&[read_part(&part_file(dir.path(), "w.exr", (4, 4), whole, "ab")).unwrap()])
                .unwrap()
                .image
                .pixels
                .len(),
            16
        );
        let huge = part_file(dir.path(), "h.exr", (70000, 4), top, "ab");
        let e = read_part(&huge).unwrap_err().to_string();
        assert!(e.contains("larger than nffkit renders"), "{e}");
    }
}
