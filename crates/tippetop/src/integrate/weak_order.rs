//! The stationary weak order of the Langevin and Brownian engines: the bias
//! of a configurational average in the chain's invariant law against the
//! Gibbs law, at three steps `h, h/2, h/4` (docs/physics.md#langevin,
//! "Weak order, measured").
//!
//! Systems with a known Gibbs law: a unit-mass particle on a line at
//! `kT = 1` with the thermostat's rate `γ = 1`, in the harmonic potential
//! `x²/2` (`⟨x²⟩ = 1`, and the chain's own stationary `⟨x²⟩` in closed
//! form) and in the anharmonic `x²/2 + x⁴/4` (`⟨x²⟩` by quadrature of
//! `e^{−U}` here); for the Brownian engine the Ornstein–Uhlenbeck process
//! `dx = −x dt + √2 dW` (`⟨x²⟩ = 1`; Euler–Maruyama's stationary variance
//! `σ²/(2λ − λ² h)`).
//!
//! The bias is measured against a shadow chain: each system carries a
//! second copy of the particle that takes the same O steps with the same
//! normals as the engine's chain, but moves by the exact Hamiltonian flow
//! instead of RK4 (for the quartic, eight RK4 substeps: a bias 8⁻⁴ of the
//! engine's; for the Brownian engine, the exact Ornstein–Uhlenbeck step
//! instead of Euler–Maruyama). The O step leaves the Maxwell law invariant at every
//! configuration and the exact flow leaves the Gibbs law invariant, so the
//! shadow chain samples the Gibbs law exactly at any step, and the mean of
//! `x² − x_shadow²` along the coupled path is the engine's bias. Its
//! variance falls with the bias (the two copies differ by the integrator's
//! error alone, not by the noise), so the quartic's bias at h = 1/32,
//! 4.9e-8, is measured to 0.7 % in a run of 4e5 time units, where a plain
//! average of `x²` would need ~1e18. Standard errors from 40 batch means
//! (each batch 10 000 relaxation times); the three steps run on independent
//! streams, so their estimates are independent.

use super::{OdeSystem, Options, Stepper, solve};

/// Key of the engines' random stream (each run has its own run index).
const SEED: u64 = 20_261_201;

/// Number of batches of the batch-means standard error.
const BATCHES: usize = 40;

/// Simulated time of each run, in units of the relaxation time `1/γ`.
const T_RUN: f64 = 400_000.0;

/// RK4 substeps of the anharmonic shadow's flow per step: its own bias is
/// RK4's at `h/8`, `8⁻⁴` = 2.4e-4 of the engine's, below the standard
/// errors.
const SHADOW_SUBSTEPS: usize = 8;

/// The potential of [`Particle`].
#[derive(Clone, Copy, Debug)]
enum Potential {
    /// `x²/2`: ω = 1.
    Harmonic,
    /// `x²/2 + x⁴/4`.
    Quartic,
}

impl Potential {
    fn force(self, x: f64) -> f64 {
        match self {
            Potential::Harmonic => -x,
            Potential::Quartic => -x - x * x * x,
        }
    }

    /// The deterministic flow over `h` of the shadow copy: exact for the
    /// harmonic potential (a rotation), [`SHADOW_SUBSTEPS`] RK4 steps for
    /// the quartic one.
    fn flow(self, x: &mut f64, v: &mut f64, h: f64) {
        match self {
            Potential::Harmonic => {
                let (s, c) = h.sin_cos();
                (*x, *v) = (c * *x + s * *v, -s * *x + c * *v);
            }
            Potential::Quartic => {
                let dt = h / SHADOW_SUBSTEPS as f64;
                for _ in 0..SHADOW_SUBSTEPS {
                    let (x0, v0) = (*x, *v);
                    let (k1x, k1v) = (v0, self.force(x0));
                    let (k2x, k2v) = (v0 + 0.5 * dt * k1v, self.force(x0 + 0.5 * dt * k1x));
                    let (k3x, k3v) = (v0 + 0.5 * dt * k2v, self.force(x0 + 0.5 * dt * k2x));
                    let (k4x, k4v) = (v0 + dt * k3v, self.force(x0 + dt * k3x));
                    *x = x0 + dt / 6.0 * (k1x + 2.0 * (k2x + k3x) + k4x);
                    *v = v0 + dt / 6.0 * (k1v + 2.0 * (k2v + k3v) + k4v);
                }
            }
        }
    }
}

/// A unit-mass particle at `kT = 1` with the thermostat's rate `γ = 1`:
/// state `(x, v, x_s, v_s)`, the engine's copy and the shadow copy. The
/// right-hand side moves the engine's copy only (the shadow's derivatives
/// are zero, so RK4 leaves it exactly as it is); the thermostat applies the
/// same O step to both velocities and, at the second half step, first moves
/// the shadow by its exact flow over the whole step, so the shadow takes
/// `O(h/2) Φ_exact(h) O(h/2)` with the engine's normals.
struct Particle {
    potential: Potential,
    /// The next thermostat call is a step's first half.
    first_half: bool,
}

impl OdeSystem<4> for Particle {
    type Error = ();
    const NOISE: usize = 1;

    fn rhs(&mut self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) -> Result<(), ()> {
        *dy = [y[1], self.potential.force(y[0]), 0.0, 0.0];
        Ok(())
    }

    fn thermostat(&mut self, y: &mut [f64; 4], h: f64, xi: &[f64]) {
        if !self.first_half {
            let (mut x, mut v) = (y[2], y[3]);
            self.potential.flow(&mut x, &mut v, 2.0 * h);
            (y[2], y[3]) = (x, v);
        }
        let d = (-h).exp();
        let s = (-(-2.0 * h).exp_m1()).sqrt();
        y[1] = d * y[1] + s * xi[0];
        y[3] = d * y[3] + s * xi[0];
        self.first_half = !self.first_half;
    }
}

/// The Ornstein–Uhlenbeck process `dx = −x dt + √2 dW` (λ = 1, σ² = 2,
/// stationary variance 1): state `(x, x_s)`, the engine's Euler–Maruyama
/// copy and the shadow taking the exact step with the same normal.
struct Ou;

impl OdeSystem<2> for Ou {
    type Error = ();
    const NOISE: usize = 1;

    fn rhs(&mut self, _t: f64, _y: &[f64; 2], dy: &mut [f64; 2]) -> Result<(), ()> {
        *dy = [0.0; 2];
        Ok(())
    }

    fn overdamped_step(&mut self, _t: f64, y: &mut [f64; 2], h: f64, xi: &[f64]) -> Result<(), ()> {
        y[0] = (1.0 - h) * y[0] + (2.0 * h).sqrt() * xi[0];
        y[1] = (-h).exp() * y[1] + (-(-2.0 * h).exp_m1()).sqrt() * xi[0];
        Ok(())
    }
}

/// A mean and its standard error.
#[derive(Clone, Copy, Debug)]
struct Est {
    mean: f64,
    se: f64,
}

/// What one coupled run measures: `⟨x²⟩` of the engine's chain and of the
/// shadow, and the bias `⟨x² − x_s²⟩`.
#[derive(Clone, Copy, Debug)]
struct Measured {
    engine: Est,
    shadow: Est,
    bias: Est,
}

/// Mean and batch-means standard error of [`BATCHES`] batch sums of
/// `per` values each.
fn batch_est(sums: &[f64], per: u64) -> Est {
    let means: Vec<f64> = sums.iter().map(|s| s / per as f64).collect();
    let nb = means.len() as f64;
    let mean = means.iter().sum::<f64>() / nb;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (nb - 1.0);
    Est {
        mean,
        se: (var / nb).sqrt(),
    }
}

/// Run `sys` from `y0` over [`T_RUN`] with the stepper `stepper(h)`,
/// averaging `x²` of the engine's copy (component 0) and of the shadow
/// (component `shadow`) at every step end.
fn coupled_run<S: OdeSystem<N, Error = ()>, const N: usize>(
    sys: &mut S,
    stepper: Stepper,
    h: f64,
    shadow: usize,
) -> Measured {
    let n = (T_RUN / h).round() as u64;
    let per = n / BATCHES as u64;
    let opts = Options {
        stepper,
        max_steps: n + 1,
        h0: None,
        h_max: None,
    };
    let mut sums = vec![[0.0; 3]; BATCHES];
    let mut k = 0u64;
    solve(
        sys,
        &opts,
        0.0,
        [0.0; N],
        (per * BATCHES as u64) as f64 * h,
        &[],
        &[],
        &[],
        &mut |_, _, _| {},
        &mut |_, _, y| {
            let (a, b) = (y[0] * y[0], y[shadow] * y[shadow]);
            let s = &mut sums[(k / per) as usize];
            s[0] += a;
            s[1] += b;
            s[2] += a - b;
            k += 1;
        },
    )
    .expect("the coupled run");
    assert_eq!(k, per * BATCHES as u64, "one sample per step");
    let col = |i: usize| batch_est(&sums.iter().map(|s| s[i]).collect::<Vec<_>>(), per);
    Measured {
        engine: col(0),
        shadow: col(1),
        bias: col(2),
    }
}

/// The Langevin engine on [`Particle`] with `potential` at step `h`.
fn langevin(potential: Potential, h: f64, run: u64) -> Measured {
    let mut sys = Particle {
        potential,
        first_half: true,
    };
    let stepper = Stepper::Langevin {
        h,
        seed: SEED,
        run,
        first_step: 0,
    };
    coupled_run(&mut sys, stepper, h, 2)
}

/// The Brownian engine on [`Ou`] at step `h`.
fn brownian(h: f64, run: u64) -> Measured {
    let stepper = Stepper::Brownian {
        h,
        seed: SEED,
        run,
        first_step: 0,
    };
    coupled_run(&mut Ou, stepper, h, 1)
}

/// The order between two steps a factor 2 apart, `log2(b₁/b₂)`, with its
/// standard error (the two estimates independent).
fn order(b1: Est, b2: Est) -> Est {
    Est {
        mean: (b1.mean / b2.mean).log2(),
        se: ((b1.se / b1.mean).powi(2) + (b2.se / b2.mean).powi(2)).sqrt() / std::f64::consts::LN_2,
    }
}

/// The order `p` from three biases at `h, h/2, h/4` under `b = c hᵖ +
/// d hᵖ⁺¹` (the first correction eliminated): `x = 2ᵖ` solves `2 b₄ x² −
/// 3 b₂ x + b₁ = 0`; of its roots `2ᵖ` and `2ᵖ⁻¹` (for a pure power) the
/// larger, as the smaller one has `c = 0`. Standard error by the delta
/// method (central differences, independent estimates).
fn three_point_order(b: [Est; 3]) -> Est {
    let p = |b1: f64, b2: f64, b4: f64| {
        let disc = 9.0 * b2 * b2 - 8.0 * b4 * b1;
        assert!(disc > 0.0, "no real order from {b1:e}, {b2:e}, {b4:e}");
        ((3.0 * b2 + disc.sqrt() * b4.signum()) / (4.0 * b4)).log2()
    };
    let m = [b[0].mean, b[1].mean, b[2].mean];
    let mean = p(m[0], m[1], m[2]);
    let mut var = 0.0;
    for i in 0..3 {
        let e = 1e-4 * m[i].abs();
        let (mut up, mut dn) = (m, m);
        up[i] += e;
        dn[i] -= e;
        let g = (p(up[0], up[1], up[2]) - p(dn[0], dn[1], dn[2])) / (2.0 * e);
        var += (g * b[i].se).powi(2);
    }
    Est {
        mean,
        se: var.sqrt(),
    }
}

/// `|measured − want| < k SE`, with the margin in the message.
fn check(what: &str, got: Est, want: f64, k: f64) {
    let z = (got.mean - want) / got.se;
    eprintln!(
        "{what}: {:.6e} ± {:.2e} against {want:.6e} ({z:+.2} SE)",
        got.mean, got.se
    );
    assert!(
        z.abs() < k,
        "{what}: {} ± {} is {z:.1} SE from {want}",
        got.mean,
        got.se
    );
}

/// `measured` is more than `k` SE from `wrong`: the check above has the
/// power to reject that value.
fn rejects(what: &str, got: Est, wrong: f64, k: f64) {
    let z = (got.mean - wrong) / got.se;
    eprintln!("{what}: {z:+.1} SE from {wrong}");
    assert!(
        z.abs() > k,
        "{what}: {} ± {} cannot tell {wrong}",
        got.mean,
        got.se
    );
}

/// The stationary `⟨x²⟩` of the Langevin chain `O(h/2) Φ(h) O(h/2)` on
/// `ẍ = −x` (ω = γ = kT = 1, `z = ωh`), `Φ` RK4, in closed form,
/// returned as its deficit `1 − ⟨x²⟩`.
///
/// In `(ωx, v)` RK4 is `R = [[C, S], [−S, C]]`, `C = 1 − z²/2 + z⁴/24`,
/// `S = z − z³/6`, `C² + S² = 1 − ε`, `ε = z⁶/72 − z⁸/576`. Just before Φ
/// the covariance `[[a, b], [b, c]]` is stationary under `Σ ← P R Σ Rᵀ P +
/// Q`, `P = diag(1, D)`, `Q = diag(0, 1 − D²)`, `D = e^{−γh}` (the two
/// half O steps are one exact O step of `h`; `x`, and so `a`, is the same
/// at the step ends). Its three equations give `b = k (c − a)`, `k = D C S
/// / (1 − D (C² − S²))`; `a/c = 1 − δ_r`, `δ_r = ε/(X + ε)`, `X = S² +
/// 2 C S k`; `c = 1 − δ_c`, `δ_c = D² ε (2X + ε)/(X + ε) / (1 − D² + D² ε
/// (2X + ε)/(X + ε))`. So `1 − a = δ_r + δ_c − δ_r δ_c`, written without
/// a difference of nearly equal numbers; for small z it is `z⁵ (ω/(72γ) +
/// γ/(144ω))`: order 5, as the RK4 energy error of a linear oscillator is
/// `ε`, of order 6 per step, and its phase error leaves the Gibbs law
/// invariant.
fn harmonic_deficit(z: f64) -> f64 {
    let (c, s) = (1.0 - z * z / 2.0 + z.powi(4) / 24.0, z - z.powi(3) / 6.0);
    let eps = z.powi(6) / 72.0 - z.powi(8) / 576.0;
    let d = (-z).exp();
    let one_minus_d2 = -(-2.0 * z).exp_m1();
    let k = d * c * s / (1.0 - d * (c * c - s * s));
    let x = s * s + 2.0 * c * s * k;
    let dr = eps / (x + eps);
    let e = d * d * eps * (2.0 * x + eps) / (x + eps);
    let dc = e / (one_minus_d2 + e);
    dr + dc - dr * dc
}

/// The same deficit by iterating the covariance recursion to its fixed
/// point (a check of the closed form's algebra).
fn harmonic_deficit_iterated(z: f64) -> f64 {
    let (c, s) = (1.0 - z * z / 2.0 + z.powi(4) / 24.0, z - z.powi(3) / 6.0);
    let d = (-z).exp();
    let (mut a, mut b, mut v) = (1.0, 0.0, 1.0);
    for _ in 0..100_000 {
        let m11 = c * c * a + 2.0 * c * s * b + s * s * v;
        let m12 = -c * s * a + (c * c - s * s) * b + c * s * v;
        let m22 = s * s * a - 2.0 * c * s * b + c * c * v;
        (a, b, v) = (m11, d * m12, d * d * m22 + 1.0 - d * d);
    }
    1.0 - a
}

/// `⟨x²⟩` in the Gibbs law of `x²/2 + x⁴/4` at kT = 1: composite Simpson
/// on `[−8, 8]` (`e^{−U(8)}` = e^{−1056}), 20 000 intervals.
fn quartic_gibbs_x2() -> f64 {
    let (l, n) = (8.0, 20_000);
    let dx = 2.0 * l / n as f64;
    let (mut z, mut m) = (0.0, 0.0);
    for i in 0..=n {
        let x = -l + i as f64 * dx;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let p = w * (-(x * x / 2.0 + x.powi(4) / 4.0)).exp();
        z += p;
        m += p * x * x;
    }
    m / z
}

/// Harmonic oscillator, `ωh` = 1, 0.5, 0.25: the measured bias of `⟨x²⟩`
/// equals the chain's closed form at each step (within 4 SE, each bias
/// over 20 SE), the engine's and the shadow's plain averages are the
/// chain's and the Gibbs law's, and the measured orders equal the closed
/// form's (4.86 and 4.96 at these steps, 5 in the limit), which the test
/// tells from 4.
#[test]
fn langevin_stationary_order_on_the_harmonic_oscillator() {
    for z in [1.0, 0.5, 0.25] {
        let (closed, iterated) = (harmonic_deficit(z), harmonic_deficit_iterated(z));
        assert!(
            (closed - iterated).abs() < 1e-14,
            "z = {z}: closed form {closed:e}, recursion {iterated:e}"
        );
    }
    let lead = harmonic_deficit(1e-2) / 1e-10;
    assert!(
        (lead / (1.0 / 72.0 + 1.0 / 144.0) - 1.0).abs() < 1e-4,
        "leading coefficient {lead}"
    );
    let steps = [1.0, 0.5, 0.25];
    let mut biases = [Est { mean: 0.0, se: 0.0 }; 3];
    for (i, &h) in steps.iter().enumerate() {
        let m = langevin(Potential::Harmonic, h, i as u64);
        let want = -harmonic_deficit(h);
        eprintln!("harmonic h = {h}: {m:?}");
        check(&format!("h = {h}: bias"), m.bias, want, 4.0);
        rejects(&format!("h = {h}: bias"), m.bias, 0.0, 20.0);
        check(&format!("h = {h}: engine <x^2>"), m.engine, 1.0 + want, 4.0);
        check(&format!("h = {h}: shadow <x^2>"), m.shadow, 1.0, 4.0);
        biases[i] = m.bias;
    }
    for i in 0..2 {
        let p = order(biases[i], biases[i + 1]);
        let want = (harmonic_deficit(steps[i]) / harmonic_deficit(steps[i + 1])).log2();
        let what = format!("order h = {} -> {}", steps[i], steps[i + 1]);
        check(&what, p, want, 4.0);
        rejects(&what, p, 4.0, 4.0);
    }
    let p = three_point_order(biases);
    eprintln!("harmonic three-point order {p:?}");
}

/// Anharmonic `x²/2 + x⁴/4`, h = 1/8, 1/16, 1/32: the engine's and the
/// shadow's `⟨x²⟩` are the Gibbs law's (quadrature; the bias is far below
/// the plain SE), each bias is resolved (over 20 SE), and the order from
/// the three biases with the first correction eliminated is 4 (within
/// 4 SE), told from 3 and 5. The orders between successive steps are
/// still pre-asymptotic (~3.3 and ~3.75: the bias changes sign near
/// h = 0.2, where the fifth-order term overtakes the fourth) and are only
/// printed.
#[test]
fn langevin_stationary_order_on_a_quartic_well() {
    let gibbs = quartic_gibbs_x2();
    let steps = [0.125, 0.0625, 0.03125];
    let mut biases = [Est { mean: 0.0, se: 0.0 }; 3];
    for (i, &h) in steps.iter().enumerate() {
        let m = langevin(Potential::Quartic, h, 10 + i as u64);
        eprintln!("quartic h = {h}: {m:?}");
        rejects(&format!("h = {h}: bias"), m.bias, 0.0, 20.0);
        check(&format!("h = {h}: engine <x^2>"), m.engine, gibbs, 4.0);
        check(&format!("h = {h}: shadow <x^2>"), m.shadow, gibbs, 4.0);
        biases[i] = m.bias;
    }
    for i in 0..2 {
        let p = order(biases[i], biases[i + 1]);
        eprintln!("quartic order h = {} -> {}: {p:?}", steps[i], steps[i + 1]);
    }
    let p = three_point_order(biases);
    check("quartic three-point order", p, 4.0, 4.0);
    rejects("quartic three-point order", p, 3.0, 4.0);
    rejects("quartic three-point order", p, 5.0, 4.0);
}

/// Brownian (Euler–Maruyama) on the Ornstein–Uhlenbeck process, λh = 0.2,
/// 0.1, 0.05: the measured bias of `⟨x²⟩` equals the closed form
/// `σ²/(2λ − λ²h) − σ²/(2λ)` (within 4 SE, each over 20 SE), the plain
/// averages are the chain's and the exact law's, and the measured orders
/// equal the closed form's (1.08 and 1.04, 1 in the limit), told from 2.
/// The Euler–Maruyama step is the system's ([`OdeSystem::overdamped_step`],
/// here [`Ou`]'s); of the engine this checks one call per step of the
/// step's length with fresh normals (a reused normal changes the variance).
#[test]
fn brownian_stationary_order_on_the_ornstein_uhlenbeck_process() {
    let steps = [0.2, 0.1, 0.05];
    let closed = |h: f64| 2.0 / (2.0 - h) - 1.0;
    let mut biases = [Est { mean: 0.0, se: 0.0 }; 3];
    for (i, &h) in steps.iter().enumerate() {
        let m = brownian(h, 20 + i as u64);
        eprintln!("brownian h = {h}: {m:?}");
        check(&format!("h = {h}: bias"), m.bias, closed(h), 4.0);
        rejects(&format!("h = {h}: bias"), m.bias, 0.0, 20.0);
        check(
            &format!("h = {h}: engine <x^2>"),
            m.engine,
            1.0 + closed(h),
            4.0,
        );
        check(&format!("h = {h}: shadow <x^2>"), m.shadow, 1.0, 4.0);
        biases[i] = m.bias;
    }
    for i in 0..2 {
        let p = order(biases[i], biases[i + 1]);
        let want = (closed(steps[i]) / closed(steps[i + 1])).log2();
        let what = format!("order h = {} -> {}", steps[i], steps[i + 1]);
        check(&what, p, want, 4.0);
        rejects(&what, p, 2.0, 4.0);
    }
    let p = three_point_order(biases);
    eprintln!("brownian three-point order {p:?}");
}
