//! Number formatting shared by the text backends.

use std::fmt::Write as _;

/// Python `repr(float)`: shortest round-trip digits, positional for exponents -4..16,
/// scientific (two-digit exponent) otherwise, always with a `.` or an exponent. The
/// reference generator prints every float this way, so matching it keeps diffs small.
pub fn py_float(x: f64) -> String {
    let mut buf = ryu::Buffer::new();
    match ryu_as_python(&mut buf, x) {
        Some(r) => r.to_string(),
        None => py_float_laid_out(x),
    }
}

/// [`py_float`] appended to `out` (no string of its own in the usual case).
pub(crate) fn push_py_float(out: &mut String, x: f64) {
    let mut buf = ryu::Buffer::new();
    match ryu_as_python(&mut buf, x) {
        Some(r) => out.push_str(r),
        None => out.push_str(&py_float_laid_out(x)),
    }
}

/// ryu's text of `x` when it is Python's as well. ryu lays out positionally from 1e-5 up to
/// 1e16 with the same digits; Python switches to an exponent below 1e-4. Those (no `e`, no
/// `0.0000` prefix) are taken as they are, the rest laid out again by the caller.
fn ryu_as_python(buf: &mut ryu::Buffer, x: f64) -> Option<&str> {
    if !x.is_finite() {
        return None;
    }
    let r = buf.format_finite(x);
    (!r.contains('e') && !r.trim_start_matches('-').starts_with("0.0000")).then_some(r)
}

/// `parts` end to end, in one allocation of the right size: for the short texts of a world
/// (poses, sizes, names), where `format!` with string arguments went through the
/// formatter's padding path and grew its buffer several times (a pose of `py_float` texts
/// took about 1,400 instructions).
pub fn cat(parts: &[&str]) -> String {
    let mut s = String::with_capacity(parts.iter().map(|p| p.len()).sum());
    for p in parts {
        s.push_str(p);
    }
    s
}

/// [`py_float`] from ryu's digits and exponent, for every value.
fn py_float_laid_out(x: f64) -> String {
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
    // Shortest round-trip digits from ryu (much cheaper than `{:e}`), laid out as Python
    // lays them out.
    let mut buf = ryu::Buffer::new();
    let r = buf.format_finite(x);
    let (sign, r) = match r.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", r),
    };
    let (mant, e10) = match r.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().unwrap_or(0)),
        None => (r, 0),
    };
    // Digits without the dot and the exponent of the first digit.
    let (int_part, frac_part) = mant.split_once('.').unwrap_or((mant, ""));
    let mut digits = String::with_capacity(24);
    digits.push_str(int_part);
    digits.push_str(frac_part);
    let lead_zeros = digits.len() - digits.trim_start_matches('0').len();
    let exp = e10 + int_part.len() as i32 - 1 - lead_zeros as i32;
    let digits = digits.trim_start_matches('0').trim_end_matches('0');
    let digits = if digits.is_empty() { "0" } else { digits };
    let mut out = String::with_capacity(digits.len() + 8);
    out.push_str(sign);
    if (-4..16).contains(&exp) {
        if exp < 0 {
            out.push_str("0.");
            out.extend(std::iter::repeat_n('0', (-exp - 1) as usize));
            out.push_str(digits);
        } else {
            let int_len = exp as usize + 1;
            if digits.len() <= int_len {
                out.push_str(digits);
                out.extend(std::iter::repeat_n('0', int_len - digits.len()));
                out.push_str(".0");
            } else {
                out.push_str(&digits[..int_len]);
                out.push('.');
                out.push_str(&digits[int_len..]);
            }
        }
    } else {
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
        let e_sign = if exp < 0 { '-' } else { '+' };
        out.push('e');
        out.push(e_sign);
        if exp.abs() < 10 {
            out.push('0');
        }
        out.push_str(&exp.abs().to_string());
    }
    out
}

/// Appends `x` with exactly `prec` decimals, the same text as `format!("{x:.prec$}")`
/// (the exact value of the double rounded half to even, a `-` on every negative value,
/// zero included), without the standard library's general exact formatter, which was a
/// quarter of a level mesh's time (Grisu, falling back to a bignum Dragon4 on many values).
/// Exact: |x| = m·2^e, so x·10^prec = m·10^prec·2^e fits in 128 bits and the rounding
/// looks at the bits shifted out.
pub fn push_fixed(out: &mut String, x: f64, prec: u32) {
    const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];
    // Beyond these the quotient could leave 64 bits; such values are not in a map.
    if !x.is_finite() || x.abs() >= 1e12 || prec as usize >= POW10.len() {
        let _ = write!(out, "{x:.*}", prec as usize);
        return;
    }
    let bits = x.to_bits();
    let exp_field = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    let (m, e2) = if exp_field == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp_field - 1075)
    };
    let scale = POW10[prec as usize];
    let p = u128::from(m) * u128::from(scale);
    let q: u128 = if e2 >= 0 {
        p << e2
    } else {
        let s = (-e2) as u32;
        if s >= 127 {
            // p < 2^73, so p / 2^s < 1/2: rounds to zero.
            0
        } else {
            let q = p >> s;
            let r = p & ((1u128 << s) - 1);
            let half = 1u128 << (s - 1);
            if r > half || (r == half && q & 1 == 1) {
                q + 1
            } else {
                q
            }
        }
    };
    let q = q as u64;
    if x.is_sign_negative() {
        out.push('-');
    }
    let mut ib = itoa::Buffer::new();
    out.push_str(ib.format(q / scale));
    if prec > 0 {
        out.push('.');
        let f = ib.format(q % scale);
        for _ in f.len()..prec as usize {
            out.push('0');
        }
        out.push_str(f);
    }
}

#[cfg(test)]
mod tests {
    use super::{push_fixed, py_float};

    /// Xorshift values of either sign spread over `decades` powers of ten from 10^`lowest`,
    /// each with the generator's state (for tests that draw more from it).
    fn random_values(mut seed: u64, decades: u64, lowest: i32) -> impl Iterator<Item = (u64, f64)> {
        std::iter::from_fn(move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let mag = 10f64.powi((seed % decades) as i32 + lowest);
            Some((
                seed,
                ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2.0 * mag,
            ))
        })
    }

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
            (-12.5, "-12.5"),
            (100.0, "100.0"),
            (-0.00012, "-0.00012"),
            (1234.5678, "1234.5678"),
            (9007199254740993.0, "9007199254740992.0"),
        ] {
            assert_eq!(py_float(x), s, "{x}");
        }
    }

    #[test]
    fn random_values_round_trip_in_python_layout() {
        // Oracle: the value round-trips, uses as many significant digits as Rust's shortest
        // `{:e}`, and is positional exactly when Python's exponent rule says so. (Digits may
        // differ from Rust's in ties: Python and ryu round half to even, e.g.
        // -649260000196054.25 prints as ...054.2.)
        assert_eq!(py_float(-6.492600001960543e14), "-649260000196054.2");
        for (_, x) in random_values(0x9E3779B97F4A7C15, 60, -30).take(20_000) {
            if x == 0.0 {
                continue;
            }
            let got = py_float(x);
            assert_eq!(got.parse::<f64>().unwrap(), x, "{got}");
            let sci = format!("{x:e}");
            let (m, e) = sci.split_once('e').unwrap();
            let e: i32 = e.parse().unwrap();
            let sig = |t: &str| {
                let t: String = t.chars().filter(|c| c.is_ascii_digit()).collect();
                t.trim_start_matches('0').trim_end_matches('0').len()
            };
            let got_mant = got.split('e').next().unwrap();
            assert_eq!(sig(got_mant), sig(m), "{got} vs {sci}");
            assert_eq!(got.contains('e'), !(-4..16).contains(&e), "{got}");
        }
    }

    #[test]
    fn the_shortcut_is_the_laid_out_text() {
        let values = random_values(0x9E3779B97F4A7C15, 44, -22).take(200_000);
        for (k, (_, x)) in values.enumerate() {
            // And round values, integers and the edges of the positional range.
            let y = [x, (x * 1e3).round(), 1e-5 * (k as f64), 1e16 - k as f64][k % 4];
            assert_eq!(super::py_float(y), super::py_float_laid_out(y), "{y:e}");
        }
        for y in [
            0.0,
            -0.0,
            1e-4,
            9.99999e-5,
            1e-5,
            1e15,
            1e16,
            9999999999999998.0,
            -1e-4,
        ] {
            assert_eq!(super::py_float(y), super::py_float_laid_out(y), "{y:e}");
        }
    }

    #[test]
    fn fixed_is_the_standard_librarys_text() {
        let check = |x: f64| {
            for prec in [0u32, 1, 2, 4, 6] {
                let mut got = String::new();
                push_fixed(&mut got, x, prec);
                assert_eq!(got, format!("{x:.*}", prec as usize), "{x:e} at {prec}");
            }
        };
        // Ties at each precision (exact binary fractions), signs, zeros, limits.
        for x in [
            0.0,
            -0.0,
            0.5,
            1.5,
            2.5,
            -2.5,
            0.25,
            0.03125,
            0.09375,
            -0.00005,
            0.00015,
            -0.00001,
            1e-320,
            -5e-324,
            1e-5,
            0.99995,
            9.99995,
            999_999.999_95,
            1e12,
            1e13,
            -1e12,
            999_999_999_999.9,
            f64::MAX,
            f64::MIN_POSITIVE,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            4503599627370496.5,
            12.3456,
            0.1 + 0.2,
        ] {
            check(x);
        }
        for k in 0..4096 {
            // Every multiple of 2^-14 below 1/4: all ties of four and six places there.
            check(k as f64 / 16384.0);
            check(-(k as f64) / 16384.0);
        }
        for (seed, x) in random_values(0x2545F4914F6CDD1D, 30, -16).take(200_000) {
            check(x);
            // Values a few ulps from a decimal tie, where a shortcut would slip.
            let tie = ((seed >> 20) % 2_000_000) as f64 / 10_000.0 + 0.00005;
            check(tie);
            check(f64::from_bits(tie.to_bits() + 1));
            check(f64::from_bits(tie.to_bits() - 1));
        }
    }
}
