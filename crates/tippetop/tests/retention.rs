//! `analysis::retention`: the Arrhenius fit on exact data (recovered to
//! rounding), its weights and Birge scaling, the extrapolation's interval,
//! bad input.

use tippetop::analysis::retention::{RatePoint, fit_arrhenius};
use tippetop::input::thermal::BOLTZMANN;

fn exact(nu: f64, e: f64, temps: &[f64], se: f64) -> Vec<RatePoint> {
    temps
        .iter()
        .map(|&t| RatePoint {
            temperature: t,
            rate: nu * (-e / (BOLTZMANN * t)).exp(),
            ln_rate_se: se,
        })
        .collect()
}

/// Rates that follow `ν e^{−E/kT}` exactly give back `E` and `ln ν` to
/// rounding, chi2 ≈ 0, and the rate at any temperature.
#[test]
fn exact_arrhenius_data_are_recovered() {
    let (nu, e) = (3e12, 0.8 * 1.602176634e-19);
    for temps in [&[400.0, 600.0][..], &[350.0, 420.0, 500.0, 700.0][..]] {
        let f = fit_arrhenius(&exact(nu, e, temps, 0.1)).unwrap();
        assert!((f.barrier / e - 1.0).abs() < 1e-10, "{}", f.barrier / e);
        assert!((f.ln_prefactor - nu.ln()).abs() < 1e-9);
        assert!((f.barrier_ev - 0.8).abs() < 1e-10);
        assert!(f.chi2 < 1e-12);
        let x = f.extrapolate(300.0);
        let want = nu * (-e / (BOLTZMANN * 300.0)).exp();
        assert!((x.rate / want - 1.0).abs() < 1e-8, "{}", x.rate / want);
        assert!(x.rate_ci95[0] < x.rate && x.rate < x.rate_ci95[1]);
        assert!((x.mean_time * x.rate - 1.0).abs() < 1e-15);
    }
}

/// The interval widens away from the data (the lever arm of `1/T`), and a
/// point off the line raises chi2 and scales the covariance (Birge ratio),
/// while with two points (dof 0) nothing is scaled.
#[test]
fn interval_and_birge_scaling() {
    let (nu, e) = (1e12, 0.5 * 1.602176634e-19);
    let pts = exact(nu, e, &[500.0, 600.0, 700.0], 0.1);
    let f = fit_arrhenius(&pts).unwrap();
    let near = f.extrapolate(600.0).ln_rate_se;
    let far = f.extrapolate(300.0).ln_rate_se;
    assert!(far > 3.0 * near, "{far} vs {near}");
    let mut off = pts.clone();
    off[1].rate *= 2.0;
    let g = fit_arrhenius(&off).unwrap();
    assert!(g.chi2 > 1.0, "{}", g.chi2);
    // Unscaled variance of the slope: S / Δ with the weights 1/se².
    let w = 100.0;
    let xs: Vec<f64> = [500.0, 600.0, 700.0]
        .iter()
        .map(|t| 1.0 / (BOLTZMANN * t))
        .collect();
    let (s, sx, sxx) = (
        3.0 * w,
        w * xs.iter().sum::<f64>(),
        w * xs.iter().map(|x| x * x).sum::<f64>(),
    );
    let unscaled = s / (s * sxx - sx * sx);
    let ratio = g.covariance[1][1] / unscaled;
    assert!(
        (ratio - g.chi2 / 1.0).abs() < 1e-9 * ratio,
        "{ratio} vs {}",
        g.chi2
    );
    let two = fit_arrhenius(&pts[..2]).unwrap();
    assert_eq!(two.dof, 0);
}

/// Bad points are input errors with the key `points` (the argument; not
/// an option of any command), the point and its field in words (no Rust
/// debug text), and the valid range; the ranges' ends are accepted.
#[test]
fn bad_rates_are_input_errors() {
    let one = exact(1e12, 1e-19, &[500.0], 0.1);
    let same = exact(1e12, 1e-19, &[500.0, 500.0], 0.1);
    let base = exact(1e12, 1e-19, &[500.0, 600.0], 0.1);
    let with = |f: fn(&mut RatePoint)| {
        let mut p = base.clone();
        f(&mut p[1]);
        p
    };
    for (pts, field) in [
        (one, ""),
        (same, ""),
        (with(|p| p.rate = 0.0), "point 1: rate: "),
        (with(|p| p.rate = f64::INFINITY), "point 1: rate: "),
        (with(|p| p.rate = 2e300), "point 1: rate: "),
        (with(|p| p.temperature = 1e308), "point 1: temperature: "),
        (with(|p| p.temperature = f64::NAN), "point 1: temperature: "),
        (with(|p| p.temperature = 5e-4), "point 1: temperature: "),
        (with(|p| p.ln_rate_se = 0.0), "point 1: ln_rate_se: "),
        (with(|p| p.ln_rate_se = 1.5), "point 1: ln_rate_se: "),
    ] {
        match fit_arrhenius(&pts) {
            Err(e @ tippetop::Error::Invalid { .. }) => {
                let msg = e.to_string();
                assert!(msg.starts_with(&format!("points: {field}")), "{msg}");
                assert!(!msg.contains("RatePoint"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
    }
    // The ends of the ranges are valid points.
    let mut ends = exact(1e12, 1e-19, &[1e-3, 1e5], 1.0);
    ends[0].rate = 1e-300;
    ends[1].rate = 1e300;
    assert!(fit_arrhenius(&ends).is_ok());
}

/// The extrapolation is checked: a target out of range or one whose rate
/// `f64` cannot hold (1e-3 K below a 1 eV barrier: `exp(-1.2e7)`) is an
/// input error naming the target's key; within range and finite it is the
/// unchecked value.
#[test]
fn extrapolation_beyond_f64_is_refused() {
    let e = 1.602176634e-19;
    let f = fit_arrhenius(&exact(1e12, e, &[500.0, 600.0], 0.1)).unwrap();
    for t in [1e-3, 1e308, 0.0, -1.0, f64::NAN] {
        match f.extrapolate_checked("--temperature", t) {
            Err(tippetop::Error::Invalid { key, .. }) => assert_eq!(key, "--temperature"),
            other => panic!("{t}: {other:?}"),
        }
    }
    assert_eq!(
        f.extrapolate_checked("--temperature", 300.0).unwrap(),
        f.extrapolate(300.0)
    );
}
