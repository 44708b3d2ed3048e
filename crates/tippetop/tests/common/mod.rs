//! Scenarios shared by several test files.

use tippetop::{
    ForceWindow, Forcing, FrictionLaw, ModelKind, Sample, Scenario, Top, Trajectory, simulate,
};

/// A uniform sphere (a = 0, A = C = 2/5 m R², the classical preset's R and
/// m) with its axis tilted by `theta`, spinning at `spin` about it, on a
/// plane with friction `mu` under the exact Coulomb law; 0.4 s, 401 samples.
#[allow(dead_code)]
pub fn uniform_sphere(theta: f64, spin: f64, mu: f64) -> Scenario {
    let mut sc = Scenario::classical();
    let (m, r) = (sc.top.mass, sc.top.radius);
    sc.top = Top {
        radius: r,
        offset: 0.0,
        mass: m,
        inertia_transverse: 0.4 * m * r * r,
        inertia_axial: 0.4 * m * r * r,
    };
    sc.surface.friction = mu;
    sc.surface.law = FrictionLaw::Coulomb;
    sc.initial.theta = theta;
    sc.initial.spin = spin;
    sc.solver.t_end = 0.4;
    sc.solver.samples = 401;
    sc
}

/// Run `sc` with `model`; panics if the run fails.
#[allow(dead_code)]
pub fn run_as(sc: &Scenario, model: ModelKind) -> Trajectory {
    let mut sc = sc.clone();
    sc.solver.model = model;
    let tr = simulate(&sc).expect("valid scenario");
    assert!(tr.error.is_none(), "{model:?} run failed: {:?}", tr.error);
    tr
}

/// Largest deviation between two runs' samples of θ, Ω (where sin θ > 0.05),
/// ω, u_x, u_y, the energy and N, each relative to its largest |value| in
/// `a`, and of J relative to its natural scale `C max|ω| R` (J is a small
/// difference of large terms once ω has grown: nano ω goes from 100 to
/// 2.7e7 rad/s while J stays C ω0 R cos θ0), as in the summary's
/// `J_max_rel_drift`. Order: [θ, Ω, ω, u_x, u_y, E, J, N].
#[allow(dead_code)]
pub fn deviations(sc: &Scenario, a: &[Sample], b: &[Sample]) -> [f64; 8] {
    assert_eq!(a.len(), b.len());
    let get: [fn(&Sample) -> f64; 8] = [
        |s| s.theta,
        |s| s.precession,
        |s| s.spin,
        |s| s.ux,
        |s| s.uy,
        |s| s.energy,
        |s| s.jellett,
        |s| s.normal,
    ];
    let jscale =
        sc.top.inertia_axial * sc.top.radius * a.iter().map(|s| s.spin.abs()).fold(0.0, f64::max);
    let mut out = [0.0; 8];
    for (q, f) in get.iter().enumerate() {
        let ok = |s: &Sample| q != 1 || s.theta.sin() > 0.05;
        let scale = if q == 6 {
            jscale
        } else {
            a.iter()
                .filter(|s| ok(s))
                .map(|s| f(s).abs())
                .fold(0.0, f64::max)
        };
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

/// Names of the [`deviations`] entries.
#[allow(dead_code)]
pub const DEVIATION_NAMES: [&str; 8] = ["theta", "Omega", "omega", "ux", "uy", "E", "J", "N"];

/// Run `sc` with two models and assert every [`deviations`] entry is at
/// most `tol`; returns the two trajectories.
#[allow(dead_code)]
pub fn crosscheck(
    name: &str,
    sc: &Scenario,
    a: ModelKind,
    b: ModelKind,
    tol: f64,
) -> (Trajectory, Trajectory) {
    let ta = run_as(sc, a);
    let tb = run_as(sc, b);
    let d = deviations(sc, &ta.samples, &tb.samples);
    let list: Vec<String> = DEVIATION_NAMES
        .iter()
        .zip(d)
        .map(|(q, v)| format!("{q} {v:.2e}"))
        .collect();
    println!(
        "{name} ({a:?} vs {b:?}): max rel deviation {}",
        list.join(", ")
    );
    for (q, v) in DEVIATION_NAMES.iter().zip(d) {
        assert!(v <= tol, "{name}: {q} deviates by {v:e} (> {tol:e})");
    }
    (ta, tb)
}

/// The nano preset's force schedules used by the invariant tests: the
/// paper's constant force, a step switched off at 8 µs (App. D), and a
/// reversal at 60 µs.
#[allow(dead_code)]
pub fn nano_schedules() -> Vec<(&'static str, Forcing)> {
    let h = 1e-22;
    vec![
        ("constant", Forcing::constant(h, h)),
        (
            "step_t0_8us",
            Forcing {
                windows: vec![ForceWindow {
                    hx: 0.0,
                    hy: h,
                    hz: 0.0,
                    start: 0.0,
                    stop: 8e-6,
                }],
            },
        ),
        (
            "reversal_at_60us",
            Forcing {
                windows: vec![
                    ForceWindow {
                        hx: h,
                        hy: h,
                        hz: 0.0,
                        start: 0.0,
                        stop: 6e-5,
                    },
                    ForceWindow {
                        hx: -h,
                        hy: -h,
                        hz: 0.0,
                        start: 6e-5,
                        stop: f64::INFINITY,
                    },
                ],
            },
        ),
    ]
}
