//! SPD `balls`: the sphereflake, a sphere with nine smaller ones on it,
//! each with nine on it, down `size` levels (91^… : (9^(size+1) − 1)/8
//! spheres), on a floor: reflection between many spheres. The P3D report's
//! balls_low/medium/high are sizes 1, 2 and 4. (`sphereflake` writes the
//! same spheres with its own options.)

use super::matrix::{axis_rotate, identity, normalize, rotate, transform_coord, Axis, Matrix};
use super::out::{Out, SpdOut};
use glam::DVec3;
use std::f64::consts::PI;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 4;

/// Primitives at `size`: the spheres and the floor polygon.
pub fn primitives(size: u32) -> u64 {
    (9u64.saturating_pow(size + 1) - 1) / 8 + 1
}

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    let radius = 1.0;
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(2.1, 1.3, 1.7), DVec3::ZERO, DVec3::Z, 45.0, 0.01, [512, 512])?;
    for l in [DVec3::new(4.0, 3.0, 2.0), DVec3::new(1.0, -4.0, 4.0), DVec3::new(-3.0, 1.0, 5.0)] {
        out.light(l)?;
    }
    out.color(DVec3::new(1.0, 0.75, 0.33), 0.8, 0.0, 0.0, 0.0, 1.0)?;
    let b = DVec3::new(12.0 * radius, 12.0 * radius, -radius / 2.0);
    out.polygon(&[
        DVec3::new(b.x, b.y, b.z),
        DVec3::new(-b.x, b.y, b.z),
        DVec3::new(-b.x, -b.y, b.z),
        DVec3::new(b.x, -b.y, b.z),
    ])?;
    out.color(DVec3::new(1.0, 0.9, 0.7), 0.5, 0.5, 37.0, 0.0, 1.0)?;
    let flake = Flake { set: objset() };
    flake.output(out, size, [0.0, 0.0, 0.0, radius / 2.0], [0.0, 0.0, 1.0, 1.0 / 3.0])
}

/// The nine directions of the child spheres (balls.c `create_objset`).
fn objset() -> [[f64; 4]; 9] {
    let dist = 1.0 / 2f64.sqrt();
    let mut trio = [[dist, dist, 0.0, 0.0], [dist, 0.0, -dist, 0.0], [0.0, dist, -dist, 0.0]];
    let mx = axis_rotate(normalize(DVec3::new(1.0, -1.0, 0.0)), (2.0 / 6f64.sqrt()).asin());
    for t in &mut trio {
        *t = transform_coord(*t, &mx);
    }
    let mut set = [[0.0; 4]; 9];
    for s in 0..3 {
        let mx = rotate(Axis::Z, s as f64 * 2.0 * PI / 3.0);
        for v in 0..3 {
            set[s * 3 + v] = transform_coord(trio[v], &mx);
        }
    }
    set
}

struct Flake {
    set: [[f64; 4]; 9],
}

impl Flake {
    /// The sphere `centre` (radius in w), then its children (balls.c
    /// `output_object`); `direction` is the unit axis it grows along, and
    /// in w the children's radius ratio.
    fn output<W: Write>(
        &self,
        out: &mut SpdOut<W>,
        depth: u32,
        centre: [f64; 4],
        direction: [f64; 4],
    ) -> io::Result<()> {
        out.sphere(DVec3::new(centre[0], centre[1], centre[2]), centre[3])?;
        if depth == 0 {
            return Ok(());
        }
        let mx: Matrix = if direction[2] >= 0.9999 {
            identity()
        } else if direction[2] <= -0.9999 {
            rotate(Axis::Y, PI)
        } else {
            let d = DVec3::new(direction[0], direction[1], direction[2]);
            let axis = normalize(DVec3::Z.cross(d));
            axis_rotate(axis, DVec3::Z.dot(d).acos())
        };
        let scale = centre[3] * (1.0 + direction[3]);
        for v in &self.set {
            let mut child = transform_coord(*v, &mx);
            for k in 0..3 {
                child[k] = child[k] * scale + centre[k];
            }
            child[3] = centre[3] * direction[3];
            let dir = [
                (child[0] - centre[0]) / scale,
                (child[1] - centre[1]) / scale,
                (child[2] - centre[2]) / scale,
                direction[3],
            ];
            self.output(out, depth - 1, child, dir)?;
        }
        Ok(())
    }
}
