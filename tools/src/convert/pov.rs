//! POV-Ray 3.7 scene description, written to render as `render` does.
//!
//! - Camera: explicit `direction`, `right` and `up` vectors, the image
//!   spanning exactly the rays `render` traces (NFF's `angle` spans the
//!   outer pixel centres, P3F's the image height: `View::pixel_size`), so
//!   the pixels match whatever POV-Ray's own handedness.
//! - Light: `light_source` at NFF's intensities (uncoloured lights 1/sqrt(n)),
//!   no fading; `--area-light S` a 4x4 jittered `area_light` square facing
//!   each point (`orient`), P3F's `al` its own rectangle.
//! - Finish: `ambient 0`, `diffuse Kd`, `phong Ks phong_size Shine` (POV's
//!   Phong highlight is NFF's `Ks (R.V)^Shine` in the light's colour),
//!   `reflection Ks`; a transmitter `transmit T` in its pigment and
//!   `interior { ior }`. Approximated: POV-Ray dims a transmitting
//!   surface's diffuse and highlight by (1 - T), and lets light through it
//!   to what it shadows; `render` does neither.
//! - `global_settings`: `max_trace_level` from the depth, `adc_bailout`
//!   from `--min-weight` (0 by default: every ray, as `render` traces
//!   them), `assumed_gamma 1`.
//! - Shapes: spheres, open cones and cylinders, boxes, planes for `pl`,
//!   polygons as one `mesh2` per run of one material (triangulated as
//!   `render` does), `pp` normals as `normal_vectors`.

use super::{num, vec3, ExportOptions, Frame};
use glam::DVec3;
use nffkit_formats::polygon::triangulate;
use nffkit_formats::{Material, Scene, Shape, View};
use nffkit_tracer::light::LightRect;
use nffkit_tracer::prepare::{point_lights, Ambient};
use std::io::{self, Write};

/// Write `scene` as POV-Ray SDL; the lines returned say what POV-Ray's
/// copy lacks or approximates.
pub fn write(scene: &Scene, opts: &ExportOptions, out: &mut dyn Write) -> io::Result<Vec<String>> {
    let mut lost = Vec::new();
    writeln!(
        out,
        "// Written by nffkit's nffconvert from an {} scene.",
        scene.dialect.to_string().to_uppercase()
    )?;
    writeln!(
        out,
        "// Render: povray +Iscene.pov +Oscene.png -D +FN File_Gamma=1.0 (+W/+H: the view's size)"
    )?;
    writeln!(out, "#version 3.7;")?;
    writeln!(
        out,
        "global_settings {{ max_trace_level {} adc_bailout {} assumed_gamma 1 ambient_light 0 }}",
        opts.depth,
        num(opts.min_weight)
    )?;
    let bg = scene.background.unwrap_or(DVec3::ZERO);
    writeln!(out, "background {{ color rgb <{}> }}", vec3(bg))?;
    if let Some(v) = &scene.view {
        camera(v, scene, opts, out)?;
        if v.hither > 0.0 {
            lost.push(format!("the hither plane ({}): POV-Ray's camera sees from the eye", num(v.hither)));
        }
    }
    lights(scene, opts, out)?;
    for (i, m) in scene.materials.iter().enumerate() {
        material(i + 1, m, out)?;
    }
    material(0, &Material::default(), out)?;
    shapes(scene, out)?;
    if scene.environment.is_some() {
        lost.push("the cube map: rays that leave the scene see the background colour".into());
    }
    if scene.materials.iter().any(|m| m.specular != DVec3::ONE) {
        lost.push("specular colours: POV-Ray's highlights and reflections here are white".into());
    }
    if scene.materials.iter().any(|m| m.t > 0.0) {
        lost.push(
            "exact transmission: POV-Ray dims a transmitter's diffuse and highlight by (1 - T) and \
             lets light through it into shadows"
                .into(),
        );
    }
    Ok(lost)
}

fn camera(v: &View, scene: &Scene, opts: &ExportOptions, out: &mut dyn Write) -> io::Result<()> {
    let Frame { forward, right, up, pixel, width, height, .. } = Frame::of(v, scene);
    writeln!(out, "camera {{\n  perspective\n  location <{}>", vec3(v.from))?;
    writeln!(out, "  direction <{}>", vec3(forward))?;
    writeln!(out, "  right <{}>", vec3(right * pixel * width as f64))?;
    writeln!(out, "  up <{}>", vec3(up * pixel * height as f64))?;
    if let Some(r) = opts.aperture.filter(|&a| a > 0.0) {
        // POV-Ray's aperture is the lens's diameter.
        let focus = opts.focus.unwrap_or((v.at - v.from).length());
        writeln!(
            out,
            "  aperture {}\n  focal_point <{}>\n  blur_samples 16\n  confidence 1\n  variance 0",
            num(2.0 * r),
            vec3(v.from + forward * focus)
        )?;
    }
    writeln!(out, "}}")
}

fn lights(scene: &Scene, opts: &ExportOptions, out: &mut dyn Write) -> io::Result<()> {
    let (resolved, _) = point_lights(&scene.lights, Ambient::Value(0.0));
    for (l, file) in resolved.iter().zip(&scene.lights) {
        let i = l.intensity;
        write!(out, "light_source {{ <{}> color rgb <{}, {}, {}>", vec3(file.position), i.x, i.y, i.z)?;
        if let Some(a) = file.area {
            let n = (a.facing - file.position).normalize_or_zero();
            let r = LightRect::facing(n.as_vec3a(), a.size[0] as f32, a.size[1] as f32);
            let d = |v: glam::Vec3A| vec3(DVec3::new(v.x as f64, v.y as f64, v.z as f64));
            write!(out, " area_light <{}>, <{}>, 4, 4 jitter adaptive 0", d(r.u), d(r.v))?;
        } else if let Some(s) = opts.area_light.filter(|&s| s > 0.0) {
            write!(out, " area_light <{0}, 0, 0>, <0, 0, {0}>, 4, 4 jitter orient adaptive 0", num(s))?;
        }
        writeln!(out, " }}")?;
    }
    Ok(())
}

/// `#declare Ti` (texture) and `Ii` (interior) for material `i` (0: the
/// default before any `f`).
fn material(i: usize, m: &Material, out: &mut dyn Write) -> io::Result<()> {
    let c = m.color;
    let transmit = if m.t > 0.0 { format!(" transmit {}", num(m.t.min(1.0))) } else { String::new() };
    writeln!(out, "#declare T{i} = texture {{")?;
    writeln!(out, "  pigment {{ color rgb <{}>{transmit} }}", vec3(c))?;
    write!(out, "  finish {{ ambient 0 diffuse {}", num(m.kd))?;
    if m.ks > 0.0 {
        write!(out, " phong {} phong_size {} reflection {}", num(m.ks), num(m.shine), num(m.ks))?;
    }
    writeln!(out, " }}\n}}")?;
    writeln!(out, "#declare I{i} = interior {{ ior {} }}", num(if m.t > 0.0 { m.ior } else { 1.0 }))
}

/// The shapes, each with its material; the polygons of a run of one
/// material in one `mesh2`.
fn shapes(scene: &Scene, out: &mut dyn Write) -> io::Result<()> {
    let mut mesh = Mesh2::default();
    let mut current = None;
    for p in &scene.primitives {
        let m = p.material.map_or(0, |m| m as usize + 1);
        if current != Some(m) {
            mesh.flush(current.unwrap_or(0), out)?;
            current = Some(m);
        }
        let with = format!("texture {{ T{m} }} interior {{ I{m} }}");
        match &p.shape {
            Shape::Sphere { center, radius } if *radius != 0.0 => {
                writeln!(out, "sphere {{ <{}>, {} {with} }}", vec3(*center), num(radius.abs()))?
            }
            Shape::Cone(cone) => {
                let nffkit_formats::Cone { base, base_radius, apex, apex_radius } = &**cone;
                let (r0, r1) = (base_radius.abs(), apex_radius.abs());
                if r0 == r1 {
                    writeln!(
                        out,
                        "cylinder {{ <{}>, <{}>, {} open {with} }}",
                        vec3(*base),
                        vec3(*apex),
                        num(r0)
                    )?
                } else if r0 > 0.0 || r1 > 0.0 {
                    writeln!(
                        out,
                        "cone {{ <{}>, {}, <{}>, {} open {with} }}",
                        vec3(*base),
                        num(r0),
                        vec3(*apex),
                        num(r1)
                    )?
                }
            }
            Shape::Polygon { vertices } => mesh.add(vertices, None),
            Shape::Patch(p) => mesh.add(&p.vertices, Some(&p.normals)),
            Shape::Plane { points } => {
                let [a, b, c] = &**points;
                let n = (*b - *a).cross(*c - *a).normalize();
                if n.is_finite() {
                    writeln!(out, "plane {{ <{}>, {} {with} }}", vec3(n), num(n.dot(*a)))?
                }
            }
            Shape::Box(b) => writeln!(out, "box {{ <{}>, <{}> {with} }}", vec3(b.min), vec3(b.max))?,
            Shape::Sphere { .. } => {}
        }
    }
    mesh.flush(current.unwrap_or(0), out)
}

/// The triangles of a run of polygons of one material.
#[derive(Default)]
struct Mesh2 {
    vertices: Vec<DVec3>,
    normals: Vec<DVec3>,
    faces: Vec<[usize; 3]>,
    /// Faces whose corners have normals (`pp`), as indices into `faces`;
    /// the others are flat.
    smooth: Vec<bool>,
}

impl Mesh2 {
    fn add(&mut self, vertices: &[DVec3], normals: Option<&Vec<DVec3>>) {
        let base = self.vertices.len();
        self.vertices.extend_from_slice(vertices);
        match normals {
            Some(n) => self.normals.extend(n.iter().map(|n| n.normalize_or_zero())),
            None => self.normals.extend(std::iter::repeat_n(DVec3::ZERO, vertices.len())),
        }
        for t in triangulate(vertices) {
            self.faces.push(t.map(|i| base + i as usize));
            self.smooth.push(normals.is_some());
        }
    }

    fn flush(&mut self, m: usize, out: &mut dyn Write) -> io::Result<()> {
        if self.faces.is_empty() {
            self.vertices.clear();
            self.normals.clear();
            return Ok(());
        }
        let smooth = self.smooth.iter().any(|&s| s);
        writeln!(out, "mesh2 {{\n  vertex_vectors {{ {}", self.vertices.len())?;
        for v in &self.vertices {
            writeln!(out, "    <{}>", vec3(*v))?;
        }
        writeln!(out, "  }}")?;
        if smooth {
            // Flat faces get their own normal at every corner.
            let mut normals = self.normals.clone();
            let mut normal_faces = Vec::with_capacity(self.faces.len());
            for (f, &s) in self.faces.iter().zip(&self.smooth) {
                if s {
                    normal_faces.push(*f);
                } else {
                    let [a, b, c] = f.map(|i| self.vertices[i]);
                    normals.push((b - a).cross(c - a).normalize_or_zero());
                    let k = normals.len() - 1;
                    normal_faces.push([k; 3]);
                }
            }
            writeln!(out, "  normal_vectors {{ {}", normals.len())?;
            for n in &normals {
                writeln!(out, "    <{}>", vec3(*n))?;
            }
            writeln!(out, "  }}")?;
            self.faces_block("face_indices", &self.faces, out)?;
            self.faces_block("normal_indices", &normal_faces, out)?;
        } else {
            self.faces_block("face_indices", &self.faces, out)?;
        }
        writeln!(out, "  texture {{ T{m} }} interior {{ I{m} }}\n}}")?;
        *self = Mesh2::default();
        Ok(())
    }

    fn faces_block(&self, name: &str, faces: &[[usize; 3]], out: &mut dyn Write) -> io::Result<()> {
        writeln!(out, "  {name} {{ {}", faces.len())?;
        for [a, b, c] in faces {
            writeln!(out, "    <{a}, {b}, {c}>")?;
        }
        writeln!(out, "  }}")
    }
}
