//! Mitsuba 3 scene XML, with the triangles in binary PLY files beside it.
//!
//! - Sensor: `perspective`, the vertical field of view spanning the same
//!   rays as `render` (edge to edge over the image height), `lookat` from
//!   the view, an `hdrfilm` of the view's size with a box filter, 16
//!   independent samples per pixel.
//! - Integrator: `path` with `max_depth` the depth.
//! - Emitters: `point` lights at NFF's intensities (uncoloured ones
//!   1/sqrt(n)) times pi and the square of their distance to the scene's
//!   centre: Mitsuba's fall off with the square of the distance, NFF's do
//!   not, so they agree at the centre, and its diffuse surfaces reflect
//!   1/pi of what NFF's do. The background is a `constant` emitter, seen
//!   by every ray that leaves the scene as in NFF, but lighting the scene
//!   too, as in NFF it does not.
//! - Materials, approximated: a transmitter is a `dielectric` of its index;
//!   an opaque one with Ks >= Kd a `conductor` (a perfect mirror tinted by
//!   Ks); one with a highlight a `twosided` `roughplastic` (diffuse colour x
//!   Kd, roughness from Shine as for glTF); the rest a `twosided`
//!   `diffuse` of colour x Kd.
//! - Shapes: `sphere`s, open `cylinder`s; everything else (polygons,
//!   patches with their normals, boxes, cones tessellated, planes as large
//!   squares) as one PLY per material.

use super::triangles::{groups, Group};
use super::{falloff_scale, num, ExportOptions, Frame};
use glam::DVec3;
use nffkit_formats::{Material, Scene, Shape};
use nffkit_tracer::prepare::{point_lights, Ambient};
use std::fmt::Write as _;

/// A Mitsuba scene: its XML and the PLY files it names.
pub struct MitsubaScene {
    /// The scene XML.
    pub xml: String,
    /// The PLY files' names (relative to the XML's folder) and bytes.
    pub plys: Vec<(String, Vec<u8>)>,
    /// What Mitsuba's copy approximates.
    pub lost: Vec<String>,
}

/// The scene as Mitsuba 3 XML, its PLY files named `ply_name(material)`.
pub fn write(scene: &Scene, opts: &ExportOptions, ply_name: impl Fn(usize) -> String) -> MitsubaScene {
    let mut x = String::new();
    let _ =
        writeln!(x, "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Written by nffkit's nffconvert. -->");
    let _ = writeln!(x, "<scene version=\"3.0.0\">");
    let _ = writeln!(
        x,
        "  <integrator type=\"path\"><integer name=\"max_depth\" value=\"{}\"/></integrator>",
        opts.depth
    );
    if let Some(v) = &scene.view {
        let f = Frame::of(v, scene);
        let (w, h) = (f.width, f.height);
        let _ = writeln!(x, "  <sensor type=\"perspective\">");
        let _ = writeln!(
            x,
            "    <string name=\"fov_axis\" value=\"y\"/>\n    <float name=\"fov\" value=\"{}\"/>",
            num(f.vertical_fov().to_degrees())
        );
        let _ = writeln!(x, "    <float name=\"near_clip\" value=\"{}\"/>", num(f.near));
        let _ = writeln!(
            x,
            "    <transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>",
            csv(v.from),
            csv(v.at),
            csv(v.up)
        );
        let _ = writeln!(
            x,
            "    <sampler type=\"independent\"><integer name=\"sample_count\" value=\"16\"/></sampler>"
        );
        let _ = writeln!(
            x,
            "    <film type=\"hdrfilm\"><integer name=\"width\" value=\"{w}\"/><integer name=\"height\" value=\"{h}\"/><rfilter type=\"box\"/></film>"
        );
        let _ = writeln!(x, "  </sensor>");
    }
    let (resolved, _) = point_lights(&scene.lights, Ambient::Value(0.0));
    for (l, file) in resolved.iter().zip(&scene.lights) {
        // Mitsuba's diffuse reflects rho/pi of the irradiance; NFF's Kd x
        // colour of the light's intensity: pi more light gives NFF's.
        let i = l.intensity * (falloff_scale(scene, file.position) * std::f64::consts::PI) as f32;
        let _ = writeln!(
            x,
            "  <emitter type=\"point\"><point name=\"position\" value=\"{}\"/><rgb name=\"intensity\" value=\"{}, {}, {}\"/></emitter>",
            csv(file.position),
            i.x,
            i.y,
            i.z
        );
    }
    if let Some(b) = scene.background.filter(|b| b.max_element() > 0.0) {
        let _ = writeln!(
            x,
            "  <emitter type=\"constant\"><rgb name=\"radiance\" value=\"{}\"/></emitter>",
            csv(b)
        );
    }
    let mut used: Vec<usize> =
        scene.primitives.iter().map(|p| p.material.map_or(0, |m| m as usize + 1)).collect();
    used.sort_unstable();
    used.dedup();
    for &m in &used {
        bsdf(m, &super::material(scene, m), &mut x);
    }
    // Spheres and cylinders natively; the rest as triangles.
    let mut rest = scene.clone();
    rest.primitives.clear();
    for p in &scene.primitives {
        let m = p.material.map_or(0, |m| m as usize + 1);
        match &p.shape {
            Shape::Sphere { center, radius } if *radius != 0.0 => {
                let _ = writeln!(
                    x,
                    "  <shape type=\"sphere\"><point name=\"center\" value=\"{}\"/><float name=\"radius\" value=\"{}\"/><ref id=\"m{m}\"/></shape>",
                    csv(*center),
                    num(radius.abs())
                );
            }
            Shape::Sphere { .. } => {}
            Shape::Cone(cone) if cone.base_radius.abs() == cone.apex_radius.abs() => {
                let nffkit_formats::Cone { base, base_radius, apex, .. } = &**cone;
                let _ = writeln!(
                    x,
                    "  <shape type=\"cylinder\"><point name=\"p0\" value=\"{}\"/><point name=\"p1\" value=\"{}\"/><float name=\"radius\" value=\"{}\"/><ref id=\"m{m}\"/></shape>",
                    csv(*base),
                    csv(*apex),
                    num(base_radius.abs())
                );
            }
            _ => rest.primitives.push(p.clone()),
        }
    }
    let (groups, mut lost) = groups(&rest, opts.tessellate);
    let mut files = Vec::new();
    for g in &groups {
        let name = ply_name(g.material);
        let _ = writeln!(
            x,
            "  <shape type=\"ply\"><string name=\"filename\" value=\"{name}\"/><ref id=\"m{}\"/></shape>",
            g.material
        );
        files.push((name, ply(g)));
    }
    let _ = writeln!(x, "</scene>");
    lost.push(
        "NFF's shading: materials become Mitsuba's diffuse, rough plastic, conductor or dielectric, \
         point lights fall off with distance (they match NFF's at the scene's centre), and the \
         background, a constant emitter, lights the scene too"
            .into(),
    );
    MitsubaScene { xml: x, plys: files, lost }
}

fn csv(v: DVec3) -> String {
    format!("{}, {}, {}", num(v.x), num(v.y), num(v.z))
}

/// The BSDF `m{i}` for material `m` (module doc).
fn bsdf(i: usize, m: &Material, x: &mut String) {
    let c = m.color * m.kd;
    let rgb = |v: DVec3| {
        format!("{}, {}, {}", num(v.x.clamp(0.0, 1.0)), num(v.y.clamp(0.0, 1.0)), num(v.z.clamp(0.0, 1.0)))
    };
    let inner = if m.t > 0.0 {
        let _ = writeln!(
            x,
            "  <bsdf type=\"dielectric\" id=\"m{i}\"><float name=\"int_ior\" value=\"{}\"/><float name=\"ext_ior\" value=\"1\"/></bsdf>",
            num(m.ior.max(1.0001))
        );
        return;
    } else if m.ks > 0.0 && m.ks >= m.kd {
        format!(
            "<bsdf type=\"conductor\"><string name=\"material\" value=\"none\"/><rgb name=\"specular_reflectance\" value=\"{}\"/></bsdf>",
            rgb(m.specular * m.ks)
        )
    } else if m.ks > 0.0 {
        let alpha = (2.0 / (m.shine.max(1.0) + 2.0)).sqrt().clamp(0.001, 1.0);
        format!(
            "<bsdf type=\"roughplastic\"><rgb name=\"diffuse_reflectance\" value=\"{}\"/><float name=\"alpha\" value=\"{}\"/></bsdf>",
            rgb(c),
            num(alpha)
        )
    } else {
        format!("<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"{}\"/></bsdf>", rgb(c))
    };
    let _ = writeln!(x, "  <bsdf type=\"twosided\" id=\"m{i}\">{inner}</bsdf>");
}

/// A group as a binary little-endian PLY: positions and normals, then
/// triangles.
fn ply(g: &Group) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment nffkit nffconvert\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        g.positions.len(),
        g.triangles.len()
    )
    .into_bytes();
    for (p, n) in g.positions.iter().zip(&g.normals) {
        let n = if n.length_squared() > 0.0 { n.normalize() } else { DVec3::Z };
        for v in p.as_vec3().to_array().into_iter().chain(n.as_vec3().to_array()) {
            out.extend(v.to_le_bytes());
        }
    }
    for t in &g.triangles {
        out.push(3);
        for i in t {
            out.extend((*i as i32).to_le_bytes());
        }
    }
    out
}
