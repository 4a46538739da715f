//! NFF and the P3D course's P3F side by side: telling which a text is
//! ([`sniff`]), and turning a scene of one into the closest scene of the
//! other, saying what the target cannot hold ([`to_nff`], [`to_p3f`]).
//!
//! The two differ in more than entities: P3F's view `angle` spans the image
//! height edge to edge (the course's camera), NFF's the centres of the
//! outer pixels of the smaller side; a P3F transmitter weighs reflection and
//! transmission by Fresnel's equations, an NFF one by its fixed Ks and T;
//! a P3F light without a colour is white, an NFF one 1/sqrt(n).

use crate::nff::P3F_KEYWORDS;
use crate::scene::{Color, Dialect, Scene};
use glam::DVec3;

/// How much of a text [`sniff`] reads.
const SNIFF_BYTES: usize = 1 << 16;

/// The view's lines only P3F has.
const P3F_VIEW_LINES: [&str; 2] = ["aperture", "focal"];

/// The dialect of a scene text (standard input, or a file whose name says
/// nothing): P3F when one of its first lines starts with a word only P3F
/// has (its entities and directives, its view's lens lines), NFF otherwise.
pub fn sniff(src: &[u8]) -> Dialect {
    let head = &src[..src.len().min(SNIFF_BYTES)];
    let p3f = head.split(|&b| b == b'\n' || b == b'\r').any(|line| {
        let word = line.split(|b| b.is_ascii_whitespace()).find(|w| !w.is_empty()).unwrap_or_default();
        P3F_KEYWORDS.iter().chain(&P3F_VIEW_LINES).any(|k| k.as_bytes() == word)
    });
    if p3f {
        Dialect::P3f
    } else {
        Dialect::Nff
    }
}

/// The dialect a file name gives: `.p3f` is P3F, `.nff` NFF, anything else
/// nothing.
pub fn from_extension(path: &std::path::Path) -> Option<Dialect> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "p3f" => Some(Dialect::P3f),
        "nff" => Some(Dialect::Nff),
        _ => None,
    }
}

/// The language of a scene text: `given` (the user's choice), else the
/// file name's (.p3f, .nff), else what the content shows ([`sniff`];
/// standard input and dropped files may have no telling name).
pub fn detect(path: &std::path::Path, src: &[u8], given: Option<Dialect>) -> Dialect {
    given.or_else(|| from_extension(path)).unwrap_or_else(|| sniff(src))
}

/// The field of view in `to`'s convention that gives a `width` x `height`
/// image the pixels `angle` gives it in `from`'s.
pub fn convert_angle(angle: f64, from: Dialect, to: Dialect, width: u32, height: u32) -> f64 {
    if from == to {
        return angle;
    }
    let pixel = from.pixel_size(angle, width, height);
    let spanned = match to {
        Dialect::Nff => (width.min(height).max(2) - 1) as f64,
        Dialect::P3f => height as f64,
    };
    2.0 * (pixel * spanned * 0.5).atan().to_degrees()
}

/// The closest NFF to a P3F scene, and what NFF could not hold, one line
/// each (with the `render` flags that give it back where there are some).
/// An NFF scene comes back as it is.
pub fn to_nff(scene: &Scene) -> (Scene, Vec<String>) {
    let mut out = scene.clone();
    let mut lost = Vec::new();
    if scene.dialect == Dialect::Nff {
        return (out, lost);
    }
    out.dialect = Dialect::Nff;
    if let Some(v) = &mut out.view {
        let [w, h] = v.resolution;
        v.angle = convert_angle(v.angle, Dialect::P3f, Dialect::Nff, w, h);
        if let Some(lens) = v.lens.take().filter(|l| l.aperture > 0.0) {
            let d = (v.at - v.from).length();
            let radius = lens.aperture * v.pixel_size(Dialect::Nff, w, h) * d;
            lost.push(format!(
                "the lens (aperture {} pixels, focal {}); `render --aperture {} --focus {}` gives the \
                 same depth of field",
                lens.aperture,
                lens.focal,
                short(radius),
                short(lens.focal * d)
            ));
        }
    }
    let specular = out.materials.iter().filter(|m| m.specular != DVec3::ONE).count();
    for m in &mut out.materials {
        m.ks *= mean(m.specular);
        m.specular = DVec3::ONE;
    }
    if specular > 0 {
        lost.push(format!(
            "{specular} specular colour{} (its highlights and reflections are white): each Ks is \
             scaled by its colour's mean",
            crate::plural(specular)
        ));
    }
    let glass = out.materials.iter().filter(|m| m.t > 0.0).count();
    if glass > 0 {
        lost.push(format!(
            "the Fresnel weighting of {glass} transmitting material{} (it weighs reflection by Ks and \
             transmission by T); `render --fresnel` weighs them as P3F does",
            crate::plural(glass)
        ));
    }
    let areas: Vec<f64> =
        out.lights.iter_mut().filter_map(|l| l.area.take()).map(|a| a.size[0].max(a.size[1])).collect();
    if let Some(size) = areas.iter().copied().reduce(f64::max) {
        lost.push(format!(
            "{} area light{} (its lights are points, written at each rectangle's centre); \
             `render --light-size {}` gives soft shadows from squares facing each point",
            areas.len(),
            crate::plural(areas.len()),
            short(size)
        ));
    }
    if let Some(dir) = out.environment.take() {
        lost.push(format!("the cube map `env {dir}`: rays that leave the scene see the background colour"));
    }
    let d = std::mem::take(&mut out.directives);
    if let Some(n) = d.spp {
        lost.push(format!("`spp {n}`: `render --spp {}` asks for it", n.max(1)));
    }
    if let Some(n) = d.accel {
        lost.push(format!("`accel {n}`: `render --accel` chooses the accelerator"));
    }
    (out, lost)
}

/// The closest P3F to an NFF scene, and what P3F could not hold, one line
/// each. A P3F scene comes back as it is.
pub fn to_p3f(scene: &Scene) -> (Scene, Vec<String>) {
    let mut out = scene.clone();
    let mut lost = Vec::new();
    if scene.dialect == Dialect::P3f {
        return (out, lost);
    }
    out.dialect = Dialect::P3f;
    if let Some(v) = &mut out.view {
        let [w, h] = v.resolution;
        v.angle = convert_angle(v.angle, Dialect::Nff, Dialect::P3f, w, h);
        v.lens = Some(crate::scene::Lens { aperture: 0.0, focal: 1.0 });
    }
    let intensity = 1.0 / (out.lights.len().max(1) as f64).sqrt();
    for l in &mut out.lights {
        l.color.get_or_insert(Color::splat(intensity));
    }
    let glass = out.materials.iter().filter(|m| m.t > 0.0).count();
    if glass > 0 {
        lost.push(format!(
            "the classic weighting of {glass} transmitting material{} (it weighs their reflection and \
             transmission by Fresnel's equations, so they render differently)",
            crate::plural(glass)
        ));
    }
    (out, lost)
}

/// The mean of a colour's channels.
fn mean(c: Color) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// A number for a suggested flag: six significant digits are plenty.
fn short(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffing_finds_p3f_words_at_line_starts_only() {
        assert_eq!(sniff(b"v\nfrom 0 0 1\n  bclr 1 1 1\n"), Dialect::P3f);
        assert_eq!(sniff(b"# a mesh of 3\r\nmesh 3 1\n"), Dialect::P3f);
        assert_eq!(sniff(b"v\nfrom 0 0 1\nb 0 0 0\n# env maps\ns 0 0 0 1\n"), Dialect::Nff);
        assert_eq!(sniff(b""), Dialect::Nff);
    }

    #[test]
    fn angles_convert_both_ways_to_the_same_pixels() {
        for (w, h) in [(512, 512), (640, 480), (300, 900), (2, 1)] {
            let nff = convert_angle(45.0, Dialect::P3f, Dialect::Nff, w, h);
            let back = convert_angle(nff, Dialect::Nff, Dialect::P3f, w, h);
            assert!((back - 45.0).abs() < 1e-12, "{w}x{h}: {back}");
        }
        // 512 pixels high: the edges span 512 pixels, the outer centres 511.
        let nff = convert_angle(90.0, Dialect::P3f, Dialect::Nff, 512, 512);
        let expected = 2.0 * (511.0f64 / 512.0).atan().to_degrees();
        assert!((nff - expected).abs() < 1e-12);
    }
}
