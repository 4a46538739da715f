//! Base-colour and emission textures, decoded once and averaged over faces.
//!
//! NFF has no textures, so a texture becomes one colour per face: the mean
//! of the texels the face covers in UV space, estimated from the nearest
//! texel at the centroids of a regular subdivision of the face's UV
//! triangle: n² sub-triangles, n = 8·sqrt(texels covered) between 2 and 16,
//! so a face over one texel is read at 64 points (its share of each
//! neighbouring texel within a few percent) and a face over the whole image
//! at 256.
//!
//! Texel values are kept as the file stores them (sRGB-encoded for 8-bit
//! images), not linearised: nffkit writes pixel values without a transfer
//! curve, as NFF renderers always have, so a face shows the texture's colour
//! as an image viewer shows it.
//!
//! Decoding is bounded (the `image` crate's [`Limits`]): a hostile file
//! cannot make the importer allocate more than [`MAX_DECODE_BYTES`].

use glam::{DVec2, DVec3};
use image::{ImageReader, Limits};
use std::io::Cursor;

/// The most memory one texture may take to decode.
pub const MAX_DECODE_BYTES: u64 = 256 << 20;
/// The largest side a texture may have.
pub const MAX_SIDE: u32 = 8192;

/// How UVs outside [0, 1] map into the image (glTF sampler wrap modes; OBJ
/// textures repeat).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// Tile the image.
    #[default]
    Repeat,
    /// Tile, mirroring every other copy.
    Mirror,
    /// Stick to the edge texel.
    Clamp,
}

/// A decoded texture, 8 bits a channel, rows top to bottom.
#[derive(Debug, Clone)]
pub struct Texture {
    width: u32,
    height: u32,
    /// Shared by every texture of one image (a glTF image used by many
    /// textures, each with its own sampler, is decoded once).
    rgb: std::rc::Rc<[[u8; 3]]>,
    /// Wrap along u and v.
    pub wrap: [Wrap; 2],
}

impl Texture {
    /// Decode an image file's bytes (PNG, JPEG and the other formats the
    /// build enables), within the memory limits; the error says why not.
    pub fn decode(bytes: &[u8]) -> Result<Texture, String> {
        let mut limits = Limits::default();
        limits.max_alloc = Some(MAX_DECODE_BYTES);
        limits.max_image_width = Some(MAX_SIDE);
        limits.max_image_height = Some(MAX_SIDE);
        let mut reader =
            ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| e.to_string())?;
        reader.limits(limits);
        let image = reader.decode().map_err(|e| e.to_string())?;
        // The RGB copy is allocated here, outside the decoder's limits:
        // fallibly, so a machine out of memory gives an error, not a panic.
        let texels = image.width() as usize * image.height() as usize;
        let mut rgb: Vec<[u8; 3]> = Vec::new();
        rgb.try_reserve_exact(texels).map_err(|_| format!("no memory for {texels} texels"))?;
        let image = image.into_rgb8();
        let (width, height) = image.dimensions();
        if width == 0 || height == 0 {
            return Err(format!("the image is {width}x{height} pixels"));
        }
        rgb.extend(image.pixels().map(|p| p.0));
        Ok(Texture { width, height, rgb: rgb.into(), wrap: [Wrap::Repeat; 2] })
    }

    /// A texture from texels (rows top to bottom), for tests and generators.
    pub fn from_texels(width: u32, height: u32, rgb: Vec<[u8; 3]>) -> Texture {
        assert_eq!(rgb.len(), width as usize * height as usize, "texel count");
        Texture { width, height, rgb: rgb.into(), wrap: [Wrap::Repeat; 2] }
    }

    /// The memory its texels take.
    pub fn bytes(&self) -> u64 {
        self.rgb.len() as u64 * 3
    }

    /// The texels, rows top to bottom.
    pub fn texels(&self) -> &[[u8; 3]] {
        &self.rgb
    }

    /// Image size in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The texel index along one axis for coordinate `t` (0 at the first
    /// texel's edge, 1 at the last one's far edge).
    fn index(t: f64, n: u32, wrap: Wrap) -> usize {
        let n_f = n as f64;
        let x = (t * n_f).floor();
        let i = match wrap {
            Wrap::Clamp => x.clamp(0.0, n_f - 1.0),
            Wrap::Repeat => x.rem_euclid(n_f),
            Wrap::Mirror => {
                let m = x.rem_euclid(2.0 * n_f);
                if m < n_f {
                    m
                } else {
                    2.0 * n_f - 1.0 - m
                }
            }
        };
        // NaN UVs (broken files) land on texel 0 rather than panicking.
        if i.is_finite() {
            (i as usize).min(n as usize - 1)
        } else {
            0
        }
    }

    /// The texel at UV `uv` (glTF convention: v = 0 is the image's top row),
    /// as colour components in [0, 1].
    pub fn texel(&self, uv: DVec2) -> DVec3 {
        let x = Self::index(uv.x, self.width, self.wrap[0]);
        let y = Self::index(uv.y, self.height, self.wrap[1]);
        let [r, g, b] = self.rgb[y * self.width as usize + x];
        DVec3::new(r as f64, g as f64, b as f64) / 255.0
    }

    /// The mean texel over a face's UV polygon: its fan triangles' means
    /// weighted by their UV areas (equally when they have none).
    pub fn mean_over_face(&self, uv: &[DVec2]) -> DVec3 {
        if uv.len() == 3 {
            return self.mean_over_triangle([uv[0], uv[1], uv[2]]);
        }
        let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
        let mut plain = DVec3::ZERO;
        for i in 1..uv.len().saturating_sub(1) {
            let t = [uv[0], uv[i], uv[i + 1]];
            let mean = self.mean_over_triangle(t);
            let area = (t[1] - t[0]).perp_dot(t[2] - t[0]).abs();
            sum += mean * area;
            weight += area;
            plain += mean;
        }
        if weight > 0.0 && weight.is_finite() {
            sum / weight
        } else {
            plain / (uv.len().saturating_sub(2).max(1)) as f64
        }
    }

    /// The mean texel over the UV triangle `uv` (module doc).
    pub fn mean_over_triangle(&self, uv: [DVec2; 3]) -> DVec3 {
        let scale = DVec2::new(self.width as f64, self.height as f64);
        let (e1, e2) = ((uv[1] - uv[0]) * scale, (uv[2] - uv[0]) * scale);
        let texels = (e1.perp_dot(e2) * 0.5).abs();
        let n = if texels.is_finite() { (8.0 * texels.sqrt()).ceil().clamp(2.0, 16.0) as u32 } else { 2 };
        let at = |a: f64, b: f64| uv[0] + (uv[1] - uv[0]) * a + (uv[2] - uv[0]) * b;
        let mut sum = DVec3::ZERO;
        let mut count = 0u32;
        let step = 1.0 / n as f64;
        for i in 0..n {
            for j in 0..n - i {
                // The upward sub-triangle at (i, j), then the downward one beside it.
                sum += self.texel(at((i as f64 + 1.0 / 3.0) * step, (j as f64 + 1.0 / 3.0) * step));
                count += 1;
                if i + j + 1 < n {
                    sum += self.texel(at((i as f64 + 2.0 / 3.0) * step, (j as f64 + 2.0 / 3.0) * step));
                    count += 1;
                }
            }
        }
        sum / count as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        // 2x2: red, green / blue, white.
        Texture::from_texels(2, 2, vec![[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]])
    }

    #[test]
    fn texel_lookup_follows_gltf_orientation_and_wrap_modes() {
        let mut t = checker();
        assert_eq!(t.texel(DVec2::new(0.25, 0.25)), DVec3::X, "top left is red");
        assert_eq!(t.texel(DVec2::new(0.25, 0.75)), DVec3::Z, "bottom left is blue");
        assert_eq!(t.texel(DVec2::new(1.25, -0.75)), DVec3::X, "repeat");
        t.wrap = [Wrap::Clamp; 2];
        assert_eq!(t.texel(DVec2::new(7.0, 7.0)), DVec3::ONE, "clamp");
        t.wrap = [Wrap::Mirror; 2];
        assert_eq!(t.texel(DVec2::new(1.25, 0.25)), DVec3::Y, "mirror: the second copy runs backwards");
        assert_eq!(t.texel(DVec2::new(f64::NAN, 0.25)), DVec3::X, "NaN does not panic");
    }

    #[test]
    fn the_mean_over_a_face_weights_texels_by_covered_area() {
        // Left half red, right half green: the triangle (0,0) (1,0) (0,1)
        // has 3/4 of its area left of u = 1/2.
        let texels = (0..64 * 64).map(|i| if i % 64 < 32 { [255, 0, 0] } else { [0, 255, 0] }).collect();
        let t = Texture::from_texels(64, 64, texels);
        let m = t.mean_over_triangle([DVec2::ZERO, DVec2::X, DVec2::Y]);
        assert!((m - DVec3::new(0.75, 0.25, 0.0)).length() < 0.03, "{m}");
        let quad = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        assert!((t.mean_over_face(&quad) - DVec3::new(0.5, 0.5, 0.0)).length() < 0.03);
        let c = checker();
        let inside_red = [DVec2::new(0.05, 0.05), DVec2::new(0.45, 0.05), DVec2::new(0.05, 0.45)];
        assert_eq!(c.mean_over_triangle(inside_red), DVec3::X);
    }

    #[test]
    fn decoding_refuses_garbage_and_oversized_images() {
        assert!(Texture::decode(b"not an image").is_err());
        let mut png = Vec::new();
        image::RgbImage::new(MAX_SIDE + 1, 1)
            .write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        assert!(Texture::decode(&png).is_err(), "wider than MAX_SIDE");
    }
}
