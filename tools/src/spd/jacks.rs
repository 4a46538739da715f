//! SPD `jacks`: a jack (three crossed cylinders with spheres on their
//! ends) with a half-size jack in each of its eight octants, down `size`
//! levels: (8^size − 1)/7 jacks, nine primitives each, all placed through
//! the SPD library's transform stack (libtx.c), which this reproduces.

use super::matrix::{identity, multiply, rotate, Axis, Matrix};
use super::out::{Out, SpdOut};
use glam::DVec3;
use std::f64::consts::PI;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 1;

/// Primitives at `size`.
pub fn primitives(size: u32) -> u64 {
    (8u64.saturating_pow(size) - 1) / 7 * 9
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(DVec3::new(0.2, 0.05, 0.2))?;
    out.viewpoint(DVec3::new(0.0, 0.0, -8.0), DVec3::ZERO, DVec3::Y, 25.0, 0.001, [256, 256])?;
    out.light(DVec3::new(-10.0, 3.0, -20.0))?;
    // lib_tx_rotate puts each new transform before the current one.
    let tx = multiply(
        &rotate(Axis::Y, -20.0 * PI / 180.0),
        &multiply(&rotate(Axis::X, -30.0 * PI / 180.0), &identity()),
    );
    out.color(DVec3::new(0.737, 0.561, 0.561), 0.7, 0.7, 20.0, 0.0, 1.0)?;
    // jacks.c sets its own tessellation, whatever -t asks.
    if out.tessellation().is_some() {
        out.tessellate(Some(2));
    }
    jack(out, &tx, 1, size)
}

/// libvec.c `lib_create_scale_matrix` with one factor.
fn scale(s: f64) -> Matrix {
    let mut m = [[0.0; 4]; 4];
    m[0][0] = s;
    m[1][1] = s;
    m[2][2] = s;
    m[3][3] = 1.0;
    m
}

/// libvec.c `lib_create_translate_matrix`.
fn translate(v: DVec3) -> Matrix {
    let mut m = identity();
    m[3][0] = v.x;
    m[3][1] = v.y;
    m[3][2] = v.z;
    m
}

/// jacks.c `make_rec_jack`: a jack, then in each octant a jack half the
/// size.
fn jack<W: Write>(out: &mut SpdOut<W>, tx: &Matrix, depth: u32, max_depth: u32) -> io::Result<()> {
    jack_object(out, &multiply(&scale(0.75), tx))?;
    if depth < max_depth {
        for i in [-0.5, 0.5] {
            for j in [-0.5, 0.5] {
                for k in [-0.5, 0.5] {
                    let moved = multiply(&translate(DVec3::new(i, j, k)), tx);
                    jack(out, &multiply(&scale(0.5), &moved), depth + 1, max_depth)?;
                }
            }
        }
    }
    Ok(())
}

/// jacks.c `make_jack_obj` through the transform `tx` (the library writes
/// each point transformed and each radius scaled, or each tessellated
/// triangle transformed).
fn jack_object<W: Write>(out: &mut SpdOut<W>, tx: &Matrix) -> io::Result<()> {
    out.set_transform(Some(tx));
    // The C's coordinates as written: -1 0 0, not -1 -0 -0.
    let ends = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::NEG_X, DVec3::NEG_Y, DVec3::NEG_Z];
    for k in 0..3 {
        out.cone(ends[k + 3], 0.1, ends[k], 0.1)?;
    }
    for e in ends {
        out.sphere(e, 0.2)?;
    }
    out.set_transform(None);
    Ok(())
}
