//! SPD `rings`: pentagonal rings of cylinders and spheres (each ring the
//! edges of a dodecahedron face) stacked in a pyramid of layers before a
//! wall: many cylinders, and shadows between them. size layers, the k-th
//! holding k² sets of six rings.

use super::matrix::{rotate, transform_point, Axis};
use super::out::Out;
use glam::DVec3;
use std::f64::consts::PI;
use std::io;

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 7;

/// Primitives at `size`: 30 cylinders and 30 spheres per set of rings, and
/// the wall.
pub fn primitives(size: u32) -> u64 {
    let sets: u64 = (1..=u64::from(size)).map(|k| k * k).sum();
    sets * 60 + 1
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    let radius = 0.07412;
    let spread = 1.0 / (PI / 8.0).sin();
    // SPREAD_OUT is 1, never above `spread`.
    let (y_diff, xz_diff) = (spread / 1.0, 1.0);
    out.background(nffkit_formats::SPD_SKY)?;
    let from = DVec3::new(-1.0, -spread, 0.5);
    let at = DVec3::new(from.x, from.y + 1.0, from.z);
    out.viewpoint(from, at, DVec3::Z, 45.0, 1.0, [512, 512])?;
    for l in [DVec3::new(3.0, -spread, 3.0), DVec3::new(-4.0, -spread, 1.0), DVec3::new(2.0, -spread, -4.0)] {
        out.light(l)?;
    }
    out.color(DVec3::ONE, 1.0, 0.0, 0.0, 0.0, 0.0)?;
    let wy = y_diff * f64::from(size + 1);
    let wxz = 1.01 * (wy - from.y) * (PI / 8.0).tan();
    out.polygon(&[
        DVec3::new(wxz + from.x, wy, wxz + from.z),
        DVec3::new(-wxz + from.x, wy, wxz + from.z),
        DVec3::new(-wxz + from.x, wy, -wxz + from.z),
        DVec3::new(wxz + from.x, wy, -wxz + from.z),
    ])?;
    let colors = [
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(1.0, 1.0, 0.0),
    ];
    let dodec = dodecahedron(radius);
    for depth in 0..size as i32 {
        let oy = y_diff * f64::from(depth + 1);
        for z in 0..=depth {
            let oz = xz_diff * f64::from(2 * z - depth);
            for x in 0..=depth {
                let offset = DVec3::new(xz_diff * f64::from(2 * x - depth), oy, oz);
                for elem in 0..30 {
                    let base = dodec[elem] + offset;
                    let prev = if elem % 5 == 0 {
                        out.color(colors[elem / 5], 0.5, 0.2, 37.0, 0.0, 0.0)?;
                        elem + 4
                    } else {
                        elem - 1
                    };
                    let apex = dodec[prev] + offset;
                    out.cone(base, radius, apex, radius)?;
                    out.sphere(base, radius)?;
                }
            }
        }
    }
    Ok(())
}

/// The 30 ring vertices (rings.c `create_dodec`): a pentagon on the XY
/// plane, then five more turned onto the faces around it.
fn dodecahedron(minor_radius: f64) -> [DVec3; 30] {
    let scale = 1.0 / (1.0 + minor_radius);
    let mut v = [DVec3::ZERO; 30];
    for (k, p) in v.iter_mut().take(5).enumerate() {
        let a = k as f64 * 2.0 * PI / 5.0;
        *p = DVec3::new(scale * a.cos(), scale * a.sin(), 0.0);
    }
    let x_rotation = 2.0 * ((PI / 3.0).cos() / (PI / 5.0).sin()).acos();
    let x_matrix = rotate(Axis::X, x_rotation);
    for pentagon in 1..6 {
        let z_matrix = rotate(Axis::Z, PI * (2.0 * (pentagon - 1) as f64 + 1.0) / 5.0);
        for k in 0..5 {
            let turned = transform_point(v[k], &x_matrix);
            v[5 * pentagon + k] = transform_point(turned, &z_matrix);
        }
    }
    v
}
