//! Cross-check of the rigid-body model (quaternion, 3D Newton–Euler, contact
//! closure from the height of the geometric centre) against the reduced
//! Euler-angle model (the paper's equations): the two share no equations of
//! motion, only the scenario and the definitions of the outputs.

mod common;

use tippetop::{FrictionLaw, ModelKind, Scenario};

/// Every output agrees to 1e-6 of its scale (J: of C max|ω| R).
fn check(name: &str, sc: &Scenario) {
    common::crosscheck(name, sc, ModelKind::Reduced, ModelKind::Rigid, 1e-6);
}

/// Nano preset over the paper's 100 µs with the paper's constant force and
/// the paper's sliding Coulomb law.
#[test]
fn crosscheck_nano_paper_window() {
    let mut sc = Scenario::nano();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.rtol = 1e-12;
    check("nano", &sc);
}

/// Classical top over 0..0.04 s with sliding Coulomb friction (before the
/// first zero slip, so the law is smooth).
#[test]
fn crosscheck_classical_sliding_short() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.t_end = 0.04;
    sc.solver.rtol = 1e-12;
    check("classical 0.04 s", &sc);
}

/// Classical top over 10 s with the regularised law (ε = 1e-2 m/s): the
/// full inversion.
#[test]
fn crosscheck_classical_regularized_10s() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Regularized { eps: 1e-2 };
    sc.solver.rtol = 1e-12;
    check("classical 10 s regularized", &sc);
}
