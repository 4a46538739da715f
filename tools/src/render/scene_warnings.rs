//! Warnings about a scene as a whole, shared by `render` and `render
//! --check`: the ways a file that reads cleanly still renders black without
//! a word. A scene with no lights renders black (background aside) unless
//! ambient light is asked for, and several public NFF files have none, or
//! only dialect lights that `--lenient` skipped. A light in the plane of a
//! flat surface gives it nothing (N·L = 0 all over it). And a view filled
//! by the backs of opaque surfaces is drawn where the spec's one-sided
//! rule would see through them (see [`nffkit_tracer::probe`]). Polygons
//! overlapping in one plane speckle ([`super::coplanar`]).

use nffkit_formats::nff::escape;
use nffkit_formats::polygon::newell_normal;
use nffkit_formats::{Light, Primitive, Scene, Shape};
use nffkit_tracer::prepare::{RenderScene, PRECISION_RANGE};
use nffkit_tracer::probe::probe_view;

use glam::DVec3;
use rayon::prelude::*;

/// A warning about the scene, with the line it points at when there is one.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneWarning {
    /// What is wrong and what to do.
    pub message: String,
    /// The line of the file it concerns.
    pub line: Option<u32>,
}

impl SceneWarning {
    /// Compiler-style, as the reader's warnings are printed (without the
    /// source line).
    pub fn render(&self, file: &str) -> String {
        let at = self.line.map(|l| format!(":{l}")).unwrap_or_default();
        format!("warning: {}\n --> {}{at}\n", escape(&self.message), escape(file))
    }
}

/// Every warning about `scene`; those about the view only when it was
/// prepared (`prepared`). `ambient`: whether `--ambient` lights it.
pub fn scene_warnings(scene: &Scene, prepared: Option<&RenderScene>, ambient: bool) -> Vec<SceneWarning> {
    let mut out = file_warnings(scene, ambient, prepared.is_some());
    out.extend(prepared.into_iter().flat_map(prepared_warnings));
    out
}

/// The warnings read from the file's primitives and lights, the first of
/// [`scene_warnings`]: for a caller that frees the primitives before the
/// scene is prepared. `rendered`: whether the view will be prepared (the
/// overlap check, costly past a million polygons, runs only then).
pub fn file_warnings(scene: &Scene, ambient: bool, rendered: bool) -> Vec<SceneWarning> {
    let flats = flat_surfaces(scene);
    let mut out: Vec<SceneWarning> = unlit(scene, ambient).into_iter().collect();
    out.extend(lights_in_surface_planes(&scene.lights, &flats));
    out.extend(rendered.then(|| super::coplanar::coplanar_overlaps(&flats)).flatten());
    out
}

/// The file's flat surfaces (polygons, patches, infinite planes, boxes) in
/// file order: all that the checks of lights in planes and of overlapping
/// polygons read. One pass over the primitives on all cores finds them; in
/// a large file of spheres that pass is the checks' whole cost.
pub fn flat_surfaces(scene: &Scene) -> Vec<&Primitive> {
    let flat = |p: &&Primitive| !matches!(p.shape, Shape::Sphere { .. } | Shape::Cone { .. });
    scene.primitives.par_iter().filter(flat).collect()
}

/// The warnings about the prepared view, the last of [`scene_warnings`].
pub fn prepared_warnings(prepared: &RenderScene) -> Vec<SceneWarning> {
    back_faces_in_view(prepared).into_iter().chain(beyond_precision(prepared)).collect()
}

/// The warning when the scene's dynamic range passes what single precision
/// resolves: its smallest objects are hit or missed by rounding.
pub fn beyond_precision(prepared: &RenderScene) -> Option<SceneWarning> {
    let range = prepared.dynamic_range();
    let what = if range.is_finite() {
        format!(
            "spans {range:.1e} times the size of its smallest object, more than single precision \
             resolves ({PRECISION_RANGE:.0e})"
        )
    } else {
        "has objects too small for single precision to give them any size".to_string()
    };
    (range > PRECISION_RANGE).then(|| SceneWarning {
        message: format!(
            "the scene {what}: small objects far from the origin or the eye may be hit or missed \
             by rounding, and accelerators may disagree on them"
        ),
        line: None,
    })
}

/// The warning to print when `scene` has no lights and nothing else lights
/// it (`ambient`: whether `--ambient` is on).
pub fn unlit(scene: &Scene, ambient: bool) -> Option<SceneWarning> {
    if !scene.lights.is_empty() || scene.primitives.is_empty() || ambient {
        return None;
    }
    Some(SceneWarning {
        message: "the scene has no lights (`l`): its objects render black; \
                  `render --ambient spd` (or a value) lights them evenly"
            .into(),
        line: None,
    })
}

/// Above this many light-surface pairs the planes are not checked (a
/// scene of millions of polygons and many lights).
const MAX_PAIRS: usize = 1 << 26;

/// How close to a plane, relative to the distances involved, a light is in
/// it: N·L at most 1e-6 on the surface (a grazing 0.00006 degrees). Only
/// a light put in the plane on purpose comes this close: the nearest of
/// mount_s7's 32,768 triangles to its light is at 6.4e-6.
const IN_PLANE: f64 = 1e-6;

/// One warning per light that lies in the plane of flat surfaces
/// (polygons, infinite planes, box faces; not patches, whose shading
/// normals vary) among `flats` ([`flat_surfaces`]): the first such
/// surface's line and how many more.
pub fn lights_in_surface_planes(lights: &[Light], flats: &[&Primitive]) -> Vec<SceneWarning> {
    if lights.is_empty() || lights.len().saturating_mul(flats.len()) > MAX_PAIRS {
        return Vec::new();
    }
    // Per light: surfaces in its plane, and the first one's line and kind.
    let mut found: Vec<(usize, Option<(u32, &'static str)>)> = vec![(0, None); lights.len()];
    for prim in flats {
        for (light, (count, first)) in lights.iter().zip(&mut found) {
            if in_a_plane_of(&prim.shape, light.position) {
                *count += 1;
                first.get_or_insert((prim.line.0, prim.shape.kind().name()));
            }
        }
    }
    let mut out = Vec::new();
    for (k, (light, (count, first))) in lights.iter().zip(found).enumerate() {
        let Some((line, kind)) = first else { continue };
        let p = light.position;
        let more = if count > 1 { format!(" and {} more surfaces", count - 1) } else { String::new() };
        out.push(SceneWarning {
            message: format!(
                "light {} at ({}, {}, {}) lies in the plane of the {kind} on line {line}{more}: \
                 it gives {} no light (N·L = 0 all over), so {} black or lit by other lights only",
                k + 1,
                p.x,
                p.y,
                p.z,
                if count > 1 { "them" } else { "it" },
                if count > 1 { "they render" } else { "it renders" },
            ),
            line: Some(line),
        });
    }
    out
}

/// Whether `light` lies in the plane of `shape` (one of a box's faces).
fn in_a_plane_of(shape: &Shape, light: DVec3) -> bool {
    let near = |distance: f64, scale: f64| distance.abs() <= IN_PLANE * scale;
    match shape {
        Shape::Polygon { vertices } => {
            let n = newell_normal(vertices).normalize_or_zero();
            let origin = vertices[0];
            let radius = vertices.iter().map(|v| v.distance(origin)).fold(0.0, f64::max);
            n != DVec3::ZERO && near(n.dot(light - origin), light.distance(origin) + radius)
        }
        Shape::Plane { points } => {
            let [a, b, c] = &**points;
            let n = (*b - *a).cross(*c - *a).normalize_or_zero();
            n != DVec3::ZERO && near(n.dot(light - *a), light.distance(*a))
        }
        Shape::Box(aabb) => {
            let nffkit_formats::AxisBox { min, max } = &**aabb;
            let scale = light.distance((*min + *max) / 2.0) + min.distance(*max);
            (0..3).any(|a| near(light[a] - min[a], scale) || near(light[a] - max[a], scale))
        }
        Shape::Sphere { .. } | Shape::Cone { .. } | Shape::Patch { .. } => false,
    }
}

/// Eye rays in the probe, per side.
const PROBE_SIDE: u32 = 32;

/// The warning when most of the view is the backs of opaque surfaces,
/// which two-sided shading draws and the spec's one-sided rule culls.
pub fn back_faces_in_view(prepared: &RenderScene) -> Option<SceneWarning> {
    let probe = probe_view(prepared, PROBE_SIDE);
    let share = probe.back_face_share();
    if share <= 0.5 {
        return None;
    }
    let first = probe.first_back_face_line.map(|l| format!(" (the first on line {l})")).unwrap_or_default();
    Some(SceneWarning {
        message: format!(
            "{:.0}% of the view is the back of opaque surfaces{first}: they face away from the \
             camera, and NFF.TXT makes opaque objects one-sided, so the spec sees through them; \
             `render --one-sided` does too (the default draws both sides)",
            share * 100.0
        ),
        line: probe.first_back_face_line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nffkit_formats::nff::{parse, ParseOptions};

    fn scene(src: &str) -> Scene {
        parse(src.as_bytes(), &ParseOptions { fragment: true, ..Default::default() }).unwrap().scene
    }

    fn in_planes(scene: &Scene) -> Vec<SceneWarning> {
        lights_in_surface_planes(&scene.lights, &flat_surfaces(scene))
    }

    #[test]
    fn unlit_warns_only_for_objects_without_any_light() {
        assert!(unlit(&scene("s 0 0 0 1\n"), false).is_some());
        assert!(unlit(&scene("s 0 0 0 1\n"), true).is_none());
        assert!(unlit(&scene("l 1 1 1\ns 0 0 0 1\n"), false).is_none());
        assert!(unlit(&scene("b 1 1 1\n"), false).is_none());
    }

    #[test]
    fn a_light_in_a_surface_plane_is_named_once_with_its_count() {
        let square = |z: f64| format!("p 4\n-1 -1 {z}\n1 -1 {z}\n1 1 {z}\n-1 1 {z}\n");
        // Two squares in the plane z = 0 (lines 2 and 7), one at z = 1.
        let src = format!("l 5 5 0\n{}{}{}", square(0.0), square(0.0), square(1.0));
        let w = in_planes(&scene(&src));
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].line, Some(2));
        assert!(w[0]
            .message
            .contains("light 1 at (5, 5, 0) lies in the plane of the polygon on line 2 and 1 more"));
        // Off the plane by a hundredth: lit at a grazing angle, no warning.
        assert!(in_planes(&scene(&format!("l 5 5 0.01\n{}", square(0.0)))).is_empty());
        // An infinite plane and a box face.
        assert_eq!(in_planes(&scene("l 3 0 0\npl 0 0 0 1 0 0 0 1 0\n")).len(), 1);
        assert_eq!(in_planes(&scene("l 1 7 7\naabb -1 -1 -1 1 1 1\n")).len(), 1);
        // Patches shade with their own normals: not warned.
        let patch = "l 5 5 0\npp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n";
        assert!(in_planes(&scene(patch)).is_empty());
    }

    /// The range is the largest coordinate over the smallest object,
    /// whichever of thousands of primitives they are (the pass is split
    /// across cores); an infinite plane counts for neither.
    #[test]
    fn beyond_precision_compares_the_span_with_the_smallest_object() {
        use nffkit_tracer::prepare::{prepare, PrepareOptions};
        let warned = |tiny: f64, far: f64| {
            let mut src =
                "v\nfrom 0 0 40\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n".to_string();
            src += "pl 0 -3 0 0 -3 1 1 -3 0\n";
            for i in 0..5000 {
                let (x, r) = match i {
                    2345 => (0.0, tiny),
                    3999 => (far, 1.0),
                    _ => ((i % 50) as f64 * 0.4 - 10.0, 0.1),
                };
                src += &format!("s {x} {} 0 {r}\n", (i / 50) as f64 * 0.2 - 10.0);
            }
            let prepared = prepare(&scene(&src), &PrepareOptions::default()).unwrap();
            beyond_precision(&prepared).is_some()
        };
        // The eye's 40 over spheres 2e-4, 2e-6 and 6e-5 across, against
        // 2^20.
        assert!(!warned(1e-4, 10.0));
        assert!(warned(1e-6, 10.0));
        assert!(!warned(3e-5, 10.0));
        // One far sphere: 1001 over 6e-5.
        assert!(warned(3e-5, 1000.0));
    }
}
