//! Reading numbers fast without giving up exactness.
//!
//! NFF files are mostly numbers, so how they are read sets the reader's
//! speed. Two paths, both correctly rounded, so a number reads to the bits
//! `str::parse::<f64>` gives (the tests hold them to it):
//!
//! - Most NFF numbers are short decimals (`0.643951`, `-12`, `3.0827`). For
//!   those Clinger's fast path is exact: with at most 15 digits the digits
//!   form an integer below 2^53 and the power of ten is at most 10^15, both
//!   exactly representable, so one IEEE division rounds correctly.
//! - Everything else (17-digit round-trip numbers, exponents, `inf`, `nan`)
//!   goes to `fast-float2`, Lemire's algorithm: one 64x128-bit product for
//!   all but pathological inputs, reading bytes directly with no UTF-8 check.
//!
//! The grammar is C's strtod for NFF's purposes (`.5`, `5.`, `-0`, `1e-16`,
//! `+2`, `inf`, `nan`).

/// Exact powers of ten for the short path.
const POW10: [f64; 16] =
    [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];

/// Parse a number token as C's strtod would (whole token), `None` if it is
/// not a number. Returns the same bits as `str::parse::<f64>`.
#[inline]
pub fn parse_number(text: &[u8]) -> Option<f64> {
    match short_decimal(text) {
        Some((v, n)) if n == text.len() => Some(v),
        _ => fast_float2::parse(text).ok(),
    }
}

/// The number at the start of `src` and its length in bytes, `None` when
/// `src` does not start with one. The number may be followed by anything:
/// the caller decides whether it ends the token.
#[inline]
pub fn number_prefix(src: &[u8]) -> Option<(f64, usize)> {
    short_decimal(src).or_else(|| fast_float2::parse_partial(src).ok())
}

/// `[+-]digits[.digits]` with 1 to 15 digits and no exponent, read exactly
/// (module doc); `None` for anything else, left to the general parser.
#[inline(always)]
fn short_decimal(src: &[u8]) -> Option<(f64, usize)> {
    let neg = src.first() == Some(&b'-');
    let mut i = (neg || src.first() == Some(&b'+')) as usize;
    if long_run(src, i) {
        return None;
    }
    let mut mantissa = 0u64;
    let int_start = i;
    i = digits(src, i, &mut mantissa);
    let int_digits = i - int_start;
    let mut frac_digits = 0;
    if src.get(i) == Some(&b'.') {
        let frac_start = i + 1;
        i = digits(src, frac_start, &mut mantissa);
        frac_digits = i - frac_start;
    }
    let all = int_digits + frac_digits;
    if all == 0 || all > 15 || matches!(src.get(i), Some(b'e' | b'E')) {
        return None;
    }
    let v = mantissa as f64 / POW10[frac_digits];
    Some((if neg { -v } else { v }, i))
}

/// Whether the 16 bytes from `i` are all digits or dots: a number too long
/// for the short path, sent on without reading it digit by digit (a test
/// that compiles to a few vector instructions).
#[inline(always)]
fn long_run(src: &[u8], i: usize) -> bool {
    let Some(bytes) = src.get(i..i + 16) else { return false };
    bytes.iter().map(|&c| (c.wrapping_sub(b'0') < 10 || c == b'.') as u8).sum::<u8>() == 16
}

/// Accumulate the decimal digits from `i` into `mantissa` (wrapping: the
/// caller rejects more than 15 digits); where they end.
#[inline(always)]
fn digits(src: &[u8], mut i: usize, mantissa: &mut u64) -> usize {
    while let Some(&c) = src.get(i) {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        *mantissa = mantissa.wrapping_mul(10).wrapping_add(d as u64);
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_standard_library() {
        for s in [
            "0",
            "-0",
            "+0",
            ".5",
            "5.",
            "-.5",
            "12",
            "0.643951",
            "1.11022e-16",
            "1e22",
            "1e23",
            "-3.1e-2",
            "1E5",
            "123456789012345678",
            "9007199254740993",
            "0.1",
            "3.0827",
            "100000",
            "2.e+1",
            "1e",
            "e5",
            ".",
            "-",
            "+",
            "1.2.3",
            "1e5.5",
            "inf",
            "nan",
            "0x10",
            "1_0",
            "",
            "0.2721655269759087",
            "12345678",
            "-87654321.12345678e-3",
            "0.00000000000000000001",
            "00000000000000000000000001.5",
            "99999999999999999999",
            "0.16666666666666666",
            "2.2250738585072011e-308",
            "4.9e-324",
            "1.7976931348623157e308",
            "1e309",
            "INF",
            "+inf",
            "-Infinity",
            "infinity",
            "NaN",
            "-nan",
            "infx",
            "1e+",
            "1e-x",
            "--1",
            "+-1",
            "1..2",
        ] {
            let ours = parse_number(s.as_bytes());
            let std = s.parse::<f64>().ok();
            assert_eq!(ours.map(f64::to_bits), std.map(f64::to_bits), "{s:?}");
        }
    }

    proptest::proptest! {
        #[test]
        fn random_decimals_agree_with_the_standard_library(
            int in "[0-9]{0,20}", frac in proptest::option::of("[0-9]{0,24}"),
            exp in proptest::option::of(-30i32..30), neg: bool,
        ) {
            let mut s = String::new();
            if neg { s.push('-'); }
            s += &int;
            if let Some(f) = &frac { s.push('.'); s += f; }
            if let Some(e) = exp { s += &format!("e{e}"); }
            let ours = parse_number(s.as_bytes());
            let std = s.parse::<f64>().ok();
            proptest::prop_assert_eq!(ours.map(f64::to_bits), std.map(f64::to_bits), "{:?}", s);
        }
    }
}
