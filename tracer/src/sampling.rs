//! Samplers: where in the pixel, on the lens and on each area light the
//! samples go (P3D report §1 and §4.1, and beyond).
//!
//! Every sample is a pure function of (pixel, sample index, dimension, seed):
//! no sampler holds state between calls, so the image cannot depend on thread
//! count or tile order. Each 2D "dimension" (pixel position, lens, each
//! light at each bounce) draws from its own shuffled copy of the pattern, the
//! decorrelation the P3D report gets from one sampler object per purpose.
//!
//! The P3D report's sample sets, shuffling and `nextSample` map onto this as:
//! a sample set is the whole pattern of one pixel and dimension
//! ([`Sampler::pattern`]), its shuffle is the index permutation applied per
//! (pixel, dimension), and `nextSample` is the next index given to
//! [`Sampler::sample_of`], without a stored table.

use crate::simd::{dispatch, LANES};
use glam::Vec2;
use strum::{Display, IntoStaticStr, VariantArray};

/// The sampling patterns. `SamplerKind::ALL` lists every one (derived,
/// so a new pattern cannot be left out of demos); the names are the
/// command line's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum SamplerKind {
    /// Independent uniform random points.
    Random,
    /// Cell centres of an n×n grid (needs a square count).
    Regular,
    /// One random point in each cell of an n×n grid (needs a square count).
    Jittered,
    /// N-rooks: one point per row and per column of an N×N grid.
    NRooks,
    /// Multi-jittered (Chiu, Shirley and Wang 1994): jittered on the n×n grid
    /// and n-rooks on the n²×n² sub-grid, x and y shuffled independently per
    /// column and row (needs a square count).
    MultiJittered,
    /// Correlated multi-jittered (Kensler 2013): one shuffle shared by all
    /// columns and rows, computed on the fly with no stored table (needs a
    /// square count).
    #[strum(serialize = "cmj")]
    CorrelatedMultiJittered,
    /// Hammersley points, randomised per pixel by a Cranley-Patterson shift
    /// in x and a random digit scramble in y.
    Hammersley,
    /// Owen-scrambled Sobol (Burley, "Practical Hash-based Owen Scrambling",
    /// JCGT 2020): the first two Sobol dimensions, nested-uniform scrambled,
    /// the index shuffled the same way.
    Sobol,
}

impl SamplerKind {
    /// Every pattern, in the order demos list them (derived by strum, so a
    /// new variant is listed without anyone remembering to).
    pub const ALL: &'static [SamplerKind] = <SamplerKind as VariantArray>::VARIANTS;

    /// The strata a pattern of `n` samples guarantees one sample in, as
    /// cells per side of a coarse grid and of a fine one (0: none), for
    /// drawing: a jittered grid's √n x √n cells; n-rooks' n rows and
    /// columns; multi-jittering's both (the P3D report's §4.1); the n rows
    /// and columns of Hammersley and Sobol at powers of two ((0, m, 2)-nets).
    pub fn strata(self, n: u32) -> (u32, u32) {
        let root = (n as f64).sqrt().round() as u32;
        match self {
            SamplerKind::Random => (0, 0),
            SamplerKind::Regular | SamplerKind::Jittered => (root, 0),
            SamplerKind::NRooks => (0, n),
            SamplerKind::MultiJittered | SamplerKind::CorrelatedMultiJittered => (root, n),
            SamplerKind::Hammersley | SamplerKind::Sobol => (0, if n.is_power_of_two() { n } else { 0 }),
        }
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// Whether the pattern is built on an n×n grid.
    pub fn needs_square(self) -> bool {
        match self {
            SamplerKind::Regular
            | SamplerKind::Jittered
            | SamplerKind::MultiJittered
            | SamplerKind::CorrelatedMultiJittered => true,
            SamplerKind::Random | SamplerKind::NRooks | SamplerKind::Hammersley | SamplerKind::Sobol => false,
        }
    }
}

/// A sampler: a pattern, a sample count and a seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampler {
    /// The pattern.
    pub kind: SamplerKind,
    /// Samples per pixel (already valid for the pattern).
    pub spp: u32,
    /// Side of the grid for grid-based patterns.
    n: u32,
    /// User seed.
    pub seed: u32,
}

impl Sampler {
    /// A sampler taking `spp` samples per pixel. Patterns built on an n×n
    /// grid round a non-square count up to the next square; the second value
    /// says so, to be shown to the user.
    pub fn new(kind: SamplerKind, spp: u32, seed: u32) -> (Sampler, Option<String>) {
        let spp = spp.max(1);
        let mut n = (spp as f64).sqrt().round() as u32;
        let mut msg = None;
        let mut count = spp;
        if kind.needs_square() {
            if n * n < spp {
                n += 1;
            }
            if n * n != spp {
                count = n * n;
                msg = Some(format!(
                    "the {kind} sampler needs a square sample count: using {count} ({n}x{n}) instead of {spp}"
                ));
            }
        }
        (Sampler { kind, spp: count, n, seed }, msg)
    }

    /// The pattern's side n (strata per axis, rounded).
    #[cfg(feature = "gpu")]
    pub(crate) fn side(&self) -> u32 {
        self.n
    }

    /// Sample `index` (< spp) of 2D dimension `dim` for pixel `(px, py)`, in
    /// [0, 1)².
    #[inline]
    pub fn sample(&self, px: u32, py: u32, index: u32, dim: u32) -> Vec2 {
        self.sample_of(self.pattern(px, py, dim), index)
    }

    /// The pattern of pixel `(px, py)` in dimension `dim`: the hash that
    /// chooses its permutation and jitter. A pixel's loop computes it once
    /// and calls [`Sampler::sample_of`] per sample (four hashes saved per
    /// sample); the samples are the same as [`Sampler::sample`]'s.
    #[inline]
    pub fn pattern(&self, px: u32, py: u32, dim: u32) -> u32 {
        hash4(px, py, dim, self.seed)
    }

    /// Samples `first..first + out.len()` of the pattern `p`, as
    /// [`Sampler::sample_of`] gives them; a multi-jittered pattern of
    /// power-of-two side [`LANES`] at a time in the vector units.
    #[inline]
    pub fn samples_of(&self, p: u32, first: u32, out: &mut [Vec2]) {
        let lane_wise =
            matches!(self.kind, SamplerKind::MultiJittered | SamplerKind::CorrelatedMultiJittered)
                && self.n > 1
                && self.n.is_power_of_two();
        if !lane_wise {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.sample_of(p, first.wrapping_add(i as u32));
            }
            return;
        }
        let correlated = self.kind == SamplerKind::CorrelatedMultiJittered;
        for (k, chunk) in out.chunks_mut(LANES).enumerate() {
            let at = first.wrapping_add((k * LANES) as u32);
            let lanes = multi_jittered_lanes(crate::simd::isa(), p, at, self.n.trailing_zeros(), correlated);
            chunk.copy_from_slice(&lanes[..chunk.len()]);
        }
    }

    /// Sample `index` of the pattern `p` (from [`Sampler::pattern`]).
    #[inline]
    pub fn sample_of(&self, p: u32, index: u32) -> Vec2 {
        let count = self.spp;
        let n = self.n;
        match self.kind {
            SamplerKind::Random => Vec2::new(randfloat(index, p), randfloat(index, p ^ 0x9e37_79b9)),
            SamplerKind::Regular => {
                let (row, col) = div_rem(permute(index, count, p), n);
                Vec2::new(over(col as f32 + 0.5, n), over(row as f32 + 0.5, n))
            }
            SamplerKind::Jittered => {
                let s = permute(index, count, p);
                let (jx, jy) = (randfloat(s, p ^ 0x68bc_21eb), randfloat(s, p ^ 0x02e5_be93));
                let (row, col) = div_rem(s, n);
                Vec2::new(over(col as f32 + jx, n), over(row as f32 + jy, n))
            }
            SamplerKind::NRooks => {
                let s = permute(index, count, p);
                let col = permute(s, count, p.wrapping_mul(0xa511_e9b3));
                let (jx, jy) = (randfloat(s, p ^ 0x68bc_21eb), randfloat(s, p ^ 0x02e5_be93));
                Vec2::new(over(col as f32 + jx, count), over(s as f32 + jy, count))
            }
            SamplerKind::MultiJittered | SamplerKind::CorrelatedMultiJittered => {
                let correlated = self.kind == SamplerKind::CorrelatedMultiJittered;
                multi_jittered(permute(index, count, p), n, p, correlated)
            }
            SamplerKind::Hammersley => {
                let s = permute(index, count, p);
                let shift = randfloat(0, p ^ 0x5bd1_e995);
                let x = over(s as f32 + 0.5, count) + shift;
                let y = (s.reverse_bits() ^ hash(p ^ 0x1b87_3593)) as f32 * (1.0 / 4_294_967_296.0);
                Vec2::new(x - x.floor(), y.min(ONE_MINUS_EPSILON))
            }
            SamplerKind::Sobol => {
                let s = nested_uniform_scramble(index, hash(p));
                let x = nested_uniform_scramble(s.reverse_bits(), hash(p ^ 0x2545_f491));
                let y = nested_uniform_scramble(sobol_dim1(s), hash(p ^ 0x9e37_79b9));
                Vec2::new(to_unit(x), to_unit(y))
            }
        }
    }
}

dispatch! {
    /// Samples `first..first + LANES` of the multi-jittered pattern `p` of
    /// side `2^shift` (`shift > 0`), as [`multi_jittered`] makes them: the
    /// same integer and IEEE operations on every lane, so the same bits,
    /// but in the vector units.
    fn multi_jittered_lanes(isa: Isa, p: u32, first: u32, shift: u32, correlated: bool) -> [Vec2; LANES] {
        |_s| {
            let (side, count) = (Pow2Side { shift }, Pow2Side { shift: 2 * shift });
            let mut out = [Vec2::ZERO; LANES];
            for (lane, o) in out.iter_mut().enumerate() {
                let s = count.permute(first.wrapping_add(lane as u32), p);
                *o = multi_jittered_on(side, s, p, correlated);
            }
            out
        }
    }
}

const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[inline]
fn to_unit(x: u32) -> f32 {
    (x as f32 * (1.0 / 4_294_967_296.0)).min(ONE_MINUS_EPSILON)
}

/// Multi-jittered sample `s` of an n×n pattern. Sample s sits in row j,
/// column k of the coarse grid; within its cell, its x sub-column is a
/// permutation of the rows (per column k, or one shared permutation when
/// correlated) and its y sub-row a permutation of the columns.
#[inline(always)]
fn multi_jittered(s: u32, n: u32, p: u32, correlated: bool) -> Vec2 {
    multi_jittered_on(AnySide(n), s, p, correlated)
}

/// [`multi_jittered`] on a grid of side `side`.
#[inline(always)]
fn multi_jittered_on(side: impl Side, s: u32, p: u32, correlated: bool) -> Vec2 {
    let (j, k) = side.div_rem(s);
    let (px, py) = if correlated {
        (p.wrapping_mul(0xa511_e9b3), p.wrapping_mul(0x63d8_3595))
    } else {
        (hash(p ^ k.wrapping_mul(0xa511_e9b3)), hash(p ^ j.wrapping_mul(0x63d8_3595) ^ 0x5555_5555))
    };
    let sx = side.permute(j, px);
    let sy = side.permute(k, py);
    let jx = randfloat(s, p.wrapping_mul(0xa399_d265));
    let jy = randfloat(s, p.wrapping_mul(0x711a_d6a5));
    Vec2::new(
        side.over(k as f32 + side.over(sx as f32 + jx)).min(ONE_MINUS_EPSILON),
        side.over(j as f32 + side.over(sy as f32 + jy)).min(ONE_MINUS_EPSILON),
    )
}

/// The side `n` of a pattern's grid and what a sample does with it:
/// [`div_rem`], [`over`] and [`permute`] by `n`.
trait Side: Copy {
    fn div_rem(self, x: u32) -> (u32, u32);
    fn over(self, x: f32) -> f32;
    fn permute(self, i: u32, p: u32) -> u32;
}

/// Any side.
#[derive(Clone, Copy)]
struct AnySide(u32);

impl Side for AnySide {
    #[inline(always)]
    fn div_rem(self, x: u32) -> (u32, u32) {
        div_rem(x, self.0)
    }
    #[inline(always)]
    fn over(self, x: f32) -> f32 {
        over(x, self.0)
    }
    #[inline(always)]
    fn permute(self, i: u32, p: u32) -> u32 {
        permute(i, self.0, p)
    }
}

/// A power of two above 1, as a shift: the same results as [`AnySide`]
/// without a branch, so a loop over lanes vectorizes.
#[derive(Clone, Copy)]
struct Pow2Side {
    shift: u32,
}

impl Pow2Side {
    #[inline(always)]
    fn mask(self) -> u32 {
        (1 << self.shift) - 1
    }
}

impl Side for Pow2Side {
    #[inline(always)]
    fn div_rem(self, x: u32) -> (u32, u32) {
        (x >> self.shift, x & self.mask())
    }
    #[inline(always)]
    fn over(self, x: f32) -> f32 {
        x * f32::from_bits((127 - self.shift) << 23)
    }
    /// [`permute`]'s cycle walk never takes a second round here.
    #[inline(always)]
    fn permute(self, i: u32, p: u32) -> u32 {
        permute_round(i, self.mask(), p).wrapping_add(p) & self.mask()
    }
}

/// Second Sobol dimension by its direction numbers' recurrence (generator
/// polynomial x + 1).
#[inline]
fn sobol_dim1(mut i: u32) -> u32 {
    let mut r = 0;
    let mut v = 1u32 << 31;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// Laine-Karras style hash permutation, as improved by Burley (2020).
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Owen scrambling of the bits of `x` (most significant first).
#[inline]
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// A good 32-bit integer hash (Wellons' "lowbias32").
#[inline]
pub fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Hash of four words, for (pixel x, pixel y, dimension, seed).
#[inline]
pub fn hash4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    hash(hash(hash(hash(a) ^ b) ^ c.wrapping_mul(0x9e37_79b9)) ^ d)
}

/// Kensler's hashed permutation: element `i` of a random permutation of
/// `0..l` chosen by `p` ("Correlated Multi-Jittered Sampling", 2013), by
/// cycle-walking a bijection on the next power of two.
#[inline]
pub fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    if l <= 1 {
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i = permute_round(i, w, p);
        if i < l {
            break;
        }
    }
    div_rem(i.wrapping_add(p), l).1
}

/// One round of [`permute`]'s bijection on `0..=w` (`w` all ones).
#[inline(always)]
fn permute_round(mut i: u32, w: u32, p: u32) -> u32 {
    i ^= p;
    i = i.wrapping_mul(0xe170_893d);
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i = i.wrapping_mul(0x0929_eb3f);
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i = i.wrapping_mul(1 | p >> 27);
    i = i.wrapping_mul(0x6935_fa69);
    i ^= (i & w) >> 11;
    i = i.wrapping_mul(0x74dc_b303);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0x9e50_1cc3);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0xc860_a3df);
    i &= w;
    i ^= i >> 5;
    i
}

/// `(x / n, x % n)`, by shift and mask when `n` is a power of two (the
/// usual sample counts and grid sides), so that a multi-jittered sample
/// does not wait on five integer divisions. `n > 0`.
#[inline(always)]
fn div_rem(x: u32, n: u32) -> (u32, u32) {
    if n.is_power_of_two() {
        (x >> n.trailing_zeros(), x & (n - 1))
    } else {
        (x / n, x % n)
    }
}

/// `x / n` in floating point, as a multiplication when `n` is a power of
/// two: then 1/n is exact, and so is the product (for the normal numbers
/// drawn here), giving the quotient's very bits.
#[inline(always)]
fn over(x: f32, n: u32) -> f32 {
    if n.is_power_of_two() {
        x * f32::from_bits((127 - n.trailing_zeros()) << 23)
    } else {
        x / n as f32
    }
}

/// Kensler's hashed float in [0, 1) for index `i` and pattern `p`.
#[inline]
pub fn randfloat(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | p >> 18);
    to_unit(i)
}

/// Shirley and Chiu's concentric map from the unit square to the unit disc
/// ("A Low Distortion Map Between Disk and Square", 1997): area-preserving
/// and continuous, so stratification survives the mapping.
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, std::f32::consts::FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (o.x / o.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The multi-jittered patterns made lane-wise, on every instruction
    /// set here, are [`Sampler::sample_of`]'s bit for bit: both kinds,
    /// sides 2 to 32, many patterns, runs of samples starting anywhere in
    /// the pattern (lanes past its end are made and left unused). Other
    /// samplers and sides take the scalar path through `samples_of`.
    #[test]
    fn lane_wise_samples_are_the_scalar_samples() {
        use crate::simd::Isa;
        let mut p = 0x2545_f491u32;
        for kind in SamplerKind::ALL.iter().copied() {
            for n in [1u32, 2, 3, 4, 8, 16, 32] {
                let (sampler, _) = Sampler::new(kind, n * n, 7);
                let count = sampler.spp;
                for _ in 0..20 {
                    p = hash(p);
                    let first = p % count;
                    let len = (count - first).min(40);
                    let want: Vec<Vec2> = (first..first + len).map(|i| sampler.sample_of(p, i)).collect();
                    let mut got = vec![Vec2::ZERO; len as usize];
                    sampler.samples_of(p, first, &mut got);
                    assert_eq!(bits(&got), bits(&want), "{kind} {n}x{n}");
                    let lane_wise =
                        matches!(kind, SamplerKind::MultiJittered | SamplerKind::CorrelatedMultiJittered);
                    if !lane_wise || n == 1 || !n.is_power_of_two() {
                        continue;
                    }
                    let correlated = kind == SamplerKind::CorrelatedMultiJittered;
                    let used = want.len().min(LANES);
                    for isa in Isa::available() {
                        let lanes = multi_jittered_lanes(isa, p, first, n.trailing_zeros(), correlated);
                        assert_eq!(bits(&lanes[..used]), bits(&want[..used]), "{kind} {n}x{n} on {isa}");
                    }
                }
            }
        }
    }

    fn bits(v: &[Vec2]) -> Vec<[u32; 2]> {
        v.iter().map(|u| [u.x.to_bits(), u.y.to_bits()]).collect()
    }

    /// The shortcuts for powers of two give the bits of the plain
    /// division, and other counts take the plain division.
    #[test]
    fn division_shortcuts_match_division() {
        let mut x = 0x1234_5678u32;
        for n in (1..=70).chain([128, 256, 1000, 1024, 4096, 65536]) {
            for _ in 0..300 {
                x = hash(x);
                let i = if x & 1 == 0 { x } else { x % (4 * n) };
                assert_eq!(div_rem(i, n), (i / n, i % n), "{i} / {n}");
                let f = (x >> 8) as f32 * (1.0 / 16_777_216.0) * (n as f32 + 1.0);
                assert_eq!(over(f, n).to_bits(), (f / n as f32).to_bits(), "{f} / {n}");
            }
        }
    }

    /// The whole pattern of pixel `(px, 3)` in dimension 0.
    fn set(kind: SamplerKind, spp: u32, px: u32) -> Vec<Vec2> {
        let (s, _) = Sampler::new(kind, spp, 7);
        (0..s.spp).map(|i| s.sample(px, 3, i, 0)).collect()
    }

    #[test]
    fn every_pattern_stays_in_the_unit_square() {
        for &kind in SamplerKind::ALL {
            for spp in [1, 4, 16, 64, 100] {
                for px in 0..20 {
                    for p in set(kind, spp, px) {
                        assert!(p.x >= 0.0 && p.x < 1.0 && p.y >= 0.0 && p.y < 1.0, "{kind} {p}");
                    }
                }
            }
        }
    }

    fn cell_counts(points: &[Vec2], nx: u32, ny: u32) -> Vec<u32> {
        let mut c = vec![0; (nx * ny) as usize];
        for p in points {
            c[((p.y * ny as f32) as u32 * nx + (p.x * nx as f32) as u32) as usize] += 1;
        }
        c
    }

    #[test]
    fn jittered_patterns_have_one_sample_per_stratum() {
        for kind in [
            SamplerKind::Jittered,
            SamplerKind::MultiJittered,
            SamplerKind::CorrelatedMultiJittered,
            SamplerKind::Regular,
        ] {
            for px in 0..10 {
                let pts = set(kind, 16, px);
                assert!(cell_counts(&pts, 4, 4).iter().all(|&c| c == 1), "{kind}");
            }
        }
    }

    #[test]
    fn rooks_patterns_have_one_sample_per_row_and_column() {
        for kind in [SamplerKind::NRooks, SamplerKind::MultiJittered, SamplerKind::CorrelatedMultiJittered] {
            for px in 0..10 {
                let pts = set(kind, 16, px);
                assert!(cell_counts(&pts, 16, 1).iter().all(|&c| c == 1), "{kind} columns");
                assert!(cell_counts(&pts, 1, 16).iter().all(|&c| c == 1), "{kind} rows");
            }
        }
    }

    #[test]
    fn low_discrepancy_sets_are_stratified_at_powers_of_two() {
        for kind in [SamplerKind::Sobol, SamplerKind::Hammersley] {
            let pts = set(kind, 16, 5);
            // Both are (0,m,2)-nets in base 2 up to the shift: one per row.
            assert!(cell_counts(&pts, 1, 16).iter().all(|&c| c == 1), "{kind} rows");
        }
        let pts = set(SamplerKind::Sobol, 16, 5);
        assert!(cell_counts(&pts, 4, 4).iter().all(|&c| c == 1), "sobol 4x4");
        assert!(cell_counts(&pts, 16, 1).iter().all(|&c| c == 1), "sobol columns");
    }

    #[test]
    fn samples_are_pure_functions() {
        for &kind in SamplerKind::ALL {
            let (s, _) = Sampler::new(kind, 16, 3);
            for i in (0..16).rev() {
                assert_eq!(s.sample(10, 20, i, 2), s.sample(10, 20, i, 2));
            }
            // A pixel's pattern computed once gives the same samples.
            let pattern = s.pattern(10, 20, 2);
            for i in 0..16 {
                assert_eq!(s.sample_of(pattern, i), s.sample(10, 20, i, 2));
            }
        }
    }

    #[test]
    fn pixels_and_dimensions_are_decorrelated() {
        for &kind in SamplerKind::ALL {
            let a = set(kind, 16, 1);
            let b = set(kind, 16, 2);
            let (s, _) = Sampler::new(kind, 16, 7);
            let c: Vec<Vec2> = (0..16).map(|i| s.sample(1, 3, i, 1)).collect();
            if kind != SamplerKind::Regular {
                assert_ne!(a, b, "{kind}: neighbouring pixels identical");
            }
            // Sample i of dimension 0 and of dimension 1 are not the same point.
            assert!(a.iter().zip(&c).filter(|(p, q)| p == q).count() < 4, "{kind}");
        }
    }

    #[test]
    fn non_square_counts_round_up_with_a_message() {
        let (s, msg) = Sampler::new(SamplerKind::Regular, 10, 0);
        assert_eq!(s.spp, 16);
        assert!(msg.unwrap().contains("16 (4x4) instead of 10"));
        let (s, msg) = Sampler::new(SamplerKind::Random, 10, 0);
        assert_eq!(s.spp, 10);
        assert!(msg.is_none());
    }

    #[test]
    fn permute_is_a_permutation() {
        for l in [1u32, 2, 3, 7, 16, 100] {
            let mut seen: Vec<u32> = (0..l).map(|i| permute(i, l, 0xdead_beef)).collect();
            seen.sort();
            assert_eq!(seen, (0..l).collect::<Vec<_>>());
        }
    }

    #[test]
    fn concentric_map_is_area_preserving_and_continuous() {
        // Equal-area rings get equal counts from a uniform grid of inputs.
        let n = 400;
        let mut rings = [0u32; 4];
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = concentric_disk(u);
                assert!(d.length() <= 1.0 + 1e-6);
                rings[((d.length_squared() * 4.0) as usize).min(3)] += 1;
            }
        }
        let expect = (n * n / 4) as f32;
        for r in rings {
            assert!((r as f32 - expect).abs() / expect < 0.02, "{rings:?}");
        }
        // Continuity: nearby inputs map to nearby outputs.
        for i in 0..1000 {
            let u = Vec2::new((i as f32 * 0.618) % 1.0, (i as f32 * 0.377) % 1.0);
            let v = u + Vec2::splat(1e-4);
            assert!((concentric_disk(u) - concentric_disk(v)).length() < 1e-3);
        }
    }
}
