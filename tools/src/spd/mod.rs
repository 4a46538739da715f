//! The Standard Procedural Databases (Eric Haines, 1987; CC0): the SPD's
//! test scenes generated as its C programs generate them, streamed as NFF.
//! [`out`] is the SPD library's NFF output, [`number`] its `%g`, and each
//! database has its module, a port of its C program that keeps every
//! arithmetic step, so that with [`Precision::Spd`] the output is the C
//! program's byte for byte.

pub mod mount;
pub mod number;
pub mod out;
mod random;
pub mod tetra;

pub use out::{Precision, SpdOut};

use std::io::{self, Write};

/// A database of the SPD.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, strum::VariantArray)]
pub enum Database {
    /// Fractal terrain, 2·4^size small triangles of every orientation,
    /// seen through four glass spheres (refraction; the P3D report's
    /// Table 1 scenes are sizes 1, 5 and 7).
    Mount,
    /// A tetrahedral pyramid (Glassner; Kay and Kajiya): 4^size triangles
    /// in mostly empty space, a test of accelerators on sparse scenes.
    Tetra,
}

impl Database {
    /// The C program's name.
    pub fn name(self) -> &'static str {
        match self {
            Database::Mount => "mount",
            Database::Tetra => "tetra",
        }
    }

    /// The C program's default size (`-s`).
    pub fn default_size(self) -> u32 {
        match self {
            Database::Mount => mount::DEFAULT_SIZE,
            Database::Tetra => tetra::DEFAULT_SIZE,
        }
    }

    /// Primitives written at `size`, by the formula in the C program's
    /// header.
    pub fn primitives(self, size: u32) -> u64 {
        match self {
            Database::Mount => mount::primitives(size),
            Database::Tetra => tetra::primitives(size),
        }
    }

    /// The largest size whose output stays within reason (about 100
    /// million primitives).
    pub fn max_size(self) -> u32 {
        (1..=20).take_while(|&s| self.primitives(s) <= 100_000_000).last().unwrap_or(1)
    }

    /// Write the database at `size` to `w`.
    pub fn write<W: Write>(self, size: u32, precision: Precision, w: W) -> io::Result<W> {
        let mut out = SpdOut::new(w, precision);
        match self {
            Database::Mount => mount::write(&mut out, size)?,
            Database::Tetra => tetra::write(&mut out, size)?,
        }
        out.finish()
    }
}
