//! The Standard Procedural Databases (Eric Haines, 1987; CC0): the SPD's
//! test scenes generated as its C programs generate them, streamed as NFF.
//! [`out`] is the SPD library's NFF output, [`number`] its `%g`, and each
//! database has its module, a port of its C program that keeps every
//! arithmetic step, so that with [`Precision::Spd`] the output is the C
//! program's byte for byte.

pub mod balls;
pub mod gears;
pub mod jacks;
pub mod lattice;
mod matrix;
pub mod mount;
pub mod number;
pub mod out;
mod random;
pub mod rings;
pub mod shells;
pub mod sombrero;
pub mod teapot;
mod teapot_data;
mod tessellate;
pub mod tetra;
pub mod tree;

pub use out::{Precision, SpdOut};

use std::io::{self, Write};

/// The most primitives a database is generated with: a billion (tens of
/// gigabytes of text; streamed, it needs no memory, but the disk).
pub const MAX_PRIMITIVES: u64 = 1_000_000_000;

/// The SPD's tessellation resolution when `-t` names none (lib.h's
/// OUTPUT_RESOLUTION).
pub const DEFAULT_RESOLUTION: u32 = 3;

/// A database of the SPD.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, strum::VariantArray)]
pub enum Database {
    /// The sphereflake: 91 spheres at size 2, 7381 at 4, on a floor;
    /// reflection between many spheres (the P3D report's balls_low, medium
    /// and high are sizes 1, 2 and 4).
    Balls,
    /// A block of intermeshing gears, some of glass: concave 144-vertex
    /// polygons, refraction, reflections between close surfaces.
    Gears,
    /// Jacks (crossed cylinders capped by spheres) with smaller jacks in
    /// their octants: objects placed through a transform stack.
    Jacks,
    /// A cubic lattice of spheres joined by cylinders, seen from its edge:
    /// very many evenly packed objects.
    Lattice,
    /// Fractal terrain, 2·4^size small triangles of every orientation,
    /// seen through four glass spheres (refraction; the P3D report's
    /// Table 1 scenes are sizes 1, 5 and 7).
    Mount,
    /// Rings of cylinders and spheres in a pyramid of layers before a
    /// wall: many cylinders, and their shadows on each other.
    Rings,
    /// A spiral shell of about 180·2^size overlapping spheres of fast
    /// growing size.
    Shells,
    /// A height field of a rippled sombrero function: 2(w − 1)² small
    /// smooth triangles, w = 32·2^(size−1).
    Sombrero,
    /// The Utah teapot as smooth-shaded triangles on a checkerboard: many
    /// small patches with normals, seen from both sides.
    Teapot,
    /// A tetrahedral pyramid (Glassner; Kay and Kajiya): 4^size triangles
    /// in mostly empty space, a test of accelerators on sparse scenes.
    Tetra,
    /// A tree of 2^(size+1) − 1 cone branches and sphere joints on a
    /// field, under seven lights: long thin cones at every angle.
    Tree,
}

impl Database {
    /// The C program's name.
    pub fn name(self) -> &'static str {
        match self {
            Database::Balls => "balls",
            Database::Mount => "mount",
            Database::Gears => "gears",
            Database::Jacks => "jacks",
            Database::Lattice => "lattice",
            Database::Rings => "rings",
            Database::Shells => "shells",
            Database::Sombrero => "sombrero",
            Database::Teapot => "teapot",
            Database::Tetra => "tetra",
            Database::Tree => "tree",
        }
    }

    /// The C program's default size (`-s`).
    pub fn default_size(self) -> u32 {
        match self {
            Database::Balls => balls::DEFAULT_SIZE,
            Database::Mount => mount::DEFAULT_SIZE,
            Database::Gears => gears::DEFAULT_SIZE,
            Database::Jacks => jacks::DEFAULT_SIZE,
            Database::Lattice => lattice::DEFAULT_SIZE,
            Database::Rings => rings::DEFAULT_SIZE,
            Database::Shells => shells::DEFAULT_SIZE,
            Database::Sombrero => sombrero::DEFAULT_SIZE,
            Database::Teapot => teapot::DEFAULT_SIZE,
            Database::Tetra => tetra::DEFAULT_SIZE,
            Database::Tree => tree::DEFAULT_SIZE,
        }
    }

    /// Primitives written at `size`, by the formula in the C program's
    /// header.
    pub fn primitives(self, size: u32) -> u64 {
        match self {
            Database::Balls => balls::primitives(size),
            Database::Mount => mount::primitives(size),
            Database::Gears => gears::primitives(size),
            Database::Jacks => jacks::primitives(size),
            Database::Lattice => lattice::primitives(size),
            Database::Rings => rings::primitives(size),
            Database::Shells => shells::primitives(size),
            Database::Sombrero => sombrero::primitives(size),
            Database::Teapot => teapot::primitives(size),
            Database::Tetra => tetra::primitives(size),
            Database::Tree => tree::primitives(size),
        }
    }

    /// The largest size of at most [`MAX_PRIMITIVES`] primitives.
    pub fn max_size(self) -> u32 {
        (1..=4096).take_while(|&s| self.primitives(s) <= MAX_PRIMITIVES).last().unwrap_or(1)
    }

    /// Write the database at `size` to `w`, curved primitives as
    /// themselves or (`tessellate`) as triangles at that resolution.
    pub fn write<W: Write>(
        self,
        size: u32,
        precision: Precision,
        tessellate: Option<u32>,
        w: W,
    ) -> io::Result<W> {
        let mut out = SpdOut::new(w, precision);
        out.tessellate(tessellate);
        match self {
            Database::Balls => balls::write(&mut out, size)?,
            Database::Mount => mount::write(&mut out, size)?,
            Database::Gears => gears::write(&mut out, size)?,
            Database::Jacks => jacks::write(&mut out, size)?,
            Database::Lattice => lattice::write(&mut out, size)?,
            Database::Rings => rings::write(&mut out, size)?,
            Database::Shells => shells::write(&mut out, size)?,
            Database::Sombrero => sombrero::write(&mut out, size)?,
            Database::Teapot => teapot::write(&mut out, size)?,
            Database::Tetra => tetra::write(&mut out, size)?,
            Database::Tree => tree::write(&mut out, size)?,
        }
        out.finish()
    }
}
