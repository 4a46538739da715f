//! SPD `shells`: a spiral shell of overlapping spheres (after Pickover),
//! about 180·2^size of them, growing exponentially: many intersecting
//! spheres of very different sizes.

use super::out::Out;
use glam::DVec3;
use std::f64::consts::PI;
use std::io;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 5;

// The C program's shape constants (its -g, -a, -b and -e options).
const GAMMA: f64 = 1.0;
const ALPHA: f64 = 0.0;
const BETA: f64 = -2.0;
const EXPONENT: f64 = 0.15;
const K: f64 = 1.0;

/// The spheres' steps at `size` and the range of `i` the C loops over.
/// (In i128, so that any size's count is computed without overflow.)
fn steps(size: u32) -> (i128, std::ops::RangeInclusive<i128>) {
    let steps = (180.0 * 2f64.powf(f64::from(size))) as i128;
    (steps, -steps * 2 / 3..=steps / 3)
}

/// Primitives at `size`.
pub fn primitives(size: u32) -> u64 {
    let (_, range) = steps(size);
    u64::try_from(range.end() - range.start() + 1).unwrap_or(u64::MAX)
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(
        DVec3::new(-6.0, -60.0, 35.0),
        DVec3::new(0.0, 8.0, -15.0),
        DVec3::Z,
        45.0,
        0.5,
        [512, 512],
    )?;
    out.light(DVec3::new(-100.0, -100.0, 100.0))?;
    out.color(DVec3::new(1.0, 0.8, 0.4), 0.8, 0.2, 10.0, 0.0, 1.0)?;
    let (steps, range) = steps(size);
    for i in range {
        let angle = 3.0 * 6.0 * PI * i as f64 / steps as f64;
        let r = K * (EXPONENT * angle).exp();
        let z = if ALPHA > 0.0 { ALPHA * angle } else { BETA * r };
        out.sphere(DVec3::new(r * angle.sin(), r * angle.cos(), z), r / GAMMA)?;
    }
    Ok(())
}
