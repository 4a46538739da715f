//! SPD `lattice`: a cubic lattice of (size+1)³ spheres joined by
//! 3·size·(size+1)² cylinders, seen from inside its edge: very many
//! objects of two kinds packed evenly, six lights.

use super::out::Out;
use glam::DVec3;
use std::io;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 12;

/// Primitives at `size`.
pub fn primitives(size: u32) -> u64 {
    let (n, m) = (u64::from(size), u64::from(size) + 1);
    m * m * m + 3 * n * m * m
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    let sf = f64::from(size);
    let inv = 1.0 / sf;
    let radius1 = 1.0 / 4.0 / sf;
    let radius2 = 1.0 / 16.0 / sf;
    let delta = (radius1 * (1.0 - ((1.0f64 / 16.0) / (1.0 / 4.0)).sqrt())) * 0.99;
    out.background(nffkit_formats::SPD_SKY)?;
    let mid = (f64::from(size >> 1) + 0.5) * inv;
    let from = DVec3::new(mid, 1.0, 1.0 - 1.0 / f64::from(size << 1));
    let at = DVec3::new(mid, -1.0, -1.0 - 1.0 / f64::from(size << 1));
    out.viewpoint(from, at, DVec3::new(0.2, 1.0, 0.0), 60.0, 0.0, [512, 512])?;
    for l in [
        DVec3::new(2.0, 0.5, 0.5),
        DVec3::new(-1.0, 0.5, 0.5),
        DVec3::new(0.5, 2.0, 0.5),
        DVec3::new(0.5, -1.0, 0.5),
        DVec3::new(0.5, 0.5, 2.0),
        DVec3::new(0.5, 0.5, -1.0),
    ] {
        out.light(l)?;
    }
    let colors = [DVec3::new(0.9, 0.1, 0.1), DVec3::new(0.1, 0.9, 0.1), DVec3::new(0.1, 0.1, 0.9)];
    for x in 0..=size {
        let x0 = f64::from(x) / sf;
        for y in 0..=size {
            let y0 = f64::from(y) / sf;
            for z in 0..=size {
                let z0 = f64::from(z) / sf;
                let centre = DVec3::new(x0, y0, z0);
                out.color(DVec3::splat(0.9), 0.5, 0.5, 37.0, 0.0, 0.0)?;
                out.sphere(centre, radius1)?;
                // A cylinder toward the next sphere along each axis that
                // has one; only that coordinate moves (c + delta and
                // c + inv - delta, added in the C's order).
                for (k, color) in colors.iter().enumerate() {
                    if [x, y, z][k] == size {
                        continue;
                    }
                    out.color(*color, 0.99, 0.0, 0.0, 0.0, 0.0)?;
                    let (mut start, mut end) = (centre, centre);
                    start[k] = centre[k] + delta;
                    end[k] = centre[k] + inv - delta;
                    out.cone(start, radius2, end, radius2)?;
                }
            }
        }
    }
    Ok(())
}
