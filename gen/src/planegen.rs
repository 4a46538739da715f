//! The checkerboard plane (P3D report §4.3): an XY-aligned board of `p 4` squares
//! in two colours, as a whole scene or added to an existing one.

use crate::options::{parse_args, parse_pair, parse_triple};
use anyhow::{bail, Result};
use glam::{DVec2, DVec3};
use nffkit_formats::{Light, Material, Primitive, Scene, Shape, SourceLine, View};

/// The board's parameters: `planegen`'s options, declared here once (the
/// binary and the golden catalogue parse them; `Default` is what the flags
/// default to).
#[derive(Debug, Clone, clap::Args)]
pub struct Board {
    /// Squares along x.
    #[arg(long, default_value_t = 16)]
    pub nx: u32,
    /// Squares along y.
    #[arg(long, default_value_t = 16)]
    pub ny: u32,
    /// Total size of the board along x.
    #[arg(long, default_value_t = 8.0)]
    pub sx: f64,
    /// Total size of the board along y.
    #[arg(long, default_value_t = 8.0)]
    pub sy: f64,
    /// First colour, R,G,B in [0,1] (the square at the -x,-y corner and
    /// every other one).
    #[arg(long, value_parser = parse_triple, default_value = "0.95,0.95,0.95")]
    pub c1: DVec3,
    /// Second colour, R,G,B in [0,1].
    #[arg(long, value_parser = parse_triple, default_value = "0.1,0.1,0.12")]
    pub c2: DVec3,
    /// Height of the plane (z).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub z: f64,
    /// Centre of the board, X,Y.
    #[arg(long, value_parser = parse_pair, default_value = "0,0", allow_hyphen_values = true)]
    pub center: DVec2,
    /// Diffuse weight of the squares.
    #[arg(long, default_value_t = 1.0)]
    pub kd: f64,
    /// Specular weight of the squares.
    #[arg(long, default_value_t = 0.0)]
    pub ks: f64,
    /// Phong exponent of the squares.
    #[arg(long, default_value_t = 1.0)]
    pub shine: f64,
    /// Turn the board about the vertical through its centre, in degrees
    /// (counter-clockwise from above): at 0 the squares' edges run along
    /// the view and across it, so the horizon is axis-aligned in the image.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub rotate: f64,
}

impl Default for Board {
    /// The flags' defaults.
    fn default() -> Self {
        parse_args(std::iter::empty::<&str>()).unwrap_or_else(|e| unreachable!("planegen's defaults: {e}"))
    }
}

impl Board {
    /// Refuse boards that make no sense, saying which option is wrong.
    pub fn validate(&self) -> Result<()> {
        if self.nx == 0 || self.ny == 0 {
            bail!("--nx and --ny must be at least 1 (got {} and {})", self.nx, self.ny);
        }
        if self.nx as u64 * self.ny as u64 > 4_000_000 {
            bail!("{}x{} squares is too many (at most 4 million)", self.nx, self.ny);
        }
        if !(self.sx > 0.0 && self.sy > 0.0 && self.sx.is_finite() && self.sy.is_finite()) {
            bail!("--sx and --sy must be positive (got {} and {})", self.sx, self.sy);
        }
        for (name, c) in [("--c1", self.c1), ("--c2", self.c2)] {
            if !c.to_array().iter().all(|v| (0.0..=1.0).contains(v)) {
                bail!("{name} components must be between 0 and 1 (got {},{},{})", c.x, c.y, c.z);
            }
        }
        for (name, v) in [("--kd", self.kd), ("--ks", self.ks), ("--shine", self.shine)] {
            if !v.is_finite() || v < 0.0 {
                bail!("{name} must be a finite, non-negative number (got {v})");
            }
        }
        if !self.rotate.is_finite() {
            bail!("--rotate must be a finite number of degrees (got {})", self.rotate);
        }
        if !self.z.is_finite() {
            bail!("--z must be a finite number (got {})", self.z);
        }
        if !self.center.is_finite() {
            bail!("--center must be finite");
        }
        Ok(())
    }

    /// The two materials, colour 1 then colour 2.
    pub fn materials(&self) -> [Material; 2] {
        let m = |color| Material {
            specular: glam::DVec3::ONE,
            color,
            kd: self.kd,
            ks: self.ks,
            shine: self.shine,
            t: 0.0,
            ior: 1.0,
        };
        [m(self.c1), m(self.c2)]
    }

    /// The squares of one colour (0 or 1), each counter-clockwise seen from
    /// +z, starting at its (−x, −y) corner.
    pub fn squares(&self, colour: u32) -> impl Iterator<Item = [DVec3; 4]> + '_ {
        let (dx, dy) = (self.sx / self.nx as f64, self.sy / self.ny as f64);
        let x0 = self.center.x - self.sx / 2.0;
        let y0 = self.center.y - self.sy / 2.0;
        let turn = self.turn();
        (0..self.ny).flat_map(move |j| {
            (0..self.nx).filter(move |i| (i + j) % 2 == colour).map(move |i| {
                // Corners from the index, not by accumulation: shared edges
                // get bit-identical coordinates.
                let xa = x0 + i as f64 * dx;
                let xb = x0 + (i + 1) as f64 * dx;
                let ya = y0 + j as f64 * dy;
                let yb = y0 + (j + 1) as f64 * dy;
                let z = self.z;
                [(xa, ya), (xb, ya), (xb, yb), (xa, yb)].map(|(x, y)| {
                    let p = turn.map_or(DVec2::new(x, y), |(c, s)| {
                        let d = DVec2::new(x, y) - self.center;
                        self.center + DVec2::new(c * d.x - s * d.y, s * d.x + c * d.y)
                    });
                    DVec3::new(p.x, p.y, z)
                })
            })
        })
    }

    /// The rotation's cosine and sine; `None` when there is none, so an
    /// unturned board's corners are computed exactly as written.
    fn turn(&self) -> Option<(f64, f64)> {
        (self.rotate != 0.0).then(|| {
            let (s, c) = self.rotate.to_radians().sin_cos();
            (c, s)
        })
    }

    /// Append the board to `scene`: its two materials, each followed by its
    /// squares (each colour's `f` line once).
    pub fn add_to(&self, scene: &mut Scene) {
        for (colour, m) in self.materials().into_iter().enumerate() {
            let index = scene.materials.len() as u32;
            scene.materials.push(m);
            for vertices in self.squares(colour as u32) {
                scene.primitives.push(Primitive {
                    shape: Shape::Polygon { vertices: vertices.to_vec() },
                    material: Some(index),
                    line: SourceLine(0),
                });
            }
        }
    }

    /// A whole scene: the board, an oblique view that shows aliasing, one
    /// light and the SPD's sky-blue background.
    pub fn scene(&self) -> Scene {
        let c = DVec3::new(self.center.x, self.center.y, self.z);
        let size = self.sx.max(self.sy);
        let view = View {
            lens: None,
            from: c + DVec3::new(0.0, -0.62 * size, 0.2 * size),
            at: c + DVec3::new(0.0, 0.0, 0.0),
            up: DVec3::Z,
            angle: 45.0,
            hither: 0.001 * size,
            resolution: [512, 512],
        };
        let mut scene = Scene {
            view: Some(view),
            background: Some(nffkit_formats::SPD_SKY),
            lights: vec![Light {
                area: None,
                position: c + DVec3::new(0.25 * size, -0.4 * size, 0.8 * size),
                color: None,
            }],
            ..Default::default()
        };
        self.add_to(&mut scene);
        scene
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_parse_as_the_binary_takes_them_with_its_defaults() {
        let d = Board::default();
        assert_eq!(
            (d.nx, d.ny, d.sx, d.sy, d.z, d.kd, d.ks, d.shine),
            (16, 16, 8.0, 8.0, 0.0, 1.0, 0.0, 1.0)
        );
        assert_eq!((d.c1, d.c2, d.center), (DVec3::splat(0.95), DVec3::new(0.1, 0.1, 0.12), DVec2::ZERO));
        let b: Board = parse_args(["--nx", "3", "--center", "-1,2"]).unwrap();
        assert_eq!((b.nx, b.ny, b.center), (3, 16, DVec2::new(-1.0, 2.0)));
        let e = parse_args::<Board, _, _>(["--nz", "3"]).unwrap_err().to_string();
        assert!(e.contains("--nz"), "{e}");
    }
    use nffkit_formats::nff::{self, ParseOptions};

    #[test]
    fn square_count_and_alternating_colours() {
        let b = Board { nx: 5, ny: 3, ..Default::default() };
        let s = b.scene();
        assert_eq!(s.primitives.len(), 15);
        assert_eq!(s.materials.len(), 2);
        assert_eq!(b.squares(0).count(), 8);
        assert_eq!(b.squares(1).count(), 7);
        // Neighbours differ in colour: the square right of a colour-0 square
        // starts where it ends and is colour 1.
        let first0 = b.squares(0).next().unwrap();
        let first1 = b.squares(1).next().unwrap();
        assert_eq!(first0[1], first1[0]);
    }

    #[test]
    fn squares_are_ccw_from_above_and_fill_the_board() {
        let b = Board {
            nx: 4,
            ny: 6,
            sx: 2.0,
            sy: 3.0,
            center: DVec2::new(1.0, -1.0),
            z: 0.5,
            ..Default::default()
        };
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let mut area = 0.0;
        for c in 0..2 {
            for q in b.squares(c) {
                let n = (q[1] - q[0]).cross(q[2] - q[1]);
                assert!(n.z > 0.0, "counter-clockwise from +z");
                area += n.z;
                for v in q {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        assert_eq!(lo, DVec3::new(0.0, -2.5, 0.5));
        assert_eq!(hi, DVec3::new(2.0, 0.5, 0.5));
        assert!((area - 6.0).abs() < 1e-12);
    }

    #[test]
    fn a_turned_board_keeps_its_centre_and_area() {
        let b = Board { nx: 2, ny: 2, sx: 2.0, sy: 2.0, rotate: 90.0, ..Default::default() };
        let first = b.squares(0).next().unwrap();
        // The (-x, -y) square turned a quarter counter-clockwise is the
        // (+x, -y) one.
        for (v, want) in first.iter().zip([(1.0, -1.0), (1.0, 0.0), (0.0, 0.0), (0.0, -1.0)]) {
            assert!((v.x - want.0).abs() < 1e-12 && (v.y - want.1).abs() < 1e-12, "{v}");
        }
        let turned = Board { rotate: 30.0, ..Default::default() };
        let area: f64 = (0..2)
            .flat_map(|c| turned.squares(c).collect::<Vec<_>>())
            .map(|q| (q[1] - q[0]).cross(q[2] - q[1]).z)
            .sum();
        assert!((area - 64.0).abs() < 1e-9);
    }

    #[test]
    fn written_scene_parses_without_diagnostics() {
        let text = nff::write(&Board::default().scene(), Vec::new()).unwrap();
        let parsed = nff::parse(&text, &ParseOptions::default()).unwrap();
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        // Each colour's material is written once.
        let fs = String::from_utf8(text).unwrap().lines().filter(|l| l.starts_with("f ")).count();
        assert_eq!(fs, 2);
    }

    #[test]
    fn bad_boards_are_refused() {
        assert!(Board { nx: 0, ..Default::default() }.validate().is_err());
        assert!(Board { sx: -1.0, ..Default::default() }.validate().is_err());
        assert!(Board { c1: DVec3::new(1.5, 0.0, 0.0), ..Default::default() }.validate().is_err());
        assert!(Board { rotate: f64::NAN, ..Default::default() }.validate().is_err());
        assert!(Board::default().validate().is_ok());
    }
}
