//! SPD `tree`: a recursive tree of cones (branches) and spheres (joints)
//! on a field, after Aono and Kunii: 2^(size+1) − 1 of each, many long
//! thin cones at every angle, and seven lights.

use super::matrix::{identity, multiply, rotate, transform_point, Axis, Matrix};
use super::out::{Out, SpdOut};
use glam::DVec3;
use std::f64::consts::PI;
use std::io::{self, Write};

/// The SPD's default size.
pub const DEFAULT_SIZE: u32 = 11;

/// Primitives at `size`: a cone and a sphere per branch, and the field.
pub fn primitives(size: u32) -> u64 {
    (2u64.saturating_pow(size + 1) - 1).saturating_mul(2).saturating_add(1)
}

const BR_DIAMETER: f64 = 0.67;
const WIDTH_HEIGHT_RATIO: f64 = 0.15;

/// Write the database.
pub fn write(out: &mut Out<'_>, size: u32) -> io::Result<()> {
    out.background(nffkit_formats::SPD_SKY)?;
    out.viewpoint(DVec3::new(4.5, 0.4, 2.0), DVec3::new(0.0, 0.0, 1.5), DVec3::Z, 45.0, 1.0, [512, 512])?;
    for l in [
        DVec3::new(-5.0, 5.0, 50.0),
        DVec3::new(30.0, -30.0, 30.0),
        DVec3::new(-40.0, -30.0, 20.0),
        DVec3::new(10.0, 30.0, 40.0),
        DVec3::new(-30.0, 40.0, 10.0),
        DVec3::new(50.0, 25.0, 20.0),
        DVec3::new(-10.0, -60.0, 30.0),
    ] {
        out.light(l)?;
    }
    out.color(DVec3::new(0.2, 0.7, 0.2), 1.0, 0.0, 0.0, 0.0, 0.0)?;
    out.polygon(&[
        DVec3::new(50.0, 50.0, 0.0),
        DVec3::new(-50.0, 50.0, 0.0),
        DVec3::new(-50.0, -50.0, 0.0),
        DVec3::new(50.0, -50.0, 0.0),
    ])?;
    out.color(DVec3::new(0.55, 0.4, 0.2), 1.0, 0.0, 0.0, 0.0, 0.0)?;
    // Each branch's frame relative to its parent's: turned by the branching
    // angle about X and the divergence about Z, shrunk, moved to the tip.
    let branch = |angle: f64, divergence: f64, contraction: f64| -> Matrix {
        let r = multiply(&rotate(Axis::X, angle * PI / 180.0), &rotate(Axis::Z, divergence * PI / 180.0));
        let mut st = identity();
        st[0][0] = contraction;
        st[1][1] = contraction;
        st[2][2] = contraction;
        st[3][2] = 1.0;
        multiply(&r, &st)
    };
    let tree = Tree { branches: [branch(40.0, 90.0, 0.65), branch(25.0, 140.0 + 90.0, 0.70)] };
    tree.grow(out, &identity(), 1.0, size)
}

struct Tree {
    branches: [Matrix; 2],
}

impl Tree {
    fn grow<W: Write>(&self, out: &mut SpdOut<W>, frame: &Matrix, scale: f64, depth: u32) -> io::Result<()> {
        let base = transform_point(DVec3::ZERO, frame);
        let base_radius = scale * WIDTH_HEIGHT_RATIO;
        let apex = transform_point(DVec3::Z, frame);
        let apex_radius = base_radius * BR_DIAMETER;
        out.cone(base, base_radius, apex, apex_radius)?;
        out.sphere(apex, apex_radius)?;
        if depth > 0 {
            for b in &self.branches {
                self.grow(out, &multiply(b, frame), scale * BR_DIAMETER, depth - 1)?;
            }
        }
        Ok(())
    }
}
