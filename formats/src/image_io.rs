//! Writing rendered images: 8-bit PNG and PPM, floating-point EXR and HDR,
//! chosen by the file extension. Files are written atomically
//! ([`crate::atomic`]), so a failed or interrupted write never leaves a
//! partial image.

use std::io::{self, Write};
use std::path::Path;

/// A linear RGB image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<[f32; 3]>,
}

/// File kinds by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageKind {
    /// 8-bit PNG (clamped).
    Png,
    /// 8-bit binary PPM (P6, clamped).
    Ppm,
    /// OpenEXR, linear 32-bit float.
    Exr,
    /// Radiance HDR, linear.
    Hdr,
}

/// A path whose extension names no image format we write.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{0}: unknown image extension (use .png, .ppm, .exr or .hdr)")]
pub struct UnknownImageKind(pub String);

impl ImageKind {
    /// The kind for a path's extension.
    pub fn from_path(path: &Path) -> Result<ImageKind, UnknownImageKind> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        Ok(match ext.as_str() {
            "png" => ImageKind::Png,
            "ppm" => ImageKind::Ppm,
            "exr" => ImageKind::Exr,
            "hdr" => ImageKind::Hdr,
            _ => return Err(UnknownImageKind(path.display().to_string())),
        })
    }
}

/// Linear value to an 8-bit code, clamped, optionally through the sRGB curve.
#[inline]
pub fn to_u8(v: f32, srgb: bool) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let v = if srgb {
        if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    } else {
        v
    };
    (v * 255.0 + 0.5) as u8
}

impl RgbImage {
    /// 8-bit RGB bytes.
    pub fn to_rgb8(&self, srgb: bool) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.map(|c| to_u8(c, srgb))).collect()
    }
}

/// Write `img` to `path` in the format its extension names.
pub fn save(img: &RgbImage, path: &Path, srgb: bool) -> io::Result<()> {
    let kind = ImageKind::from_path(path).map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    let bytes = encode(img, kind, srgb)?;
    crate::atomic::write_bytes(path, &bytes)
}

/// Encode to bytes in memory.
pub fn encode(img: &RgbImage, kind: ImageKind, srgb: bool) -> io::Result<Vec<u8>> {
    let to_io = |e: image::ImageError| io::Error::other(e.to_string());
    let mut buf = Vec::new();
    match kind {
        ImageKind::Png => {
            let rgb = image::RgbImage::from_raw(img.width, img.height, img.to_rgb8(srgb))
                .expect("buffer size matches dimensions");
            rgb.write_to(&mut io::Cursor::new(&mut buf), image::ImageFormat::Png).map_err(to_io)?;
        }
        ImageKind::Ppm => {
            write!(buf, "P6\n{} {}\n255\n", img.width, img.height)?;
            buf.extend(img.to_rgb8(srgb));
        }
        ImageKind::Exr => {
            let attrs = exr::prelude::LayerAttributes::default();
            buf = encode_exr(
                img,
                attrs,
                exr::prelude::IntegerBounds::from_dimensions((img.width as usize, img.height as usize)),
            )?;
        }
        ImageKind::Hdr => {
            let flat: Vec<f32> = img.pixels.iter().flatten().copied().collect();
            let rgb = image::Rgb32FImage::from_raw(img.width, img.height, flat)
                .expect("buffer size matches dimensions");
            image::DynamicImage::ImageRgb32F(rgb)
                .write_to(&mut io::Cursor::new(&mut buf), image::ImageFormat::Hdr)
                .map_err(to_io)?;
        }
    }
    Ok(buf)
}

/// Encode `img` as OpenEXR (RGB, 32-bit float, RLE in 64x64 tiles) with the
/// given layer attributes (its data window position among them) inside
/// `display_window`. Chunks are compressed on one thread and written in
/// increasing order, so the same pixels always give the same bytes (the
/// parallel writer orders chunks as they finish).
pub fn encode_exr(
    img: &RgbImage,
    attributes: exr::prelude::LayerAttributes,
    display_window: exr::prelude::IntegerBounds,
) -> io::Result<Vec<u8>> {
    use exr::prelude::*;
    let w = img.width as usize;
    let pixels = |p: Vec2<usize>| {
        let [r, g, b] = img.pixels[p.y() * w + p.x()];
        (r, g, b)
    };
    let encoding = Encoding { line_order: LineOrder::Increasing, ..Encoding::FAST_LOSSLESS };
    let layer = Layer::new((w, img.height as usize), attributes, encoding, SpecificChannels::rgb(pixels));
    let mut image = Image::from_layer(layer);
    image.attributes.display_window = display_window;
    let mut out = io::Cursor::new(Vec::new());
    image.write().non_parallel().to_buffered(&mut out).map_err(|e| io::Error::other(e.to_string()))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_by_extension() {
        assert_eq!(ImageKind::from_path(Path::new("a.PNG")).unwrap(), ImageKind::Png);
        assert_eq!(ImageKind::from_path(Path::new("a.exr")).unwrap(), ImageKind::Exr);
        let e = ImageKind::from_path(Path::new("a.jpg")).unwrap_err().to_string();
        assert!(e.contains("a.jpg") && e.contains(".png, .ppm"), "{e}");
    }

    #[test]
    fn quantisation_clamps_and_rounds() {
        assert_eq!(to_u8(-1.0, false), 0);
        assert_eq!(to_u8(2.0, false), 255);
        assert_eq!(to_u8(0.5, false), 128);
        assert_eq!(to_u8(f32::NAN, false), 0);
        assert!(to_u8(0.5, true) > 180);
    }

    #[test]
    fn every_kind_writes_and_png_reads_back() {
        let dir = tempfile::tempdir().unwrap();
        let img = RgbImage { width: 3, height: 2, pixels: vec![[0.25, 0.5, 1.0]; 6] };
        for ext in ["png", "ppm", "exr", "hdr"] {
            let p = dir.path().join(format!("x.{ext}"));
            save(&img, &p, false).unwrap();
            assert!(std::fs::metadata(&p).unwrap().len() > 0);
        }
        let back = image::open(dir.path().join("x.png")).unwrap().to_rgb8();
        assert_eq!(back.get_pixel(2, 1).0, [64, 128, 255]);
        // Only the four images: no temporary file left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 4);
    }
}
