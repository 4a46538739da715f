//! Labels on images, drawn with the public-domain 8x8 bitmap font of the
//! `font8x8` crate.

use font8x8::UnicodeFonts;
use nffkit_formats::image_io::RgbImage;

/// Draw `text` with its top-left corner at `(x, y)`, clipped to the image.
pub fn draw_text(img: &mut RgbImage, x: u32, y: u32, text: &str, color: [f32; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let Some(glyph) = font8x8::BASIC_FONTS.get(ch) else { continue };
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) != 0 {
                    let (px, py) = (x + i as u32 * 8 + col, y + row as u32);
                    if px < img.width && py < img.height {
                        img.pixels[(py * img.width + px) as usize] = color;
                    }
                }
            }
        }
    }
}
