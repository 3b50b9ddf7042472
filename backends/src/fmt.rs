//! Number formatting shared by the text backends.

/// Python `repr(float)`: shortest round-trip digits, positional for exponents -4..16,
/// scientific (two-digit exponent) otherwise, always with a `.` or an exponent. The
/// reference generator prints every float this way, so matching it keeps diffs small.
pub fn py_float(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0.0".into()
        } else {
            "0.0".into()
        };
    }
    let sci = format!("{x:e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if (-4..16).contains(&exp) {
        let s = format!("{x}");
        if s.contains('.') {
            s
        } else {
            s + ".0"
        }
    } else {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{mantissa}e{sign}{:02}", exp.abs())
    }
}

#[cfg(test)]
mod tests {
    use super::py_float;

    #[test]
    fn matches_python_repr() {
        for (x, s) in [
            (0.0, "0.0"),
            (1.0, "1.0"),
            (std::f64::consts::FRAC_PI_2, "1.5707963267948966"),
            (1e-5, "1e-05"),
            (0.0001, "0.0001"),
            (25323.0, "25323.0"),
            (1e16, "1e+16"),
            (123456789012345.0, "123456789012345.0"),
            (-2.5e-7, "-2.5e-07"),
            (0.1 + 0.2, "0.30000000000000004"),
        ] {
            assert_eq!(py_float(x), s, "{x}");
        }
    }
}
