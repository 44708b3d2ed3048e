//! The counter-based random stream the fixed-step (Langevin) engines draw
//! from (`tippetop::random`): Random123's known-answer vectors
//! through the key layout, purity (same key, same bits, in any order and on
//! any thread), the limits, and statistics with stated error bars on fixed
//! seeds. Each statistical check is a function that the last tests feed with
//! a deliberately broken generator, to show that it fails when it should.
//!
//! Error bars: for n independent draws the standard error of a sample mean
//! of f(z) is sd(f(z))/√n, so with n = 10⁶: mean of z 1.0e-3, mean of z²
//! (true 1) √2/√n = 1.41e-3, mean of z³ √15/√n = 3.9e-3, mean of z⁴ (true 3)
//! √(105 − 9)/√n = 9.8e-3, a correlation coefficient 1/√n = 1.0e-3. Every
//! check allows 5 standard errors (a correct generator fails one with
//! probability 6e-7). The Kolmogorov–Smirnov checks reject at significance
//! 1e-3 (Kolmogorov's limit law with Stephens' finite-n correction).

use std::f64::consts::SQRT_2;
use tippetop::detmath;
use tippetop::random::{BLOCKS_PER_STEP, MAX_RUN, Stream, box_muller, normals, unit_open};

/// One million: the sample size of the statistical checks.
const N: usize = 1_000_000;

/// The fixed seed of the statistical checks (any other should pass too, with
/// the stated probability).
const SEED: u64 = 20_261_124;

// ---------------------------------------------------------------------------
// Known answers and layout

/// Random123's known-answer vectors for philox4x32_10, from the Random123
/// distribution's `tests/kat_vectors` (DEShawResearch/random123, commit
/// 9545ff6413f258be2f04c1d319d99aaef7521150, lines 27–29; each line is
/// `philox4x32 10 ctr0 ctr1 ctr2 ctr3 key0 key1   out0 out1 out2 out3`),
/// reached through the documented layout: key = seed (low, high), counter =
/// (block, step low, step high, run). A wrong constant, round count or key
/// schedule in the generator, or a word in the wrong place in the layout,
/// fails one of the three.
#[test]
fn known_answer_vectors_through_the_layout() {
    // philox4x32 10 00000000 00000000 00000000 00000000 00000000 00000000
    //   6627e8d5 e169c58d bc57ac4c 9b00dbd8
    assert_eq!(
        Stream::new(0, 0).block(0, 0),
        [0x6627_e8d5, 0xe169_c58d, 0xbc57_ac4c, 0x9b00_dbd8]
    );
    // philox4x32 10 ffffffff ffffffff ffffffff ffffffff ffffffff ffffffff
    //   408f276d 41c83b0e a20bc7c6 6d5451fd
    assert_eq!(
        Stream::new(u64::MAX, MAX_RUN).block(u64::MAX, u32::MAX),
        [0x408f_276d, 0x41c8_3b0e, 0xa20b_c7c6, 0x6d54_51fd]
    );
    // philox4x32 10 243f6a88 85a308d3 13198a2e 03707344 a4093822 299f31d0
    //   d16cfe09 94fdcceb 5001e420 24126ea1   (the digits of π)
    let stream = Stream::new(0x299f_31d0_a409_3822, 0x0370_7344);
    assert_eq!(
        stream.block(0x1319_8a2e_85a3_08d3, 0x243f_6a88),
        [0xd16c_fe09, 0x94fd_cceb, 0x5001_e420, 0x2412_6ea1]
    );
    assert_eq!(stream.seed(), 0x299f_31d0_a409_3822);
    assert_eq!(stream.run(), 0x0370_7344);
}

/// Uniform 2j, 2j + 1 are `unit_open` of the block's words (w0 | w1 << 32)
/// and (w2 | w3 << 32); normals 2j, 2j + 1 are the Box–Muller pair of those.
#[test]
fn uniforms_and_normals_are_the_documented_functions_of_the_block() {
    let s = Stream::new(3, 4);
    for (step, j) in [(0u64, 0u32), (5, 1), (u64::MAX, 77), (1 << 40, u32::MAX)] {
        let w = s.block(step, j);
        let u1 = unit_open(u64::from(w[0]) | (u64::from(w[1]) << 32));
        let u2 = unit_open(u64::from(w[2]) | (u64::from(w[3]) << 32));
        let k = 2 * u64::from(j);
        assert_eq!(s.uniform(step, k).to_bits(), u1.to_bits());
        assert_eq!(s.uniform(step, k + 1).to_bits(), u2.to_bits());
        let (z0, z1) = box_muller(u1, u2);
        assert_eq!(s.normal(step, k).to_bits(), z0.to_bits());
        assert_eq!(s.normal(step, k + 1).to_bits(), z1.to_bits());
    }
}

/// `unit_open` is exact: the extremes are 2⁻⁵³ and 1 − 2⁻⁵³ (never 0 or 1,
/// so `ln u` is finite), and the grid is the odd multiples of 2⁻⁵³. A
/// `(bits >> 11) as f64 * 2⁻⁵³` mapping would give 0 for bits = 0.
#[test]
fn unit_open_endpoints_are_exact() {
    let e = 2f64.powi(-53);
    assert_eq!(unit_open(0), e);
    assert_eq!(unit_open(u64::MAX), 1.0 - e);
    assert_eq!(unit_open(1 << 63), 0.5 + e);
    assert_eq!(unit_open((1 << 63) - 1), 0.5 - e);
    assert_eq!(unit_open(1 << 12), 3.0 * e);
    let (z0, z1) = box_muller(e, 0.25);
    assert!((z1 - (106.0 * 2f64.ln()).sqrt()).abs() < 1e-12 && z0.abs() < 1e-12);
}

// ---------------------------------------------------------------------------
// Purity

/// The normals of steps `steps` of `stream`, `per_step` each, as bits.
fn bits(
    stream: &Stream,
    steps: impl Iterator<Item = u64>,
    per_step: usize,
) -> Vec<(u64, Vec<u64>)> {
    steps
        .map(|step| {
            let mut z = vec![0.0; per_step];
            stream.normals(step, &mut z);
            (step, z.iter().map(|x| x.to_bits()).collect())
        })
        .collect()
}

/// Same key, same bits: two streams built apart, the free function, steps
/// taken forwards, backwards and split over two threads in interleaved order
/// all give the same bits for each step. A generator with internal state
/// (one advancing counter) would give other numbers in another order.
#[test]
fn same_key_same_bits_in_any_order_and_thread() {
    let (seed, run) = (99, 12);
    let forward = bits(&Stream::new(seed, run), 0..200, 7);
    let mut backward = bits(&Stream::new(seed, run), (0..200).rev(), 7);
    backward.reverse();
    assert_eq!(forward, backward);
    let (even, odd) = std::thread::scope(|sc| {
        let a = sc.spawn(|| bits(&Stream::new(seed, run), (0..100).rev().map(|i| 2 * i), 7));
        let b = sc.spawn(|| bits(&Stream::new(seed, run), (1..200).step_by(2), 7));
        (a.join().unwrap(), b.join().unwrap())
    });
    let mut merged: Vec<_> = even.into_iter().chain(odd).collect();
    merged.sort_by_key(|(step, _)| *step);
    assert_eq!(forward, merged);
    for (step, b) in &forward {
        let mut z = [0.0; 7];
        normals(seed, run, *step, &mut z);
        assert_eq!(b, &z.map(f64::to_bits).to_vec());
    }
}

/// Normal k and uniform k alone are element k of the bulk call, for every
/// length (odd ones drop the last pair's second normal) and across the bulk
/// path's 128-number chunks: a longer call extends a shorter one.
#[test]
fn single_draws_equal_the_bulk_calls_and_prefixes_agree() {
    let s = Stream::new(SEED, 3);
    let step = 123_456_789_012;
    let mut long_z = vec![0.0; 301];
    let mut long_u = vec![0.0; 301];
    s.normals(step, &mut long_z);
    s.uniforms(step, &mut long_u);
    for (k, (z, u)) in long_z.iter().zip(&long_u).enumerate() {
        assert_eq!(
            s.normal(step, k as u64).to_bits(),
            z.to_bits(),
            "normal {k}"
        );
        assert_eq!(
            s.uniform(step, k as u64).to_bits(),
            u.to_bits(),
            "uniform {k}"
        );
    }
    for len in [0, 1, 2, 5, 127, 128, 129, 256, 257] {
        let mut z = vec![0.0; len];
        let mut u = vec![0.0; len];
        s.normals(step, &mut z);
        s.uniforms(step, &mut u);
        assert_eq!(z, long_z[..len], "normals, length {len}");
        assert_eq!(u, long_u[..len], "uniforms, length {len}");
    }
}

/// Neighbouring keys give different numbers: seed, run, step and index each
/// change the draw (a layout that dropped one of them would repeat numbers).
#[test]
fn every_key_part_changes_the_draw() {
    let base = Stream::new(5, 6).normal(7, 8);
    for other in [
        Stream::new(4, 6).normal(7, 8),
        Stream::new(5, 5).normal(7, 8),
        Stream::new(5, 6).normal(6, 8),
        Stream::new(5, 6).normal(7, 9),
        Stream::new(5 | 1 << 32, 6).normal(7, 8),
        Stream::new(5, 6).normal(7 | 1 << 32, 8),
        Stream::new(5, 6).normal(7, 8 + (1 << 32)),
    ] {
        assert_ne!(base.to_bits(), other.to_bits());
    }
}

/// The limits: the last run and the last index of a step work, one more
/// panics (rather than wrapping onto another run's or step's blocks).
#[test]
fn limits() {
    let s = Stream::new(1, MAX_RUN);
    let last = 2 * BLOCKS_PER_STEP - 1;
    assert!(s.normal(0, last).is_finite() && s.uniform(0, last) > 0.0);
    assert!(std::panic::catch_unwind(|| Stream::new(1, MAX_RUN + 1)).is_err());
    assert!(std::panic::catch_unwind(|| s.normal(0, last + 1)).is_err());
    assert!(std::panic::catch_unwind(|| s.uniform(0, last + 1)).is_err());
}

// ---------------------------------------------------------------------------
// Statistical checks (functions, so the broken generators below can be fed
// to them)

/// N draws from `f(step, out)`: 1 000 steps of 1 000 numbers.
fn sample(f: impl Fn(u64, &mut [f64])) -> Vec<f64> {
    let mut out = vec![0.0; N];
    for (step, chunk) in out.chunks_mut(1000).enumerate() {
        f(step as u64, chunk);
    }
    out
}

/// Mean of f over `x`.
fn mean(x: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    x.iter().map(|&v| f(v)).sum::<f64>() / x.len() as f64
}

/// (power p, sample mean of z^p, its deviation from the truth in standard
/// errors).
type Moment = (u32, f64, f64);

/// Moments of standard normals about 0, each within 5 standard errors:
/// returns the first that fails, or the list of all.
fn normal_moments(z: &[f64]) -> Result<Vec<Moment>, Moment> {
    let n = z.len() as f64;
    // (power, true value, variance of z^p = E z^2p − (E z^p)²)
    let mut all = Vec::new();
    for (p, truth, var) in [(1, 0.0, 1.0), (2, 1.0, 2.0), (3, 0.0, 15.0), (4, 3.0, 96.0)] {
        let m = mean(z, |v| v.powi(p));
        let sigmas = (m - truth) / (var / n).sqrt();
        if sigmas.abs() > 5.0 {
            return Err((p as u32, m, sigmas));
        }
        all.push((p as u32, m, sigmas));
    }
    Ok(all)
}

/// Kolmogorov–Smirnov statistic D of `x` against `cdf` and its p-value
/// (Kolmogorov's series at λ = (√n + 0.12 + 0.11/√n) D, Stephens 1970).
fn ks(mut x: Vec<f64>, cdf: impl Fn(f64) -> f64) -> (f64, f64) {
    x.sort_by(f64::total_cmp);
    let n = x.len() as f64;
    let d = x
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let f = cdf(v);
            (f - i as f64 / n).max((i + 1) as f64 / n - f)
        })
        .fold(0.0, f64::max);
    let lambda = (n.sqrt() + 0.12 + 0.11 / n.sqrt()) * d;
    let p = (1..=100)
        .map(|k| {
            let k = k as f64;
            2.0 * (-1f64).powf(k - 1.0) * (-2.0 * k * k * lambda * lambda).exp()
        })
        .sum::<f64>()
        .clamp(0.0, 1.0);
    (d, p)
}

/// The KS significance level of the checks.
const KS_ALPHA: f64 = 1e-3;

/// The standard normal distribution function.
fn phi(z: f64) -> f64 {
    0.5 * libm::erfc(-z / SQRT_2)
}

/// Pearson correlation of the pairs (x_i, y_i), and its deviation from 0 in
/// standard errors (1/√n for independent draws).
fn correlation(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (mean(x, |v| v), mean(y, |v| v));
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    let r = sxy / (sxx * syy).sqrt();
    (r, r * n.sqrt())
}

/// The lag-1 pairs of a key part: normal k of step s against normal k of
/// step s + 1 (`Step`), of run r + 1 (`Run`), of seed + 1 (`Seed`), or
/// normal k + 1 of the same step (`Component`: both the Box–Muller partner
/// and the first normal of the next block).
#[derive(Debug, Clone, Copy)]
enum Lag {
    Step,
    Run,
    Seed,
    Component,
}

/// N pairs (x, y) of neighbouring normals for `lag`.
fn lag_pairs(lag: Lag) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut y) = (Vec::with_capacity(N), Vec::with_capacity(N));
    let mut a = vec![0.0; 1001];
    let mut b = vec![0.0; 1001];
    for i in 0..1000u64 {
        match lag {
            Lag::Step => {
                Stream::new(SEED, 0).normals(i, &mut a);
                Stream::new(SEED, 0).normals(i + 1, &mut b);
            }
            Lag::Run => {
                Stream::new(SEED, i).normals(42, &mut a);
                Stream::new(SEED, i + 1).normals(42, &mut b);
            }
            Lag::Seed => {
                Stream::new(SEED + i, 0).normals(42, &mut a);
                Stream::new(SEED + i + 1, 0).normals(42, &mut b);
            }
            Lag::Component => {
                Stream::new(SEED, 0).normals(i, &mut a);
                b[..1000].copy_from_slice(&a[1..]);
            }
        }
        x.extend_from_slice(&a[..1000]);
        y.extend_from_slice(&b[..1000]);
    }
    (x, y)
}

/// Lag-1 correlation of the values and of their squares (the squares catch
/// dependence with no linear correlation, such as a Box–Muller pair sharing
/// a wrong radius), each within 5 standard errors of 0.
fn uncorrelated(x: &[f64], y: &[f64]) -> Result<[(f64, f64); 2], String> {
    let sq = |v: &[f64]| v.iter().map(|a| a * a).collect::<Vec<_>>();
    let lin = correlation(x, y);
    let squares = correlation(&sq(x), &sq(y));
    for (what, (r, s)) in [("values", lin), ("squares", squares)] {
        if s.abs() > 5.0 {
            return Err(format!("{what}: r = {r:.2e}, {s:.1} standard errors"));
        }
    }
    Ok([lin, squares])
}

// ---------------------------------------------------------------------------
// The checks on the stream (measured values printed: `--nocapture`)

/// Mean, second, third and fourth moments of 10⁶ normals (1 000 steps of
/// 1 000) within 5 standard errors of 0, 1, 0, 3.
#[test]
fn normal_moments_within_five_standard_errors() {
    let z = sample(|step, out| Stream::new(SEED, 0).normals(step, out));
    let m =
        normal_moments(&z).unwrap_or_else(|e| panic!("moment {}: {} ({:.1} SE)", e.0, e.1, e.2));
    eprintln!("normal moments (p, value, SE from truth): {m:?}");
}

/// KS test of 10⁶ uniforms against U(0, 1) and 10⁶ normals against Φ, and the
/// uniforms' range (all strictly inside (0, 1)). Measured on SEED: uniforms
/// D = 1.71e-3, p = 0.006 (a low draw, though above α); normals D = 6.6e-4,
/// p = 0.78. Checked once by hand over 300 other runs of 10⁵ draws: the
/// p-values are uniform (below 0.05: 13 for uniforms and 17 for normals,
/// 15 expected; KS of the p-values p = 0.65 and 0.73).
#[test]
fn kolmogorov_smirnov_uniforms_and_normals() {
    let u = sample(|step, out| Stream::new(SEED, 1).uniforms(step, out));
    assert!(u.iter().all(|&v| v > 0.0 && v < 1.0));
    let (d, p) = ks(u, |v| v);
    eprintln!("KS uniforms: D = {d:.3e}, p = {p:.3}");
    assert!(p > KS_ALPHA, "uniforms: D = {d}, p = {p}");
    let z = sample(|step, out| Stream::new(SEED, 2).normals(step, out));
    let (d, p) = ks(z, phi);
    eprintln!("KS normals: D = {d:.3e}, p = {p:.3}");
    assert!(p > KS_ALPHA, "normals: D = {d}, p = {p}");
}

/// No lag-1 correlation (values or squares) between neighbouring steps,
/// runs, seeds and components, 10⁶ pairs each.
#[test]
fn no_correlation_between_neighbouring_steps_runs_seeds_components() {
    for lag in [Lag::Step, Lag::Run, Lag::Seed, Lag::Component] {
        let (x, y) = lag_pairs(lag);
        let r = uncorrelated(&x, &y).unwrap_or_else(|e| panic!("{lag:?}: {e}"));
        eprintln!(
            "lag-1 {lag:?}: (r, SE) values {:?}, squares {:?}",
            r[0], r[1]
        );
    }
    // The uniforms of one block (u1 feeds the radius, u2 the angle).
    let u = sample(|step, out| Stream::new(SEED, 3).uniforms(step, out));
    let (a, b): (Vec<f64>, Vec<f64>) = u.chunks_exact(2).map(|p| (p[0], p[1])).unzip();
    let (r, s) = correlation(&a, &b);
    eprintln!("uniform pairs: r = {r:.2e} ({s:.1} SE, n = {})", a.len());
    assert!(s.abs() < 5.0);
}

// ---------------------------------------------------------------------------
// The checks fail on broken generators

/// Normals with the wrong scale (1.01: E z² = 1.0201, 14 SE off) or of the
/// wrong shape (Irwin–Hall: the sum of 12 uniforms minus 6, variance 1 but
/// E z⁴ = 2.9, 10 SE off) fail the moment check; so does the radius
/// √(−ln u) instead of √(−2 ln u) (variance 1/2).
#[test]
fn the_moment_check_rejects_broken_normals() {
    let s = Stream::new(SEED, 4);
    let scaled = sample(|step, out| {
        s.normals(step, out);
        out.iter_mut().for_each(|z| *z *= 1.01);
    });
    assert_eq!(normal_moments(&scaled).unwrap_err().0, 2);
    let irwin_hall = sample(|step, out| {
        let mut u = vec![0.0; 12 * out.len()];
        s.uniforms(step, &mut u);
        for (z, u) in out.iter_mut().zip(u.chunks_exact(12)) {
            *z = u.iter().sum::<f64>() - 6.0;
        }
    });
    assert_eq!(normal_moments(&irwin_hall).unwrap_err().0, 4);
    let half = sample(|step, out| {
        s.normals(step, out);
        out.iter_mut().for_each(|z| *z /= SQRT_2);
    });
    assert_eq!(normal_moments(&half).unwrap_err().0, 2);
}

/// The KS checks reject uniforms bent by u ↦ u^1.01 (D ≈ 3.7e-3, against a
/// critical 1.95e-3 at n = 10⁶) and normals scaled by 1.02 (D ≈ 4.7e-3).
#[test]
fn the_ks_checks_reject_broken_distributions() {
    let s = Stream::new(SEED, 5);
    let u = sample(|step, out| {
        s.uniforms(step, out);
        out.iter_mut().for_each(|u| *u = u.powf(1.01));
    });
    let (d, p) = ks(u, |v| v);
    assert!(p < KS_ALPHA, "bent uniforms: D = {d}, p = {p}");
    let z = sample(|step, out| {
        s.normals(step, out);
        out.iter_mut().for_each(|z| *z *= 1.02);
    });
    let (d, p) = ks(z, phi);
    assert!(p < KS_ALPHA, "scaled normals: D = {d}, p = {p}");
}

/// The correlation check rejects: a stream that ignores the step (every step
/// the same numbers: r = 1); an AR(1) sequence with ρ = 0.01 (10 SE); and a
/// Box–Muller pair that reuses u₁ for the angle (values uncorrelated by
/// symmetry, squares correlated: caught by the squares).
#[test]
fn the_correlation_check_rejects_dependent_draws() {
    let s = Stream::new(SEED, 6);
    let stuck = sample(|_step, out| s.normals(0, out));
    assert!(uncorrelated(&stuck[..N - 1000], &stuck[1000..]).is_err());
    let w = sample(|step, out| s.normals(step, out));
    let rho: f64 = 0.01;
    let mut ar = w.clone();
    for i in 1..N {
        ar[i] = rho * ar[i - 1] + (1.0 - rho * rho).sqrt() * w[i];
    }
    assert!(uncorrelated(&ar[..N - 1], &ar[1..]).is_err());
    let u = sample(|step, out| s.uniforms(step, out));
    let (x, y): (Vec<f64>, Vec<f64>) = u.iter().map(|&u1| box_muller(u1, u1)).unzip();
    assert!(uncorrelated(&x, &y).is_err());
}

// ---------------------------------------------------------------------------
// Our own `ln` and `sin_cos` (`tippetop::detmath`, session 7): errors in ulps
// against references, and the normals' tails and histogram.

/// Distance in units in the last place between two finite doubles of the
/// same sign (0 for equal bits; ±0 count as equal).
fn ulps(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    assert_eq!(a.is_sign_negative(), b.is_sign_negative(), "{a} vs {b}");
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
}

/// Test points in (0, 1): 10⁶ uniforms of the stream's grid (odd multiples
/// of 2⁻⁵³), the grid's ends, powers of two and their neighbours, and points
/// around √2/2 (where `ln`'s reduction switches exponent).
fn unit_points() -> Vec<f64> {
    let mut u = sample(|step, out| Stream::new(SEED, 9).uniforms(step, out));
    let e = 2f64.powi(-53);
    u.extend([e, 3.0 * e, 1.0 - e, 0.5 - e, 0.5 + e, 0.25 + e, 0.75 - e]);
    for k in 1..=53 {
        let p = 2f64.powi(-k);
        u.extend([p, p * (1.0 + 2f64.powi(-52)), p * (1.0 - 2f64.powi(-53))]);
    }
    let r = std::f64::consts::FRAC_1_SQRT_2;
    for d in -64i64..=64 {
        u.push(f64::from_bits((r.to_bits() as i64 + d) as u64));
    }
    // Small arguments of `ln` decade by decade.
    for k in 1..300 {
        u.push(10f64.powi(-k / 20) * 0.999_999_7);
    }
    u
}

/// `detmath::ln` within 1 ulp of glibc's `ln` (itself within 1 ulp of the
/// exact value; fdlibm's stated bound is 1 ulp) on (0, 1) and on [1, 4]; the
/// largest difference is printed. A wrong coefficient (`LG1` off by 1e-12)
/// gives ~10 ulps near √2.
#[test]
fn own_ln_within_one_ulp_of_libm() {
    let mut pts = unit_points();
    pts.extend((0..10_000).map(|i| 1.0 + 3.0 * i as f64 / 10_000.0));
    let mut worst = (0, 0.0);
    for &x in &pts {
        let d = ulps(detmath::ln(x), x.ln());
        if d > worst.0 {
            worst = (d, x);
        }
    }
    eprintln!(
        "ln: largest difference {} ulp at x = {:e}",
        worst.0, worst.1
    );
    assert!(worst.0 <= 1, "ln: {} ulps at {:e}", worst.0, worst.1);
    assert_eq!(detmath::ln(1.0), 0.0);
    assert_eq!(detmath::ln(2f64.powi(-53)), -53.0 * std::f64::consts::LN_2);
}

/// `(sin 2πu, cos 2πu)` to about 1e-32 absolute: glibc's `sin_cos` of the
/// rounded product `p = fl(2π u)`, corrected to first order by the product's
/// exact error `e = 2π u − p` (from a fused multiply–add and the part of 2π
/// below the double `TAU`): `sin(p + e) = sin p + e cos p + O(e²)`,
/// `|e| ≤ 4.5e-16`.
fn sin_cos_2pi_reference(u: f64) -> (f64, f64) {
    use std::f64::consts::TAU;
    const TAU_LO: f64 = 2.449_293_598_294_706_4e-16; // 2π − TAU
    let p = TAU * u;
    let e = TAU.mul_add(u, -p) + TAU_LO * u;
    let (s, c) = p.sin_cos();
    (s + e * c, c - e * s)
}

/// `detmath::sin_cos_turns(u)` within 2 ulps of `(sin 2πu, cos 2πu)` for
/// every test point (also near the zeros at u = 1/4, 1/2, 3/4, where the
/// libm route `sin_cos(TAU * u)` is off by up to 10¹⁶ ulps in relative
/// terms because of the product's rounding), and exact at the quadrant
/// points. A swapped or wrongly signed quadrant fails by far more.
#[test]
fn own_sin_cos_within_two_ulps() {
    let mut worst = (0, 0.0);
    for u in unit_points() {
        let (s, c) = detmath::sin_cos_turns(u);
        let (rs, rc) = sin_cos_2pi_reference(u);
        let d = ulps(s, rs).max(ulps(c, rc));
        if d > worst.0 {
            worst = (d, u);
        }
    }
    eprintln!(
        "sin_cos_turns: largest difference {} ulp at u = {:e}",
        worst.0, worst.1
    );
    assert!(
        worst.0 <= 2,
        "sin_cos_turns: {} ulps at u = {:e}",
        worst.0,
        worst.1
    );
    for (u, s, c) in [
        (0.0, 0.0, 1.0),
        (0.25, 1.0, 0.0),
        (0.5, 0.0, -1.0),
        (0.75, -1.0, 0.0),
        (1.0, 0.0, 1.0),
    ] {
        let (gs, gc) = detmath::sin_cos_turns(u);
        assert!(gs == s && gc == c, "u = {u}: ({gs}, {gc})");
    }
}

/// The kernel alone against glibc on [−π/4, π/4]: within 1 ulp (fdlibm's
/// bound for both kernels).
#[test]
fn own_sin_cos_kernel_within_one_ulp_of_libm() {
    let q = std::f64::consts::FRAC_PI_4;
    let mut worst = 0;
    for i in 0..=200_000 {
        let x = -q + 2.0 * q * i as f64 / 200_000.0;
        let (s, c) = detmath::sin_cos_kernel(x);
        worst = worst.max(ulps(s, x.sin())).max(ulps(c, x.cos()));
    }
    eprintln!("sin_cos_kernel: largest difference {worst} ulp");
    assert!(worst <= 1);
}

/// Tail beyond 4σ: the count of |z| > 4 among 4·10⁶ normals of the stream is
/// binomial with p = erfc(4/√2) = 6.334e-5, mean 253.4, standard deviation
/// 15.9; it must lie within 5 of those (174 … 333). A transform whose tail is
/// cut (e.g. uniforms on a 2⁻³² grid: |z| ≤ 6.7, or a `ln` wrong for small u)
/// shows at 5σ (p = 5.7e-7, expected 2.3): printed, and checked to be at
/// most 12 (Poisson(2.3) exceeds 12 with probability 5e-6).
#[test]
fn normal_tails_beyond_four_and_five_sigma() {
    let mut z = Vec::with_capacity(4 * N);
    for run in 0..4 {
        z.extend(sample(|step, out| {
            Stream::new(SEED, 20 + run).normals(step, out)
        }));
    }
    let n = z.len() as f64;
    let p4 = libm::erfc(4.0 / SQRT_2);
    let c4 = z.iter().filter(|v| v.abs() > 4.0).count() as f64;
    let c5 = z.iter().filter(|v| v.abs() > 5.0).count();
    let (m, sd) = (n * p4, (n * p4 * (1.0 - p4)).sqrt());
    eprintln!(
        "|z| > 4: {c4} (expected {m:.1} ± {sd:.1}, {:.2} SE); |z| > 5: {c5} (expected {:.1})",
        (c4 - m) / sd,
        n * libm::erfc(5.0 / SQRT_2)
    );
    assert!(
        (c4 - m).abs() <= 5.0 * sd,
        "|z| > 4: {c4} against {m} ± {sd}"
    );
    assert!(c5 <= 12, "|z| > 5: {c5}");
    let zmax = z.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(zmax < (106.0 * 2f64.ln()).sqrt(), "{zmax}");
}

/// Pearson's χ² of `z` over 100 equiprobable bins of the standard normal
/// (edges Φ⁻¹(i/100) by bisection of Φ), and its critical value at
/// significance 1e-3 for 99 degrees of freedom (Wilson–Hilferty: 148.2).
fn chi_square_normal(z: &[f64]) -> (f64, f64) {
    const BINS: usize = 100;
    let edges: Vec<f64> = (1..BINS)
        .map(|i| {
            let p = i as f64 / BINS as f64;
            let (mut lo, mut hi) = (-10.0, 10.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if phi(mid) < p { lo = mid } else { hi = mid }
            }
            0.5 * (lo + hi)
        })
        .collect();
    let mut count = [0u64; BINS];
    for &v in z {
        count[edges.partition_point(|&e| e < v)] += 1;
    }
    let expected = z.len() as f64 / BINS as f64;
    let chi2 = count
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum::<f64>();
    let k = (BINS - 1) as f64;
    let crit = k * (1.0 - 2.0 / (9.0 * k) + 3.090_232 * (2.0 / (9.0 * k)).sqrt()).powi(3);
    (chi2, crit)
}

/// χ² of 10⁶ normals of the stream over 100 equiprobable bins below the
/// 1e-3 critical value (measured value printed; the mean of χ² is 99 and its
/// standard deviation 14). The same check rejects normals scaled by 1.01.
#[test]
fn chi_square_of_normals_and_its_power() {
    let z = sample(|step, out| Stream::new(SEED, 30).normals(step, out));
    let (chi2, crit) = chi_square_normal(&z);
    eprintln!("chi2 normals (99 dof): {chi2:.1} (critical {crit:.1})");
    assert!(chi2 < crit, "chi2 = {chi2} above {crit}");
    let scaled: Vec<f64> = z.iter().map(|v| 1.01 * v).collect();
    let (chi2, _) = chi_square_normal(&scaled);
    eprintln!("chi2 of normals x 1.01: {chi2:.1}");
    assert!(
        chi2 > crit,
        "the chi2 check missed a 1 % scale error: {chi2}"
    );
}
