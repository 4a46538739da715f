//! SPD `mount`: a fractal mountain (Carpenter's midpoint displacement on a
//! square grid) with a pyramid of four glass spheres in front: many small
//! triangles of every orientation, and refraction through spheres. The
//! scenes of the P3D report's Table 1 are sizes 1, 5 and 7.
//!
//! The displacement seeds come from the SPD's original hash, which repeats
//! within the mountain; it is kept, as the SPD keeps it, so the scenes are
//! the ones whose statistics were published (November 1987 IEEE CG&A).

use super::matrix::{axis_rotate, normalize, rotate, transform_vector, Axis};
use super::out::{Out, SpdOut};
use super::random::gauss_rand;
use glam::DVec3;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 6;

/// Primitives at `size`: 2·4^size triangles and 4 spheres.
pub fn primitives(size: u32) -> u64 {
    4u64.saturating_pow(size).saturating_mul(2).saturating_add(4)
}

const FRACTAL_DIMENSION: f64 = 2.2;
const MOUNTAIN_NO: i64 = 21;
const CORNER: f64 = -1.0;
/// √2 as mount.c writes it (8 digits: the outputs depend on them).
#[allow(clippy::approx_constant)]
const ROOT_2: f64 = 1.4142136;
const WIDTH: f64 = 2.0;

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(-1.6, 1.6, 1.7), DVec3::ZERO, DVec3::Z, 45.0, 0.01, [512, 512])?;
    out.light(DVec3::new(-100.0, -100.0, 100.0))?;
    out.color(DVec3::ONE, 0.1, 0.1, 6.7, 0.9, 1.5)?;
    spheres(out, DVec3::new(-0.8, 0.8, 1.0), 0.17)?;
    out.color(DVec3::new(0.5, 0.45, 0.35), 1.0, 0.0, 0.0, 0.0, 0.0)?;
    let n = 1i64 << size;
    let ratio = 2.0 / (2f64.ln() / (FRACTAL_DIMENSION - 1.0)).exp();
    let mountain = Mountain { size, points: n as f64, roughness: (ratio * ratio - 1.0).sqrt() };
    mountain.grow(out, n, 0, 0, [0.0; 4])
}

/// The pyramid of crystal spheres: one above `centre`, three around it.
fn spheres<W: Write>(out: &mut SpdOut<W>, centre: DVec3, radius: f64) -> io::Result<()> {
    let axis = normalize(DVec3::new(1.0, 1.0, 0.0));
    let angle = (-1.0f64 / 3.0).acos();
    let top = DVec3::new(0.0, 0.0, radius * (3.0f64 / 2.0).sqrt());
    out.sphere(centre + top, radius)?;
    let turned = transform_vector(top, &axis_rotate(axis, angle));
    for i in 0..3 {
        let p = transform_vector(turned, &rotate(Axis::Z, i as f64 * 2.0 * std::f64::consts::PI / 3.0));
        out.sphere(p + centre, radius)?;
    }
    Ok(())
}

struct Mountain {
    size: u32,
    points: f64,
    roughness: f64,
}

impl Mountain {
    /// The original hash: `((A << (23 - C)) + (B << (15 - C)) + (A << (7 -
    /// C))) & 0xffff`, on unsigned longs (a shift past the width of the
    /// operand is taken as C compilers on x86-64 do: modulo 64).
    fn hash(&self, a: i64, b: i64) -> i64 {
        let shl = |x: i64, by: i64| (x as u64).wrapping_shl(by as u32);
        let c = i64::from(self.size);
        let sum = shl(a, 23 - c).wrapping_add(shl(b, 15 - c)).wrapping_add(shl(a, 7 - c));
        (sum & 0xffff) as i64
    }

    fn rand(&self, a: i64, b: i64) -> f64 {
        gauss_rand(MOUNTAIN_NO + self.hash(a, b))
    }

    /// The square of side `width` grid steps at (x, y), with heights `z`
    /// at its corners (lower left, lower right, upper right, upper left):
    /// two triangles, or four squares with displaced midpoints.
    fn grow<W: Write>(&self, out: &mut SpdOut<W>, width: i64, x: i64, y: i64, z: [f64; 4]) -> io::Result<()> {
        let [ll, lr, ur, ul] = z;
        if width == 1 {
            let l = CORNER + x as f64 * WIDTH / self.points;
            let r = CORNER + (x + 1) as f64 * WIDTH / self.points;
            let lo = CORNER + y as f64 * WIDTH / self.points;
            let up = CORNER + (y + 1) as f64 * WIDTH / self.points;
            let corner =
                [DVec3::new(l, lo, ll), DVec3::new(r, lo, lr), DVec3::new(r, up, ur), DVec3::new(l, up, ul)];
            for tri in 0..2 {
                out.polygon(&[0, 1, 2].map(|k| corner[(k + tri * 2) % 4]))?;
            }
            return Ok(());
        }
        let half = width >> 1;
        let rise = half as f64 * WIDTH / self.points * self.roughness;
        let lower = (ll + lr) / 2.0 + rise * self.rand(x + half, y);
        let right = (lr + ur) / 2.0 + rise * self.rand(x + width, y + half);
        let upper = (ur + ul) / 2.0 + rise * self.rand(x + half, y + width);
        let left = (ul + ll) / 2.0 + rise * self.rand(x, y + half);
        let middle = (ll + lr + ur + ul) / 4.0 + ROOT_2 * rise * self.rand(x + half, y + half);
        self.grow(out, half, x, y, [ll, lower, middle, left])?;
        self.grow(out, half, x + half, y, [lower, lr, right, middle])?;
        self.grow(out, half, x + half, y + half, [middle, right, ur, upper])?;
        self.grow(out, half, x, y + half, [left, middle, upper, ul])
    }
}
