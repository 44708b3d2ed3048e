//! The pose paid for only when read (issue #28 item 7): a run without the
//! pose (`simulate_with_pose(.., false, ..)`, the vector model's motion
//! alone, ten components; the reduced model's, eight) is the run with the pose less its pose columns,
//! bit for bit. The reason: the attitude's quadratures and the position are
//! outside the error norm and no other rate reads them
//! (`OdeSystem::CONTROLLED`'s contract), so the step sequence, the events
//! and every other column cannot depend on whether they are integrated.

use tippetop::trajectory::{COLUMNS, POSE_COLUMNS};
use tippetop::{Scenario, Simulation, Trajectory, simulate_with_pose};

/// The scenarios compared: both friction laws (the exact law's stick/slip
/// events included), an applied force schedule, the nano top, a Langevin
/// and a Brownian run.
fn cases() -> Vec<(&'static str, Scenario)> {
    let toml = |text: &str| Scenario::from_toml_str(text).unwrap();
    let thermal = "preset = \"nano\"\n[surface]\nfriction = 0.0\n\
        [thermal]\ntemperature = 300.0\ndamping_translational = 1e11\n\
        damping_rotational = 1e11\nseed = 1\n";
    vec![
        (
            "classical coulomb (stick/slip)",
            toml("preset = \"classical\"\n[solver]\nt_end = 6.0\n"),
        ),
        (
            "classical regularized",
            toml(
                "preset = \"classical\"\n[surface]\nfriction_law = \"regularized\"\n\
                 friction_eps = 1e-3\n[solver]\nrtol = 1e-8\nt_end = 3.0\n",
            ),
        ),
        (
            "classical with an applied force",
            toml(
                "preset = \"classical\"\n[[force]]\nhx = 2e-3\nhy = -7e-4\nstart = 0.5\n\
                 stop = 1.5\n[solver]\nt_end = 2.0\n",
            ),
        ),
        ("nano", toml("preset = \"nano\"\n[solver]\nt_end = 2e-5\n")),
        (
            "reduced classical coulomb (stick/slip)",
            toml("preset = \"classical\"\n[solver]\nmodel = \"reduced\"\nt_end = 6.0\n"),
        ),
        (
            "reduced nano",
            toml("preset = \"nano\"\n[solver]\nmodel = \"reduced\"\nt_end = 2e-5\n"),
        ),
        (
            "reduced classical regularized, stiff (Rodas4P)",
            toml(
                "preset = \"classical\"\n[surface]\nfriction_law = \"regularized\"\n\
                 friction_eps = 1e-3\n[solver]\nmodel = \"reduced\"\nmethod = \"stiff\"\nt_end = 1.0\n",
            ),
        ),
        (
            "vector classical rk4",
            toml(
                "preset = \"classical\"\n[solver]\nmethod = \"rk4\"\nsteps = 10000\nt_end = 1.0\n",
            ),
        ),
        (
            "langevin",
            toml(&format!(
                "{thermal}[solver]\nmethod = \"langevin\"\ndt = 1e-14\nt_end = 2e-12\nsamples = 51\n"
            )),
        ),
        (
            "brownian",
            toml(&format!(
                "{thermal}[solver]\nmethod = \"brownian\"\ndt = 2e-15\nt_end = 2e-13\nsamples = 51\n"
            )),
        ),
    ]
}

/// Every column of every row but the pose's, the events, the summary and
/// the error, as bits (NaN-safe).
fn motion_bits(tr: &Trajectory) -> (Vec<u64>, String) {
    let mut bits = Vec::new();
    for s in &tr.samples {
        for (c, v) in COLUMNS.iter().zip(s.values()) {
            if !POSE_COLUMNS.contains(c) {
                bits.push(v.to_bits());
            }
        }
    }
    let rest = format!(
        "{:?}\n{:?}\n{:?}",
        tr.events,
        tr.summary,
        tr.error.as_ref().map(|e| e.to_string())
    );
    (bits, rest)
}

#[test]
fn a_run_without_the_pose_is_the_run_with_it_less_the_pose_bit_for_bit() {
    for (name, sc) in cases() {
        let with = simulate_with_pose(&sc, true, &mut |_| {}).unwrap();
        let without = simulate_with_pose(&sc, false, &mut |_| {}).unwrap();
        assert!(with.error.is_none(), "{name}: {:?}", with.error);
        assert!(with.samples.len() > 10, "{name}");
        // The default run is the run with the pose.
        assert_eq!(
            motion_bits(&tippetop::simulate(&sc).unwrap()),
            motion_bits(&with),
            "{name}"
        );
        let (a, ra) = motion_bits(&with);
        let (b, rb) = motion_bits(&without);
        assert_eq!(a.len(), b.len(), "{name}: rows");
        if let Some(i) = a.iter().zip(&b).position(|(x, y)| x != y) {
            let cols = COLUMNS.len() - POSE_COLUMNS.len();
            panic!(
                "{name}: row {} column {} differs: {} against {}",
                i / cols,
                i % cols,
                f64::from_bits(a[i]),
                f64::from_bits(b[i])
            );
        }
        assert_eq!(ra, rb, "{name}: events, summary, error");
        // The pose: computed (finite) with it, NaN without it.
        for (s, t) in with.samples.iter().zip(&without.samples) {
            let (vs, vt) = (s.values(), t.values());
            for (i, c) in COLUMNS.iter().enumerate() {
                if POSE_COLUMNS.contains(c) {
                    assert!(vs[i].is_finite() && vt[i].is_nan(), "{name}: {c}");
                }
            }
        }
    }
}

/// The exact law's run has stick/slip switches, so the comparison above
/// covers the events' restarts (an independent check that the case does
/// what its name says).
#[test]
fn the_coulomb_case_sticks_and_slips() {
    let (_, sc) = &cases()[0];
    let tr = simulate_with_pose(sc, false, &mut |_| {}).unwrap();
    let kinds: Vec<&str> = tr.events.iter().map(|e| e.kind.as_str()).collect();
    assert!(kinds.contains(&"stick"), "{kinds:?}");
    assert!(tr.summary.rolling_fraction > 0.0);
}

/// Paused and resumed without the pose: the same rows as one call.
#[test]
fn a_simulation_without_the_pose_pauses_without_changing_a_bit() {
    let (_, sc) = &cases()[1];
    let whole = simulate_with_pose(sc, false, &mut |_| {}).unwrap();
    let mut sim = Simulation::with_pose(sc, false).unwrap();
    sim.integrate_to(1.0).unwrap();
    assert!(sim.state().qw.is_nan() && sim.state().theta.is_finite());
    sim.integrate_to(sc.solver.t_end).unwrap();
    assert_eq!(motion_bits(&sim.into_trajectory()), motion_bits(&whole));
}
