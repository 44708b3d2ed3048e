//! Deterministic elementary functions in plain `f64` arithmetic: the same
//! bits on every platform and in every caller (scalar or several runs side
//! by side), independent of the system's math library.
//!
//! Why: the normals of the Langevin noise (`numeric::random`) went through
//! the platform's `ln`, `sin` and `cos` (glibc's, ~25 ns a Box–Muller
//! pair); these are the same functions written as short polynomials with
//! no branches on the data, so a loop over several pairs can be vectorised
//! by the compiler, whose bits depend on nothing but IEEE 754 double
//! arithmetic. Rust does not contract `a * b + c` into a fused
//! multiply–add, so the compiler keeps every rounding as written (scalar and
//! vector code give the same bits).
//!
//! Sources: fdlibm (Sun Microsystems 1993, as kept in musl's
//! `src/math/log.c`, `__sin.c`, `__cos.c`;
//! its constants given here as their bit patterns, the decimal value
//! beside each), whose stated errors are below 1 ulp. Our tests
//! (`tests/integrate/random.rs`) measure the errors against glibc over the
//! ranges used: `ln` within 1 ulp on (0, 4], `sin_cos_turns` within 2 ulps
//! of the exactly rounded `sin 2πu`, `cos 2πu` on [0, 1].
//!
//! Tried and dropped: fdlibm's `atan2` and `exp` for the wells'
//! torque, within 1 ulp of glibc's and with fewer instructions, but slower
//! (their divisions on the critical path against glibc's table-driven,
//! FMA-using versions: RK4's 4 evaluations 570–780 ns against 490 ns;
//! docs/performance.md).

/// ln 2, high part (its last 32 bits are zero, so `k ln2_hi` is exact for
/// `|k| < 2¹¹`).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000); // 0.6931471803691238
/// ln 2 − `LN2_HI`.
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76); // 1.9082149292705877e-10
/// 2⁵².
const TWO52: f64 = 4_503_599_627_370_496.0;
const LG1: f64 = f64::from_bits(0x3fe5_5555_5555_5593); // 0.6666666666666735
const LG2: f64 = f64::from_bits(0x3fd9_9999_9997_fa04); // 0.3999999999940942
const LG3: f64 = f64::from_bits(0x3fd2_4924_9422_9359); // 0.2857142874366239
const LG4: f64 = f64::from_bits(0x3fcc_71c5_1d8e_78af); // 0.22222198432149784
const LG5: f64 = f64::from_bits(0x3fc7_4664_96cb_03de); // 0.1818357216161805
const LG6: f64 = f64::from_bits(0x3fc3_9a09_d078_c69f); // 0.15313837699209373
const LG7: f64 = f64::from_bits(0x3fc2_f112_df3e_5244); // 0.14798198605116586

/// The natural logarithm of a positive, normal, finite `x` (fdlibm's
/// algorithm without its special cases: `x = 2^k (1 + f)` with
/// `√2/2 ≤ 1 + f < √2`, `ln(1 + f) = f − f²/2 + s (f²/2 + R(s²))`,
/// `s = f/(2 + f)`). Error below 1 ulp (measured: tests). Zero, negative,
/// subnormal, infinite or NaN inputs give meaningless values (no check:
/// the callers pass uniforms in [2⁻⁵³, 1)).
#[inline(always)]
#[must_use]
pub fn ln(x: f64) -> f64 {
    let bits = x.to_bits();
    // Reduce x into [√2/2, √2): shift the exponent so that mantissas at or
    // above √2/2's (0x6a09e) carry into the next power of two.
    let hx = (bits >> 32) + (0x3ff0_0000 - 0x3fe6_a09e);
    let biased = hx >> 20; // k + 1023
    let hx = (hx & 0x000f_ffff) + 0x3fe6_a09e;
    let m = f64::from_bits((hx << 32) | (bits & 0xffff_ffff));
    // k as f64 through the bits of 2⁵² + (k + 1023) (exact; an integer
    // conversion the compiler can vectorise without AVX-512).
    let dk = f64::from_bits(0x4330_0000_0000_0000 | biased) - (TWO52 + 1023.0);
    let f = m - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    s * (hfsq + r) + dk * LN2_LO - hfsq + f + dk * LN2_HI
}

const S1: f64 = f64::from_bits(0xbfc5_5555_5555_5549); // -0.16666666666666632
const S2: f64 = f64::from_bits(0x3f81_1111_1110_f8a6); // 0.00833333333332249
const S3: f64 = f64::from_bits(0xbf2a_01a0_19c1_61d5); // -0.0001984126982985795
const S4: f64 = f64::from_bits(0x3ec7_1de3_57b1_fe7d); // 2.7557313707070068e-06
const S5: f64 = f64::from_bits(0xbe5a_e5e6_8a2b_9ceb); // -2.5050760253406863e-08
const S6: f64 = f64::from_bits(0x3de5_d93a_5acf_d57c); // 1.58969099521155e-10
const C1: f64 = f64::from_bits(0x3fa5_5555_5555_554c); // 0.0416666666666666
const C2: f64 = f64::from_bits(0xbf56_c16c_16c1_5177); // -0.001388888888887411
const C3: f64 = f64::from_bits(0x3efa_01a0_19cb_1590); // 2.480158728947673e-05
const C4: f64 = f64::from_bits(0xbe92_7e4f_809c_52ad); // -2.7557314351390663e-07
const C5: f64 = f64::from_bits(0x3e21_ee9e_bdb4_b1c4); // 2.087572321298175e-09
const C6: f64 = f64::from_bits(0xbda8_fae9_be88_38d4); // -1.1359647557788195e-11

/// `(sin x, cos x)` for `|x| ≤ π/4` (fdlibm's kernels `__sin(x, 0, 0)`
/// and `__cos(x, 0)`; each below 1 ulp there).
#[inline(always)]
#[must_use]
pub fn sin_cos_kernel(x: f64) -> (f64, f64) {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    let sin = x + v * (S1 + z * r);
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let cos = w + (((1.0 - w) - hz) + z * r);
    (sin, cos)
}

/// `(sin 2πu, cos 2πu)` for `u` in [0, 1] given in turns: `n = round(4u)`,
/// `f = u − n/4` (exact: Sterbenz, and `f = u` for `n = 0`), the kernel at
/// `2πf` in [−π/4, π/4], then the quadrant `n mod 4` by exact swaps and
/// sign changes. The only roundings are `2π` itself, the product `2πf` and
/// the kernel's: the result is within 2 ulps of the exactly rounded value
/// (measured: tests), including near the zeros at `u = 1/2`, `1/4`, `3/4`,
/// where `sin(TAU * u)` of the rounded argument loses relative accuracy.
#[inline(always)]
#[must_use]
pub fn sin_cos_turns(u: f64) -> (f64, f64) {
    // n = 4u rounded to the nearest integer (ties to even) by adding 2⁵²:
    // 0 ≤ 4u ≤ 4, so the sum's last bits are n, and its difference with
    // 2⁵² is n exactly.
    let t = 4.0 * u + TWO52;
    let q = t.to_bits();
    let n = t - TWO52;
    let f = u - 0.25 * n;
    let (s, c) = sin_cos_kernel(std::f64::consts::TAU * f);
    // Quadrant n mod 4 by masks on the low two bits of q (no branches on
    // the data): swap for odd n, then flip the signs.
    let swap = 0u64.wrapping_sub(q & 1); // all ones if n is odd
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let s1 = (sb & !swap) | (cb & swap);
    let c1 = (cb & !swap) | (sb & swap);
    let neg_s = (q & 2) << 62;
    let neg_c = ((q + 1) & 2) << 62;
    (f64::from_bits(s1 ^ neg_s), f64::from_bits(c1 ^ neg_c))
}
