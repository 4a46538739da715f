//! Image metrics, in one place: root-mean-square error and mean SSIM for
//! the anti-aliasing demo, and NVIDIA's FLIP (Andersson et al., "FLIP: A
//! Difference Evaluator for Alternating Images", HPG 2020, through the
//! `nv-flip` crate) for golden-image regression. All of them read images as
//! displayed: values clamped to [0, 1].

use nffkit_formats::image_io::RgbImage;

/// Root-mean-square difference over all channels, after clamping to [0, 1]
/// (what the 8-bit image shows).
pub fn rmse(a: &RgbImage, b: &RgbImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| {
            (0..3).map(|i| (p[i].clamp(0.0, 1.0) - q[i].clamp(0.0, 1.0)) as f64).map(|d| d * d).sum::<f64>()
        })
        .sum();
    (sum / (3 * a.pixels.len().max(1)) as f64).sqrt()
}

fn luminance(img: &RgbImage) -> Vec<f64> {
    img.pixels
        .iter()
        .map(|p| {
            (0.2126 * p[0].clamp(0.0, 1.0) + 0.7152 * p[1].clamp(0.0, 1.0) + 0.0722 * p[2].clamp(0.0, 1.0))
                as f64
        })
        .collect()
}

/// Mean SSIM (Wang et al. 2004) of luminance over non-overlapping 8x8
/// windows, with the usual constants for a [0, 1] range.
pub fn mean_ssim(a: &RgbImage, b: &RgbImage) -> f64 {
    let (la, lb) = (luminance(a), luminance(b));
    let (w, h) = (a.width as usize, a.height as usize);
    let (c1, c2) = (0.01f64.powi(2), 0.03f64.powi(2));
    let (mut total, mut n) = (0.0, 0);
    for by in (0..h.saturating_sub(7)).step_by(8) {
        for bx in (0..w.saturating_sub(7)).step_by(8) {
            let idx = |x: usize, y: usize| (by + y) * w + bx + x;
            let cells: Vec<(f64, f64)> =
                (0..64).map(|k| (la[idx(k % 8, k / 8)], lb[idx(k % 8, k / 8)])).collect();
            let ma = cells.iter().map(|c| c.0).sum::<f64>() / 64.0;
            let mb = cells.iter().map(|c| c.1).sum::<f64>() / 64.0;
            let va = cells.iter().map(|c| (c.0 - ma).powi(2)).sum::<f64>() / 63.0;
            let vb = cells.iter().map(|c| (c.1 - mb).powi(2)).sum::<f64>() / 63.0;
            let cov = cells.iter().map(|c| (c.0 - ma) * (c.1 - mb)).sum::<f64>() / 63.0;
            total += ((2.0 * ma * mb + c1) * (2.0 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            n += 1;
        }
    }
    if n == 0 {
        1.0
    } else {
        total / n as f64
    }
}

/// What FLIP says about a test image against its reference.
pub struct Flip {
    /// Mean of the per-pixel FLIP error (0: identical, 1: as different as
    /// FLIP measures).
    pub mean: f64,
    /// The per-pixel error on FLIP's own "magma" colour scale.
    pub error_map: RgbImage,
}

/// FLIP (LDR) of `test` against `reference`, viewed at FLIP's default 67
/// pixels per degree. The images must have the same size.
pub fn flip(reference: &RgbImage, test: &RgbImage) -> Flip {
    assert_eq!((reference.width, reference.height), (test.width, test.height), "FLIP needs equal sizes");
    let (w, h) = (reference.width, reference.height);
    let as_flip = |img: &RgbImage| nv_flip::FlipImageRgb8::with_data(w, h, &img.to_rgb8(false));
    let errors = nv_flip::flip(as_flip(reference), as_flip(test), nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let values = errors.to_vec();
    let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
    let map = errors.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    let error_map = RgbImage {
        width: w,
        height: h,
        pixels: map.chunks_exact(3).map(|c| [c[0], c[1], c[2]].map(|v| v as f32 / 255.0)).collect(),
    };
    Flip { mean, error_map }
}

/// How closely two renders of one scene agree (the GPU's against the
/// CPU's): FLIP's mean, and the 8-bit pixels off by more than 2/255 in
/// any channel.
#[derive(Debug, Clone, Copy)]
pub struct Agreement {
    /// Mean FLIP error.
    pub flip: f64,
    /// Pixels off by more than 2/255.
    pub off: usize,
    /// Pixels in all.
    pub pixels: usize,
    /// The largest difference of a channel, in 1/255.
    pub max_off: u8,
}

impl Agreement {
    /// The share of pixels off by more than 2/255.
    pub fn off_share(&self) -> f64 {
        self.off as f64 / self.pixels.max(1) as f64
    }

    /// Whether the images agree within float differences: mean FLIP at
    /// most 0.005 and no more than 0.1% of pixels off by more than 2/255.
    pub fn within_float(&self) -> bool {
        self.flip <= 0.005 && self.off_share() <= 0.001
    }
}

impl std::fmt::Display for Agreement {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "mean FLIP {:.5}, {} of {} pixels ({:.3}%) off by more than 2/255 (at most {}/255)",
            self.flip,
            self.off,
            self.pixels,
            100.0 * self.off_share(),
            self.max_off
        )
    }
}

/// [`Agreement`] of `test` with `reference` (same size).
pub fn agreement(reference: &RgbImage, test: &RgbImage) -> Agreement {
    let (a, b) = (reference.to_rgb8(false), test.to_rgb8(false));
    let mut off = 0;
    let mut max_off = 0u8;
    for (p, q) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        max_off = max_off.max(d);
        off += (d > 2) as usize;
    }
    Agreement { flip: flip(reference, test).mean, off, pixels: a.len() / 3, max_off }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(scale: f32) -> RgbImage {
        let (w, h) = (32, 32);
        let pixels =
            (0..w * h).map(|i| [(i % w) as f32 / w as f32 * scale, (i / w) as f32 / h as f32, 0.5]).collect();
        RgbImage { width: w, height: h, pixels }
    }

    #[test]
    fn identical_images_are_perfect_and_changes_are_seen() {
        let a = gradient(1.0);
        assert_eq!(rmse(&a, &a), 0.0);
        assert!((mean_ssim(&a, &a) - 1.0).abs() < 1e-12);
        let same = flip(&a, &a);
        assert_eq!(same.mean, 0.0);
        assert_eq!((same.error_map.width, same.error_map.height), (32, 32));
        let b = gradient(0.5);
        assert!(rmse(&a, &b) > 0.1);
        assert!(flip(&a, &b).mean > flip(&a, &gradient(0.95)).mean);
        assert!(flip(&a, &gradient(0.95)).mean > 0.0);
    }
}
