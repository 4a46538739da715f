//! Which vector unit the packet kernels use, chosen once at run time, and
//! the lanes and vectors they are written over.
//!
//! The kernels (packet traversal and the lane-wise tests and setups in
//! [`crate::packet`]) are written once, generic over a vector type
//! [`vector::F32s`], as loops over [`LANES`] lanes. [`dispatch!`] compiles
//! that one body several times, each inside a function with
//! `#[target_feature]` for one instruction set, and calls the widest the
//! processor has: AVX-512 (one 16-lane register per loop), AVX2 (two 8-lane
//! ones), or the portable build (SSE2 on x86-64, plain arrays elsewhere).
//! The compiler never fuses a multiply and an add on its own, so every build
//! computes the same bits: results do not depend on the machine.
//!
//! `NFFKIT_SIMD=portable|avx2|avx512` caps the choice (for measuring the
//! difference and for the test that the kernels agree).

pub(crate) mod lanes;
pub(crate) mod vec3;
pub(crate) mod vector;

pub use lanes::LANES;
use std::sync::OnceLock;
use strum::{Display, IntoStaticStr, VariantArray};

/// An instruction set the kernels are compiled for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, VariantArray, IntoStaticStr, Display)]
#[strum(serialize_all = "kebab-case")]
pub enum Isa {
    /// The target's baseline (SSE2 on x86-64, NEON on aarch64).
    Portable,
    /// AVX2 and FMA (8 lanes of f32).
    Avx2,
    /// AVX-512 F/VL/BW/DQ (16 lanes of f32).
    Avx512,
}

impl Isa {
    /// Whether this processor can run code built for `self` (asked of the
    /// processor once: every dispatched kernel call checks it).
    #[inline]
    pub fn supported(self) -> bool {
        static SETS: OnceLock<u8> = OnceLock::new();
        let sets = *SETS.get_or_init(|| {
            Isa::VARIANTS.iter().filter(|i| i.detected()).fold(0, |sets, &i| sets | 1 << i as u8)
        });
        sets >> self as u8 & 1 != 0
    }

    /// [`Isa::supported`], asking the processor.
    fn detected(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.detected()
                    && is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// Every instruction set this processor can run, narrowest first.
    pub fn available() -> Vec<Isa> {
        Isa::VARIANTS.iter().copied().filter(|i| i.supported()).collect()
    }
}

/// What is wrong with `NFFKIT_SIMD`, if it is set to no instruction set's
/// name (it is then ignored): for the tools to say so.
pub fn cap_problem() -> Option<String> {
    let v = std::env::var("NFFKIT_SIMD").ok()?;
    let names: Vec<&str> = Isa::VARIANTS.iter().map(|i| <&str>::from(*i)).collect();
    (!names.contains(&v.trim()))
        .then(|| format!("NFFKIT_SIMD={v} names no instruction set ({}); ignored", names.join(", ")))
}

/// The instruction set the kernels use: the widest supported, capped by
/// `NFFKIT_SIMD` when set.
pub fn isa() -> Isa {
    static CHOSEN: OnceLock<Isa> = OnceLock::new();
    *CHOSEN.get_or_init(|| {
        let cap = std::env::var("NFFKIT_SIMD")
            .ok()
            .and_then(|v| Isa::VARIANTS.iter().copied().find(|i| <&str>::from(*i) == v.trim()))
            .unwrap_or(Isa::Avx512);
        Isa::available().into_iter().filter(|&i| i <= cap).max().unwrap_or(Isa::Portable)
    })
}

/// Define `$name` running `$body` compiled for the instruction set it is
/// given (pass [`isa()`] for the widest). The body is written as
/// `|s| expr`: `s` is the [`vector::Simd`] proof of the set it runs on,
/// from which generic `#[inline(always)]` kernels make their vectors, so
/// they are compiled with the instruction set too. The function may take
/// type parameters with one bound each (`fn name<H: Bound>(...)`).
///
/// Inside the body, call no vector method through a closure (nor
/// `array::map` with one): a closure is compiled without the instruction
/// set, so the intrinsics in it can stay calls that pass their vectors
/// through memory.
///
/// ```ignore
/// dispatch! {
///     /// Docs.
///     pub(crate) fn kernel(isa: Isa, a: &A, b: &mut B) -> R { |s| body(s, a, b) }
/// }
/// ```
macro_rules! dispatch {
    ($(#[$m:meta])* $vis:vis fn $name:ident $(<$($g:ident: $b:path),*>)?
        ($isa:ident: Isa $(, $p:ident: $t:ty)* $(,)?) $(-> $r:ty)? { |$s:ident| $body:expr }) => {
        $(#[$m])*
        #[allow(unsafe_code, clippy::too_many_arguments)]
        $vis fn $name $(<$($g: $b),*>)? ($isa: $crate::simd::Isa $(, $p: $t)*) $(-> $r)? {
            use $crate::simd::vector::Simd;
            #[cfg(target_arch = "x86_64")]
            {
                #[allow(clippy::too_many_arguments)]
                #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx512 $(<$($g: $b),*>)? ($($p: $t),*) $(-> $r)? {
                    // SAFETY: called below only when the set is supported.
                    let $s = unsafe { Simd::<$crate::simd::vector::Avx512>::new_unchecked() };
                    $body
                }
                #[allow(clippy::too_many_arguments)]
                #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx2 $(<$($g: $b),*>)? ($($p: $t),*) $(-> $r)? {
                    // SAFETY: as for `avx512`.
                    let $s = unsafe { Simd::<$crate::simd::vector::Avx2>::new_unchecked() };
                    $body
                }
                // SAFETY: `Isa::supported` confirmed the features.
                match $isa {
                    $crate::simd::Isa::Avx512 if $isa.supported() => {
                        return unsafe { avx512 $(::<$($g),*>)? ($($p),*) }
                    }
                    $crate::simd::Isa::Avx2 if $isa.supported() => {
                        return unsafe { avx2 $(::<$($g),*>)? ($($p),*) }
                    }
                    _ => {}
                }
            }
            let _ = $isa;
            #[cfg(target_arch = "x86_64")]
            let $s = Simd::<$crate::simd::vector::Sse>::new();
            #[cfg(not(target_arch = "x86_64"))]
            let $s = Simd::<$crate::simd::vector::Scalar4>::new();
            $body
        }
    };
}
pub(crate) use dispatch;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chosen_set_is_supported_and_portable_always_is() {
        assert!(isa().supported());
        assert!(Isa::available().contains(&Isa::Portable));
    }
}
