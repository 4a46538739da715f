//! SPD `tetra`: a tetrahedral pyramid (Glassner's and Kay & Kajiya's test
//! scene), 4^size triangles, mostly empty space: a test of how an
//! accelerator handles many small objects spread through a volume with
//! holes.

use super::out::{Out, SpdOut};
use glam::DVec3;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 6;

/// Triangles at `size`.
pub fn primitives(size: u32) -> u64 {
    4u64.saturating_pow(size)
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(
        DVec3::new(1.022846, -3.177154, -2.174512),
        DVec3::new(-0.004103, -0.004103, 0.216539),
        DVec3::new(-0.816497, -0.816497, 0.816497),
        45.0,
        1.0,
        [512, 512],
    )?;
    out.light(DVec3::new(2.0, -18.0, -5.0))?;
    out.color(DVec3::new(1.0, 0.2, 0.2), 1.0, 0.0, 0.0, 0.0, 0.0)?;
    tetra(out, size, DVec3::ZERO, 1.0)
}

/// The corners of the cube of half-side `half` around `centre` whose signs
/// multiply to +1: a tetrahedron's vertices (or its sub-tetrahedra's
/// centres at half the size), in the C program's loop order.
fn corners(centre: DVec3, half: f64) -> impl Iterator<Item = DVec3> {
    let dirs = [-1.0, 1.0];
    dirs.into_iter()
        .flat_map(move |x| {
            dirs.into_iter().flat_map(move |y| dirs.into_iter().map(move |z| DVec3::new(x, y, z)))
        })
        .filter(|d| d.x * d.y * d.z == 1.0)
        .map(move |d| centre + d * half)
}

fn tetra<W: Write>(out: &mut SpdOut<W>, depth: u32, centre: DVec3, half: f64) -> io::Result<()> {
    if depth <= 1 {
        let p: Vec<DVec3> = corners(centre, half).collect();
        // Faces 0 1 2, 3 2 1, 2 3 0, 1 0 3: vertices (face + k) mod 4,
        // the odd faces reversed.
        for face in 0..4 {
            let mut order = [face, face + 1, face + 2].map(|k| k % 4);
            if face % 2 == 1 {
                order.swap(0, 2);
            }
            out.polygon(&order.map(|k| p[k]))?;
        }
        return Ok(());
    }
    for sub in corners(centre, half / 2.0) {
        tetra(out, depth - 1, sub, half / 2.0)?;
    }
    Ok(())
}
