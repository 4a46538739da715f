//! SPD `teapot`: the Utah teapot's 32 bicubic Bézier patches, each cut
//! into size × size quadrilaterals of two smooth-shaded triangles
//! (degenerate ones at the lid's and bottom's cusps left out), on a
//! checkerboard of size × size squares: many small patches with normals,
//! seen from both sides.

use super::matrix::{multiply, normalize, transform_coord, Matrix};
use super::out::{Out, SpdOut};
use super::teapot_data::{PATCHES, VERTICES};
use glam::DVec3;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 6;

/// Primitives at `size`: its header's 32·2·n² − 8n patches (the cusps'
/// degenerate triangles left out) and n² squares.
pub fn primitives(size: u32) -> u64 {
    let n = u64::from(size);
    (64 * n * n - 8 * n) + n * n
}

/// The Bézier basis (teapot.c `ms`).
const BEZIER: Matrix =
    [[-1.0, 3.0, -3.0, 1.0], [3.0, -6.0, 3.0, 0.0], [-3.0, 3.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]];

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(4.86, 7.2, 5.4), DVec3::ZERO, DVec3::Z, 45.0, 1.0, [512, 512])?;
    out.light(DVec3::new(-3.1, 9.8, 12.1))?;
    out.light(DVec3::new(11.3, 5.1, 8.8))?;
    checkerboard(out, size)?;
    teapot(out, size)
}

/// teapot.c `output_checkerboard`: the odd squares white, then the even
/// ones grey.
fn checkerboard<W: Write>(out: &mut SpdOut<W>, size: u32) -> io::Result<()> {
    let n = size as i32;
    let corner = |s: i32, t: i32, i: i32| {
        DVec3::new(
            4.0 * (2.0 * f64::from(s + i32::from(i % 3 != 0)) / f64::from(n) - 1.0),
            4.0 * (2.0 * f64::from(t + i32::from(i / 2 != 0)) / f64::from(n) - 1.0),
            0.0,
        )
    };
    for (color, odd) in [(DVec3::ONE, 1), (DVec3::splat(0.5), 0)] {
        out.color(color, 0.5, 0.5, 30.0, 0.0, 0.0)?;
        for s in 0..n {
            for t in 0..n {
                if (s + t) % 2 == odd {
                    out.polygon(&[0, 1, 2, 3].map(|i| corner(s, t, i)))?;
                }
            }
        }
    }
    Ok(())
}

/// teapot.c `output_teapot`: each patch's M·G·Mᵀ per coordinate, then
/// the points, tangents and normals at the grid's corners.
fn teapot<W: Write>(out: &mut SpdOut<W>, size: u32) -> io::Result<()> {
    out.color(DVec3::new(1.0, 0.5, 0.1), 0.75, 0.25, 37.0, 0.0, 0.0)?;
    let transposed: Matrix = std::array::from_fn(|r| std::array::from_fn(|c| BEZIER[c][r]));
    let n = size as i32;
    for patch in &PATCHES {
        let mgm: [Matrix; 3] = std::array::from_fn(|i| {
            let g: Matrix =
                std::array::from_fn(|r| std::array::from_fn(|c| VERTICES[patch[r * 4 + c] as usize][i]));
            multiply(&multiply(&BEZIER, &g), &transposed)
        });
        for s_step in 0..n {
            for t_step in 0..n {
                for tri in 0..2 {
                    let mut st = [(0.0, 0.0); 3];
                    for (v, slot) in st.iter_mut().enumerate() {
                        let corner = (v as i32 + tri * 2) % 4;
                        *slot = (
                            f64::from(s_step + i32::from(corner / 2 != 0)) / f64::from(n),
                            f64::from(t_step + i32::from(corner % 3 != 0)) / f64::from(n),
                        );
                    }
                    let (mut vert, mut norm) = ([DVec3::ZERO; 3], [DVec3::ZERO; 3]);
                    for k in 0..3 {
                        (vert[k], norm[k]) = point_on(&mgm, st[k].0, st[k].1);
                    }
                    if fix_cusp(&vert, &mut norm) {
                        out.patch(&vert, &norm)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// teapot.c `points_from_basis` for one (s, t): the point, and the unit
/// normal t-tangent × s-tangent.
fn point_on(mgm: &[Matrix; 3], s: f64, t: f64) -> (DVec3, DVec3) {
    // Power vectors (s³, s², s, 1) and their derivatives, built as the C
    // builds them.
    let (mut sp, mut tp, mut dsp, mut dtp) = ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
    let (mut sval, mut tval, mut dsval, mut dtval) = (1.0, 1.0, 0.0, 0.0);
    for p in (0..4).rev() {
        sp[p] = sval;
        tp[p] = tval;
        sval *= s;
        tval *= t;
        if p == 3 {
            dsp[p] = 0.0;
            dtp[p] = 0.0;
            dsval = 1.0;
            dtval = 1.0;
        } else {
            dsp[p] = dsval * (3 - p) as f64;
            dtp[p] = dtval * (3 - p) as f64;
            dsval *= s;
            dtval *= t;
        }
    }
    let dot4 = |a: [f64; 4], b: [f64; 4]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    let (mut vert, mut sdir, mut tdir) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for i in 0..3 {
        vert[i] = dot4(transform_coord(sp, &mgm[i]), tp);
        sdir[i] = dot4(transform_coord(dsp, &mgm[i]), tp);
        tdir[i] = dot4(transform_coord(sp, &mgm[i]), dtp);
    }
    // glam's cross is the C's CROSS bit for bit (its products commute).
    let n = DVec3::from_array(tdir).cross(DVec3::from_array(sdir));
    (DVec3::from_array(vert), normalize(n))
}

/// teapot.c `check_for_cusp`: a triangle with two corners on the axis is
/// degenerate (false); one corner on it gets the axis as its normal (up at
/// the lid, down at the bottom).
fn fix_cusp(vert: &[DVec3; 3], norm: &mut [DVec3; 3]) -> bool {
    let on_axis: Vec<usize> =
        (0..3).filter(|&i| vert[i].x.abs() <= 0.0001 && vert[i].y.abs() <= 0.0001).collect();
    match on_axis.as_slice() {
        [] => true,
        [i] => {
            norm[*i] = if vert[*i].z > 1.5 { DVec3::Z } else { DVec3::NEG_Z };
            true
        }
        _ => false,
    }
}
