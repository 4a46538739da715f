//! The SPD library's NFF output (`lib_output_*` in the SPD's libpr*.c and
//! libply.c), line for line, streamed: each entity goes to the writer as it
//! is made, so a database of millions of primitives never sits in memory.

use super::matrix::{invert, transform_normal, transform_point, Matrix};
use super::number::push_g;
use super::tessellate::{self, Patch};
use glam::DVec3;
use nffkit_formats::nff::format_number;
use std::io::{self, Write};

/// How numbers are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Precision {
    /// As the SPD's C programs write them (`%g`: six significant digits),
    /// byte for byte.
    Spd,
    /// Every digit needed to read the same double back.
    #[default]
    Full,
}

/// The SPD's degenerate-edge tolerance (def.h's EPSILON2 off the Mac).
const EPSILON2: f64 = 1.0e-6;

/// The stream every database writes to (any writer, behind a reference).
pub type Out<'a> = SpdOut<&'a mut dyn Write>;

/// An NFF stream written the SPD library's way.
pub struct SpdOut<W: Write> {
    w: W,
    precision: Precision,
    line: String,
    recent: Recent,
    /// Curved primitives as triangles at this resolution (the SPD's -t).
    tessellate: Option<u32>,
    /// The library's current transform (libtx.c), when one is active.
    transform: Option<Transform>,
}

/// A transform and what writing through it needs.
struct Transform {
    m: Matrix,
    /// For normals: the inverse, used transposed.
    inverse: Matrix,
    /// Radii scale by the length of the first row (libtx.c
    /// `lib_tx_unwind`'s X scale).
    scale: f64,
}

/// The text of recently written numbers, by their bits: the databases
/// repeat values (grid coordinates, shared corners), and an exact decimal
/// conversion costs far more than a lookup.
struct Recent {
    slots: Vec<Slot>,
}

/// A number's bits and its text; an empty slot has length 0, which no
/// number's text has.
#[derive(Clone, Copy)]
struct Slot {
    bits: u64,
    len: u8,
    text: [u8; 23],
}

impl Recent {
    /// Slots, indexed by the top 12 bits of a multiplicative hash.
    const SLOTS: usize = 1 << 12;

    fn new() -> Recent {
        Recent { slots: vec![Slot { bits: 0, len: 0, text: [0; 23] }; Self::SLOTS] }
    }

    /// Append `x` in `%g` to `out`, from the table when it is there.
    fn push(&mut self, out: &mut String, x: f64) {
        let bits = x.to_bits();
        let slot = &mut self.slots[(bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 52) as usize];
        if slot.bits == bits && slot.len > 0 {
            out.push_str(std::str::from_utf8(&slot.text[..slot.len as usize]).expect("stored from a str"));
            return;
        }
        let start = out.len();
        push_g(out, x);
        let text = &out.as_bytes()[start..];
        // %g's longest text, -1.23457e-308, is 13 bytes.
        *slot = Slot { bits, len: text.len() as u8, text: [0; 23] };
        slot.text[..text.len()].copy_from_slice(text);
    }
}

impl<W: Write> SpdOut<W> {
    /// Write to `w` with numbers in `precision`.
    pub fn new(w: W, precision: Precision) -> Self {
        SpdOut {
            w,
            precision,
            line: String::with_capacity(128),
            recent: Recent::new(),
            tessellate: None,
            transform: None,
        }
    }

    /// Write curved primitives as triangles at resolution `res` (the
    /// SPD's `-t res`), or as themselves (`None`, its `-c`).
    pub fn tessellate(&mut self, res: Option<u32>) {
        self.tessellate = res;
    }

    /// The resolution curved primitives are tessellated at, if they are.
    pub fn tessellation(&self) -> Option<u32> {
        self.tessellate
    }

    /// Write what follows through `m` (the library's current transform), or
    /// as given (`None`).
    pub fn set_transform(&mut self, m: Option<&Matrix>) {
        self.transform = m.map(|m| {
            let row = DVec3::new(m[0][0] / m[3][3], m[0][1] / m[3][3], m[0][2] / m[3][3]);
            Transform { m: *m, inverse: invert(m), scale: row.dot(row).sqrt() }
        });
    }

    /// The writer, flushed.
    pub fn finish(mut self) -> io::Result<W> {
        self.w.flush()?;
        Ok(self.w)
    }

    fn num(&mut self, x: f64) {
        match self.precision {
            Precision::Spd => self.recent.push(&mut self.line, x),
            Precision::Full => self.line.push_str(&format_number(x)),
        }
    }

    /// The keyword (if any) then the numbers, space separated, and a
    /// newline.
    fn entity(&mut self, keyword: &str, numbers: &[f64]) -> io::Result<()> {
        self.line.clear();
        self.line.push_str(keyword);
        for &x in numbers {
            if !self.line.is_empty() {
                self.line.push(' ');
            }
            self.num(x);
        }
        self.line.push('\n');
        self.w.write_all(self.line.as_bytes())
    }

    /// `lib_output_background_color`.
    pub fn background(&mut self, c: DVec3) -> io::Result<()> {
        self.entity("b", &c.to_array())
    }

    /// `lib_output_viewpoint` (NFF writes neither the aspect ratio nor
    /// anything but the resolution's integers).
    pub fn viewpoint(
        &mut self,
        from: DVec3,
        at: DVec3,
        up: DVec3,
        angle: f64,
        hither: f64,
        resolution: [u32; 2],
    ) -> io::Result<()> {
        self.w.write_all(b"v\n")?;
        self.entity("from", &from.to_array())?;
        self.entity("at", &at.to_array())?;
        self.entity("up", &up.to_array())?;
        self.entity("angle", &[angle])?;
        self.entity("hither", &[hither])?;
        writeln!(self.w, "resolution {} {}", resolution[0], resolution[1])
    }

    /// `lib_output_light` (NFF: the position only).
    pub fn light(&mut self, p: DVec3) -> io::Result<()> {
        self.entity("l", &p.to_array())
    }

    /// `lib_output_color`: the Phong exponent from the highlight's
    /// half-angle `ang` in degrees (0: 100000, 90 or more: 1, else
    /// log(1/2) / log(cos ang)).
    pub fn color(&mut self, c: DVec3, kd: f64, ks: f64, ang: f64, kt: f64, ior: f64) -> io::Result<()> {
        let radians = std::f64::consts::PI * ang / 180.0;
        let phong = if radians <= 0.0 {
            100000.0
        } else if radians >= std::f64::consts::PI / 2.0 {
            1.0
        } else {
            0.5f64.ln() / radians.cos().ln()
        };
        self.entity("f", &[c.x, c.y, c.z, kd, ks, phong, kt, ior])
    }

    /// `lib_output_sphere`: `s`, or triangles when tessellating.
    pub fn sphere(&mut self, centre: DVec3, radius: f64) -> io::Result<()> {
        if let Some(res) = self.tessellate {
            let mut result = Ok(());
            tessellate::sphere(centre, radius, res, |p| {
                if result.is_ok() {
                    result = self.transformed_patch(p);
                }
            });
            return result;
        }
        let (centre, radius) = match &self.transform {
            Some(t) => (transform_point(centre, &t.m), radius * t.scale),
            None => (centre, radius),
        };
        self.entity("s", &[centre.x, centre.y, centre.z, radius])
    }

    /// `lib_output_cylcone`: `c`, or triangles when tessellating.
    pub fn cone(&mut self, base: DVec3, base_radius: f64, apex: DVec3, apex_radius: f64) -> io::Result<()> {
        if let Some(res) = self.tessellate {
            let mut result = Ok(());
            tessellate::cone(base, base_radius, apex, apex_radius, res, |p| {
                if result.is_ok() {
                    result = self.transformed_patch(p);
                }
            });
            return result;
        }
        let (base, base_radius, apex, apex_radius) = match &self.transform {
            Some(t) => (
                transform_point(base, &t.m),
                base_radius * t.scale,
                transform_point(apex, &t.m),
                apex_radius * t.scale,
            ),
            None => (base, base_radius, apex, apex_radius),
        };
        self.entity("c", &[base.x, base.y, base.z, base_radius, apex.x, apex.y, apex.z, apex_radius])
    }

    /// A tessellated primitive's triangle through the current transform
    /// (libply.c `split_polygon`: points by it, normals by its inverse
    /// transposed, not renormalised).
    fn transformed_patch(&mut self, (v, n): Patch) -> io::Result<()> {
        match &self.transform {
            Some(t) => {
                let v = v.map(|p| transform_point(p, &t.m));
                let n = n.map(|p| transform_normal(p, &t.inverse));
                self.patch(&v, &n)
            }
            None => self.patch(&v, &n),
        }
    }

    /// `lib_output_polygon`: adjacent vertices closer than EPSILON2 are
    /// merged first, and what has fewer than three left is not written.
    pub fn polygon(&mut self, vertices: &[DVec3]) -> io::Result<()> {
        let n = vertices.len();
        if (0..n).all(|i| (vertices[i] - vertices[(i + 1) % n]).length() >= EPSILON2) {
            return self.write_polygon(vertices);
        }
        let mut v: Vec<DVec3> = vertices.to_vec();
        let mut i = 0;
        while i < v.len() {
            if (v[i] - v[(i + 1) % v.len()]).length() < EPSILON2 {
                v.remove(i);
            } else {
                i += 1;
            }
        }
        if v.len() < 3 {
            return Ok(());
        }
        self.write_polygon(&v)
    }

    /// `lib_output_polypatch` of a triangle: `pp 3`, each corner with its
    /// normal.
    pub fn patch(&mut self, v: &[DVec3; 3], n: &[DVec3; 3]) -> io::Result<()> {
        self.w.write_all(b"pp 3\n")?;
        for (p, m) in v.iter().zip(n) {
            self.entity("", &[p.x, p.y, p.z, m.x, m.y, m.z])?;
        }
        Ok(())
    }

    fn write_polygon(&mut self, v: &[DVec3]) -> io::Result<()> {
        writeln!(self.w, "p {}", v.len())?;
        for p in v {
            self.entity("", &p.to_array())?;
        }
        Ok(())
    }
}
