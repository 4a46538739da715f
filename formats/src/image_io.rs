//! Writing rendered images: 8-bit PNG and PPM, floating-point EXR and HDR,
//! chosen by the file extension. Files are written atomically
//! ([`crate::atomic`]), so a failed or interrupted write never leaves a
//! partial image.

use std::io;
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

    /// Whether the kind stores 8-bit codes, which [`encode_rgb8`] writes
    /// without the floating-point image.
    pub fn is_8bit(self) -> bool {
        matches!(self, ImageKind::Png | ImageKind::Ppm)
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

/// 8-bit RGB bytes of linear `pixels` ([`to_u8`] per channel), in order.
pub fn rgb8(pixels: impl ExactSizeIterator<Item = [f32; 3]>, srgb: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(pixels.len() * 3);
    for p in pixels {
        out.extend(p.map(|c| to_u8(c, srgb)));
    }
    out
}

impl RgbImage {
    /// 8-bit RGB bytes.
    pub fn to_rgb8(&self, srgb: bool) -> Vec<u8> {
        rgb8(self.pixels.iter().copied(), srgb)
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
        ImageKind::Png | ImageKind::Ppm => buf = encode_rgb8(img.width, img.height, img.to_rgb8(srgb), kind)?,
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

/// Encode 8-bit RGB bytes (`width * height` pixels, top row first, as
/// [`rgb8`] makes them) as a PNG or PPM file's bytes; the floating-point
/// kinds need [`encode`].
pub fn encode_rgb8(width: u32, height: u32, rgb: Vec<u8>, kind: ImageKind) -> io::Result<Vec<u8>> {
    let invalid = |what: String| io::Error::new(io::ErrorKind::InvalidInput, what);
    if rgb.len() as u64 != width as u64 * height as u64 * 3 {
        return Err(invalid(format!("{} bytes are not a {width}x{height} RGB image", rgb.len())));
    }
    match kind {
        ImageKind::Png => {
            let mut buf = Vec::new();
            let rgb = image::RgbImage::from_raw(width, height, rgb).expect("buffer size checked above");
            rgb.write_to(&mut io::Cursor::new(&mut buf), image::ImageFormat::Png)
                .map_err(|e| io::Error::other(e.to_string()))?;
            Ok(buf)
        }
        ImageKind::Ppm => {
            let mut buf = format!("P6\n{width} {height}\n255\n").into_bytes();
            buf.extend(rgb);
            Ok(buf)
        }
        ImageKind::Exr | ImageKind::Hdr => Err(invalid(format!("{kind:?} is not an 8-bit format"))),
    }
}

/// Encode `img` as OpenEXR (RGB, 32-bit float, RLE in 64x64 tiles) with the
/// given layer attributes (its data window position among them) inside
/// `display_window`. The same pixels and attributes always give the same
/// bytes: chunks are compressed on one thread and written in increasing
/// order (the parallel writer orders them as they finish), and the header's
/// attributes are put in name order (the `exr` crate writes custom
/// attributes in its hash map's order, which changes from run to run).
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
    let mut bytes = out.into_inner();
    sort_exr_header(&mut bytes)?;
    Ok(bytes)
}

/// One attribute of an EXR header: its name and its whole record (name,
/// type name, size and value) as bytes.
struct HeaderAttribute<'a> {
    name: &'a [u8],
    record: &'a [u8],
}

/// The attributes of a single-part EXR file's header, in file order, and
/// the offset of the byte that ends the header. Layout (OpenEXR file
/// layout, "Header"): magic and version (8 bytes), then attributes, each a
/// null-terminated name, a null-terminated type name, a little-endian i32
/// size and that many value bytes, then one null byte.
fn exr_header(bytes: &[u8]) -> io::Result<(Vec<HeaderAttribute<'_>>, usize)> {
    const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
    const MULTI_PART: u8 = 0x10; // bit 12 of the version field
    let bad = |what: &str| io::Error::other(format!("EXR header: {what}"));
    if bytes.len() < 8 || bytes[..4] != MAGIC {
        return Err(bad("no OpenEXR magic number"));
    }
    if bytes[5] & MULTI_PART != 0 {
        return Err(bad("multi-part files are not written here"));
    }
    let until_null = |at: usize| -> io::Result<usize> {
        let len = bytes.get(at..).and_then(|b| b.iter().position(|&c| c == 0));
        len.map(|n| at + n).ok_or_else(|| bad("unterminated name"))
    };
    let (mut attributes, mut at) = (Vec::new(), 8);
    while *bytes.get(at).ok_or_else(|| bad("no end of header"))? != 0 {
        let name_end = until_null(at)?;
        let type_end = until_null(name_end + 1)?;
        let size_at = type_end + 1;
        let size = bytes.get(size_at..size_at + 4).ok_or_else(|| bad("truncated attribute"))?;
        let size = usize::try_from(i32::from_le_bytes([size[0], size[1], size[2], size[3]]))
            .map_err(|_| bad("negative attribute size"))?;
        let end = size_at + 4 + size;
        let record = bytes.get(at..end).ok_or_else(|| bad("truncated attribute"))?;
        attributes.push(HeaderAttribute { name: &bytes[at..name_end], record });
        at = end;
    }
    Ok((attributes, at))
}

/// Rewrite a single-part EXR file's header with its attributes in name
/// order. The header keeps its length, so the offset table and chunks that
/// follow stay where they are.
fn sort_exr_header(bytes: &mut [u8]) -> io::Result<()> {
    let (mut attributes, end) = exr_header(bytes)?;
    attributes.sort_by(|a, b| a.name.cmp(b.name));
    let sorted: Vec<u8> = attributes.iter().flat_map(|a| a.record.iter().copied()).collect();
    bytes[8..end].copy_from_slice(&sorted);
    Ok(())
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
    fn eight_bit_encoding_checks_its_bytes_and_kind() {
        let img = RgbImage { width: 3, height: 2, pixels: vec![[0.25, 0.5, 1.0]; 6] };
        for kind in [ImageKind::Png, ImageKind::Ppm] {
            let direct = encode_rgb8(3, 2, img.to_rgb8(false), kind).unwrap();
            assert_eq!(direct, encode(&img, kind, false).unwrap(), "{kind:?}");
            let e = encode_rgb8(3, 2, vec![0; 17], kind).unwrap_err().to_string();
            assert!(e.contains("17 bytes are not a 3x2"), "{e}");
        }
        let e = encode_rgb8(3, 2, img.to_rgb8(false), ImageKind::Exr).unwrap_err().to_string();
        assert!(e.contains("not an 8-bit format"), "{e}");
    }

    #[test]
    fn exr_headers_list_attributes_in_name_order() {
        use exr::prelude::{AttributeValue, IntegerBounds, LayerAttributes, ReadChannels, ReadLayers, Text};
        let img = RgbImage { width: 3, height: 2, pixels: vec![[0.25, 0.5, 1.0]; 6] };
        let encode = || {
            let mut attrs = LayerAttributes::named(Text::from("part"));
            for key in ["z.last", "m.middle", "a.first", "q.other", "c.more", "k.keys"] {
                attrs.other.insert(Text::from(key), AttributeValue::Text(Text::from(key)));
            }
            encode_exr(&img, attrs, IntegerBounds::from_dimensions((3, 2))).unwrap()
        };
        let first = encode();
        let (attributes, _) = exr_header(&first).unwrap();
        let names: Vec<&[u8]> = attributes.iter().map(|a| a.name).collect();
        assert!(names.windows(2).all(|w| w[0] < w[1]), "{names:?}");
        assert!(names.contains(&&b"z.last"[..]) && names.contains(&&b"dataWindow"[..]), "{names:?}");
        // A fresh hash map each time: the order it iterates in varies.
        for _ in 0..8 {
            assert_eq!(encode(), first);
        }
        // The sorted file still reads, pixels and attributes.
        let read = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgb_channels(
                |size, _| vec![[0f32; 3]; size.area()],
                |px: &mut Vec<[f32; 3]>, at, (r, g, b): (f32, f32, f32)| px[at.y() * 3 + at.x()] = [r, g, b],
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(io::Cursor::new(&first))
            .unwrap();
        assert_eq!(read.layer_data.channel_data.pixels, img.pixels);
        assert_eq!(read.layer_data.attributes.other.len(), 6);
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
