//! Reconstruction filters, applied by filter importance sampling (as in
//! pbrt-v4): each pixel's sample offsets are drawn from the filter's own
//! (absolute) profile, and each sample is weighted by the filter's sign.
//! Pixels then never share samples, which keeps tiles independent and the
//! image identical for any thread count.

use glam::Vec2;
use strum::{Display, IntoStaticStr, VariantArray};

/// The filters; `FilterKind::ALL` lists them, the names are the
/// command line's.
#[derive(Debug, Clone, Copy, PartialEq, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum FilterKind {
    /// The P3D report's plain average over the pixel (radius 1/2).
    Box,
    /// Triangle, radius 1.
    Tent,
    /// Gaussian, σ = 0.5, radius 1.5.
    Gaussian,
    /// Mitchell-Netravali, B = C = 1/3, radius 2 (has negative lobes).
    Mitchell,
}

impl FilterKind {
    /// Every filter (derived by strum).
    pub const ALL: &'static [FilterKind] = <FilterKind as VariantArray>::VARIANTS;

    /// Command-line name.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// Support radius in pixels.
    pub fn radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian => 1.5,
            FilterKind::Mitchell => 2.0,
        }
    }

    /// The 1D profile (the 2D filter is its separable product).
    pub fn eval(self, x: f32) -> f32 {
        let ax = x.abs();
        match self {
            FilterKind::Box => (ax <= 0.5) as u8 as f32,
            FilterKind::Tent => (1.0 - ax).max(0.0),
            FilterKind::Gaussian => {
                let g = |v: f32| (-v * v / (2.0 * 0.25)).exp();
                (g(x) - g(1.5)).max(0.0)
            }
            FilterKind::Mitchell => {
                let (b, c) = (1.0 / 3.0, 1.0 / 3.0);
                if ax < 1.0 {
                    ((12.0 - 9.0 * b - 6.0 * c) * ax.powi(3)
                        + (-18.0 + 12.0 * b + 6.0 * c) * ax * ax
                        + (6.0 - 2.0 * b))
                        / 6.0
                } else if ax < 2.0 {
                    ((-b - 6.0 * c) * ax.powi(3)
                        + (6.0 * b + 30.0 * c) * ax * ax
                        + (-12.0 * b - 48.0 * c) * ax
                        + (8.0 * b + 24.0 * c))
                        / 6.0
                } else {
                    0.0
                }
            }
        }
    }
}

const TABLE: usize = 256;

/// A filter ready for sampling: the inverse CDF of |profile|, tabulated.
#[derive(Debug, Clone)]
pub struct Filter {
    /// Which filter.
    pub kind: FilterKind,
    cdf: Vec<f32>,
}

impl Filter {
    /// Tabulate `kind`.
    pub fn new(kind: FilterKind) -> Filter {
        let r = kind.radius();
        let mut cdf = Vec::with_capacity(TABLE + 1);
        cdf.push(0.0);
        let mut acc = 0.0;
        for i in 0..TABLE {
            let x = -r + (i as f32 + 0.5) / TABLE as f32 * 2.0 * r;
            acc += kind.eval(x).abs();
            cdf.push(acc);
        }
        for c in &mut cdf {
            *c /= acc;
        }
        Filter { kind, cdf }
    }

    /// Map `u` in [0,1)² to a pixel offset distributed like |filter|, with
    /// the sample's weight (the filter's sign: ±1).
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        if self.kind == FilterKind::Box {
            return (u - Vec2::splat(0.5), 1.0);
        }
        let x = self.sample_1d(u.x);
        let y = self.sample_1d(u.y);
        let w = self.kind.eval(x) * self.kind.eval(y);
        (Vec2::new(x, y), if w < 0.0 { -1.0 } else { 1.0 })
    }

    /// The tabulated CDF of |profile|: `TABLE + 1` values from 0 to 1.
    #[cfg(feature = "gpu")]
    pub(crate) fn cdf(&self) -> &[f32] {
        &self.cdf
    }

    fn sample_1d(&self, u: f32) -> f32 {
        // First bin whose upper CDF value exceeds u, then linear within it.
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, TABLE) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let r = self.kind.radius();
        -r + (i as f32 + t) / TABLE as f32 * 2.0 * r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_stay_within_the_radius_and_follow_the_profile() {
        for &kind in FilterKind::ALL {
            let f = Filter::new(kind);
            let mut mean_abs = 0.0;
            for i in 0..1000 {
                let u = Vec2::new((i as f32 + 0.5) / 1000.0, 0.5);
                let (o, _) = f.sample(u);
                assert!(o.x.abs() <= kind.radius() + 1e-5, "{kind} {o}");
                mean_abs += o.x.abs() / 1000.0;
            }
            // E|x| under the density |f| / integral |f|, by a fine Riemann sum.
            let r = kind.radius();
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..100_000 {
                let x = -r + (i as f32 + 0.5) / 100_000.0 * 2.0 * r;
                num += x.abs() * kind.eval(x).abs();
                den += kind.eval(x).abs();
            }
            let expect = num / den;
            assert!((mean_abs - expect).abs() < 0.01 * r, "{kind}: {mean_abs} vs {expect}");
        }
    }

    #[test]
    fn mitchell_has_negative_lobes() {
        let f = Filter::new(FilterKind::Mitchell);
        let negative = (0..1000).filter(|i| f.sample(Vec2::new(*i as f32 / 1000.0, 0.5)).1 < 0.0).count();
        assert!(negative > 0);
    }
}
