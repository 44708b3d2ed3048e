//! Full inversion of a dissipating top (docs/physics.md#stability "Full
//! inversion", `analysis::stability::inversion`): the least energy at fixed
//! Jellett's J decides where a top with a smooth friction law ends. Checked
//! against the friction linearisation (an independent computation: dual
//! numbers through the axis model, eigenvalues), against the zero-slip steady
//! motions' closed forms, against long runs, and through the bit harness: a
//! map over the initial spin puts the full-inversion boundary where the
//! threshold says (issue #16's known-answer case).

use std::f64::consts::PI;

use tippetop::{
    Scenario, Top,
    analysis::bit,
    analysis::stability::{self, Physics, SmoothLaw, inversion},
    input::scenario::bit::BitScenario,
};

const G: f64 = 9.8;

/// The classical preset's top and two with A ≠ C inside the inversion
/// window 1 − a/R < A/C < 1 + a/R (a/R = 0.1).
fn tops() -> Vec<(String, Top)> {
    let mut out = vec![("A = C".to_string(), Top::classical())];
    for ac in [0.95, 1.05] {
        let mut t = Top::classical();
        t.inertia_axial = t.inertia_transverse / ac;
        out.push((format!("A/C = {ac}"), t));
    }
    out
}

/// Largest real part of the inverted top's eigenvalues with friction, at
/// the spin `n` about the vertical (the structural zeros removed).
fn inverted_max_re(top: Top, eps: f64, n: f64) -> f64 {
    let ph = Physics {
        top,
        gravity: G,
        mu: 0.3,
        law: SmoothLaw::Regularized,
        eps,
    };
    // At θ = π, k = −Z: a spin n about +Z is ω = −n about k.
    stability::linearise(&ph, PI, 0.0, -n, 1e-10)
        .unwrap()
        .max_re
}

/// The closed-form threshold n_c = (R + a) √(m g a/(R [C (R + a) − A R]))
/// is where the friction linearisation at θ = π changes from unstable to
/// stable, for two friction scales and three tops: a strict minimum of the
/// energy at fixed J is what dissipation makes stable.
#[test]
fn inverted_threshold_is_where_the_linearisation_turns_stable() {
    for (name, top) in tops() {
        let nc = inversion::inverted_threshold(&top, G).unwrap();
        for eps in [1.5e-3, 0.1] {
            let f = |n: f64| inverted_max_re(top, eps, n);
            let (mut lo, mut hi) = (nc * 0.99, nc * 1.01);
            assert!(f(lo) > 0.0, "{name} eps {eps}: stable below n_c? {}", f(lo));
            assert!(
                f(hi) < 0.0,
                "{name} eps {eps}: unstable above n_c? {}",
                f(hi)
            );
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if f(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let n_star = 0.5 * (lo + hi);
            assert!(
                (n_star / nc - 1.0).abs() < 1e-6,
                "{name} eps {eps}: linearisation turns at {n_star}, closed form {nc}"
            );
        }
    }
    // Outside the window (A/C = 1.15 > 1 + a/R) no spin makes π a minimum.
    let mut top = Top::classical();
    top.inertia_axial = top.inertia_transverse / 1.15;
    assert_eq!(inversion::inverted_threshold(&top, G), None);
    for n in [50.0, 500.0, 5000.0] {
        assert!(inverted_max_re(top, 0.1, n) > 0.0, "stable at {n}?");
    }
}

/// The least-energy state is a zero-slip steady motion with the same J
/// (the family of `relative_equilibrium_precession_sq`), and for A = C it
/// has the closed form cos θ* = (R² + a² − √(J² R/(C m g)))/(2 a R) (V_J is
/// convex in cos θ there).
#[test]
fn least_energy_state_is_the_zero_slip_steady_motion_with_that_j() {
    let top = Top::classical();
    let (r, a, c, m) = (top.radius, top.offset, top.inertia_axial, top.mass);
    for w0 in [40.0, 45.0, 50.0, 54.0, 54.5] {
        let j = stability::jellett(&top, 0.1, 0.0, w0);
        let x = (r * r + a * a - (j * j * r / (c * m * G)).sqrt()) / (2.0 * a * r);
        assert!(x.abs() < 1.0, "w0 {w0}: no interior minimum");
        let th = inversion::final_theta(&top, G, &[], j);
        assert!(
            (th - x.acos()).abs() < 1e-9,
            "w0 {w0}: {th} vs {}",
            x.acos()
        );
    }
    // Tops with an interior minimum below the threshold (A/C = 1, 1.05).
    for (name, top) in tops()
        .into_iter()
        .filter(|(_, t)| t.inertia_axial <= t.inertia_transverse)
    {
        let w_c = inversion::initial_spin_for_threshold(&top, G, 0.1).unwrap();
        for f in [0.7, 0.8, 0.9, 0.97] {
            let w0 = f * w_c;
            let j = stability::jellett(&top, 0.1, 0.0, w0);
            let th = inversion::final_theta(&top, G, &[], j);
            assert!(th > 0.01 && th < PI - 0.01, "{name} w0 {w0}: {th}");
            // A minimum: V′ = 0 there and V above it on both sides.
            let v = |x: f64| inversion::potential(&top, G, &[], j, x);
            assert!(
                v(th - 1e-4) > v(th) && v(th + 1e-4) > v(th),
                "{name} w0 {w0}"
            );
            let o2 = stability::relative_equilibrium_precession_sq(&top, G, th).unwrap();
            // J of the steady motion at θ*, with either sense of precession.
            let js = [o2.sqrt(), -o2.sqrt()].map(|om| {
                let w = stability::relative_equilibrium_spin(&top, th, om);
                stability::jellett(&top, th, om, w)
            });
            let best = js
                .iter()
                .map(|x| (x / j - 1.0).abs())
                .fold(f64::MAX, f64::min);
            assert!(best < 1e-10, "{name} w0 {w0}: J* {js:?} vs J {j}");
        }
    }
    // A/C = 0.95: no interior minimum; below the threshold at π the least
    // energy is upright, and the upright top is a local minimum below
    // n_up (its quadratic coefficient changes sign there).
    let top95 = tops()[1].1;
    let w_c = inversion::initial_spin_for_threshold(&top95, G, 0.1).unwrap();
    for f in [0.7, 0.9, 0.97] {
        let j = stability::jellett(&top95, 0.1, 0.0, f * w_c);
        assert_eq!(inversion::final_theta(&top95, G, &[], j), 0.0, "f {f}");
    }
    for (name, top) in tops() {
        let n_up = inversion::upright_threshold(&top, G).unwrap();
        let (r, a, c) = (top.radius, top.offset, top.inertia_axial);
        for (n, sign) in [(0.999 * n_up, 1.0), (1.001 * n_up, -1.0)] {
            let j = c * n * (r - a);
            let v = |x: f64| inversion::potential(&top, G, &[], j, x);
            let k0 = (v(1e-3) + v(-1e-3) - 2.0 * v(0.0)) / 1e-6;
            assert!(k0 * sign > 0.0, "{name} n {n}: curvature {k0}");
        }
    }
    // Slow enough (√(J² R/(C m g)) < (R − a)², here ω₀ < 36.6 rad/s) the
    // upright top is the minimum; above the threshold π, exactly.
    let j = stability::jellett(&top, 0.1, 0.0, 30.0);
    assert_eq!(inversion::final_theta(&top, G, &[], j), 0.0);
    let j = stability::jellett(&top, 0.1, 0.0, 70.0);
    assert_eq!(inversion::final_theta(&top, G, &[], j), PI);
}

/// The energy alone (E₀ >= V_J(π)) is a weaker bound than the threshold:
/// for the classical preset 43.9 against 54.6 rad/s (35 % low in energy).
#[test]
fn energy_bound_is_below_the_threshold() {
    for (name, top) in tops() {
        let w_e = inversion::energy_bound_spin(&top, G, 0.1);
        let w_c = inversion::initial_spin_for_threshold(&top, G, 0.1).unwrap();
        assert!(w_e < w_c, "{name}: {w_e} vs {w_c}");
        // At ω₀ = w_e the energy equals V_J(π) (its definition).
        let j = stability::jellett(&top, 0.1, 0.0, w_e);
        let e0 = 0.5 * top.inertia_axial * w_e * w_e + top.mass * G * top.height(0.1);
        let v_pi = inversion::potential(&top, G, &[], j, PI);
        assert!((e0 / v_pi - 1.0).abs() < 1e-13, "{name}: {e0} vs {v_pi}");
    }
}

fn classical_regularized(spin: f64) -> Scenario {
    let mut sc = Scenario::classical();
    sc.surface.friction = 0.3;
    sc.surface.law = tippetop::FrictionLaw::Regularized { eps: 0.1 };
    sc.initial.spin = spin;
    sc
}

/// Long runs with the regularised law end at the least-energy state of
/// their J: below the threshold at the interior minimum, above it at π.
/// (After 1 500 s the remaining nutation about the minimum is < 1e-7 rad
/// at these spins; the tolerance 1e-6 rad leaves a factor 10.)
#[test]
fn dissipating_top_ends_at_the_least_energy_state() {
    for w0 in [54.0, 54.5, 56.0, 70.0] {
        let mut sc = classical_regularized(w0);
        sc.solver.t_end = 1500.0;
        sc.solver.samples = 301;
        let tr = tippetop::simulate(&sc).unwrap();
        let end = tr.samples.last().unwrap();
        let th = inversion::final_theta(&sc.top, G, &[], end.jellett);
        assert!(
            (end.theta - th).abs() < 1e-6,
            "w0 {w0}: θ(1500 s) = {} vs least energy {th}",
            end.theta
        );
    }
}

/// Issue #16's known-answer case: `one = [π − δ, π]`, no force, a map over
/// the initial spin. The write succeeds exactly above the threshold, within
/// one grid cell (1 rad/s): full inversion needs θ = π stable at the spin
/// J gives there.
#[test]
fn a_map_over_the_initial_spin_puts_the_inversion_boundary_at_the_threshold() {
    let delta = 0.1;
    let top = Top::classical();
    let w_c = inversion::initial_spin_for_threshold(&top, G, 0.1).unwrap();
    let w_delta = inversion::initial_spin_threshold(&top, G, &[], 0.1, delta).unwrap();
    // θ* = π − δ is reached a little below the threshold (54.594 vs 54.638).
    assert!(w_delta < w_c && w_c - w_delta < 0.1, "{w_delta} {w_c}");
    let text = format!(
        "preset = \"classical\"\n\
         [surface]\nfriction = 0.3\nfriction_law = \"regularized\"\nfriction_eps = 0.1\n\
         [bit]\nzero = [0.0, 0.5]\none = [{}, {}]\nhold = 100.0\nphase = 1000.0\n\
         [solver]\nsamples = 2001\n",
        PI - delta,
        PI
    );
    let mut boundary = None;
    let mut prev = None;
    for w0 in (48..=62).map(f64::from) {
        let bs = BitScenario::load(None, Some(&text), &[format!("initial.spin={w0}")]).unwrap();
        let r = bit::run_one(&bs, 0);
        assert_eq!(r.status, "ok", "w0 {w0}");
        let ok = r.write.success();
        if prev == Some(false) && ok {
            boundary = Some(w0);
        }
        if let Some(p) = prev {
            assert!(!p || ok, "w0 {w0}: succeeds below a failure");
        }
        prev = Some(ok);
    }
    let b = boundary.expect("no boundary in 48..62 rad/s");
    assert!(
        b - 1.0 < w_c && w_c <= b && b - 1.0 < w_delta && w_delta <= b,
        "boundary cell ({}, {b}] vs threshold {w_c} (δ-window {w_delta})",
        b - 1.0
    );
}
