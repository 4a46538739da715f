//! P3F's environment: a cube map (skybox) that every ray leaving the scene
//! looks up, eye, reflected or refracted, in place of the background colour.
//!
//! The lookup is the P3D course's (its template's `GetSkyboxColor`), so a
//! scene looks as its author saw it: the face is the direction's major axis,
//! +x the `left` image and -x the `right` one (the course's skyboxes are
//! seen from inside, with +z the `front`), the face coordinates are
//! `(sc/|ma| + 1)/2` with `(sc, tc)` per face as below, and the texel is the
//! nearest one at `((w - 1)s, (h - 1)t)` counted from the image's lower-left
//! corner. Texels are 8-bit, read as `value / 255`.

use glam::Vec3A;

/// The six faces in the course's order (its `CubeMap` enum), which is the
/// order of [`CubeMap::new`]'s images: their file names without extension.
pub const FACES: [&str; 6] = ["right", "left", "top", "bottom", "front", "back"];

/// One face: 8-bit RGB texels, rows top to bottom (as image files hold them).
#[derive(Debug, Clone)]
pub struct Face {
    width: u32,
    height: u32,
    rgb: Vec<[u8; 3]>,
}

impl Face {
    /// A face of `width` x `height` texels, rows top to bottom; `None`
    /// when the count does not match or the image is empty.
    pub fn new(width: u32, height: u32, rgb: Vec<[u8; 3]>) -> Option<Face> {
        (width > 0 && height > 0 && rgb.len() == width as usize * height as usize).then_some(Face {
            width,
            height,
            rgb,
        })
    }

    /// Width, height and the texels, rows top to bottom.
    #[cfg(feature = "gpu")]
    pub(crate) fn texels(&self) -> (u32, u32, &[[u8; 3]]) {
        (self.width, self.height, &self.rgb)
    }

    /// The texel at column `x` and row `y` counted from the bottom.
    fn texel_from_bottom(&self, x: u32, y: u32) -> Vec3A {
        let row = self.height - 1 - y.min(self.height - 1);
        let [r, g, b] = self.rgb[row as usize * self.width as usize + x.min(self.width - 1) as usize];
        Vec3A::new(r as f32, g as f32, b as f32) / 255.0
    }
}

/// A skybox: six faces in [`FACES`] order.
#[derive(Debug, Clone)]
pub struct CubeMap {
    faces: [Face; 6],
}

impl CubeMap {
    /// A cube map of six faces, in [`FACES`] order.
    pub fn new(faces: [Face; 6]) -> CubeMap {
        CubeMap { faces }
    }

    /// The six faces, in [`FACES`] order.
    #[cfg(feature = "gpu")]
    pub(crate) fn faces(&self) -> &[Face; 6] {
        &self.faces
    }

    /// The colour seen in direction `d` (any length but zero).
    #[inline]
    pub fn lookup(&self, d: Vec3A) -> Vec3A {
        let a = d.abs();
        // The major axis, ties going as the course's comparisons send them.
        let (mut face, mut ma) = if a.x > a.y {
            (if d.x >= 0.0 { 1 } else { 0 }, a.x)
        } else {
            (if d.y >= 0.0 { 2 } else { 3 }, a.y)
        };
        if a.z > ma {
            (face, ma) = (if d.z >= 0.0 { 4 } else { 5 }, a.z);
        }
        let (sc, tc) = match face {
            0 => (-d.z, d.y),
            1 => (d.z, d.y),
            2 => (-d.x, -d.z),
            3 => (-d.x, d.z),
            4 => (-d.x, d.y),
            _ => (d.x, d.y),
        };
        if ma.is_nan() || ma <= 0.0 {
            return Vec3A::ZERO; // a zero or NaN direction
        }
        let s = (sc / ma + 1.0) * 0.5;
        let t = (tc / ma + 1.0) * 0.5;
        let f = &self.faces[face];
        // Truncation, as the course's int(); s and t lie in [0, 1].
        let x = ((f.width - 1) as f32 * s.clamp(0.0, 1.0)) as u32;
        let y = ((f.height - 1) as f32 * t.clamp(0.0, 1.0)) as u32;
        f.texel_from_bottom(x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Faces of 3x3 texels: face `i`'s centre texel is `(i, 100, 200)`,
    /// the rest `(255, 255, 255)`.
    fn marked() -> CubeMap {
        let face = |i: u8| {
            let mut rgb = vec![[255u8; 3]; 9];
            rgb[4] = [i, 100, 200];
            Face::new(3, 3, rgb).unwrap()
        };
        CubeMap::new([face(0), face(1), face(2), face(3), face(4), face(5)])
    }

    #[test]
    fn each_axis_sees_the_centre_of_its_face_in_the_courses_orientation() {
        let map = marked();
        for (d, name) in [
            (Vec3A::X, "left"),
            (Vec3A::NEG_X, "right"),
            (Vec3A::Y, "top"),
            (Vec3A::NEG_Y, "bottom"),
            (Vec3A::Z, "front"),
            (Vec3A::NEG_Z, "back"),
        ] {
            let face = FACES.iter().position(|f| *f == name).unwrap() as f32;
            let c = map.lookup(d * 7.0);
            assert_eq!(c, Vec3A::new(face, 100.0, 200.0) / 255.0, "{d} should see {name}");
        }
    }

    #[test]
    fn faces_are_read_from_their_lower_left_corner() {
        // A 3x3 front face whose texel in row r (from the top), column c
        // holds 10r + c + 1.
        let plain = Face::new(1, 1, vec![[0; 3]]).unwrap();
        let rgb = (0..9u8).map(|i| [10 * (i / 3) + i % 3 + 1, 0, 0]).collect();
        let front = Face::new(3, 3, rgb).unwrap();
        let faces = [plain.clone(), plain.clone(), plain.clone(), plain.clone(), front, plain];
        let map = CubeMap::new(faces);
        let red = |d: Vec3A| (map.lookup(d).x * 255.0).round() as u8;
        // Seen from inside looking at +z, s = (-x + 1)/2: +x is the left
        // column; t = (y + 1)/2 from the bottom row; both truncated.
        assert_eq!(red(Vec3A::new(0.9, 0.9, 1.0)), 11, "s 0.05, t 0.95: column 0, row 1 from the bottom");
        assert_eq!(red(Vec3A::new(-0.9, -0.9, 1.0)), 22, "s 0.95, t 0.05: column 1, bottom row");
        assert_eq!(red(Vec3A::new(0.9, -0.9, 1.0)), 21);
        assert_eq!(map.lookup(Vec3A::ZERO), Vec3A::ZERO);
    }
}
