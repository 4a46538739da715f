//! A vector of f32 lanes as the packet kernels need it, one implementation
//! per instruction set: [`Avx512`] (16 lanes), [`Avx2`] (8), [`Sse`] (4,
//! the x86-64 baseline) and [`Scalar4`] (4, plain arrays, for other
//! targets). The kernels are generic over [`F32s`] and process a packet's
//! [`LANES`] in `LANES / W` groups.
//!
//! Every operation is the IEEE one the scalar code uses (no fused
//! multiply-add, `max(a, b)` as `a > b ? a : b`), so a lane computes the
//! bits its ray computes alone.
//!
//! Safety rests on one rule: a vector exists only where its instruction set
//! was proven present. The only constructors are [`Simd::splat`] and
//! [`Simd::load`], and a [`Simd`] proof is made by
//! [`dispatch!`](crate::simd::dispatch) after the run-time check (or from
//! a vector that already exists). Every other operation takes a vector, so
//! it too runs only on a processor that has the instructions.

// The one module that makes and uses vectors: the unsafe code the crate
// allows is here.
#![allow(unsafe_code)]

use super::lanes::LANES;
use std::marker::PhantomData;

/// Proof that this processor runs the instructions of `V`, and the way to
/// make vectors of it.
#[derive(Clone, Copy)]
pub(crate) struct Simd<V>(PhantomData<V>);

impl<V: F32s> Simd<V> {
    /// A proof taken on trust.
    ///
    /// # Safety
    ///
    /// The processor must support `V`'s instruction set (checked with
    /// [`crate::simd::Isa::supported`]).
    #[inline(always)]
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(crate) unsafe fn new_unchecked() -> Simd<V> {
        Simd(PhantomData)
    }

    /// The proof a vector carries: it could only be made with one.
    #[inline(always)]
    pub(crate) fn of(_: V) -> Simd<V> {
        Simd(PhantomData)
    }

    /// Every lane `x`.
    #[inline(always)]
    pub(crate) fn splat(self, x: f32) -> V {
        // SAFETY: `self` proves the instruction set is present.
        unsafe { V::splat_unchecked(x) }
    }

    /// Lanes `g * W ..` of `a`.
    #[inline(always)]
    pub(crate) fn load(self, a: &[f32; LANES], g: usize) -> V {
        // SAFETY: as for `splat`.
        unsafe { V::load_unchecked(a, g) }
    }
}

/// Lanes of f32 and their comparison masks.
///
/// # Safety
///
/// An implementation promises that its safe methods need no instruction
/// beyond those that making a value needed: they are called wherever a
/// value exists.
pub(crate) unsafe trait F32s: Copy {
    /// Lanes per vector.
    const W: usize;
    /// A comparison result.
    type M: Copy;
    /// Every lane `x`.
    ///
    /// # Safety
    ///
    /// The processor must support the instruction set (see [`Simd`]).
    unsafe fn splat_unchecked(x: f32) -> Self;
    /// Lanes `g * W ..` of `a`.
    ///
    /// # Safety
    ///
    /// As for [`F32s::splat_unchecked`].
    unsafe fn load_unchecked(a: &[f32; LANES], g: usize) -> Self;
    /// Store into lanes `g * W ..` of `a`.
    fn store(self, a: &mut [f32; LANES], g: usize);
    /// `self + o`.
    fn add(self, o: Self) -> Self;
    /// `self - o`.
    fn sub(self, o: Self) -> Self;
    /// `self * o`.
    fn mul(self, o: Self) -> Self;
    /// `self / o`.
    fn div(self, o: Self) -> Self;
    /// `self < o ? self : o`.
    fn min(self, o: Self) -> Self;
    /// `self > o ? self : o`.
    fn max(self, o: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// The magnitude of `self` with the sign of `s` ([`f32::copysign`]).
    fn copysign(self, s: Self) -> Self;
    /// `-self` (the sign bit flipped).
    fn neg(self) -> Self;
    /// `self < o`.
    fn lt(self, o: Self) -> Self::M;
    /// `self <= o`.
    fn le(self, o: Self) -> Self::M;
    /// `self == o`.
    fn eq(self, o: Self) -> Self::M;
    /// `b` and not `a`.
    fn andnot(a: Self::M, b: Self::M) -> Self::M;
    /// Both.
    fn and(a: Self::M, b: Self::M) -> Self::M;
    /// Either.
    fn or(a: Self::M, b: Self::M) -> Self::M;
    /// `m ? a : b` per lane.
    fn select(m: Self::M, a: Self, b: Self) -> Self;
    /// One bit per lane, lane 0 lowest.
    fn bits(m: Self::M) -> u32;
    /// The mask whose [`F32s::bits`] are the low [`F32s::W`] bits of `bits`.
    fn from_bits(bits: u32) -> Self::M;
    /// The smallest lane (`min` in any order: exact when no lane is NaN).
    fn hmin(self) -> f32;
    /// [`F32s::hmin`] of four vectors at once: their lanes transposed
    /// and reduced together, fewer steps than four reductions.
    #[inline(always)]
    fn hmin4(v: [Self; 4]) -> [f32; 4] {
        v.map(Self::hmin)
    }
    /// `self as i32` (truncating, saturating, NaN to 0), the integer's
    /// bits held in the lane.
    fn to_i32_bits(self) -> Self;
    /// Lanes holding integer bits added, wrapping.
    fn add_i32(self, o: Self) -> Self;
    /// Lanes holding integer bits subtracted, wrapping.
    fn sub_i32(self, o: Self) -> Self;
}

/// The conversion every implementation shares: NaN to 0, saturation at
/// the `i32` ends (the hardware gives `i32::MIN` for both), as Rust's `as`.
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
fn to_i32_bits_with<V: F32s>(x: V, truncate: impl Fn(V) -> V) -> V {
    const TWO_31: f32 = 2147483648.0;
    let s = Simd::of(x);
    let x = V::select(x.eq(x), x, s.splat(0.0));
    let t = truncate(x.max(s.splat(-TWO_31)));
    V::select(s.splat(TWO_31).le(x), s.splat(f32::from_bits(i32::MAX as u32)), t)
}

/// Ask for the cache line `bytes` past the start of `items` to be brought
/// into the cache, for a loop that will read it soon (a hint: nothing is
/// read, and no address faults). A no-op off x86-64.
#[inline(always)]
pub(crate) fn prefetch<T>(items: &[T], bytes: usize) {
    let at = items.as_ptr().cast::<i8>().wrapping_add(bytes);
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is in every x86-64 processor, and a prefetch reads no
    // memory and never faults, whatever the address.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(at)
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = at;
}

/// The mask bits of group `g` placed at their packet lanes.
#[inline(always)]
pub(crate) fn group_bits<V: F32s>(m: V::M, g: usize) -> u32 {
    V::bits(m) << (g * V::W)
}

/// Whether any lane of group `g` is in `mask`.
#[inline(always)]
pub(crate) fn group_active<V: F32s>(mask: u32, g: usize) -> bool {
    let group = if V::W >= 32 { u32::MAX } else { (1u32 << V::W) - 1 };
    (mask >> (g * V::W)) & group != 0
}

/// Four lanes in a plain array: the portable fallback off x86-64.
#[derive(Clone, Copy)]
pub(crate) struct Scalar4([f32; 4]);

impl Scalar4 {
    #[inline(always)]
    fn map2(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        Scalar4(std::array::from_fn(|i| f(self.0[i], o.0[i])))
    }

    #[inline(always)]
    fn cmp(self, o: Self, f: impl Fn(f32, f32) -> bool) -> [bool; 4] {
        std::array::from_fn(|i| f(self.0[i], o.0[i]))
    }
}

// SAFETY: plain Rust, which every processor runs.
unsafe impl F32s for Scalar4 {
    const W: usize = 4;
    type M = [bool; 4];
    #[inline(always)]
    unsafe fn splat_unchecked(x: f32) -> Self {
        Scalar4([x; 4])
    }
    #[inline(always)]
    unsafe fn load_unchecked(a: &[f32; LANES], g: usize) -> Self {
        Scalar4(std::array::from_fn(|i| a[g * 4 + i]))
    }
    #[inline(always)]
    fn store(self, a: &mut [f32; LANES], g: usize) {
        a[g * 4..g * 4 + 4].copy_from_slice(&self.0);
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.map2(o, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.map2(o, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.map2(o, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.map2(o, |a, b| a / b)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.map2(o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        self.map2(o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Scalar4(self.0.map(f32::sqrt))
    }
    #[inline(always)]
    fn copysign(self, s: Self) -> Self {
        self.map2(s, f32::copysign)
    }
    #[inline(always)]
    fn neg(self) -> Self {
        Scalar4(self.0.map(|a| -a))
    }
    #[inline(always)]
    fn lt(self, o: Self) -> [bool; 4] {
        self.cmp(o, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, o: Self) -> [bool; 4] {
        self.cmp(o, |a, b| a <= b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> [bool; 4] {
        self.cmp(o, |a, b| a == b)
    }
    #[inline(always)]
    fn andnot(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        std::array::from_fn(|i| !a[i] && b[i])
    }
    #[inline(always)]
    fn and(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        std::array::from_fn(|i| a[i] && b[i])
    }
    #[inline(always)]
    fn or(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        std::array::from_fn(|i| a[i] || b[i])
    }
    #[inline(always)]
    fn select(m: [bool; 4], a: Self, b: Self) -> Self {
        Scalar4(std::array::from_fn(|i| if m[i] { a.0[i] } else { b.0[i] }))
    }
    #[inline(always)]
    fn bits(m: [bool; 4]) -> u32 {
        m.iter().enumerate().fold(0, |acc, (i, &b)| acc | (u32::from(b) << i))
    }
    #[inline(always)]
    fn from_bits(bits: u32) -> [bool; 4] {
        std::array::from_fn(|i| bits >> i & 1 != 0)
    }
    #[inline(always)]
    fn hmin(self) -> f32 {
        let [a, b, c, d] = self.0;
        let (x, y) = (if a < b { a } else { b }, if c < d { c } else { d });
        if x < y {
            x
        } else {
            y
        }
    }
    #[inline(always)]
    fn to_i32_bits(self) -> Self {
        Scalar4(self.0.map(|x| f32::from_bits((x as i32) as u32)))
    }
    #[inline(always)]
    fn add_i32(self, o: Self) -> Self {
        self.map2(o, |a, b| f32::from_bits((a.to_bits() as i32).wrapping_add(b.to_bits() as i32) as u32))
    }
    #[inline(always)]
    fn sub_i32(self, o: Self) -> Self {
        self.map2(o, |a, b| f32::from_bits((a.to_bits() as i32).wrapping_sub(b.to_bits() as i32) as u32))
    }
}

impl Simd<Scalar4> {
    /// Plain arrays need no proof.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    pub(crate) fn new() -> Simd<Scalar4> {
        Simd(PhantomData)
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{Avx2, Avx512, Sse};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::{F32s, Simd, LANES};
    use std::arch::x86_64::*;
    use std::marker::PhantomData;

    impl Simd<Sse> {
        /// SSE2 is part of x86-64 itself: no check is needed.
        pub(crate) fn new() -> Simd<Sse> {
            Simd(PhantomData)
        }
    }

    /// Generates the shared body of a 128/256-bit implementation, whose
    /// masks are vectors of all-ones or zero lanes.
    macro_rules! sse_like {
        ($name:ident, $v:ty, $w:expr, $set1:ident, $loadu:ident, $storeu:ident, $add:ident, $sub:ident,
         $mul:ident, $div:ident, $min:ident, $max:ident, $sqrt:ident, $and:ident, $or:ident, $andnot:ident,
         $xor:ident, $movemask:ident, $blend:expr, $lt:expr, $le:expr, $eq:expr,
         $cvtt:ident, $addi:ident, $subi:ident, $tosi:ident, $tops:ident, $hmin:expr, $hmin4:expr,
         $from_bits:expr) => {
            /// See the module doc.
            #[derive(Clone, Copy)]
            pub(crate) struct $name($v);

            // SAFETY: every method below uses the intrinsics of the set
            // that making a value needed, and no others.
            unsafe impl F32s for $name {
                const W: usize = $w;
                type M = $v;
                #[inline(always)]
                unsafe fn splat_unchecked(x: f32) -> Self {
                    $name(unsafe { $set1(x) })
                }
                #[inline(always)]
                unsafe fn load_unchecked(a: &[f32; LANES], g: usize) -> Self {
                    let s = &a[g * $w..g * $w + $w];
                    $name(unsafe { $loadu(s.as_ptr()) })
                }
                #[inline(always)]
                fn store(self, a: &mut [f32; LANES], g: usize) {
                    let s = &mut a[g * $w..g * $w + $w];
                    unsafe { $storeu(s.as_mut_ptr(), self.0) }
                }
                #[inline(always)]
                fn add(self, o: Self) -> Self {
                    $name(unsafe { $add(self.0, o.0) })
                }
                #[inline(always)]
                fn sub(self, o: Self) -> Self {
                    $name(unsafe { $sub(self.0, o.0) })
                }
                #[inline(always)]
                fn mul(self, o: Self) -> Self {
                    $name(unsafe { $mul(self.0, o.0) })
                }
                #[inline(always)]
                fn div(self, o: Self) -> Self {
                    $name(unsafe { $div(self.0, o.0) })
                }
                #[inline(always)]
                fn min(self, o: Self) -> Self {
                    $name(unsafe { $min(self.0, o.0) })
                }
                #[inline(always)]
                fn max(self, o: Self) -> Self {
                    $name(unsafe { $max(self.0, o.0) })
                }
                #[inline(always)]
                fn sqrt(self) -> Self {
                    $name(unsafe { $sqrt(self.0) })
                }
                #[inline(always)]
                fn copysign(self, s: Self) -> Self {
                    unsafe {
                        let sign = $set1(-0.0);
                        $name($or($andnot(sign, self.0), $and(sign, s.0)))
                    }
                }
                #[inline(always)]
                fn neg(self) -> Self {
                    $name(unsafe { $xor(self.0, $set1(-0.0)) })
                }
                #[inline(always)]
                fn lt(self, o: Self) -> $v {
                    unsafe { $lt(self.0, o.0) }
                }
                #[inline(always)]
                fn le(self, o: Self) -> $v {
                    unsafe { $le(self.0, o.0) }
                }
                #[inline(always)]
                fn eq(self, o: Self) -> $v {
                    unsafe { $eq(self.0, o.0) }
                }
                #[inline(always)]
                fn andnot(a: $v, b: $v) -> $v {
                    unsafe { $andnot(a, b) }
                }
                #[inline(always)]
                fn and(a: $v, b: $v) -> $v {
                    unsafe { $and(a, b) }
                }
                #[inline(always)]
                fn or(a: $v, b: $v) -> $v {
                    unsafe { $or(a, b) }
                }
                #[inline(always)]
                fn select(m: $v, a: Self, b: Self) -> Self {
                    $name(unsafe { $blend(b.0, a.0, m) })
                }
                #[inline(always)]
                fn bits(m: $v) -> u32 {
                    unsafe { $movemask(m) as u32 }
                }
                #[inline(always)]
                fn from_bits(bits: u32) -> $v {
                    unsafe { $from_bits(bits as i32) }
                }
                #[inline(always)]
                fn hmin(self) -> f32 {
                    unsafe { $hmin(self.0) }
                }
                #[inline(always)]
                fn hmin4([a, b, c, d]: [Self; 4]) -> [f32; 4] {
                    unsafe { $hmin4([a.0, b.0, c.0, d.0]) }
                }
                #[inline(always)]
                fn to_i32_bits(self) -> Self {
                    super::to_i32_bits_with(self, |x: Self| $name(unsafe { $tops($cvtt(x.0)) }))
                }
                #[inline(always)]
                fn add_i32(self, o: Self) -> Self {
                    $name(unsafe { $tops($addi($tosi(self.0), $tosi(o.0))) })
                }
                #[inline(always)]
                fn sub_i32(self, o: Self) -> Self {
                    $name(unsafe { $tops($subi($tosi(self.0), $tosi(o.0))) })
                }
            }
        };
    }

    /// Smallest of four lanes.
    #[inline(always)]
    unsafe fn sse_hmin(v: __m128) -> f32 {
        unsafe {
            let m = _mm_min_ps(v, _mm_shuffle_ps::<0b01_00_11_10>(v, v));
            let m = _mm_min_ps(m, _mm_shuffle_ps::<0b10_11_00_01>(m, m));
            _mm_cvtss_f32(m)
        }
    }

    /// Smallest of eight lanes.
    #[inline(always)]
    unsafe fn avx_hmin(v: __m256) -> f32 {
        unsafe { sse_hmin(avx_halves_min(v)) }
    }

    /// Lane by lane the smaller of the two halves.
    #[inline(always)]
    unsafe fn avx_halves_min(v: __m256) -> __m128 {
        unsafe { _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v)) }
    }

    /// Smallest lane of each of four vectors: a 4x4 transpose folded into
    /// the reduction.
    #[inline(always)]
    unsafe fn sse_hmin4([a, b, c, d]: [__m128; 4]) -> [f32; 4] {
        unsafe {
            // Lanes (a0 b0 a1 b1) against (a2 b2 a3 b3), the same for c, d.
            let ab = _mm_min_ps(_mm_unpacklo_ps(a, b), _mm_unpackhi_ps(a, b));
            let cd = _mm_min_ps(_mm_unpacklo_ps(c, d), _mm_unpackhi_ps(c, d));
            let m = _mm_min_ps(_mm_movelh_ps(ab, cd), _mm_movehl_ps(cd, ab));
            let mut out = [0.0; 4];
            _mm_storeu_ps(out.as_mut_ptr(), m);
            out
        }
    }

    /// Smallest lane of each of four vectors of eight. (No closure: one is
    /// compiled without AVX, and the intrinsics in it would be calls.)
    #[inline(always)]
    unsafe fn avx_hmin4([a, b, c, d]: [__m256; 4]) -> [f32; 4] {
        unsafe { sse_hmin4([avx_halves_min(a), avx_halves_min(b), avx_halves_min(c), avx_halves_min(d)]) }
    }

    /// SSE blend without SSE4.1: `(a & !m) | (b & m)`.
    #[inline(always)]
    unsafe fn sse_blend(a: __m128, b: __m128, m: __m128) -> __m128 {
        unsafe { _mm_or_ps(_mm_andnot_ps(m, a), _mm_and_ps(m, b)) }
    }

    sse_like!(
        Sse,
        __m128,
        4,
        _mm_set1_ps,
        _mm_loadu_ps,
        _mm_storeu_ps,
        _mm_add_ps,
        _mm_sub_ps,
        _mm_mul_ps,
        _mm_div_ps,
        _mm_min_ps,
        _mm_max_ps,
        _mm_sqrt_ps,
        _mm_and_ps,
        _mm_or_ps,
        _mm_andnot_ps,
        _mm_xor_ps,
        _mm_movemask_ps,
        sse_blend,
        _mm_cmplt_ps,
        _mm_cmple_ps,
        _mm_cmpeq_ps,
        _mm_cvttps_epi32,
        _mm_add_epi32,
        _mm_sub_epi32,
        _mm_castps_si128,
        _mm_castsi128_ps,
        sse_hmin,
        sse_hmin4,
        |b| {
            let lanes = _mm_setr_epi32(1, 2, 4, 8);
            _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(b), lanes), lanes))
        }
    );

    sse_like!(
        Avx2,
        __m256,
        8,
        _mm256_set1_ps,
        _mm256_loadu_ps,
        _mm256_storeu_ps,
        _mm256_add_ps,
        _mm256_sub_ps,
        _mm256_mul_ps,
        _mm256_div_ps,
        _mm256_min_ps,
        _mm256_max_ps,
        _mm256_sqrt_ps,
        _mm256_and_ps,
        _mm256_or_ps,
        _mm256_andnot_ps,
        _mm256_xor_ps,
        _mm256_movemask_ps,
        _mm256_blendv_ps,
        |a, b| _mm256_cmp_ps::<_CMP_LT_OQ>(a, b),
        |a, b| _mm256_cmp_ps::<_CMP_LE_OQ>(a, b),
        |a, b| _mm256_cmp_ps::<_CMP_EQ_OQ>(a, b),
        _mm256_cvttps_epi32,
        _mm256_add_epi32,
        _mm256_sub_epi32,
        _mm256_castps_si256,
        _mm256_castsi256_ps,
        avx_hmin,
        avx_hmin4,
        |b| {
            let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(b), lanes), lanes))
        }
    );

    /// Sixteen lanes with AVX-512 mask registers.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx512(__m512);

    // SAFETY: as for the SSE-like sets: AVX-512 F/VL/BW/DQ intrinsics only.
    unsafe impl F32s for Avx512 {
        const W: usize = 16;
        type M = __mmask16;
        #[inline(always)]
        unsafe fn splat_unchecked(x: f32) -> Self {
            Avx512(unsafe { _mm512_set1_ps(x) })
        }
        #[inline(always)]
        unsafe fn load_unchecked(a: &[f32; LANES], g: usize) -> Self {
            let s = &a[g * 16..g * 16 + 16];
            Avx512(unsafe { _mm512_loadu_ps(s.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f32; LANES], g: usize) {
            let s = &mut a[g * 16..g * 16 + 16];
            unsafe { _mm512_storeu_ps(s.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_add_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sub(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn div(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_div_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn min(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn max(self, o: Self) -> Self {
            Avx512(unsafe { _mm512_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx512(unsafe { _mm512_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn copysign(self, s: Self) -> Self {
            unsafe {
                let sign = _mm512_set1_epi32(i32::MIN);
                let mag = _mm512_andnot_si512(sign, _mm512_castps_si512(self.0));
                let sg = _mm512_and_si512(sign, _mm512_castps_si512(s.0));
                Avx512(_mm512_castsi512_ps(_mm512_or_si512(mag, sg)))
            }
        }
        #[inline(always)]
        fn neg(self) -> Self {
            unsafe {
                let sign = _mm512_set1_epi32(i32::MIN);
                Avx512(_mm512_castsi512_ps(_mm512_xor_si512(sign, _mm512_castps_si512(self.0))))
            }
        }
        #[inline(always)]
        fn lt(self, o: Self) -> __mmask16 {
            unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn le(self, o: Self) -> __mmask16 {
            unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn eq(self, o: Self) -> __mmask16 {
            unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, o.0) }
        }
        #[inline(always)]
        fn andnot(a: __mmask16, b: __mmask16) -> __mmask16 {
            !a & b
        }
        #[inline(always)]
        fn and(a: __mmask16, b: __mmask16) -> __mmask16 {
            a & b
        }
        #[inline(always)]
        fn or(a: __mmask16, b: __mmask16) -> __mmask16 {
            a | b
        }
        #[inline(always)]
        fn select(m: __mmask16, a: Self, b: Self) -> Self {
            Avx512(unsafe { _mm512_mask_blend_ps(m, b.0, a.0) })
        }
        #[inline(always)]
        fn bits(m: __mmask16) -> u32 {
            u32::from(m)
        }
        #[inline(always)]
        fn from_bits(bits: u32) -> __mmask16 {
            bits as __mmask16
        }
        #[inline(always)]
        fn hmin(self) -> f32 {
            unsafe { _mm512_reduce_min_ps(self.0) }
        }
        /// The four vectors' 128-bit blocks paired and reduced until each
        /// block holds one vector's four candidates, then each block
        /// reduced in place.
        #[inline(always)]
        fn hmin4(v: [Self; 4]) -> [f32; 4] {
            let [a, b, c, d] = v.map(|x| x.0);
            unsafe {
                // Blocks (min(a0, a2), min(a1, a3), min(b0, b2), min(b1, b3)).
                let pair = |x, y| {
                    _mm512_min_ps(
                        _mm512_shuffle_f32x4::<0b01_00_01_00>(x, y),
                        _mm512_shuffle_f32x4::<0b11_10_11_10>(x, y),
                    )
                };
                let (ab, cd) = (pair(a, b), pair(c, d));
                // Block k holds vector k's four candidates.
                let m = _mm512_min_ps(
                    _mm512_shuffle_f32x4::<0b10_00_10_00>(ab, cd),
                    _mm512_shuffle_f32x4::<0b11_01_11_01>(ab, cd),
                );
                let m = _mm512_min_ps(m, _mm512_permute_ps::<0b01_00_11_10>(m));
                let m = _mm512_min_ps(m, _mm512_permute_ps::<0b10_11_00_01>(m));
                let firsts = _mm512_permutexvar_ps(
                    _mm512_setr_epi32(0, 4, 8, 12, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0),
                    m,
                );
                let mut out = [0.0; 4];
                _mm_storeu_ps(out.as_mut_ptr(), _mm512_castps512_ps128(firsts));
                out
            }
        }
        #[inline(always)]
        fn to_i32_bits(self) -> Self {
            super::to_i32_bits_with(self, |x: Self| {
                Avx512(unsafe { _mm512_castsi512_ps(_mm512_cvttps_epi32(x.0)) })
            })
        }
        #[inline(always)]
        fn add_i32(self, o: Self) -> Self {
            unsafe {
                let sum = _mm512_add_epi32(_mm512_castps_si512(self.0), _mm512_castps_si512(o.0));
                Avx512(_mm512_castsi512_ps(sum))
            }
        }
        #[inline(always)]
        fn sub_i32(self, o: Self) -> Self {
            unsafe {
                let d = _mm512_sub_epi32(_mm512_castps_si512(self.0), _mm512_castps_si512(o.0));
                Avx512(_mm512_castsi512_ps(d))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation of `V`, on awkward values, against [`Scalar4`].
    fn agrees_with_scalar<V: F32s>(s: Simd<V>) {
        let special = [0.0, -0.0, 1.0, -1.5, 3.25, 1e30, -1e-30, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        let mut a = [0.0f32; LANES];
        let mut b = [0.0f32; LANES];
        for k in 0..special.len() * special.len() / LANES + 1 {
            for i in 0..LANES {
                let n = k * LANES + i;
                a[i] = special[n % special.len()];
                b[i] = special[(n / special.len() + n) % special.len()];
            }
            for g in 0..LANES / V::W {
                let (x, y) = (s.load(&a, g), s.load(&b, g));
                type Op<'a> = &'a dyn Fn(f32, f32) -> f32;
                let int = |x: f32| x.to_bits() as i32;
                let ops: [(V, Op); 12] = [
                    (x.add(y), &|p, q| p + q),
                    (x.sub(y), &|p, q| p - q),
                    (x.mul(y), &|p, q| p * q),
                    (x.div(y), &|p, q| p / q),
                    (x.min(y), &|p, q| if p < q { p } else { q }),
                    (x.max(y), &|p, q| if p > q { p } else { q }),
                    (x.sqrt(), &|p, _| p.sqrt()),
                    (x.copysign(y), &|p, q| p.copysign(q)),
                    (x.neg(), &|p, _| -p),
                    (x.mul(s.splat(3e9)).to_i32_bits(), &|p, _| f32::from_bits(((p * 3e9) as i32) as u32)),
                    (x.add_i32(y), &|p, q| f32::from_bits(int(p).wrapping_add(int(q)) as u32)),
                    (x.sub_i32(y), &|p, q| f32::from_bits(int(p).wrapping_sub(int(q)) as u32)),
                ];
                for (k_op, (v, f)) in ops.iter().enumerate() {
                    let mut out = [0.0f32; LANES];
                    v.store(&mut out, g);
                    for i in 0..V::W {
                        let (p, q) = (a[g * V::W + i], b[g * V::W + i]);
                        let want = f(p, q);
                        assert!(
                            out[g * V::W + i].to_bits() == want.to_bits()
                                || (want.is_nan() && out[g * V::W + i].is_nan()),
                            "op {k_op} on ({p}, {q})"
                        );
                    }
                }
                let masks = [(V::bits(x.lt(y)), 0), (V::bits(x.le(y)), 1), (V::bits(x.eq(y)), 2)];
                let sel = V::select(x.lt(y), x, y);
                let mut s = [0.0f32; LANES];
                sel.store(&mut s, g);
                for i in 0..V::W {
                    let (p, q) = (a[g * V::W + i], b[g * V::W + i]);
                    let want = [p < q, p <= q, p == q];
                    for (m, op) in masks {
                        assert_eq!(m >> i & 1 != 0, want[op], "compare {op} on ({p}, {q})");
                    }
                    let w = if p < q { p } else { q };
                    assert!(s[g * V::W + i].to_bits() == w.to_bits(), "select on ({p}, {q})");
                    let both = V::bits(V::and(x.lt(y), x.le(y))) >> i & 1 != 0;
                    let either = V::bits(V::or(x.lt(y), x.eq(y))) >> i & 1 != 0;
                    let but = V::bits(V::andnot(x.eq(y), x.le(y))) >> i & 1 != 0;
                    assert_eq!((both, either, but), (p < q, p <= q, p < q));
                }
            }
        }
        // Masks from bits: every pattern of four or eight lanes, about 300
        // spread over the patterns of sixteen, and a few chosen ones; the
        // bits above the vector's lanes are set, to be ignored.
        let all = (1u64 << V::W) - 1;
        for bits in (0..=all).step_by((all / 300).max(1) as usize).chain([all, 0b1010, 1 << (V::W - 1)]) {
            let bits = bits as u32;
            assert_eq!(V::bits(V::from_bits(bits | !all as u32)), bits & all as u32, "from_bits {bits:b}");
        }
        assert_eq!(
            group_bits::<V>(s.splat(1.0).lt(s.splat(2.0)), 1 % (LANES / V::W))
                >> ((1 % (LANES / V::W)) * V::W)
                & 1,
            1
        );
    }

    /// [`F32s::hmin`] and [`F32s::hmin4`] of `V` against a scalar fold,
    /// with the smallest lane in every position of every vector.
    fn reduces_like_scalar<V: F32s>(s: Simd<V>) {
        let values = [3.0, -0.5, 1e30, f32::INFINITY, 2.5, -7.25, 0.0, 1e-30, 4.0];
        let mut lanes = [[0.0f32; LANES]; 4];
        for k in 0..40 {
            for (v, l) in lanes.iter_mut().enumerate() {
                for (i, x) in l.iter_mut().enumerate() {
                    *x = values[(i * 7 + v * 3 + k) % values.len()] + (i + v) as f32;
                }
                // The smallest lane moves through every position.
                l[(k + 5 * v) % V::W] = -1000.0 - (k * 4 + v) as f32;
            }
            let fold = |l: &[f32]| l.iter().copied().fold(f32::INFINITY, |m, x| if x < m { x } else { m });
            let vectors: [V; 4] = std::array::from_fn(|v| s.load(&lanes[v], 0));
            let want: [f32; 4] = std::array::from_fn(|v| fold(&lanes[v][..V::W]));
            assert_eq!(vectors.map(V::hmin), want, "hmin, round {k}");
            assert_eq!(V::hmin4(vectors), want, "hmin4, round {k}");
        }
    }

    #[test]
    fn every_vector_type_computes_the_scalar_bits() {
        reduces_like_scalar(Simd::<Scalar4>::new());
        agrees_with_scalar(Simd::<Scalar4>::new());
        #[cfg(target_arch = "x86_64")]
        {
            use crate::simd::Isa;
            agrees_with_scalar(Simd::<Sse>::new());
            reduces_like_scalar(Simd::<Sse>::new());
            if Isa::Avx2.supported() {
                // SAFETY: checked just above.
                agrees_with_scalar(unsafe { Simd::<Avx2>::new_unchecked() });
                // SAFETY: checked above.
                reduces_like_scalar(unsafe { Simd::<Avx2>::new_unchecked() });
            }
            if Isa::Avx512.supported() {
                // SAFETY: checked just above.
                agrees_with_scalar(unsafe { Simd::<Avx512>::new_unchecked() });
                // SAFETY: checked above.
                reduces_like_scalar(unsafe { Simd::<Avx512>::new_unchecked() });
            }
        }
    }
}
