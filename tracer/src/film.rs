//! The film: linear RGB pixels, and the false-colour cost image.

use glam::Vec3A;
use nffkit_formats::image_io::{self, RgbImage};

/// A rendered image in linear RGB.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels, top row first.
    pub pixels: Vec<Vec3A>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Film {
        Film { width, height, pixels: vec![Vec3A::ZERO; (width * height) as usize] }
    }

    /// The pixel at `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> Vec3A {
        self.pixels[(y * self.width + x) as usize]
    }

    /// 8-bit RGB bytes for [`image_io::encode_rgb8`], without the
    /// floating-point image [`Film::to_image`] makes.
    pub fn to_rgb8(&self, srgb: bool) -> Vec<u8> {
        image_io::rgb8(self.pixels.iter().map(|p| p.to_array()), srgb)
    }

    /// As an image for the file writers.
    pub fn to_image(&self) -> RgbImage {
        RgbImage {
            width: self.width,
            height: self.height,
            pixels: self.pixels.iter().map(|p| p.to_array()).collect(),
        }
    }
}

/// A perceptually ordered colour scale (an approximation of matplotlib's
/// "inferno", by piecewise-linear interpolation of nine stops).
pub fn inferno(t: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 9] = [
        [0.001, 0.000, 0.014],
        [0.087, 0.044, 0.224],
        [0.258, 0.039, 0.406],
        [0.416, 0.090, 0.433],
        [0.578, 0.148, 0.404],
        [0.735, 0.216, 0.330],
        [0.865, 0.317, 0.226],
        [0.955, 0.474, 0.102],
        [0.988, 0.998, 0.645],
    ];
    let x = t.clamp(0.0, 1.0) * 8.0;
    let i = (x as usize).min(7);
    let f = x - i as f32;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f]
}

/// The per-pixel traversal work as a heat map, with a colour bar along the
/// bottom (16 pixels high, black ticks at each quarter of the scale).
/// Returns the image and the work value at the top of the scale.
pub fn cost_heatmap(cost: &[u64], width: u32, height: u32) -> (RgbImage, u64) {
    let max = cost.iter().copied().max().unwrap_or(0).max(1);
    let bar = 16;
    let mut pixels: Vec<[f32; 3]> = cost.iter().map(|&c| inferno(c as f32 / max as f32)).collect();
    for y in 0..bar {
        for x in 0..width {
            let t = x as f32 / (width.max(2) - 1) as f32;
            let tick = y < 4 && (0..=4).any(|q| x == q * (width - 1) / 4);
            pixels.push(if tick { [1.0, 1.0, 1.0] } else { inferno(t) });
        }
    }
    (RgbImage { width, height: height + bar, pixels }, max)
}
