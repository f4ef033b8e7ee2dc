//! Number formatting compatible with C's `%.17g`.

/// Formats `v` like C's `printf("%.17g", v)`.
pub fn g17(v: f64) -> String {
    if v.is_nan() {
        return if v.is_sign_negative() {
            "-nan".into()
        } else {
            "nan".into()
        };
    }
    if v.is_infinite() {
        return if v < 0.0 { "-inf".into() } else { "inf".into() };
    }
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0".into()
        } else {
            "0".into()
        };
    }
    const P: i32 = 17;
    // Scientific form with P significant digits gives the decimal exponent.
    let sci = format!("{:.*e}", (P - 1) as usize, v);
    let (mantissa, exp) = sci.split_once('e').expect("exponent");
    let exp: i32 = exp.parse().expect("exponent digits");
    if !(-4..P).contains(&exp) {
        let m = trim_zeros(mantissa);
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{m}e{sign}{:02}", exp.abs())
    } else {
        let decimals = (P - 1 - exp).max(0) as usize;
        trim_zeros(&format!("{v:.decimals$}")).to_string()
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::g17;

    #[test]
    fn matches_printf() {
        assert_eq!(g17(-13.0), "-13");
        assert_eq!(g17(0.86), "0.85999999999999999");
        assert_eq!(g17(9.9999999999999937e-05), "9.9999999999999937e-05");
        assert_eq!(g17(250.00000000000011), "250.00000000000011");
        assert_eq!(g17(1e20), "1e+20");
        assert_eq!(g17(-5.8841032900000005), "-5.8841032900000005");
        assert_eq!(g17(0.1), "0.10000000000000001");
        assert_eq!(g17(123456789012345678.0), "1.2345678901234568e+17");
    }
}
