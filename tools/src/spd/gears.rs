//! SPD `gears`: a size³ block of intermeshing gears, each with a 144-vertex
//! concave top and bottom, some of glass: large concave polygons,
//! refraction and many reflections between close surfaces.

use super::matrix::{rotate, transform_vector, Axis};
use super::out::{Out, SpdOut};
use glam::DVec3;
use std::f64::consts::PI;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 4;

/// Teeth per gear (a multiple of 4).
const TEETH: usize = 36;
const OUTER_EDGE_RATIO: f64 = 0.995;
const INNER_EDGE_RATIO: f64 = 0.9;
const EDGE_DIFF: f64 = 1.0 - INNER_EDGE_RATIO;
const DEPTH_RATIO: f64 = 0.1;

/// Primitives at `size`: per gear a top, a bottom and 144 sides; and the
/// ground.
pub fn primitives(size: u32) -> u64 {
    u64::from(size).pow(3) * (2 + 4 * TEETH as u64) + 1
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(-1.1, -2.1, 2.6), DVec3::ZERO, DVec3::Z, 45.0, 1.0, [512, 512])?;
    for l in [
        DVec3::new(2.0, 4.0, 4.0),
        DVec3::new(-2.0, 4.0, 3.0),
        DVec3::new(2.0, -2.5, 2.5),
        DVec3::new(-1.0, -4.0, 2.0),
        DVec3::new(-1.111, -2.121, 2.626),
    ] {
        out.light(l)?;
    }
    out.color(DVec3::new(1.0, 0.85, 0.7), 0.3, 0.6, 37.0, 0.0, 0.0)?;
    out.polygon(&[
        DVec3::new(2.0, 2.0, 0.0),
        DVec3::new(-2.0, 2.0, 0.0),
        DVec3::new(-2.0, -2.0, 0.0),
        DVec3::new(2.0, -2.0, 0.0),
    ])?;
    let sf = f64::from(size);
    let outer_radius = 1.0 / (sf - f64::from(size - 1) * EDGE_DIFF / 2.0);
    let zero = DVec3::new(-1.0 + outer_radius, -1.0 + outer_radius, 1.0);
    let step = outer_radius * (2.0 - EDGE_DIFF);
    let offset = DVec3::new(step, step, -1.0 / sf);
    let fraction = |a: f64| a - (a as i32) as f64;
    let n = size as i32;
    for iz in 0..n {
        let cz = zero.z + f64::from(iz) * offset.z;
        for iy in 0..n {
            let cy = zero.y + f64::from(iy) * offset.y;
            for ix in 0..n {
                let centre = DVec3::new(zero.x + f64::from(ix) * offset.x, cy, cz);
                let color = DVec3::new(
                    0.01 + fraction(f64::from(ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0),
                    0.01 + fraction(f64::from(iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0),
                    0.01 + fraction(f64::from(iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0),
                );
                let scale = color.x.max(color.y).max(color.z);
                let color = DVec3::new(color.x / scale, color.y / scale, color.z / scale);
                if (ix * 4 + iy * 2 + iz) % 5 == 0 {
                    out.color(color, 0.2, 0.0, 0.0, 0.8, 1.1)?;
                } else {
                    out.color(color, 1.0, 0.0, 0.0, 0.0, 0.0)?;
                }
                let angle = PI * f64::from((ix + iy + iz) % 2) / TEETH as f64;
                let thickness = DEPTH_RATIO.min(1.0 / (2.0 * sf));
                gear(
                    out,
                    centre,
                    angle,
                    OUTER_EDGE_RATIO * outer_radius,
                    (1.0 - EDGE_DIFF) * outer_radius,
                    thickness,
                )?;
            }
        }
    }
    Ok(())
}

/// The four outline points of one tooth (gears.c `create_tooth`).
fn tooth(gear_angle: f64, tooth_angle: f64, centre: DVec3, outer: DVec3, inner: DVec3) -> [DVec3; 4] {
    let at = |factor: f64, p: DVec3| {
        transform_vector(p, &rotate(Axis::Z, gear_angle + factor * tooth_angle)) + centre
    };
    [at(-0.19, outer), at(0.19, outer), at(0.3, inner), at(0.7, inner)]
}

/// One gear: its top outline, the sides, its bottom outline.
fn gear<W: Write>(
    out: &mut SpdOut<W>,
    centre: DVec3,
    offset: f64,
    outer: f64,
    inner: f64,
    thickness: f64,
) -> io::Result<()> {
    let tooth_angle = 2.0 * PI / TEETH as f64;
    let outline = |z: f64, sign: f64| -> Vec<DVec3> {
        (0..TEETH)
            .flat_map(|t| {
                let gear_angle = offset + sign * 2.0 * PI * t as f64 / TEETH as f64;
                tooth(
                    gear_angle,
                    sign * tooth_angle,
                    centre,
                    DVec3::new(outer, 0.0, z),
                    DVec3::new(inner, 0.0, z),
                )
            })
            .collect()
    };
    let top = outline(0.0, 1.0);
    out.polygon(&top)?;
    for k in 0..top.len() {
        let (a, b) = (top[k], top[(k + 1) % top.len()]);
        let down = DVec3::new(0.0, 0.0, thickness);
        out.polygon(&[a, a - down, b - down, b])?;
    }
    out.polygon(&outline(-thickness, -1.0))
}
