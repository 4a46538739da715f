//! The SPD "balls" database (sphereflake), sphere for sphere as the SPD's
//! own program writes it, streamed so any level fits in constant memory.
//!
//! Geometry (as the SPD builds it): a root sphere of radius 1/2 at the
//! origin with axis +Z; each child has a third of its parent's radius and
//! touches it. The nine child directions, in the parent's frame: three tilted
//! arccos(sqrt(2/3)) from the axis at azimuths 45°, 165°, 285°, six on the
//! equator at 15°, 75°, ..., 315°, emitted per group k as (upper 45°+120k,
//! equator 15°+120k, equator 75°+120k). A child's frame is the minimal
//! rotation taking +Z to its direction. Output is depth-first pre-order.

use crate::options::{parse_args, parse_resolution, parse_squares};
use crate::planegen::Board;
use anyhow::{bail, Result};
use glam::{DMat3, DVec2, DVec3};
use nffkit_formats::nff::NffWriter;
use nffkit_formats::{Light, Material, Primitive, Scene, Shape, SourceLine, View};
use std::io::{self, Write};

/// What goes under the flake.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Floor {
    /// The SPD's single square at z = −1/2.
    Square,
    /// A checkerboard of nx × ny squares in its place.
    Checker(u32, u32),
    /// Nothing.
    None,
}

/// The generator's options: `sphereflake`'s, declared here once (the
/// binary and the golden catalogue parse them; `Default` is what the flags
/// default to).
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct Sphereflake {
    /// Recursion level (the SPD's size factor; its balls_s1..s4 are 1..4):
    /// 1 + 9 + ... + 9^level spheres.
    #[arg(long, default_value_t = 4)]
    pub level: u32,
    /// Image size in the view, W,H.
    #[arg(long, value_parser = parse_resolution, default_value = "512,512")]
    pub resolution: [u32; 2],
    /// Leave out the floor.
    #[arg(long, conflicts_with = "checker")]
    pub no_floor: bool,
    /// Put a checkerboard of NX,NY squares under the flake instead of the
    /// single floor square.
    #[arg(long, value_parser = parse_squares, value_name = "NX,NY")]
    pub checker: Option<[u32; 2]>,
}

impl Default for Sphereflake {
    /// The flags' defaults.
    fn default() -> Self {
        parse_args(std::iter::empty::<&str>()).unwrap_or_else(|e| unreachable!("sphereflake's defaults: {e}"))
    }
}

/// The highest level written: level 9 is 435 million spheres.
pub const MAX_LEVEL: u32 = 9;

/// Number of spheres at `level`.
pub fn sphere_count(level: u32) -> u64 {
    (0..=level).map(|l| 9u64.pow(l)).sum()
}

/// The nine child directions in a parent frame whose axis is +Z.
fn child_directions() -> [DVec3; 9] {
    let tilt = (2.0f64 / 3.0).sqrt().acos();
    let dir = |azimuth: f64, polar: f64| {
        let (a, p) = (azimuth.to_radians(), polar);
        DVec3::new(p.sin() * a.cos(), p.sin() * a.sin(), p.cos())
    };
    let mut out = [DVec3::ZERO; 9];
    for k in 0..3 {
        let base = 120.0 * k as f64;
        out[3 * k] = dir(45.0 + base, tilt);
        out[3 * k + 1] = dir(15.0 + base, std::f64::consts::FRAC_PI_2);
        out[3 * k + 2] = dir(75.0 + base, std::f64::consts::FRAC_PI_2);
    }
    out
}

/// The minimal rotation taking +Z to unit vector `d` (Rodrigues), with the
/// SPD's special cases near ±Z.
fn frame_to(d: DVec3) -> DMat3 {
    if (d - DVec3::Z).length() < 1e-4 {
        return DMat3::IDENTITY;
    }
    if (d + DVec3::Z).length() < 1e-4 {
        return DMat3::from_rotation_y(std::f64::consts::PI);
    }
    let axis = DVec3::Z.cross(d).normalize();
    DMat3::from_axis_angle(axis, DVec3::Z.dot(d).clamp(-1.0, 1.0).acos())
}

/// Visit every sphere (centre, radius) in the SPD's order.
pub fn for_each_sphere(level: u32, f: &mut dyn FnMut(DVec3, f64) -> io::Result<()>) -> io::Result<()> {
    let dirs = child_directions();
    fn rec(
        c: DVec3,
        r: f64,
        frame: DMat3,
        depth: u32,
        dirs: &[DVec3; 9],
        f: &mut dyn FnMut(DVec3, f64) -> io::Result<()>,
    ) -> io::Result<()> {
        f(c, r)?;
        if depth == 0 {
            return Ok(());
        }
        let child_r = r / 3.0;
        for d in dirs {
            let world = (frame * *d).normalize();
            rec(c + world * (r + child_r), child_r, frame_to(world), depth - 1, dirs, f)?;
        }
        Ok(())
    }
    rec(DVec3::ZERO, 0.5, DMat3::IDENTITY, level, &dirs, f)
}

/// The material of the floor square.
pub fn floor_material() -> Material {
    Material {
        specular: glam::DVec3::ONE,
        color: DVec3::new(1.0, 0.75, 0.33),
        kd: 0.8,
        ks: 0.0,
        shine: 100000.0,
        t: 0.0,
        ior: 1.0,
    }
}

/// The material of the spheres.
pub fn sphere_material() -> Material {
    Material {
        specular: glam::DVec3::ONE,
        color: DVec3::new(1.0, 0.9, 0.7),
        kd: 0.5,
        ks: 0.5,
        shine: 3.0827,
        t: 0.0,
        ior: 1.0,
    }
}

impl Sphereflake {
    /// The flake at `level` over `floor`, at the default resolution.
    pub fn at(level: u32, floor: Floor) -> Sphereflake {
        let (no_floor, checker) = match floor {
            Floor::Square => (false, None),
            Floor::Checker(nx, ny) => (false, Some([nx, ny])),
            Floor::None => (true, None),
        };
        Sphereflake { level, no_floor, checker, ..Default::default() }
    }

    /// What goes under the flake.
    pub fn floor(&self) -> Floor {
        match (self.no_floor, self.checker) {
            (true, _) => Floor::None,
            (_, Some([nx, ny])) => Floor::Checker(nx, ny),
            _ => Floor::Square,
        }
    }

    /// Refuse levels past [`MAX_LEVEL`], saying how many spheres they ask.
    pub fn validate(&self) -> Result<()> {
        if self.level > MAX_LEVEL {
            bail!(
                "--level {} would write {} spheres; the highest level is {MAX_LEVEL} ({} spheres)",
                self.level,
                sphere_count(self.level),
                sphere_count(MAX_LEVEL)
            );
        }
        Ok(())
    }

    /// Everything before the spheres: background, view, lights and floor.
    fn header(&self) -> Scene {
        let mut scene = Scene {
            view: Some(View {
                lens: None,
                from: DVec3::new(2.1, 1.3, 1.7),
                at: DVec3::ZERO,
                up: DVec3::Z,
                angle: 45.0,
                hither: 0.01,
                resolution: self.resolution,
            }),
            background: Some(nffkit_formats::SPD_SKY),
            lights: [(4.0, 3.0, 2.0), (1.0, -4.0, 4.0), (-3.0, 1.0, 5.0)]
                .iter()
                .map(|&(x, y, z)| Light { area: None, position: DVec3::new(x, y, z), color: None })
                .collect(),
            ..Default::default()
        };
        match self.floor() {
            Floor::Square => {
                scene.materials.push(floor_material());
                let v = [(12.0, 12.0), (-12.0, 12.0), (-12.0, -12.0), (12.0, -12.0)]
                    .map(|(x, y)| DVec3::new(x, y, -0.5))
                    .to_vec();
                scene.primitives.push(Primitive {
                    shape: Shape::Polygon { vertices: v },
                    material: Some(0),
                    line: SourceLine(0),
                });
            }
            Floor::Checker(nx, ny) => {
                let board = Board {
                    nx,
                    ny,
                    sx: 24.0,
                    sy: 24.0,
                    c1: floor_material().color,
                    c2: DVec3::new(0.25, 0.2, 0.15),
                    z: -0.5,
                    center: DVec2::ZERO,
                    kd: 0.8,
                    ks: 0.0,
                    shine: 1.0,
                    rotate: 0.0,
                };
                board.add_to(&mut scene);
            }
            Floor::None => {}
        }
        scene.materials.push(sphere_material());
        scene
    }

    /// Stream the database as NFF text.
    pub fn write<W: Write>(&self, out: W) -> io::Result<W> {
        let header = self.header();
        let out = nffkit_formats::nff::write(&header, out)?;
        let mut w = NffWriter::new(out);
        for_each_sphere(self.level, &mut |c, r| w.sphere(c, r))?;
        Ok(w.into_inner())
    }

    /// The database as an in-memory scene (for rendering without a file).
    pub fn scene(&self) -> Scene {
        let mut scene = self.header();
        let material = Some(scene.materials.len() as u32 - 1);
        let _ = for_each_sphere(self.level, &mut |center, radius| {
            scene.primitives.push(Primitive {
                shape: Shape::Sphere { center, radius },
                material,
                line: SourceLine(0),
            });
            Ok(())
        });
        scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_per_level() {
        for level in 0..4 {
            let mut n = 0;
            for_each_sphere(level, &mut |_, _| {
                n += 1;
                Ok(())
            })
            .unwrap();
            assert_eq!(n, sphere_count(level));
        }
        assert_eq!(sphere_count(7), 5_380_840);
    }

    #[test]
    fn children_touch_their_parents_in_pre_order() {
        let mut spheres = Vec::new();
        for_each_sphere(2, &mut |c, r| {
            spheres.push((c, r));
            Ok(())
        })
        .unwrap();
        // Pre-order: sphere 1 is the first child, 2..=10 its children.
        let (root, child) = (spheres[0], spheres[1]);
        assert!(((child.0 - root.0).length() - (root.1 + child.1)).abs() < 1e-12);
        for grandchild in &spheres[2..11] {
            assert!((grandchild.1 - child.1 / 3.0).abs() < 1e-15);
            assert!(((grandchild.0 - child.0).length() - (child.1 + grandchild.1)).abs() < 1e-12);
        }
        // The second child of the root comes after the first's whole subtree.
        assert!((spheres[11].1 - root.1 / 3.0).abs() < 1e-15);
    }
}
