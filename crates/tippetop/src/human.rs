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

/// `x` exactly as it was given (the shortest digits that parse back to
/// it), for a message that quotes an input value: plain decimals for zero
/// and `1e-3 <= |x| < 1e7` (`-1`, `0.25`, `1500000`), powers of ten
/// outside (`3e-10`, `3.55e-10`, `1.196e-24`, not
/// `0.000000000355`), and `inf`, `-inf`, `NaN` for what is not finite.
pub fn exact(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A year \[s\] (365.25 days).
pub const YEAR: f64 = 365.25 * 86400.0;

/// What a text for people says of a time beyond any time scale (see
/// [`beyond_any_time_scale`]) instead of its power of ten.
pub const BEYOND_ANY_TIME_SCALE: &str = "beyond any time scale (over 10^100 years)";

/// Whether `10^log10_seconds` seconds is beyond any time scale: over
/// 10^100 years, which no process, measurement or design comes near (the
/// universe is about 1.4 × 10^10 years old), so its digits mean nothing
/// to a reader.
pub fn beyond_any_time_scale(log10_seconds: f64) -> bool {
    log10_seconds > 100.0 + YEAR.log10()
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

/// `x` in `unit` with an SI prefix and `digits` significant figures, the
/// mantissa in [1, 1000): `si(3.081e-6, "s", 4)` is `3.081 µs`,
/// `si(1.414e-21, "N", 4)` `1.414 zN`, from yocto (1e-24) to yotta
/// (1e24); outside that, and for 0 or what is not finite, [`sig`] with the
/// bare unit.
pub fn si(x: f64, unit: &str, digits: usize) -> String {
    const PREFIXES: [&str; 17] = [
        "y", "z", "a", "f", "p", "n", "µ", "m", "", "k", "M", "G", "T", "P", "E", "Z", "Y",
    ];
    if x == 0.0 || !x.is_finite() {
        return format!("{} {unit}", sig(x, digits));
    }
    // The exponent after rounding (999.96 ms is 1.000 s).
    let sci = format!("{:.*e}", digits.clamp(1, 17) - 1, x.abs());
    let exp: i32 = sci
        .split_once('e')
        .expect("`e` format")
        .1
        .parse()
        .expect("exponent");
    let k = exp.div_euclid(3);
    if !(-8..=8).contains(&k) {
        return format!("{} {unit}", sig(x, digits));
    }
    // The mantissa rounded to `digits` figures, written without a power
    // of ten (it is in [1, 1000): `420`, not `4.2e2`).
    let digits = digits.clamp(1, 17);
    let v: f64 = format!("{:.*e}", digits - 1, x / 10f64.powi(3 * k))
        .parse()
        .expect("a number");
    let decimals = (digits as i32 - 1 - (exp - 3 * k)).max(0) as usize;
    format!("{v:.decimals$} {}{unit}", PREFIXES[(k + 8) as usize])
}

/// A wall-clock duration for people: `42 s`, `3 min 20 s`, `2 h 05 min`,
/// `3.2 days`; under a second as [`si`] (`350 ms`).
pub fn duration(seconds: f64) -> String {
    if !seconds.is_finite() || seconds < 0.0 {
        return "unknown".into();
    }
    if seconds < 1.0 {
        return si(seconds, "s", 2);
    }
    let s = seconds.round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else if s < 48 * 3600 {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    } else {
        format!("{} days", sig(seconds / 86400.0, 2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An input value is quoted with the digits that parse back to it, in
    /// powers of ten outside [1e-3, 1e7).
    #[test]
    fn exact_values_read_and_round_trip() {
        for (x, want) in [
            (-1.0, "-1"),
            (0.0, "0"),
            (0.25, "0.25"),
            (1e-3, "0.001"),
            (1.5e6, "1500000"),
            (1e7, "1e7"),
            (3e-10, "3e-10"),
            (3.55e-10, "3.55e-10"),
            (-1.196e-24, "-1.196e-24"),
            (0.1 + 0.2, "0.30000000000000004"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(exact(x), want);
            if x.is_finite() {
                assert_eq!(want.parse::<f64>().unwrap().to_bits(), x.to_bits());
            }
        }
    }

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

    #[test]
    fn times_beyond_any_time_scale() {
        let log10_years = |y: f64| y + YEAR.log10();
        assert!(!beyond_any_time_scale(log10_years(100.0)));
        assert!(beyond_any_time_scale(log10_years(100.01)));
        assert!(beyond_any_time_scale(log10_years(664.0)));
        assert!(!beyond_any_time_scale(log10_years(15.0)));
        assert!(!beyond_any_time_scale(f64::NAN));
    }

    #[test]
    fn si_prefixes_and_durations() {
        assert_eq!(si(3.081e-6, "s", 4), "3.081 µs");
        assert_eq!(si(1.414e-22, "N", 4), "141.4 yN");
        assert_eq!(si(1.414e-21, "N", 4), "1.414 zN");
        assert_eq!(si(0.0123, "s", 3), "12.3 ms");
        assert_eq!(si(0.99996, "s", 4), "1.000 s");
        assert_eq!(si(1.0, "s", 3), "1.00 s");
        assert_eq!(si(2.5e9, "rad/s", 2), "2.5 Grad/s");
        assert_eq!(si(-4.2e-10, "m", 2), "-420 pm");
        assert_eq!(si(0.0, "s", 3), "0 s");
        assert_eq!(si(1e-30, "s", 3), "1.00e-30 s");
        assert_eq!(duration(0.35), "350 ms");
        assert_eq!(duration(42.4), "42 s");
        assert_eq!(duration(200.0), "3 min 20 s");
        assert_eq!(duration(7500.0), "2 h 05 min");
        assert_eq!(duration(3.2 * 86400.0), "3.2 days");
        assert_eq!(duration(f64::INFINITY), "unknown");
    }
}
