//! The exact one-dimensional answers (`analysis::rare::exact`, issue 27)
//! against independent closed forms, to 1e-8 relative: a flat potential,
//! a linear one (drift), a harmonic well (series), the Kramers deep-well
//! limit with its first correction in 1/barrier, barriers of 200 and
//! 1000 kT in log space; and which scenarios are refused, with the reason.

use std::f64::consts::PI;

use tippetop::analysis::ensemble::Exit;
use tippetop::analysis::rare::exact::{self, Diffusion, Quantity, ThetaDiffusion};
use tippetop::input::thermal::BOLTZMANN;
use tippetop::{ContactMode, Forcing, Method, ModelKind, Scenario, Well};

fn rel(got: f64, want: f64) -> f64 {
    ((got - want) / want).abs()
}

fn assert_rel(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        rel(got, want) <= tol,
        "{what}: {got:e} against {want:e} (relative {:.2e})",
        rel(got, want)
    );
}

/// A flat potential with constant D: `τ = (x − lo)(hi − x)/(2D)` between
/// two absorbing edges, `((hi − L)² − (x − L)²)/(2D)` with the domain's
/// end `L` reflecting (and its mirror), `P(hi first) = (x − lo)/(hi − lo)`.
#[test]
fn flat_potential() {
    let d = 0.7;
    let (l, h) = (-1.0, 3.0);
    let flat = Diffusion::new(l, h, |_| 0.0, move |_| d);
    let (lo, hi) = (0.2, 2.5);
    for x in [0.2001, 0.5, 1.35, 2.0, 2.4999] {
        let t = flat.mean_exit_time(Some(lo), Some(hi), x).unwrap();
        assert_rel("two edges", t.value, (x - lo) * (hi - x) / (2.0 * d), 1e-8);
        assert_rel("its log", t.ln.exp(), t.value, 1e-15);
        let t = flat.mean_exit_time(None, Some(hi), x).unwrap();
        assert_rel(
            "reflecting below",
            t.value,
            ((hi - l).powi(2) - (x - l).powi(2)) / (2.0 * d),
            1e-8,
        );
        let t = flat.mean_exit_time(Some(lo), None, x).unwrap();
        assert_rel(
            "reflecting above",
            t.value,
            ((h - lo).powi(2) - (h - x).powi(2)) / (2.0 * d),
            1e-8,
        );
        let s = flat.splitting(lo, hi, x).unwrap();
        assert_rel(
            "P(hi first)",
            s.upper_first.value,
            (x - lo) / (hi - lo),
            1e-8,
        );
        assert_rel(
            "P(lo first)",
            s.lower_first.value,
            (hi - x) / (hi - lo),
            1e-8,
        );
    }
    // On an edge: 0 and certain.
    assert_eq!(
        flat.mean_exit_time(Some(lo), Some(hi), lo).unwrap().value,
        0.0
    );
    assert_eq!(flat.splitting(lo, hi, hi).unwrap().upper_first.value, 1.0);
    // No edge: never leaves.
    assert!(flat.mean_exit_time(None, None, 1.0).is_err());
}

/// A linear potential, `ln π = k x`, constant D: the drift `v = D k`. With
/// `u = x − lo`, `L = hi − lo`: `P(hi first) = (1 − e^{−k u})/(1 − e^{−k L})`
/// and `τ = [L P(hi first) − u]/v` (the solution of `D τ″ + v τ′ = −1`).
/// At `k = ∓200` the small probability (down to e^{−600}) is checked in
/// log space.
#[test]
fn linear_potential() {
    let d = 2.0;
    let (lo, hi) = (0.0, 3.0);
    for k in [-20.0, -3.0, 0.5, 3.0, 20.0] {
        let lin = Diffusion::new(-1.0, 4.0, move |x| k * x, move |_| d);
        for x in [0.1, 1.0, 1.7, 2.9] {
            let (u, l) = (x - lo, hi - lo);
            let p_hi = (1.0 - (-k * u).exp()) / (1.0 - (-k * l).exp());
            let s = lin.splitting(lo, hi, x).unwrap();
            assert_rel(
                &format!("k {k} x {x}: P(hi)"),
                s.upper_first.value,
                p_hi,
                1e-8,
            );
            let p_lo = ((-k * u).exp() - (-k * l).exp()) / (1.0 - (-k * l).exp());
            assert_rel(
                &format!("k {k} x {x}: P(lo)"),
                s.lower_first.value,
                p_lo,
                1e-8,
            );
            let tau = (l * p_hi - u) / (d * k);
            let t = lin.mean_exit_time(Some(lo), Some(hi), x).unwrap();
            assert_rel(&format!("k {k} x {x}: τ"), t.value, tau, 1e-8);
        }
    }
    // Steep: ln P(hi first) = ln(e^{|k| u} − 1) − ln(e^{|k| L} − 1) for
    // k < 0, written without overflow.
    for k in [-200.0, 200.0] {
        let lin = Diffusion::new(-1.0, 4.0, move |x| k * x, move |_| d);
        let x = 1.0;
        let (u, l) = (x - lo, hi - lo);
        let s = lin.splitting(lo, hi, x).unwrap();
        let a = k.abs();
        let ln_small = a * u + (-(-a * u).exp()).ln_1p() - a * l - (-(-a * l).exp()).ln_1p();
        let (small, _) = if k < 0.0 {
            (s.upper_first, s.lower_first)
        } else {
            (s.lower_first, s.upper_first)
        };
        // For k > 0: P(lo first) = (e^{−k u} − e^{−k L})/(1 − e^{−k L}).
        let want = if k < 0.0 {
            ln_small
        } else {
            -a * u + (-(-a * (l - u)).exp()).ln_1p() - (-(-a * l).exp()).ln_1p()
        };
        assert!(
            (small.ln - want).abs() <= 1e-8 * want.abs(),
            "k {k}: ln P {} against {want}",
            small.ln
        );
    }
}

/// `Σ_n 2^n β^{2n+2}/((2n+1)!! (2n+2))` = `∫_0^β e^{v²} ∫_0^v e^{−u²} du dv`
/// (from `e^{v²} ∫_0^v e^{−u²} = Σ 2^n v^{2n+1}/(2n+1)!!`).
fn ou_series(beta: f64) -> f64 {
    let (mut sum, mut term_pow, mut dfact) = (0.0, beta * beta, 1.0);
    for n in 0..200 {
        let t = term_pow / (dfact * (2 * n + 2) as f64);
        sum += t;
        if t < 1e-18 * sum {
            break;
        }
        term_pow *= 2.0 * beta * beta;
        dfact *= (2 * n + 3) as f64;
    }
    sum
}

/// `∫_0^β e^{v²} dv = Σ β^{2n+1}/(n! (2n+1))` (odd in β).
fn erfi_integral(beta: f64) -> f64 {
    let (mut sum, mut p, mut fact) = (0.0, beta, 1.0);
    for n in 0..400 {
        let t = p / (fact * (2 * n + 1) as f64);
        sum += t;
        if t.abs() < 1e-18 * sum.abs() {
            break;
        }
        p *= beta * beta;
        fact *= (n + 1) as f64;
    }
    sum
}

/// A harmonic well (Ornstein–Uhlenbeck), `ln π = −x²/(2s²)`, constant D,
/// edges ±a: `τ(x) = (2 s²/D) [F(α) − F(ξ)]` with `α = a/(s√2)`,
/// `ξ = |x|/(s√2)` and `F` the series [`ou_series`]; `P(a first) =
/// (E(ξ) + E(α))/(2 E(α))` with `E` = [`erfi_integral`] and ξ signed.
#[test]
fn harmonic_well() {
    let (d, s) = (1.5, 0.4);
    let ou = Diffusion::new(-10.0, 10.0, move |x| -x * x / (2.0 * s * s), move |_| d);
    for alpha in [0.5, 1.0, 2.0, 3.0] {
        let a = alpha * s * 2f64.sqrt();
        for frac in [0.0, 0.3, -0.5, 0.9] {
            let x = frac * a;
            let xi = x / (s * 2f64.sqrt());
            let want = 2.0 * s * s / d * (ou_series(alpha) - ou_series(xi.abs()));
            let t = ou.mean_exit_time(Some(-a), Some(a), x).unwrap();
            assert_rel(&format!("α {alpha}, x/a {frac}: τ"), t.value, want, 1e-8);
            let p = (erfi_integral(xi) + erfi_integral(alpha)) / (2.0 * erfi_integral(alpha));
            let sp = ou.splitting(-a, a, x).unwrap();
            assert_rel(
                &format!("α {alpha}, x/a {frac}: P"),
                sp.upper_first.value,
                p,
                1e-8,
            );
        }
    }
}

/// The quartic double well `U = E (x² − 1)²` (E the barrier in kT), D = 1,
/// from the well's bottom at −1 to the other well's at +1 (reflecting far
/// out at −3). Kramers' (Smoluchowski) time is `τ_K = 2π e^E/(E √32)`
/// (the curvatures 8E and −4E); Laplace's method to the next order gives
/// `τ = τ_K (1 + 3/(8E) + O(E^−2))` (3/(16E) from the well, where
/// `(x² − 1)² = 4ε² − 4ε³ + ε⁴`, and 3/(16E) from the barrier, where it is
/// `1 − 2x² + x⁴`; the correction of `∫ e^{−E(a₂x² + a₃x³ + a₄x⁴)}` is
/// `15a₃²/(16a₂³E) − 3a₄/(4a₂²E)`), up to exponentially small terms.
fn double_well(e: f64) -> Diffusion {
    Diffusion::new(-3.0, 3.0, move |x| -e * (x * x - 1.0).powi(2), |_| 1.0)
}

fn kramers_ln(e: f64) -> f64 {
    (2.0 * PI).ln() + e - e.ln() - 32f64.sqrt().ln()
}

#[test]
fn kramers_deep_well_limit() {
    let mut last: Option<f64> = None;
    for e in [10.0, 20.0, 40.0, 80.0, 160.0] {
        let t = double_well(e)
            .mean_exit_time(None, Some(1.0), -1.0)
            .unwrap();
        let ratio = (t.ln - kramers_ln(e)).exp();
        // (τ/τ_K − 1) E → 3/8, the remainder O(1/E).
        let r = (ratio - 1.0) * e;
        let dev = (r - 0.375).abs();
        eprintln!(
            "E = {e} kT: τ/τ_K − 1 = {:.6e}, times E = {r:.6}",
            ratio - 1.0
        );
        assert!(
            dev < 2.0 / e,
            "E = {e}: (τ/τ_K − 1) E = {r}, not 3/8 + O(1/E)"
        );
        if let Some(prev) = last {
            // Doubling E halves the remainder (order 1/E), within 25 %.
            let q = dev / prev;
            assert!((0.375..0.625).contains(&q), "E = {e}: remainder ratio {q}");
        }
        last = Some(dev);
    }
}

/// Barriers of 200 and 1000 kT: the answers stay finite in log space
/// (e^{1000} overflows f64: the value is inf, its log is not) and agree
/// with the Laplace asymptotics to O(E^−2); the splitting probability of
/// climbing over the barrier, e^{−200}-small, also.
#[test]
fn huge_barriers_in_log_space() {
    for e in [200.0, 1000.0] {
        let t = double_well(e)
            .mean_exit_time(None, Some(1.0), -1.0)
            .unwrap();
        let want = kramers_ln(e) + (1.0 + 3.0 / (8.0 * e)).ln();
        assert!(t.ln.is_finite(), "E = {e}: ln τ = {}", t.ln);
        assert!(
            (t.ln - want).abs() < 2.0 / (e * e),
            "E = {e}: ln τ {} against {want}",
            t.ln
        );
        if e > 709.0 {
            assert!(t.value.is_infinite());
        } else {
            assert_rel("value", t.value, t.ln.exp(), 1e-15);
        }
        // P(reach +1 before −1.2 | −1) = ∫_{−1.2}^{−1} S′ / ∫_{−1.2}^{1} S′,
        // S′ = e^{E f}, f = (x² − 1)²: Laplace at the end point −1.2
        // (f = 0.1936, f′ = −2.112) over Laplace at the barrier (f = 1,
        // curvature −4): ln P = 0.1936 E − ln(2.112 E) − E − ½ ln(π/(2E))
        // + O(1/E).
        let s = double_well(e).splitting(-1.2, 1.0, -1.0).unwrap();
        let f0 = (1.44f64 - 1.0).powi(2);
        let want_p = f0 * e - (2.112 * e).ln() - e - 0.5 * (PI / (2.0 * e)).ln();
        assert!(s.upper_first.ln.is_finite());
        assert!(
            (s.upper_first.ln - want_p).abs() < 5.0 / e,
            "E = {e}: ln P {} against {want_p}",
            s.upper_first.ln
        );
        assert_rel("P(down)", s.lower_first.value, 1.0, 1e-12);
        eprintln!(
            "E = {e} kT: ln τ = {} (asymptotics {want}), ln P(up) = {} ({want_p})",
            t.ln, s.upper_first.ln
        );
    }
}

// ---------------------------------------------------------------------------
// The θ diffusion of a scenario.

/// A Brownian nano top on the plane at 300 K (the first-passage test's).
fn brownian_top() -> Scenario {
    let t = 300.0;
    let mut sc = Scenario::nano();
    sc.top.offset = 0.5 * sc.top.radius;
    sc.surface.friction = 0.0;
    sc.forcing = Forcing::none();
    sc.set_wells(&[Well {
        theta: std::f64::consts::FRAC_PI_2,
        depth: 2.0 * BOLTZMANN * t,
        width: 0.3,
    }]);
    sc.initial.theta = std::f64::consts::FRAC_PI_2;
    sc.initial.spin = 0.0;
    sc.solver.method = Method::Brownian;
    sc.solver.dt = Some(5e-16);
    sc.solver.t_end = 1e-12;
    sc.solver.samples = 11;
    sc.thermal.temperature = t;
    sc.thermal.damping_translational = 2.2e12;
    sc.thermal.damping_rotational = 2.2e12;
    sc.thermal.seed = Some(1);
    sc
}

fn refusal(sc: &Scenario) -> String {
    match ThetaDiffusion::of(sc) {
        Ok(_) => panic!("accepted"),
        Err(e) => {
            assert!(e.is_input());
            e.to_string()
        }
    }
}

#[test]
fn scenarios_that_are_not_one_dimensional_are_refused() {
    assert!(ThetaDiffusion::of(&brownian_top()).is_ok());
    let mut sc = brownian_top();
    sc.solver.method = Method::Langevin;
    sc.solver.dt = Some(4e-15);
    let m = refusal(&sc);
    assert!(
        m.starts_with("solver.method: no exact 1D answer") && m.contains("θ̇"),
        "{m}"
    );
    let mut sc = brownian_top();
    sc.surface.contact = ContactMode::Unilateral;
    assert!(refusal(&sc).starts_with("surface.contact:"));
    sc.solver.model = ModelKind::Rigid;
    let m = refusal(&sc);
    assert!(m.contains("free body above a wall"), "{m}");
    let mut sc = brownian_top();
    sc.forcing.windows.push(tippetop::ForceWindow {
        hx: 1e-12,
        hy: 0.0,
        hz: 0.0,
        start: 1e-13,
        stop: f64::INFINITY,
    });
    let m = refusal(&sc);
    assert!(
        m.starts_with("force.0.hx:") && m.contains("time-dependent"),
        "{m}"
    );
    // H_y and h_z do not move θ, whenever they act; a constant H_x is exact.
    let mut sc = brownian_top();
    sc.forcing.windows.push(tippetop::ForceWindow {
        hx: 0.0,
        hy: 3e-12,
        hz: 1e-12,
        start: 1e-13,
        stop: 2e-13,
    });
    sc.forcing.windows.push(tippetop::ForceWindow {
        hx: 2e-12,
        hy: 0.0,
        hz: 0.0,
        start: 0.0,
        stop: f64::INFINITY,
    });
    let d = ThetaDiffusion::of(&sc).unwrap();
    assert_eq!(d.hx, 2e-12);
    let mut sc = brownian_top();
    sc.thermal.temperature = 0.0;
    assert!(refusal(&sc).starts_with("thermal.temperature:"));
}

/// The mapping of target and reset conditions onto the θ window, and the
/// quantities, against the generic functions.
#[test]
fn conditions_map_onto_the_window() {
    let sc = brownian_top();
    let d = ThetaDiffusion::of(&sc).unwrap().diffusion();
    let x0 = sc.initial.theta;
    let cond = |s: &str| Exit::parse(s).unwrap();
    // Target above, reset below: P(upper first).
    let e = exact::exact(&sc, &cond("theta>1.9"), Some(&cond("theta<1.2"))).unwrap();
    assert_eq!(e.quantity, Quantity::Probability);
    let s = d.splitting(1.2, 1.9, x0).unwrap();
    assert_eq!(e.value, s.upper_first);
    // Several terms: the innermost edge of each side counts; the reset's
    // edge nearer than the target's on the same side shadows it.
    let e = exact::exact(
        &sc,
        &cond("theta>1.9,theta<0.5,theta>2.5"),
        Some(&cond("theta<1.2")),
    )
    .unwrap();
    assert_eq!(e.value, s.upper_first);
    assert!(!e.lower.unwrap().target && e.upper.unwrap().target);
    // Mean time to one edge (the pole reflecting).
    let e = exact::exact(&sc, &cond("theta>1.9"), None).unwrap();
    assert_eq!(e.quantity, Quantity::MeanFirstPassageTime);
    assert_eq!(e.value, d.mean_exit_time(None, Some(1.9), x0).unwrap());
    // The watched path: each absorbing edge moved out by β sqrt(2 D dt).
    let dt = sc.solver.dt.unwrap();
    let td = ThetaDiffusion::of(&sc).unwrap();
    let w = d
        .mean_exit_time(
            None,
            Some(1.9 + exact::BGK_BETA * (2.0 * td.diffusivity(1.9) * dt).sqrt()),
            x0,
        )
        .unwrap();
    assert_eq!(e.watched.unwrap(), w);
    assert!(w.value > e.value.value);
    assert_eq!(
        d.watched_edges(None, Some(1.9), dt),
        (
            None,
            Some(1.9 + exact::BGK_BETA * (2.0 * td.diffusivity(1.9) * dt).sqrt())
        )
    );
    // A target that never holds on [0, π].
    let err = exact::exact(&sc, &cond("theta>4"), None).unwrap_err();
    assert!(err.to_string().starts_with("--target:"), "{err}");
    // A target on another column.
    let err = exact::exact(&sc, &cond("omega>4"), None).unwrap_err();
    assert!(
        err.to_string().contains("not a condition on theta"),
        "{err}"
    );
    // A reset that cannot happen before the target: P = 1.
    let e = exact::exact(&sc, &cond("theta>1.9"), Some(&cond("theta>2.5"))).unwrap();
    assert_eq!(e.value.value, 1.0);
}
