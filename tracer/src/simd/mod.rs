//! Which vector unit the packet kernels use, chosen once at run time.
//!
//! The kernels (packet traversal and the lane-wise sphere and triangle
//! tests in [`crate::packet`] and the BVH's packet traversal) are written
//! once as plain loops over [`crate::packet::LANES`] lanes. [`dispatch!`]
//! compiles that one body several times, each inside a function with
//! `#[target_feature]` for one instruction set, and calls the widest the
//! processor has: AVX-512 (one 16-lane register per loop), AVX2 (two 8-lane
//! ones), or the portable build (SSE2 on x86-64, NEON on aarch64). The
//! compiler never fuses a multiply and an add on its own, so every build
//! computes the same bits: results do not depend on the machine.
//!
//! `NFFKIT_SIMD=portable|avx2|avx512` caps the choice (for measuring the
//! difference and for the test that the kernels agree).

pub mod vec3;
pub mod vector;

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
    /// Whether this processor can run code built for `self`.
    pub fn supported(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.supported()
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
/// given (pass [`isa()`](crate::simd::isa) for the widest). In the body, the
/// type `V` is that set's [`vector::F32s`]; the body should call
/// `#[inline(always)]` functions generic over it, so they are compiled with
/// the instruction set too.
///
/// ```ignore
/// dispatch! {
///     /// Docs.
///     pub fn kernel(isa: Isa, a: &A, b: &mut B) -> R { body(a, b) }
/// }
/// ```
#[macro_export]
macro_rules! dispatch {
    ($(#[$m:meta])* $vis:vis fn $name:ident($isa:ident: Isa $(, $p:ident: $t:ty)* $(,)?) $(-> $r:ty)? $body:block) => {
        $(#[$m])*
        #[allow(unsafe_code, clippy::too_many_arguments)]
        $vis fn $name($isa: $crate::simd::Isa $(, $p: $t)*) $(-> $r)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[allow(clippy::too_many_arguments)]
                #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx512($($p: $t),*) $(-> $r)? {
                    #[allow(unused)]
                    type V = $crate::simd::vector::Avx512;
                    $body
                }
                #[allow(clippy::too_many_arguments)]
                #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx2($($p: $t),*) $(-> $r)? {
                    #[allow(unused)]
                    type V = $crate::simd::vector::Avx2;
                    $body
                }
                // SAFETY: `Isa::Avx512`/`Avx2` are only chosen (by `isa()`
                // or a caller) when `Isa::supported` confirmed the features.
                match $isa {
                    $crate::simd::Isa::Avx512 if $isa.supported() => return unsafe { avx512($($p),*) },
                    $crate::simd::Isa::Avx2 if $isa.supported() => return unsafe { avx2($($p),*) },
                    _ => {}
                }
            }
            let _ = $isa;
            #[cfg(target_arch = "x86_64")]
            #[allow(unused)]
            type V = $crate::simd::vector::Sse;
            #[cfg(not(target_arch = "x86_64"))]
            #[allow(unused)]
            type V = $crate::simd::vector::Scalar4;
            $body
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chosen_set_is_supported_and_portable_always_is() {
        assert!(isa().supported());
        assert!(Isa::available().contains(&Isa::Portable));
    }
}
