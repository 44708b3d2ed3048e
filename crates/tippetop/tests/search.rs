//! The protocol search's optimiser (`analysis::search::minimize_box`,
//! argmin's Nelder–Mead with restarts on the unit cube) on test problems
//! with known minima (issue #16: "the optimiser finds the optimum of a test
//! problem with a known minimum"), its budget, and its determinism.

use std::cell::Cell;

use tippetop::analysis::search::minimize_box;

/// A shifted, scaled quadratic bowl in 4 dimensions with its minimum inside
/// the box: found to 1e-6 in every coordinate.
#[test]
fn finds_the_minimum_of_a_quadratic_bowl() {
    let c = [0.3, -1.2, 7.5, 1e-3];
    let w = [1.0, 10.0, 0.01, 1e6];
    let mut f = |x: &[f64]| {
        x.iter()
            .zip(c.iter().zip(&w))
            .map(|(xi, (ci, wi))| wi * (xi - ci).powi(2))
            .sum::<f64>()
    };
    let lo = [-1.0, -2.0, 0.0, 0.0];
    let hi = [1.0, 2.0, 10.0, 2e-3];
    let o = minimize_box(&mut f, &lo, &hi, 7, 3000).unwrap();
    for i in 0..4 {
        let tol = 1e-6 * (hi[i] - lo[i]);
        assert!((o.x[i] - c[i]).abs() < tol, "x {:?} vs {c:?}", o.x);
    }
    assert!(o.value < 1e-10, "{}", o.value);
}

/// Rosenbrock's valley on [−2, 2]²: the minimum (1, 1) with f = 0.
#[test]
fn finds_the_minimum_of_rosenbrock() {
    let mut f = |x: &[f64]| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
    let o = minimize_box(&mut f, &[-2.0, -2.0], &[2.0, 2.0], 1, 4000).unwrap();
    assert!(
        (o.x[0] - 1.0).abs() < 1e-5 && (o.x[1] - 1.0).abs() < 1e-5,
        "{:?}",
        o.x
    );
    assert!(o.value < 1e-10, "{}", o.value);
}

/// A minimum outside the box: the answer is on the bound (x = 1 for
/// (x − 3)² on [0, 1], and the free coordinate at its own minimum).
#[test]
fn a_minimum_outside_the_box_lands_on_the_bound() {
    let mut f = |x: &[f64]| (x[0] - 3.0).powi(2) + (x[1] - 0.25).powi(2);
    let o = minimize_box(&mut f, &[0.0, 0.0], &[1.0, 1.0], 3, 2000).unwrap();
    assert_eq!(o.x[0], 1.0);
    assert!((o.x[1] - 0.25).abs() < 1e-6, "{:?}", o.x);
}

/// The budget bounds the evaluations, restarts spend what is left, and the
/// same seed gives the same bits; another seed restarts elsewhere.
#[test]
fn budget_restarts_and_determinism() {
    let calls = Cell::new(0usize);
    let mut f = |x: &[f64]| {
        calls.set(calls.get() + 1);
        // Two wells: a local one at 0.2 and the global one at 0.8.
        let a = (x[0] - 0.2).powi(2);
        let b = (x[0] - 0.8).powi(2) - 0.01;
        a.min(b) + (x[1] - 0.5).powi(2)
    };
    let o = minimize_box(&mut f, &[0.0, 0.0], &[1.0, 1.0], 11, 500).unwrap();
    assert!(
        o.evaluations <= 500 && calls.get() == o.evaluations,
        "{o:?}"
    );
    assert_eq!(o.evaluations, 500, "restarts spend the budget");
    assert!(o.starts > 1, "{o:?}");
    assert!((o.x[0] - 0.8).abs() < 1e-6, "global well not found: {o:?}");
    let mut g = |x: &[f64]| {
        let a = (x[0] - 0.2).powi(2);
        let b = (x[0] - 0.8).powi(2) - 0.01;
        a.min(b) + (x[1] - 0.5).powi(2)
    };
    let o2 = minimize_box(&mut g, &[0.0, 0.0], &[1.0, 1.0], 11, 500).unwrap();
    assert_eq!(o.x, o2.x);
    assert_eq!(o.value.to_bits(), o2.value.to_bits());
    assert!(minimize_box(&mut g, &[0.0], &[1.0], 1, 0).is_none());
}
