//! Cross-check of the rigid-body model (quaternion, 3D Newton–Euler, contact
//! closure from the height of the geometric centre) against the reduced
//! Euler-angle model (the paper's equations): the two share no equations of
//! motion, only the scenario and the definitions of the outputs.

use tippetop::{FrictionLaw, ModelKind, Sample, Scenario, Trajectory, simulate};

fn run(sc: &Scenario, model: ModelKind) -> Trajectory {
    let mut sc = sc.clone();
    sc.solver.model = model;
    let tr = simulate(&sc).expect("valid scenario");
    assert!(tr.error.is_none(), "{model:?} run failed: {:?}", tr.error);
    tr
}

/// Largest deviation of each quantity over the samples, relative to its
/// largest |value| over the window: [θ, Ω (where sin θ > 0.05), ω, u_x, u_y].
fn deviations(a: &[Sample], b: &[Sample]) -> [f64; 5] {
    assert_eq!(a.len(), b.len());
    let get: [fn(&Sample) -> f64; 5] = [
        |s| s.theta,
        |s| s.precession,
        |s| s.spin,
        |s| s.ux,
        |s| s.uy,
    ];
    let mut out = [0.0; 5];
    for (q, f) in get.iter().enumerate() {
        let ok = |s: &Sample| q != 1 || s.theta.sin() > 0.05;
        let scale = a
            .iter()
            .filter(|s| ok(s))
            .map(|s| f(s).abs())
            .fold(0.0, f64::max);
        let dev = a
            .iter()
            .zip(b)
            .filter(|(s, _)| ok(s))
            .map(|(x, y)| {
                assert_eq!(x.t, y.t);
                (f(x) - f(y)).abs()
            })
            .fold(0.0, f64::max);
        out[q] = dev / scale;
    }
    out
}

fn check(name: &str, sc: &Scenario) {
    let r = run(sc, ModelKind::Reduced);
    let g = run(sc, ModelKind::Rigid);
    let d = deviations(&r.samples, &g.samples);
    println!(
        "{name}: max rel deviation theta {:.2e} Omega {:.2e} omega {:.2e} ux {:.2e} uy {:.2e}",
        d[0], d[1], d[2], d[3], d[4]
    );
    for (q, v) in ["theta", "Omega", "omega", "ux", "uy"].iter().zip(d) {
        assert!(v <= 1e-6, "{name}: {q} deviates by {v:e} of its max");
    }
    // The other outputs are computed independently too.
    let e = r
        .samples
        .iter()
        .zip(&g.samples)
        .map(|(x, y)| (x.energy - y.energy).abs())
        .fold(0.0, f64::max)
        / r.samples.iter().map(|s| s.energy.abs()).fold(0.0, f64::max);
    // J is a small difference of large terms once ω has grown (nano: ω goes
    // from 100 to 2.7e7 rad/s while J stays C ω0 R cos θ0): its scale is
    // C max|ω| R, as in the summary's J_max_rel_drift.
    let jscale = sc.top.inertia_axial
        * sc.top.radius
        * r.samples.iter().map(|s| s.spin.abs()).fold(0.0, f64::max);
    let j = r
        .samples
        .iter()
        .zip(&g.samples)
        .map(|(x, y)| (x.jellett - y.jellett).abs())
        .fold(0.0, f64::max)
        / jscale;
    let n = r
        .samples
        .iter()
        .zip(&g.samples)
        .map(|(x, y)| (x.normal - y.normal).abs())
        .fold(0.0, f64::max)
        / r.samples.iter().map(|s| s.normal.abs()).fold(0.0, f64::max);
    println!("{name}: energy {e:.2e} J {j:.2e} N {n:.2e}");
    assert!(
        e <= 1e-6 && j <= 1e-6 && n <= 1e-6,
        "{name}: E {e:e} J {j:e} N {n:e}"
    );
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
