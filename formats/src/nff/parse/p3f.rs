//! P3F's own entities: the P3D course's `f` with a specular colour, lights
//! that always have a colour, `al` area lights, `mesh`, `env` and the
//! directives `spp` and `accel` (docs/p3f.md says what each means as
//! rendered). `bclr`, `box` and the view's `aperture` and `focal` lines
//! share NFF's code in `mod.rs` and `view.rs`.
//!
//! Students extend the language: values past the course's on an `f` line,
//! and unknown directives, are warned about and skipped unless `--strict`
//! (see `Parser::unknown`).

use super::{geometry_checks, Entity, Parser, Res, What};
use crate::nff::lexer::Token;
use crate::nff::number::parse_number;
use crate::scene::{Light, LightArea, Material, Shape};
use glam::DVec3;

/// The names of the eleven values of a P3F `f` line.
pub(super) const F_NAMES: [&str; 11] = [
    "red",
    "green",
    "blue",
    "Kd",
    "specular red",
    "specular green",
    "specular blue",
    "Ks",
    "Shine",
    "T",
    "index of refraction",
];

/// The most triangles one `mesh` may declare: past this the count is an
/// error before anything is read (a 100,000-triangle dragon is 1/600 of it).
const MAX_MESH_TRIANGLES: u64 = 1 << 26;

/// The course's accelerators by `accel` number.
const ACCELERATORS: [&str; 3] = ["none", "uniform grid", "BVH"];

impl<'a> Parser<'a> {
    /// `f R G B Kd Rs Gs Bs Ks Shine T ior`.
    pub(super) fn p3f_material(&mut self, e: Entity) -> Res<()> {
        let mut v = [0.0; 11];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = self.number(What::P3fValue(i), e).map_err(|mut d| {
                d.note = Some(format!(
                    "a P3F `f` takes 11 numbers: red green blue Kd, specular red green blue Ks, \
                     Shine T index_of_refraction; the one on line {} has {i}",
                    e.line
                ));
                d
            })?;
        }
        self.beyond_the_course(e, "`f` takes 11 numbers")?;
        self.scene.materials.push(Material {
            color: DVec3::new(v[0], v[1], v[2]),
            kd: v[3],
            specular: DVec3::new(v[4], v[5], v[6]),
            ks: v[7],
            shine: v[8],
            t: v[9],
            ior: v[10],
        });
        Ok(())
    }

    /// Numbers left on the line of the entity's last value: a student's
    /// extension, warned about and skipped (an error with --strict).
    fn beyond_the_course(&mut self, e: Entity, takes: &str) -> Res<()> {
        let Some(last) = self.last else { return Ok(()) };
        let mut extra: Vec<Token<'a>> = Vec::new();
        while let Some(t) = self.peek().filter(|t| t.line == last.line && parse_number(t.text).is_some()) {
            self.bump();
            extra.push(t);
        }
        let Some(first) = extra.first() else { return Ok(()) };
        let values = extra.iter().map(|t| t.display()).collect::<Vec<_>>().join(" ");
        let n = extra.len();
        let message = format!(
            "{n} value{} after the course's on this `{}` line ({takes}): `{values}`",
            if n == 1 { "" } else { "s" },
            e.keyword
        );
        if self.opts.strict {
            return Err(self.error_at(first, message + " (--strict)"));
        }
        self.warn(first, message + "; ignored");
        Ok(())
    }

    /// `l X Y Z R G B`: the course's lights always have a colour; one
    /// without is white, with a warning.
    pub(super) fn p3f_light(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        self.warn_if_after_objects(&t, "light");
        let position = self.vec3(What::Text("a light position coordinate"), e)?;
        let color = self.light_color(&t, e)?;
        self.push_light(&t, Light { position, color: Some(color), area: None });
        Ok(())
    }

    /// A light's colour, white when no number follows.
    fn light_color(&mut self, t: &Token<'a>, e: Entity) -> Res<DVec3> {
        if self.peek().is_some_and(|n| parse_number(n.text).is_some()) {
            return self.vec3(What::Text("a light colour component"), e);
        }
        self.warn(t, "a P3F light has a colour (`R G B` after its position); using white".into());
        Ok(DVec3::ONE)
    }

    /// `al X Y Z  Ax Ay Az  W H  R G B`: a W by H rectangle centred on
    /// (X, Y, Z), facing (Ax, Ay, Az).
    pub(super) fn area_light(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        self.warn_if_after_objects(&t, "light");
        let position = self.vec3(What::Text("an area light centre coordinate"), e)?;
        let facing = self.vec3(What::Text("a coordinate of the point the area light faces"), e)?;
        let mut size = [0.0; 2];
        for (s, what) in size.iter_mut().zip(["the area light's width", "the area light's height"]) {
            let at = self.peek();
            *s = self.number(What::Text(what), e)?;
            if *s < 0.0 {
                let at = at.expect("a number was read");
                return Err(self.error_at(&at, format!("{what} must not be negative, found {s}")));
            }
        }
        if facing == position {
            return Err(self.error_at(
                &t,
                "the area light faces its own centre: the point it faces gives its orientation".into(),
            ));
        }
        let color = self.light_color(&t, e)?;
        self.push_light(&t, Light { position, color: Some(color), area: Some(LightArea { facing, size }) });
        Ok(())
    }

    /// `mesh NV NT`, NV vertices, NT triangles of three vertex indices:
    /// 1-based, or negative counting back from the end (-1 is the last).
    /// Each triangle becomes a polygon, so it renders as one.
    pub(super) fn mesh(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let (nv, _) = self.count("a mesh vertex count", 1, super::MAX_VERTICES, e)?;
        let (nt, _) = self.count("a mesh triangle count", 0, MAX_MESH_TRIANGLES, e)?;
        let mut vertices = Vec::with_capacity(nv.min(4096) as usize);
        for i in 0..nv {
            vertices.push(self.vec3(What::MeshVertex { i, n: nv }, e)?);
        }
        for j in 0..nt {
            let mut corners = [DVec3::ZERO; 3];
            let mut first = None;
            for c in &mut corners {
                let (index, at) = self.mesh_index(nv, j, nt, e)?;
                first.get_or_insert(at);
                *c = vertices[index];
            }
            let at = first.unwrap_or(t);
            let corners = corners.to_vec();
            for w in geometry_checks::polygon(&corners, None) {
                self.warn(&at, format!("mesh triangle {} of {nt}: {w}", j + 1));
            }
            self.object(at, Shape::Polygon { vertices: corners });
        }
        Ok(())
    }

    /// One vertex index of triangle `j` of `nt` in a mesh of `nv` vertices,
    /// as a 0-based index, with its token.
    fn mesh_index(&mut self, nv: u64, j: u64, nt: u64, e: Entity) -> Res<(usize, Token<'a>)> {
        if self.peeked.is_none() {
            // The hot path: a whole number in range, read in one pass.
            if let Some((v, t)) = self.lexer.number() {
                let k = v as i64;
                if k as f64 == v && (1..=nv as i64).contains(&k) {
                    self.last = Some(t);
                    return Ok((k as usize - 1, t));
                }
                self.peeked = Some(Some(t));
            }
        }
        let what = format!("a vertex index of mesh triangle {} of {nt}", j + 1);
        let Some(t) = self.peek() else {
            return Err(self.eof_error(What::Text(&what), e));
        };
        let Some(k) = std::str::from_utf8(t.text).ok().and_then(|s| s.parse::<i64>().ok()) else {
            return Err(
                self.error_at(&t, format!("expected {what} (a whole number), found `{}`", t.display()))
            );
        };
        self.bump();
        let index = match k {
            1.. if k as u64 <= nv => k as u64 - 1,
            ..=-1 if k.unsigned_abs() <= nv => nv - k.unsigned_abs(),
            0 => {
                return Err(self.error_at(
                    &t,
                    "vertex index 0: mesh indices count from 1 (or back from -1, the last vertex)".into(),
                ))
            }
            _ => return Err(self.error_at(&t, format!("vertex index {k} is past the mesh's {nv} vertices"))),
        };
        Ok((index as usize, t))
    }

    /// `env DIR`: the folder of the cube map's six images, relative to the
    /// scene file (the renderer loads them).
    pub(super) fn environment(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let what = "the folder of the cube map's six images";
        let dir = match self.peek() {
            Some(d) if d.line == t.line => d,
            Some(d) => {
                let mut err =
                    self.error_at(&d, format!("expected {what} after `env`, found `{}`", d.display()));
                err.note = Some(format!("the `env` on line {} has no folder on its line", e.line));
                return Err(err);
            }
            None => return Err(self.eof_error(What::Text(what), e)),
        };
        self.bump();
        let Ok(path) = std::str::from_utf8(dir.text) else {
            return Err(self.error_at(&dir, "the cube map's folder name is not UTF-8 text".into()));
        };
        if self.scene.environment.is_some() {
            self.warn(&t, "second `env`; it replaces the first".into());
        }
        self.scene.environment = Some(path.to_string());
        Ok(())
    }

    /// `spp N` and `accel N`: defaults for the renderer, which the command
    /// line overrides. `spp 0` asks for the pixel centre alone.
    pub(super) fn directive(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        let spp = e.keyword == "spp";
        // `spp 0` is the course's "one fixed sample per pixel" (its centre).
        let (what, max) = if spp { ("a sample count", 65536) } else { ("an accelerator number", u64::MAX) };
        let (n, at) = self.count(what, 0, max, e)?;
        let previous = if spp {
            self.scene.directives.spp.replace(n as u32)
        } else if n < ACCELERATORS.len() as u64 {
            self.scene.directives.accel.replace(n as u32)
        } else {
            let known = ACCELERATORS.iter().enumerate().map(|(i, a)| format!("{i} {a}")).collect::<Vec<_>>();
            self.warn(
                &at,
                format!(
                    "`accel {n}` names none of the course's accelerators ({}); ignored",
                    known.join(", ")
                ),
            );
            return Ok(());
        };
        if previous.is_some() {
            self.warn(&t, format!("second `{}`; it replaces the first", e.keyword));
        }
        Ok(())
    }
}
