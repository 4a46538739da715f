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
    // %e's six digits and exponent; %g's fixed form has the same digits
    // (its decimals are chosen to give six), so they are moved, not
    // formatted again. The exponent comes from the rounded text, since
    // rounding may carry into the next power of ten (9.999995 → 1.00000e+01).
    let mut e_form = [0u8; 32];
    let mut cursor = std::io::Cursor::new(&mut e_form[..]);
    let _ = std::io::Write::write_fmt(&mut cursor, format_args!("{:.*e}", (PRECISION - 1) as usize, x.abs()));
    let e_len = cursor.position() as usize;
    let e_form = std::str::from_utf8(&e_form[..e_len]).expect("{:e} writes ASCII");
    let (mantissa, exponent) = e_form.split_once('e').expect("{:e} has an exponent");
    let exponent: i32 = exponent.parse().expect("{:e} exponent is an integer");
    let mut digits = [b'0'; PRECISION as usize];
    for (slot, d) in digits.iter_mut().zip(mantissa.bytes().filter(u8::is_ascii_digit)) {
        *slot = d;
    }
    if x < 0.0 {
        out.push('-');
    }
    let start = out.len();
    if (-4..PRECISION).contains(&exponent) {
        if exponent >= 0 {
            let point = exponent as usize + 1;
            out.extend(digits[..point].iter().map(|&d| d as char));
            out.push('.');
            out.extend(digits[point..].iter().map(|&d| d as char));
        } else {
            out.push_str("0.");
            out.extend(std::iter::repeat_n('0', (-exponent - 1) as usize));
            out.extend(digits.iter().map(|&d| d as char));
        }
        trim_zeros(out, start);
    } else {
        out.push_str(mantissa);
        trim_zeros(out, start);
        let sign = if exponent < 0 { '-' } else { '+' };
        let _ = write!(out, "e{sign}{:02}", exponent.abs());
    }
}

/// `x` as C's `%g` writes it.
pub fn g(x: f64) -> String {
    let mut s = String::new();
    push_g(&mut s, x);
    s
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
}
