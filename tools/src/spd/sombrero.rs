//! SPD `sombrero`: a height field of the function
//! 3·cos(2πr)·e^(−r)/3 over a square, as 2·(w − 1)² triangles for a w × w
//! grid (w = 32·2^(size−1)): a dense, smooth, rippled surface.

use super::out::{Out, SpdOut};
use glam::DVec3;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 1;

/// Grid points per side at `size`.
fn width(size: u32) -> u64 {
    2u64.saturating_pow(size - 1).saturating_mul(32)
}

/// Primitives at `size`.
pub fn primitives(size: u32) -> u64 {
    let w = width(size) - 1;
    w.saturating_mul(w).saturating_mul(2)
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(0.0, 5.0, -8.0), DVec3::ZERO, DVec3::Z, 40.0, 0.01, [512, 512])?;
    out.light(DVec3::new(10.0, 10.0, -10.0))?;
    out.color(DVec3::new(1.0, 0.1, 0.1), 0.8, 0.0, 40.0, 0.0, 1.0)?;
    let w = width(size) as usize;
    let data = sombrero(w, -4.0, 4.0, -4.0, 4.0);
    height_field(out, &data, w, [-4.0, 4.0], -3.0, [-4.0, 4.0])
}

/// π as sombrero.c writes it (12 digits: the heights depend on them).
#[allow(clippy::approx_constant)]
const PI_SOMBRERO: f64 = 3.14159265358;

/// The heights, row by row (sombrero.c `create_sombrero`: the
/// coordinates are stepped by repeated addition, and each height is
/// stored as a float).
fn sombrero(w: usize, x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<f32> {
    let (a, b, c) = (1.0, 1.0, 3.0);
    let two_pi_a = 2.0 * PI_SOMBRERO * a;
    let dx = (x1 - x0) / w as f64;
    let dy = (y1 - y0) / w as f64;
    let mut data = Vec::with_capacity(w * w);
    let mut y = y0;
    for _ in 0..w {
        let mut x = x0;
        for _ in 0..w {
            let r = (x * x + y * y).sqrt();
            data.push((c * (two_pi_a * r).cos() * (-b * (x * x + y * y).sqrt()).exp() / 3.0) as f32);
            x += dx;
        }
        y += dy;
    }
    data
}

/// libply.c `lib_output_polygon_height`: two triangles per grid square,
/// x across, z down, height in y above `y0`.
fn height_field<W: Write>(
    out: &mut SpdOut<W>,
    data: &[f32],
    w: usize,
    x: [f64; 2],
    y0: f64,
    z: [f64; 2],
) -> io::Result<()> {
    let xd = (x[1] - x[0]) / (w - 1) as f64;
    let zd = (z[1] - z[0]) / (w - 1) as f64;
    let at = |i: usize, j: usize| {
        DVec3::new(x[0] + j as f64 * xd, y0 + f64::from(data[i * w + j]), z[0] + i as f64 * zd)
    };
    for i in 0..w - 1 {
        for j in 0..w - 1 {
            let (a, b, c) = (at(i, j), at(i + 1, j + 1), at(i, j + 1));
            out.polygon(&[a, b, c])?;
            out.polygon(&[a, at(i + 1, j), b])?;
        }
    }
    Ok(())
}
