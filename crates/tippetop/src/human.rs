//! Numbers for people: one format for every human-facing text (console,
//! report.md, bit.md, device.md, the stability analysis), so that no
//! output shows 17 digits, `4.0415e1` or `0.0000e0`.
//!
//! [`sig`] gives `digits` significant figures: plain decimals for
//! `1e-3 <= |x| < 10^digits` (`40.41`, `0.02366`, `1234` with 4 figures),
//! powers of ten outside (`1.812e-6`, `1.235e4`), `0` for zero, and the words `inf`, `-inf`,
//! `NaN` for what is not finite. Machine outputs (CSV, JSON) keep full
//! precision and do not use it.

/// `x` with `digits` significant figures (1 to 17), as the module says.
pub fn sig(x: f64, digits: usize) -> String {
    let digits = digits.clamp(1, 17);
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    // The exponent after rounding to `digits` figures (9.9996 -> 10.00).
    let sci = format!("{:.*e}", digits - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("`e` format has an exponent");
    let exp: i32 = exp.parse().expect("an integer exponent");
    if (-3..digits as i32).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{mantissa}e{exp}")
    }
}

/// [`sig`] with 4 significant figures.
pub fn s4(x: f64) -> String {
    sig(x, 4)
}

/// A complex number `re ± im i` for people, each part by [`s4`]
/// (`0.3436+107.3i`, `-2.668e-4-0.5030i`).
pub fn complex(re: f64, im: f64) -> String {
    let sign = if im < 0.0 { '-' } else { '+' };
    format!("{}{sign}{}i", s4(re), s4(im.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_figures_without_noise() {
        for (x, want) in [
            (40.415, "40.41"),
            (99.446, "99.45"),
            (0.0, "0"),
            (-0.0, "0"),
            (1.812383e-6, "1.812e-6"),
            (3.4360e-1, "0.3436"),
            (-1.9767e3, "-1977"),
            (1.0106e2, "101.1"),
            (12346.0, "1.235e4"),
            (99_999.0, "1.000e5"),
            (9.9996, "10.00"),
            (0.00099996, "0.001000"),
            (0.00012345, "1.234e-4"),
            (0.0012345, "0.001234"),
            (2.0000000000000002e-7, "2.000e-7"),
            (f64::INFINITY, "inf"),
            (f64::NAN, "NaN"),
            (1e300, "1.000e300"),
        ] {
            assert_eq!(s4(x), want, "{x:e}");
        }
        assert_eq!(sig(0.04061824921529044, 3), "0.0406");
        assert_eq!(sig(1.2207963267948965, 3), "1.22");
        assert_eq!(complex(0.34360, -107.32), "0.3436-107.3i");
        assert_eq!(complex(-2.6681e-4, 0.503), "-2.668e-4+0.5030i");
    }
}
