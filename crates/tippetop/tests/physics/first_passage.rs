//! Escape out of a window of θ in the overdamped (Brownian) mode, against
//! the exact mean first-passage time of its one-dimensional diffusion
//! (docs/physics.md §22, "the Kramers check"): what the retention
//! machinery (`--first-passage`, escape rates, `tippetop retention`)
//! measures, checked where the answer is known in closed form.
//!
//! The Brownian mode's θ is a reversible diffusion with coefficient
//! `D(θ) = kT/Γ_θ`, `Γ_θ = γ_r A + γ_t m a² sin²θ` (the tilt mode's
//! friction: the rotation about the horizontal axis and the centre's
//! vertical velocity `a sin θ θ̇`), and stationary density
//! `π(θ) ∝ sin θ s(θ) e^{−U/kT}`, `s = sqrt(1 + m a² sin²θ/A)` (§21). Its
//! mean exit time from `(lo, hi)` started at `θ0` solves `L τ = −1`,
//! `τ(lo) = τ(hi) = 0`, `L f = (π D f′)′/π`:
//!
//! ```text
//! τ(θ0) = c I1(θ0) − I2(θ0),  I1(x) = ∫_lo^x dy/(π D),  I2(x) = ∫_lo^x dy (∫_lo^y π)/(π D),
//! c = I2(hi)/I1(hi)
//! ```
//!
//! (Gardiner, Handbook of Stochastic Methods, §5.2.7), here by Simpson's
//! rule on 20 000 intervals (its error ~1e-12 relative). The run is
//! watched at every step (rows every `dt`), and a discretely watched path
//! exits later than the continuous one: to leading order the window is
//! wider by `β sqrt(2 D Δ)` at each edge, `β = −ζ(1/2)/sqrt(2π) = 0.5826`
//! (Broadie, Glasserman & Kou, Math. Finance 7, 325 (1997)); the expected
//! value uses that window (the correction is 1.2 % of τ here, a third of
//! the standard error).

use tippetop::analysis::ensemble::{Ensemble, Exit};
use tippetop::thermal::BOLTZMANN;
use tippetop::{Forcing, Method, Scenario, Well};

const T: f64 = 300.0;
const GAMMA: f64 = 2.2e12;
const DT: f64 = 5e-16;
const HALF: f64 = 0.35;

/// The nano top made eccentric (`a = R/2`, so `m a²/A = 0.375`: the tilt
/// mode's friction grows by up to 37 % with sin²θ), no gravity, no force,
/// frictionless, a Gaussian well of 2 kT at θ = π/2 (width 0.3 rad), in
/// the Brownian mode at 300 K with `γ_t = γ_r = 2.2e12 s⁻¹` (nano-physical's),
/// `dt = 5e-16 s` (`dt` times the well's rate `d/(w² γ_r A)` = 2e-4),
/// started at θ = π/2 and watched at every step until 8e-11 s (12 mean
/// exit times).
fn escaping_top() -> Scenario {
    let mut sc = Scenario::nano();
    sc.top.offset = 0.5 * sc.top.radius;
    sc.surface.friction = 0.0;
    sc.surface.gravity = 0.0;
    sc.forcing = Forcing { windows: vec![] };
    sc.wells = vec![Well {
        theta: std::f64::consts::FRAC_PI_2,
        depth: 2.0 * BOLTZMANN * T,
        width: 0.3,
    }];
    sc.initial.theta = std::f64::consts::FRAC_PI_2;
    sc.initial.spin = 0.0;
    sc.solver.method = Method::Brownian;
    sc.solver.dt = Some(DT);
    sc.solver.t_end = 8e-11;
    sc.solver.samples = 160_001;
    sc.thermal.temperature = T;
    sc.thermal.damping_translational = GAMMA;
    sc.thermal.damping_rotational = GAMMA;
    sc.thermal.seed = Some(20261124);
    sc
}

/// The exact mean exit time from `(lo, hi)` started at `x0` of the
/// diffusion with coefficient `d` and stationary density `p`
/// (unnormalised): the module doc's formula, by Simpson's rule.
fn mean_exit_time(
    d: &dyn Fn(f64) -> f64,
    p: &dyn Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    x0: f64,
) -> f64 {
    let n = 20_000; // even
    let h = (hi - lo) / n as f64;
    let ys: Vec<f64> = (0..=n).map(|i| lo + h * i as f64).collect();
    // Cumulative integrals on the grid by Simpson over pairs of intervals
    // (the odd nodes by the trapezoid from the previous even node, whose
    // error O(h³) per node is ~1e-12 here).
    let cumulative = |f: &dyn Fn(usize) -> f64| -> Vec<f64> {
        let mut c = vec![0.0; n + 1];
        for i in (0..n).step_by(2) {
            let (f0, f1, f2) = (f(i), f(i + 1), f(i + 2));
            c[i + 1] = c[i] + h / 12.0 * (5.0 * f0 + 8.0 * f1 - f2);
            c[i + 2] = c[i] + h / 3.0 * (f0 + 4.0 * f1 + f2);
        }
        c
    };
    let pv: Vec<f64> = ys.iter().map(|&y| p(y)).collect();
    let inner = cumulative(&|i| pv[i]);
    let i1 = cumulative(&|i| 1.0 / (pv[i] * d(ys[i])));
    let i2 = cumulative(&|i| inner[i] / (pv[i] * d(ys[i])));
    let c = i2[n] / i1[n];
    // x0 on the grid (the tests start at the window's centre).
    let k = ((x0 - lo) / h).round() as usize;
    assert!((ys[k] - x0).abs() < 1e-12 * hi.abs(), "x0 off the grid");
    c * i1[k] - i2[k]
}

#[test]
fn brownian_escape_time_is_the_exact_mean_first_passage_time() {
    let sc = escaping_top();
    let centre = std::f64::consts::FRAC_PI_2;
    let (lo, hi) = (centre - HALF, centre + HALF);
    let runs = 1000;
    let e = Ensemble::new(None, Some(sc.to_toml_string()), vec![], runs)
        .unwrap()
        .with_exit(Some(
            Exit::parse(&format!("theta<{lo},theta>{hi}")).unwrap(),
        ));
    let mut times = Vec::with_capacity(runs);
    e.run_streaming(0..runs, Some(2), &mut |row| {
        times.push(
            row.first_passage
                .expect("every run exits before 12 mean times"),
        );
        true
    })
    .unwrap();
    let n = times.len() as f64;
    let mean = times.iter().sum::<f64>() / n;
    let var = times.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();

    let kt = BOLTZMANN * T;
    let (m, a, big_a) = (sc.top.mass, sc.top.offset, sc.top.inertia_transverse);
    let well = sc.wells[0];
    let u = |th: f64| -well.depth * (-(th - well.theta).powi(2) / (2.0 * well.width.powi(2))).exp();
    let p = |th: f64| {
        let s2 = th.sin().powi(2);
        th.sin() * (1.0 + m * a * a * s2 / big_a).sqrt() * (-u(th) / kt).exp()
    };
    let d = |th: f64| kt / (GAMMA * big_a + GAMMA * m * a * a * th.sin().powi(2));
    // Discrete watching: the window widened by β sqrt(2 D Δ) at each edge.
    let beta = 0.5826;
    let (lo_w, hi_w) = (
        lo - beta * (2.0 * d(lo) * DT).sqrt(),
        hi + beta * (2.0 * d(hi) * DT).sqrt(),
    );
    // Keep the start on the quadrature grid: a window symmetric about it.
    let half_w = (centre - lo_w).max(hi_w - centre);
    let want = mean_exit_time(&d, &p, centre - half_w, centre + half_w, centre);
    let continuous = mean_exit_time(&d, &p, lo, hi, centre);
    // Power: the standard error is a few per cent, and a model that forgot
    // the centre's vertical motion in the tilt's friction (D = kT/(γ_r A))
    // would exit 26 % sooner.
    let wrong = mean_exit_time(&|_| kt / (GAMMA * big_a), &p, lo, hi, centre);
    eprintln!(
        "mean exit time {mean:e} ± {se:e} s over {runs} runs; exact {continuous:e} (continuous), \
         {want:e} (watched every dt); without the vertical motion {wrong:e}"
    );
    assert!(se < 0.04 * want, "SE {se:e} too large to test");
    assert!(
        (wrong - want).abs() > 6.0 * se,
        "no power against {wrong:e}"
    );
    assert!(
        (mean - want).abs() < 4.0 * se,
        "mean exit time {mean:e} ± {se:e}, exact {want:e} ({:.2} SE)",
        (mean - want) / se
    );
}
