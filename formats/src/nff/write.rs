//! The NFF writer. [`NffWriter`] streams entities one at a time (generators
//! write millions of spheres without holding them); [`write`] writes a whole
//! [`Scene`], in its own dialect (NFF or the course's P3F).

use crate::scene::{AxisBox, Cone, Dialect, Light, Material, Scene, Shape, View};
use glam::DVec3;
use std::io::{self, Write};

/// The shortest text that parses back to exactly `x`: plain decimals for
/// ordinary magnitudes, C-like exponents (`1.11022e-16`) for tiny and huge
/// ones.
pub fn format_number(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-5..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Writes NFF (or P3F) entities in the spec's layout.
pub struct NffWriter<W: Write> {
    out: W,
    dialect: Dialect,
}

impl<W: Write> NffWriter<W> {
    /// A writer over any byte sink (wrap files in a `BufWriter`).
    pub fn new(out: W) -> Self {
        NffWriter { out, dialect: Dialect::Nff }
    }

    /// A writer of `dialect`: in P3F, the background is `bclr`, views
    /// end with their lens, lights carry their area and `f` its specular
    /// colour (NFF drops what it cannot hold: [`crate::dialect::to_nff`]
    /// says what, and writes the closest NFF).
    pub fn with_dialect(out: W, dialect: Dialect) -> Self {
        NffWriter { out, dialect }
    }

    fn p3f(&self) -> bool {
        self.dialect == Dialect::P3f
    }

    /// The sink back, for flushing or inspection.
    pub fn into_inner(self) -> W {
        self.out
    }

    fn nums(&mut self, xs: &[f64]) -> io::Result<()> {
        for (i, x) in xs.iter().enumerate() {
            if i > 0 {
                self.out.write_all(b" ")?;
            }
            self.out.write_all(format_number(*x).as_bytes())?;
        }
        self.out.write_all(b"\n")
    }

    fn vec(&mut self, prefix: &str, v: DVec3) -> io::Result<()> {
        self.out.write_all(prefix.as_bytes())?;
        self.nums(&v.to_array())
    }

    /// A comment line (`# text`); newlines in `text` start new comment lines.
    pub fn comment(&mut self, text: &str) -> io::Result<()> {
        for line in text.lines() {
            writeln!(self.out, "# {line}")?;
        }
        Ok(())
    }

    /// `b r g b`.
    pub fn background(&mut self, c: DVec3) -> io::Result<()> {
        self.vec(if self.p3f() { "bclr " } else { "b " }, c)
    }

    /// The `v` block.
    pub fn view(&mut self, v: &View) -> io::Result<()> {
        self.out.write_all(b"v\n")?;
        self.vec("from ", v.from)?;
        self.vec("at ", v.at)?;
        self.vec("up ", v.up)?;
        self.out.write_all(b"angle ")?;
        self.nums(&[v.angle])?;
        self.out.write_all(b"hither ")?;
        self.nums(&[v.hither])?;
        writeln!(self.out, "resolution {} {}", v.resolution[0], v.resolution[1])?;
        match v.lens.filter(|_| self.p3f()) {
            Some(lens) => {
                self.out.write_all(b"aperture ")?;
                self.nums(&[lens.aperture])?;
                self.out.write_all(b"focal ")?;
                self.nums(&[lens.focal])
            }
            None => Ok(()),
        }
    }

    /// `l x y z [r g b]`.
    pub fn light(&mut self, l: &Light) -> io::Result<()> {
        if let (Some(area), true) = (l.area, self.p3f()) {
            let (p, a, c) = (l.position, area.facing, l.color.unwrap_or(DVec3::ONE));
            self.out.write_all(b"al ")?;
            return self.nums(&[p.x, p.y, p.z, a.x, a.y, a.z, area.size[0], area.size[1], c.x, c.y, c.z]);
        }
        match l.color {
            None => self.vec("l ", l.position),
            Some(c) => {
                self.out.write_all(b"l ")?;
                self.nums(&[l.position.x, l.position.y, l.position.z, c.x, c.y, c.z])
            }
        }
    }

    /// `f r g b Kd Ks Shine T ior`.
    pub fn material(&mut self, m: &Material) -> io::Result<()> {
        self.out.write_all(b"f ")?;
        let (c, s) = (m.color, m.specular);
        if self.p3f() {
            return self.nums(&[c.x, c.y, c.z, m.kd, s.x, s.y, s.z, m.ks, m.shine, m.t, m.ior]);
        }
        self.nums(&[c.x, c.y, c.z, m.kd, m.ks, m.shine, m.t, m.ior])
    }

    /// `s x y z r`.
    pub fn sphere(&mut self, center: DVec3, radius: f64) -> io::Result<()> {
        self.out.write_all(b"s ")?;
        self.nums(&[center.x, center.y, center.z, radius])
    }

    /// `p n` and one line per vertex.
    pub fn polygon(&mut self, vertices: &[DVec3]) -> io::Result<()> {
        writeln!(self.out, "p {}", vertices.len())?;
        for v in vertices {
            self.nums(&v.to_array())?;
        }
        Ok(())
    }

    /// `pp n` and one line per vertex with its normal.
    pub fn patch(&mut self, vertices: &[DVec3], normals: &[DVec3]) -> io::Result<()> {
        writeln!(self.out, "pp {}", vertices.len())?;
        for (v, n) in vertices.iter().zip(normals) {
            self.nums(&[v.x, v.y, v.z, n.x, n.y, n.z])?;
        }
        Ok(())
    }

    /// P3F's directives and `env` line.
    fn directives(&mut self, scene: &Scene) -> io::Result<()> {
        if let Some(n) = scene.directives.accel {
            writeln!(self.out, "accel {n}")?;
        }
        if let Some(n) = scene.directives.spp {
            writeln!(self.out, "spp {n}")?;
        }
        match &scene.environment {
            Some(dir) => writeln!(self.out, "env {dir}"),
            None => Ok(()),
        }
    }

    /// Any shape. Cones use the spec's three-line layout.
    pub fn shape(&mut self, s: &Shape) -> io::Result<()> {
        match s {
            Shape::Sphere { center, radius } => self.sphere(*center, *radius),
            Shape::Cone(cone) => {
                let Cone { base, base_radius, apex, apex_radius } = &**cone;
                self.out.write_all(b"c\n")?;
                self.nums(&[base.x, base.y, base.z, *base_radius])?;
                self.nums(&[apex.x, apex.y, apex.z, *apex_radius])
            }
            Shape::Polygon { vertices } => self.polygon(vertices),
            Shape::Patch(p) => self.patch(&p.vertices, &p.normals),
            Shape::Plane { points } => {
                let [a, b, c] = &**points;
                self.out.write_all(b"pl ")?;
                self.nums(&[a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z])
            }
            Shape::Box(aabb) => {
                let AxisBox { min, max } = &**aabb;
                self.out.write_all(if self.p3f() { b"box " } else { b"aabb " })?;
                self.nums(&[min.x, min.y, min.z, max.x, max.y, max.z])
            }
        }
    }
}

/// Write a whole scene: background, view, lights, then materials and
/// primitives in order, each `f` line once, before the first primitive that
/// uses it.
pub fn write<W: Write>(scene: &Scene, out: W) -> io::Result<W> {
    let mut w = NffWriter::with_dialect(out, scene.dialect);
    if w.p3f() {
        w.directives(scene)?;
    }
    if let Some(b) = scene.background {
        w.background(b)?;
    }
    if let Some(v) = &scene.view {
        w.view(v)?;
    }
    for l in &scene.lights {
        w.light(l)?;
    }
    let mut written = 0usize; // materials[..written] are out
    for p in &scene.primitives {
        if let Some(m) = p.material {
            while written <= m as usize {
                w.material(&scene.materials[written])?;
                written += 1;
            }
        }
        w.shape(&p.shape)?;
    }
    for m in &scene.materials[written.min(scene.materials.len())..] {
        w.material(m)?;
    }
    Ok(w.into_inner())
}
