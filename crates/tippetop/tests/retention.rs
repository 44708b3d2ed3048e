//! `analysis::retention`: the Arrhenius fit on exact data (recovered to
//! rounding), its weights and Birge scaling, the extrapolation's interval,
//! bad input.

use tippetop::analysis::retention::{RatePoint, fit_arrhenius};
use tippetop::thermal::BOLTZMANN;

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

#[test]
fn bad_rates_are_input_errors() {
    let one = exact(1e12, 1e-19, &[500.0], 0.1);
    let same = exact(1e12, 1e-19, &[500.0, 500.0], 0.1);
    let mut zero = exact(1e12, 1e-19, &[500.0, 600.0], 0.1);
    zero[0].rate = 0.0;
    for pts in [one, same, zero] {
        match fit_arrhenius(&pts) {
            Err(tippetop::Error::Invalid { key, .. }) => assert_eq!(key, "--rates"),
            other => panic!("{other:?}"),
        }
    }
}
