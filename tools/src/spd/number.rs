//! Numbers as the SPD's C programs print them: `printf("%g")`, six
//! significant digits, trailing zeros dropped, exponent form below 1e-4
//! and from 1e6 (C11 §7.21.6.1), and `-0` kept.

use std::fmt::Write;

/// Significant digits of `%g`.
const PRECISION: i32 = 6;

/// Append `x` to `out` as C's `%g` writes it.
pub fn push_g(out: &mut String, x: f64) {
    if !x.is_finite() {
        out.push_str(match (x.is_nan(), x > 0.0) {
            (true, _) => "nan",
            (false, true) => "inf",
            (false, false) => "-inf",
        });
        return;
    }
    if x == 0.0 {
        out.push_str(if x.is_sign_negative() { "-0" } else { "0" });
        return;
    }
    let (digits, exponent) = six_digits(x.abs());
    if x < 0.0 {
        out.push('-');
    }
    let start = out.len();
    let digit = |k: usize| char::from(b'0' + digits[k]);
    if (-4..PRECISION).contains(&exponent) {
        // The fixed form has the same six digits (its decimals are chosen
        // to give six), so they are moved, not computed again.
        if exponent >= 0 {
            let point = exponent as usize + 1;
            out.extend((0..point).map(digit));
            out.push('.');
            out.extend((point..6).map(digit));
        } else {
            out.push_str("0.");
            out.extend(std::iter::repeat_n('0', (-exponent - 1) as usize));
            out.extend((0..6).map(digit));
        }
        trim_zeros(out, start);
    } else {
        out.push(digit(0));
        out.push('.');
        out.extend((1..6).map(digit));
        trim_zeros(out, start);
        let sign = if exponent < 0 { '-' } else { '+' };
        let _ = write!(out, "e{sign}{:02}", exponent.abs());
    }
}

/// The six significant digits of `a` (positive, finite) rounded as
/// printf rounds (to nearest, ties to even, on the exact binary value),
/// and the decimal exponent of the first.
///
/// The fast way scales `a` by an exact power of ten (one rounding, so an
/// error under 2^-53 of the result, about 1e-10 at six digits) and
/// rounds; where that leaves the value within 1e-9 of a rounding tie, or
/// the power is not exact, the exact formatter decides.
fn six_digits(a: f64) -> ([u8; 6], i32) {
    const EXACT_POWERS: i32 = 22;
    let mut exponent = a.log10().floor() as i32;
    for _ in 0..2 {
        let k = PRECISION - 1 - exponent;
        if k.abs() > EXACT_POWERS {
            break;
        }
        let power = 10f64.powi(k.abs());
        let scaled = if k >= 0 { a * power } else { a / power };
        // Near a tie (the range's ends 99999.5 and 999999.5 included) the
        // scaling error could decide: the exact way does.
        if (scaled - scaled.floor() - 0.5).abs() < 1e-9 {
            break;
        }
        if scaled < 99_999.5 {
            exponent -= 1;
            continue;
        }
        if scaled >= 999_999.5 {
            exponent += 1;
            continue;
        }
        let n = scaled.round() as u32;
        let mut digits = [0u8; 6];
        let mut rest = n;
        for d in digits.iter_mut().rev() {
            *d = (rest % 10) as u8;
            rest /= 10;
        }
        return (digits, exponent);
    }
    exact_six_digits(a)
}

/// [`six_digits`] by the standard library's exact formatting.
fn exact_six_digits(a: f64) -> ([u8; 6], i32) {
    let mut text = [0u8; 32];
    let mut cursor = std::io::Cursor::new(&mut text[..]);
    let _ = std::io::Write::write_fmt(&mut cursor, format_args!("{:.*e}", (PRECISION - 1) as usize, a));
    let len = cursor.position() as usize;
    let text = std::str::from_utf8(&text[..len]).expect("{:e} writes ASCII");
    let (mantissa, exponent) = text.split_once('e').expect("{:e} has an exponent");
    let mut digits = [0u8; 6];
    for (slot, d) in digits.iter_mut().zip(mantissa.bytes().filter(u8::is_ascii_digit)) {
        *slot = d - b'0';
    }
    (digits, exponent.parse().expect("{:e} exponent is an integer"))
}

/// Drop the trailing zeros of the fraction of the number written from
/// `start`, and the point if nothing follows it.
fn trim_zeros(out: &mut String, start: usize) {
    if out[start..].contains('.') {
        let kept = out.trim_end_matches('0').trim_end_matches('.').len();
        out.truncate(kept);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(x: f64) -> String {
        let mut s = String::new();
        push_g(&mut s, x);
        s
    }

    #[test]
    fn numbers_read_as_glibc_printf_g_writes_them() {
        // Each pair: the value and glibc's `printf("%g")` of it.
        let cases = [
            (0.078, "0.078"),
            (1.022846, "1.02285"),
            (-3.177154, "-3.17715"),
            (0.216539, "0.216539"),
            (100000.0, "100000"),
            (1000000.0, "1e+06"),
            (123456789.0, "1.23457e+08"),
            (0.0001, "0.0001"),
            (0.00001234, "1.234e-05"),
            (1.1102230246251565e-16, "1.11022e-16"),
            (-0.0, "-0"),
            (0.0, "0"),
            (9.9999951, "10"),
            (999999.5, "1e+06"),
            (0.5481, "0.5481"),
            (101.14838036066063, "101.148"),
            (1.5, "1.5"),
            (-2.5e-300, "-2.5e-300"),
            (0.30000000000000004, "0.3"),
        ];
        for (x, want) in cases {
            assert_eq!(g(x), want, "{x:e}");
        }
    }

    #[test]
    fn the_fast_digits_are_the_exact_ones() {
        // Values across the range, ties of six digits (exact in binary:
        // 0.5-multiples), and near-ties.
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut values = vec![1.234565, 2.5, 1000005.0, 0.1250005, 999999.5, 99999.95, 1e-5, 9.999995e-5];
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let mantissa = (x >> 11) as f64 / (1u64 << 53) as f64;
            let exponent = (x % 80) as i32 - 40;
            values.push((1.0 + mantissa) * 10f64.powi(exponent));
        }
        for v in values {
            assert_eq!(six_digits(v), exact_six_digits(v), "{v:e}");
        }
    }
}
