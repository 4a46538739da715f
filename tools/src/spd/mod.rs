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
pub(crate) mod tessellate;
pub mod tetra;
pub mod tree;

pub use out::{Out, Precision, SpdOut};

use anyhow::bail;
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

/// What the program of one database is: its name, default size, count
/// formula and generator (streaming to any writer).
struct Program {
    name: &'static str,
    default_size: u32,
    primitives: fn(u32) -> u64,
    write: fn(&mut Out<'_>, u32) -> io::Result<()>,
}

/// The programs, in [`Database`]'s order.
const PROGRAMS: [Program; 11] = [
    Program {
        name: "balls",
        default_size: balls::DEFAULT_SIZE,
        primitives: balls::primitives,
        write: balls::write,
    },
    Program {
        name: "gears",
        default_size: gears::DEFAULT_SIZE,
        primitives: gears::primitives,
        write: gears::write,
    },
    Program {
        name: "jacks",
        default_size: jacks::DEFAULT_SIZE,
        primitives: jacks::primitives,
        write: jacks::write,
    },
    Program {
        name: "lattice",
        default_size: lattice::DEFAULT_SIZE,
        primitives: lattice::primitives,
        write: lattice::write,
    },
    Program {
        name: "mount",
        default_size: mount::DEFAULT_SIZE,
        primitives: mount::primitives,
        write: mount::write,
    },
    Program {
        name: "rings",
        default_size: rings::DEFAULT_SIZE,
        primitives: rings::primitives,
        write: rings::write,
    },
    Program {
        name: "shells",
        default_size: shells::DEFAULT_SIZE,
        primitives: shells::primitives,
        write: shells::write,
    },
    Program {
        name: "sombrero",
        default_size: sombrero::DEFAULT_SIZE,
        primitives: sombrero::primitives,
        write: sombrero::write,
    },
    Program {
        name: "teapot",
        default_size: teapot::DEFAULT_SIZE,
        primitives: teapot::primitives,
        write: teapot::write,
    },
    Program {
        name: "tetra",
        default_size: tetra::DEFAULT_SIZE,
        primitives: tetra::primitives,
        write: tetra::write,
    },
    Program {
        name: "tree",
        default_size: tree::DEFAULT_SIZE,
        primitives: tree::primitives,
        write: tree::write,
    },
];

impl Database {
    fn program(self) -> &'static Program {
        &PROGRAMS[self as usize]
    }

    /// The C program's name.
    pub fn name(self) -> &'static str {
        self.program().name
    }

    /// The C program's default size (`-s`).
    pub fn default_size(self) -> u32 {
        self.program().default_size
    }

    /// Primitives written at `size`, by the formula in the C program's
    /// header.
    pub fn primitives(self, size: u32) -> u64 {
        (self.program().primitives)(size)
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
        mut w: W,
    ) -> io::Result<W> {
        let mut out = SpdOut::new(&mut w as &mut dyn Write, precision);
        out.tessellate(tessellate);
        (self.program().write)(&mut out, size)?;
        out.finish()?;
        Ok(w)
    }
}

/// What to generate: `spd`'s options, declared once for the binary and the
/// golden catalogue.
#[derive(Debug, Clone, clap::Args)]
pub struct Generate {
    /// The database.
    #[arg(required_unless_present = "list")]
    pub database: Option<Database>,
    /// Size (the SPD's -s): how finely the scene is divided [default: the
    /// database's own, see --list].
    #[arg(short, long)]
    pub size: Option<u32>,
    /// Write spheres, cylinders and cones as smooth-shaded triangles (the
    /// SPD's -t), RES × RES quadrilaterals per cube face of a sphere and
    /// 4·RES sides per cylinder or cone [default RES: 3, the SPD's; jacks
    /// always uses 2, as its program does].
    #[arg(short, long, value_name = "RES", num_args = 0..=1,
          value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub tessellate: Option<Option<u32>>,
    /// How numbers are written.
    #[arg(long, value_enum, default_value_t = Precision::Full)]
    pub precision: Precision,
    /// List the databases, their default and largest sizes and their
    /// primitive counts.
    #[arg(long, conflicts_with_all = ["database", "size"])]
    pub list: bool,
}

impl Generate {
    /// The database and size asked for, checked.
    pub fn checked(&self) -> anyhow::Result<(Database, u32)> {
        let Some(db) = self.database else { bail!("name a database (spd --list shows them)") };
        let size = self.size.unwrap_or(db.default_size());
        if !(1..=db.max_size()).contains(&size) {
            bail!(
                "--size {size}: {} takes sizes 1 to {} (size {} makes {} primitives)",
                db.name(),
                db.max_size(),
                db.max_size(),
                db.primitives(db.max_size())
            );
        }
        Ok((db, size))
    }

    /// The tessellation resolution asked for, if any (`--tessellate`
    /// alone: [`DEFAULT_RESOLUTION`]).
    pub fn resolution(&self) -> Option<u32> {
        self.tessellate.map(|res| res.unwrap_or(DEFAULT_RESOLUTION))
    }

    /// Write the scene to `w`.
    pub fn write<W: Write>(&self, w: W) -> anyhow::Result<W> {
        let (db, size) = self.checked()?;
        Ok(db.write(size, self.precision, self.resolution(), w)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    #[test]
    fn each_database_finds_its_own_program() {
        for db in Database::value_variants() {
            assert_eq!(db.name(), db.to_possible_value().unwrap().get_name());
        }
    }
}
