//! The view and lights written for a converted model: the framing view
//! (from a fixed direction, or the one of several that shows the most lit
//! surface when the model lights itself), a file's own camera, and the
//! light at the eye for views that would otherwise see nothing lit.

use super::{Options, Up};
use glam::DVec3;
use nffkit_formats::mesh::MeshCamera;
use nffkit_formats::{Light, View};

/// The field of view of the framing view, degrees.
const FRAMING_ANGLE: f64 = 40.0;

/// The framing direction (from the model's centre toward the eye) used
/// unless another is chosen.
pub fn default_direction(up: Up) -> DVec3 {
    match up {
        Up::Y => DVec3::new(0.55, 0.45, 0.95).normalize(),
        Up::Z => DVec3::new(0.55, -0.95, 0.45).normalize(),
    }
}

fn up_vector(up: Up) -> DVec3 {
    match up {
        Up::Y => DVec3::Y,
        Up::Z => DVec3::Z,
    }
}

/// Directions tried when the model lights itself: the default, then eight
/// around the up axis at 25° and eight at 5° above the horizon (an
/// open-fronted room is seen through its opening from one of them, and
/// from the lower ones under its ceiling).
pub fn candidate_directions(up: Up) -> Vec<DVec3> {
    let u = up_vector(up);
    let (a, b) = match up {
        Up::Y => (DVec3::Z, DVec3::X),
        Up::Z => (-DVec3::Y, DVec3::X),
    };
    let mut dirs = vec![default_direction(up)];
    for elevation in [25f64.to_radians(), 5f64.to_radians()] {
        for k in 0..8 {
            let azimuth = k as f64 * std::f64::consts::FRAC_PI_4;
            let horizontal = a * azimuth.cos() + b * azimuth.sin();
            dirs.push((horizontal * elevation.cos() + u * elevation.sin()).normalize());
        }
    }
    dirs
}

/// The view looking at box `b` from direction `dir` (unit, centre to eye),
/// far enough for the bounding sphere to fit, and its two framing lights:
/// one above and right of the eye, one to the left of the model.
pub fn framing(b: (DVec3, DVec3), o: &Options, dir: DVec3) -> (View, Vec<Light>) {
    let center = (b.0 + b.1) * 0.5;
    let radius = ((b.1 - b.0).length() * 0.5).max(1e-9);
    let dist = radius / (FRAMING_ANGLE.to_radians() * 0.5).sin() * 1.05;
    let up = up_vector(o.up);
    let from = center + dir * dist;
    let right = (-dir).cross(up).normalize_or(DVec3::X);
    let view = View {
        lens: None,
        from,
        at: center,
        up,
        angle: FRAMING_ANGLE,
        hither: dist * 1e-3,
        resolution: o.resolution.unwrap_or([512, 512]),
    };
    let lights = vec![
        Light { area: None, position: from + (up * 1.5 + right * 1.0) * radius * 2.0, color: None },
        Light {
            area: None,
            position: center + (up * 1.0 - right * 2.0 + dir * 0.5) * radius * 3.0,
            color: None,
        },
    ];
    (view, lights)
}

/// NFF's `angle` for a glTF vertical field of view `yfov` (radians, between
/// the image's top and bottom edges) on a `w` × `h` image. NFF measures
/// between the centres of the outer pixel rows (or columns) of the smaller
/// side, n = min(w, h) pixels: the pixel pitch at unit distance is
/// p = 2·tan(yfov/2)/h, and those centres lie (n − 1)·p apart, so
/// angle = 2·atan(tan(yfov/2)·(n − 1)/h).
pub fn nff_angle(yfov: f64, w: u32, h: u32) -> f64 {
    let n = w.min(h).max(2) as f64;
    (2.0 * ((yfov * 0.5).tan() * (n - 1.0) / h as f64).atan()).to_degrees()
}

/// The image size for a file camera: the user's, else 512 wide at the
/// camera's aspect ratio (512 × 512 when it has none).
pub fn camera_resolution(cam: &MeshCamera, o: &Options) -> [u32; 2] {
    o.resolution.unwrap_or_else(|| match cam.aspect {
        Some(a) if a.is_finite() && a > 0.0 => [512, ((512.0 / a).round() as u32).clamp(1, 65536)],
        _ => [512, 512],
    })
}

/// The NFF view of a file camera, after the same placement as the
/// positions (`place`, which scales by `scale`, --fit included): a negative
/// scale mirrors directions too.
pub fn camera_view(
    cam: &MeshCamera,
    o: &Options,
    place: impl Fn(DVec3) -> DVec3,
    scale: f64,
    focus: DVec3,
) -> View {
    let [w, h] = camera_resolution(cam, o);
    let from = place(cam.from);
    let s = scale.signum();
    let direction = cam.direction * s;
    // `at` only fixes the direction; its distance is the focus for depth of
    // field, so it is put level with the model's centre.
    let dist = (focus - from).dot(direction).max(cam.znear.max(1e-9) * scale.abs() * 10.0);
    View {
        lens: None,
        from,
        at: from + direction * dist,
        up: cam.up * s,
        angle: nff_angle(cam.yfov, w, h),
        hither: cam.znear * scale.abs(),
        resolution: [w, h],
    }
}

/// A light at the eye.
pub fn eye_light(view: &View, color: Option<DVec3>) -> Light {
    Light { area: None, position: view.from, color }
}

/// Whether the eye lies inside box `b`.
pub fn inside(view: &View, b: (DVec3, DVec3)) -> bool {
    view.from.cmpge(b.0).all() && view.from.cmple(b.1).all()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_angle_conversion_matches_the_edges() {
        // A 2-row image: the centres of its outer rows are half a pixel in
        // from each edge, so half the edge-to-edge extent.
        let a = nff_angle(2.0 * 1f64.atan(), 2, 2);
        assert!((a - 2.0 * 0.5f64.atan().to_degrees()).abs() < 1e-9, "{a}");
        // A wide image: the smaller side is vertical, as in glTF.
        let a = nff_angle(60f64.to_radians(), 1024, 513);
        let expect = 2.0 * (30f64.to_radians().tan() * 512.0 / 513.0).atan();
        assert!((a - expect.to_degrees()).abs() < 1e-9);
        // A tall image: the smaller side is horizontal.
        let a = nff_angle(60f64.to_radians(), 257, 512);
        let expect = 2.0 * (30f64.to_radians().tan() * 256.0 / 512.0).atan();
        assert!((a - expect.to_degrees()).abs() < 1e-9);
    }

    #[test]
    fn candidates_are_unit_and_start_with_the_default() {
        for up in [Up::Y, Up::Z] {
            let c = candidate_directions(up);
            assert_eq!(c[0], default_direction(up));
            assert!(c.iter().all(|d| (d.length() - 1.0).abs() < 1e-12));
            assert_eq!(c.len(), 17);
        }
    }
}
