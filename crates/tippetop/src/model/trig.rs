//! A fast `sin_cos` for the reduced model's right-hand side, which takes
//! sin θ and cos θ at every evaluation (the libm call was about a tenth of a
//! whole run).
//!
//! The method is fdlibm's: reduce `x` by a multiple `n` of π/2 with π/2 split
//! in 33-bit parts (Cody–Waite; `n·part` is exact for `|n| < 2^20`, and a
//! second and third part are subtracted only when the first leaves too few
//! correct bits, i.e. near a multiple of π/2), giving `x − n π/2 = y0 + y1`
//! with `|y0| <= π/4` to ~118 bits; then the published fdlibm minimax
//! polynomials for sin and cos on `[−π/4, π/4]` (`__kernel_sin`,
//! `__kernel_cos`, with the tail `y1` corrected for). The results are
//! within 1 ulp of the libm's `sin`/`cos` (tested). Outside `|x| < 1e5`,
//! and for NaN and ±∞, it falls back to [`f64::sin_cos`].
//!
//! It is inlined (no call), and sin and cos are evaluated side by side, so
//! the processor overlaps the two polynomials with each other and with the
//! rest of the right-hand side.

/// 2/π.
const INV_PIO2: f64 = f64::from_bits(0x3FE4_5F30_6DC9_C883);
/// First 33 bits of π/2.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// π/2 − `PIO2_1`.
const PIO2_1T: f64 = f64::from_bits(0x3DD0_B461_1A62_6331);
/// Second 33 bits of π/2.
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000);
/// π/2 − `PIO2_1` − `PIO2_2`.
const PIO2_2T: f64 = f64::from_bits(0x3BA3_198A_2E03_7073);
/// Third 33 bits of π/2.
const PIO2_3: f64 = f64::from_bits(0x3BA3_198A_2E00_0000);
/// π/2 − `PIO2_1` − `PIO2_2` − `PIO2_3`.
const PIO2_3T: f64 = f64::from_bits(0x397B_839A_2520_49C1);

/// 1.5 · 2^52: adding and subtracting it rounds a double of magnitude
/// below 2^51 to the nearest integer (ties to even).
const ROUND: f64 = 6_755_399_441_055_744.0;

/// |x| from which the reduction is left to the libm (`n < 2^20` is needed
/// for the products `n · PIO2_k` to be exact; 1e5 keeps far from it).
const MAX_REDUCED: f64 = 1e5;

/// Below this |x|, sin x rounds to x and cos x to 1.
const TINY: f64 = f64::from_bits(0x3E40_0000_0000_0000); // 2^-27

// fdlibm __kernel_sin: sin x ≈ x + S1 x³ + … + S6 x¹³ on [−π/4, π/4].
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);

// fdlibm __kernel_cos: cos x ≈ 1 − x²/2 + C1 x⁴ + … + C6 x¹⁴ on [−π/4, π/4].
const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

/// sin(x + y) for |x| <= π/4 and |y| <= ulp(x)/2 (the reduced argument and
/// its tail); `tail = false` ignores `y` (an unreduced argument).
#[inline(always)]
fn kernel_sin(x: f64, y: f64, tail: bool) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    if tail {
        x - ((z * (0.5 * y - v * r) - y) - v * S1)
    } else {
        x + v * (S1 + z * r)
    }
}

/// cos(x + y) for |x| <= π/4 and |y| <= ulp(x)/2.
#[inline(always)]
fn kernel_cos(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// Biased exponent of `x`.
#[inline(always)]
fn exponent(x: f64) -> i64 {
    ((x.to_bits() >> 52) & 0x7ff) as i64
}

/// `(n, y0, y1)` with `x − n π/2 = y0 + y1` (`|y0| <= π/4` up to rounding,
/// `y1` the tail of `y0`) for `|x| < MAX_REDUCED` (fdlibm's medium-size
/// reduction).
#[inline(always)]
fn rem_pio2(x: f64) -> (i32, f64, f64) {
    let fnn = (x * INV_PIO2 + ROUND) - ROUND;
    let n = fnn as i32;
    // x − fnn·PIO2_1 is exact (33-bit parts, |n| < 2^20).
    let mut r = x - fnn * PIO2_1;
    let mut w = fnn * PIO2_1T;
    let mut y0 = r - w;
    let j = exponent(x);
    // Bits lost to cancellation: more than 16 and the 33+53-bit π/2 is
    // not enough; take the next 33 bits (and once more past 49).
    if j - exponent(y0) > 16 {
        let t = r;
        w = fnn * PIO2_2;
        r = t - w;
        w = fnn * PIO2_2T - ((t - r) - w);
        y0 = r - w;
        if j - exponent(y0) > 49 {
            let t = r;
            w = fnn * PIO2_3;
            r = t - w;
            w = fnn * PIO2_3T - ((t - r) - w);
            y0 = r - w;
        }
    }
    let y1 = (r - y0) - w;
    (n, y0, y1)
}

/// [`f64::sin_cos`], kept out of line (the rare case of [`sin_cos`]).
#[cold]
#[inline(never)]
fn libm_sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}

/// `(sin x, cos x)`, each within 1 ulp of the libm's (see the module
/// documentation); [`f64::sin_cos`] for |x| >= 1e5, ±∞ and NaN.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let ax = x.abs();
    if ax <= std::f64::consts::FRAC_PI_4 {
        if ax < TINY {
            // Also keeps the sign of ±0.
            return (x, 1.0);
        }
        return (kernel_sin(x, 0.0, false), kernel_cos(x, 0.0));
    }
    // Also NaN (the comparison is false).
    if !(ax < MAX_REDUCED) {
        return libm_sin_cos(x);
    }
    let (n, y0, y1) = rem_pio2(x);
    let s = kernel_sin(y0, y1, true);
    let c = kernel_cos(y0, y1);
    match n & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in ulps between two doubles of the same sign class (±0
    /// equal), `u64::MAX` if exactly one is NaN, 0 if both are.
    fn ulps(a: f64, b: f64) -> u64 {
        match (a.is_nan(), b.is_nan()) {
            (true, true) => return 0,
            (false, false) => {}
            _ => return u64::MAX,
        }
        // Map to integers ordered as the doubles are.
        let key = |x: f64| {
            let b = x.to_bits() as i64;
            if b < 0 { i64::MIN - b } else { b }
        };
        key(a).abs_diff(key(b))
    }

    /// Largest ulp distance of our sin and cos from the libm's at `x`.
    fn err(x: f64) -> u64 {
        let (s, c) = sin_cos(x);
        ulps(s, x.sin()).max(ulps(c, x.cos()))
    }

    /// A fixed xorshift sequence, uniform in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn ulps_measures_what_it_should() {
        assert_eq!(ulps(1.0, 1.0), 0);
        assert_eq!(ulps(1.0, f64::from_bits(1.0f64.to_bits() + 1)), 1);
        assert_eq!(ulps(0.0, -0.0), 0);
        assert_eq!(ulps(f64::from_bits(1), -f64::from_bits(1)), 2);
        assert_eq!(ulps(f64::NAN, 1.0), u64::MAX);
        assert_eq!(ulps(-1.0, 1.0), 2 * 1.0f64.to_bits());
    }

    #[test]
    fn constants_are_the_published_values() {
        // The bit patterns above against the decimal values fdlibm prints
        // beside them (a typo in either shows here).
        let pairs: [(f64, f64); 19] = [
            (INV_PIO2, 6.36619772367581382433e-01),
            (PIO2_1, 1.57079632673412561417e+00),
            (PIO2_1T, 6.07710050650619224932e-11),
            (PIO2_2, 6.07710050630396597660e-11),
            (PIO2_2T, 2.02226624879595063154e-21),
            (PIO2_3, 2.02226624871116645580e-21),
            (PIO2_3T, 8.47842766036889956997e-32),
            (S1, -1.66666666666666324348e-01),
            (S2, 8.33333333332248946124e-03),
            (S3, -1.98412698298579493134e-04),
            (S4, 2.75573137070700676789e-06),
            (S5, -2.50507602534068634195e-08),
            (S6, 1.58969099521155010221e-10),
            (C1, 4.16666666666666019037e-02),
            (C2, -1.38888888888741095749e-03),
            (C3, 2.48015872894767294178e-05),
            (C4, -2.75573143513906633035e-07),
            (C5, 2.08757232129817482790e-09),
            (C6, -1.13596475577881948265e-11),
        ];
        for (i, (bits, dec)) in pairs.into_iter().enumerate() {
            assert_eq!(bits.to_bits(), dec.to_bits(), "constant {i}");
        }
        // The three parts and tail add up to π/2 (to double precision).
        assert_eq!(PIO2_1 + PIO2_1T, std::f64::consts::FRAC_PI_2);
        assert_eq!(PIO2_1 + (PIO2_2 + PIO2_2T), std::f64::consts::FRAC_PI_2);
    }

    #[test]
    fn within_one_ulp_of_libm_on_random_points() {
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        let mut worst = (0, 0.0);
        let mut n = 0;
        for i in 0..1_200_000 {
            let u = rng.next();
            let x = match i % 3 {
                // The model's range, θ in (0, π), and beyond.
                0 => 8.0 * u - 4.0,
                // Log-uniform magnitude 1e-30 .. 1e5 (past the libm
                // fallback), random sign.
                1 => {
                    let m = 10f64.powf(-30.0 + 35.5 * u);
                    if rng.next() < 0.5 { -m } else { m }
                }
                // Within a few ulps of a multiple of π/2 (the hard case
                // for the reduction), k up to 63 000.
                _ => {
                    let k = (u * 63_000.0).floor();
                    let x = k * std::f64::consts::FRAC_PI_2;
                    let d = (rng.next() * 64.0) as i64 - 32;
                    f64::from_bits((x.to_bits() as i64 + d) as u64)
                }
            };
            let e = err(x);
            if e > worst.0 {
                worst = (e, x);
            }
            n += 1;
        }
        assert!(n >= 1_000_000);
        assert!(worst.0 <= 1, "{} ulps at x = {:e}", worst.0, worst.1);
    }

    #[test]
    fn edge_points() {
        let mut xs = vec![
            0.0,
            -0.0,
            5e-324,
            -5e-324,
            1e-310,
            f64::MIN_POSITIVE,
            TINY,
            -TINY,
            f64::from_bits(TINY.to_bits() - 1),
            std::f64::consts::FRAC_PI_4,
            f64::from_bits(std::f64::consts::FRAC_PI_4.to_bits() + 1),
            std::f64::consts::PI,
            -std::f64::consts::PI,
            2.0 * std::f64::consts::PI,
            MAX_REDUCED,
            f64::from_bits(MAX_REDUCED.to_bits() - 1),
            1e10,
            1e300,
            f64::MAX,
        ];
        for k in -200..=200 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2;
            xs.extend([
                x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits().wrapping_sub(1)),
            ]);
        }
        // Multiples of π/2 near which doubles come closest (n π/2 for large n).
        for k in [6381.0, 12762.0, 25524.0, 51048.0, 63000.0] {
            xs.push(k * std::f64::consts::FRAC_PI_2);
        }
        for &x in &xs {
            for x in [x, -x] {
                assert!(err(x) <= 1, "{} ulps at x = {x:e}", err(x));
            }
        }
        // The sign of zero is kept.
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}: ({s}, {c})");
        }
    }

    #[test]
    fn pythagoras() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for _ in 0..100_000 {
            let x = 200.0 * rng.next() - 100.0;
            let (s, c) = sin_cos(x);
            assert!((s * s + c * c - 1.0).abs() <= 4.0 * f64::EPSILON, "x = {x}");
        }
    }
}
