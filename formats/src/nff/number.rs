//! Reading numbers fast without giving up exactness.
//!
//! Most NFF numbers are short decimals (`0.643951`, `-12`, `1e-2`). For
//! those, Clinger's fast path is exact: when the decimal digits form an
//! integer below 2^53 and the power of ten is at most 22, both are exactly
//! representable and one IEEE multiplication or division rounds correctly.
//! Everything else (long mantissas, large exponents, `inf`, `nan`) goes to
//! the standard library's parser.

/// Exact powers of ten representable in f64.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18,
    1e19, 1e20, 1e21, 1e22,
];

/// Parse a number token as C's strtod would (whole token), `None` if it is
/// not a number. Returns the same bits as `str::parse::<f64>`.
#[inline]
pub fn parse_number(text: &[u8]) -> Option<f64> {
    fast_path(text).or_else(|| std::str::from_utf8(text).ok()?.parse::<f64>().ok())
}

#[inline]
fn fast_path(text: &[u8]) -> Option<f64> {
    let (neg, mut rest) = match text.first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    };
    let mut mantissa: u64 = 0;
    let mut digits = 0u32;
    let mut exp10: i32 = 0;
    let mut seen_digit = false;
    while let Some((&c, tail)) = rest.split_first() {
        if !c.is_ascii_digit() {
            break;
        }
        mantissa = mantissa.checked_mul(10)?.checked_add((c - b'0') as u64)?;
        digits += (mantissa != 0) as u32;
        seen_digit = true;
        rest = tail;
    }
    if let Some((&b'.', tail)) = rest.split_first() {
        rest = tail;
        while let Some((&c, tail)) = rest.split_first() {
            if !c.is_ascii_digit() {
                break;
            }
            mantissa = mantissa.checked_mul(10)?.checked_add((c - b'0') as u64)?;
            digits += (mantissa != 0) as u32;
            exp10 -= 1;
            seen_digit = true;
            rest = tail;
        }
    }
    if !seen_digit || digits > 19 {
        return None;
    }
    if let Some((&(b'e' | b'E'), tail)) = rest.split_first() {
        let (eneg, mut t) = match tail.first()? {
            b'-' => (true, &tail[1..]),
            b'+' => (false, &tail[1..]),
            _ => (false, tail),
        };
        let mut e: i32 = 0;
        let mut any = false;
        while let Some((&c, tail)) = t.split_first() {
            if !c.is_ascii_digit() {
                return None;
            }
            e = e.checked_mul(10)?.checked_add((c - b'0') as i32)?;
            any = true;
            t = tail;
        }
        if !any {
            return None;
        }
        exp10 += if eneg { -e } else { e };
        rest = t;
    }
    if !rest.is_empty() || mantissa >= 1 << 53 || exp10.unsigned_abs() > 22 {
        return None;
    }
    let m = mantissa as f64;
    let v = if exp10 >= 0 { m * POW10[exp10 as usize] } else { m / POW10[(-exp10) as usize] };
    Some(if neg { -v } else { v })
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
