//! The bit scenario (issue #16): the run built from `[bit]`, `[[write]]`,
//! `[[erase]]` (times, windows, the preset's force replaced), `--set` of
//! the new keys, and a run judged on its continuous solution.

use tippetop::analysis::bit::{self, Mode};
use tippetop::input::scenario::bit::BitScenario;

const FILE: &str = r#"preset = "nano"
[solver]
samples = 401
[bit]
hold = 2e-5
phase = 1e-4
[[write]]
hx = 1e-22
hy = 2e-22
start = 1e-5
stop = 3e-5
[[write]]
hz = 5e-23
[[erase]]
hx = -1e-22
start = 2e-5
"#;

#[test]
fn the_run_is_two_phases_with_the_protocols_as_force_windows() {
    let bs = BitScenario::load(None, Some(FILE), &[]).unwrap();
    let sc = &bs.scenario;
    assert_eq!(sc.solver.t_end, 2e-4);
    let w = &sc.forcing.windows;
    assert_eq!(w.len(), 3, "the preset's window is replaced: {w:?}");
    assert_eq!(
        (w[0].hx, w[0].hy, w[0].start, w[0].stop),
        (1e-22, 2e-22, 1e-5, 3e-5)
    );
    // Defaults: start 0, stop = phase.
    assert_eq!((w[1].hz, w[1].start, w[1].stop), (5e-23, 0.0, 1e-4));
    // The erase windows are shifted by one phase.
    assert_eq!(
        (w[2].hx, w[2].start, w[2].stop),
        (-1e-22, 1e-4 + 2e-5, 2e-4)
    );
    assert_eq!(bs.bit.zero, [0.0, 0.5]);
    let one = bs.bit.one;
    assert!((one[0] - (std::f64::consts::FRAC_PI_2 - 0.35)).abs() < 1e-15);
    // --set reaches the new keys, and appends a window.
    let sets = [
        "write.0.hy=3e-22".to_string(),
        "erase.1.hx=4e-22".to_string(),
        "bit.phase=2e-4".to_string(),
    ];
    let bs = BitScenario::load(None, Some(FILE), &sets).unwrap();
    let w = &bs.scenario.forcing.windows;
    assert_eq!(w[0].hy, 3e-22);
    assert_eq!((w[3].hx, w[3].start, w[3].stop), (4e-22, 2e-4, 4e-4));
    assert_eq!(bs.scenario.solver.t_end, 4e-4);
    // The run's scenario text is a plain scenario (no bit tables).
    let text = bs.scenario.to_toml_string();
    assert!(
        !text.contains("[bit]") && !text.contains("[[write]]"),
        "{text}"
    );
    assert_eq!(
        tippetop::Scenario::from_toml_str(&text).unwrap(),
        bs.scenario
    );
}

/// The bit judged on the continuous solution (events at the window edges
/// and the phases' ends), checked against what an independent reading of
/// the run says: the rows, the dense state at the switching time, and
/// other sample spacings.
#[test]
fn run_results_follow_the_continuous_solution() {
    let nano = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/bit/nano.toml"
    ))
    .unwrap();
    let bs = BitScenario::load(None, Some(&nano), &[]).unwrap();
    let (traj, stays) = tippetop::simulate_watching(&bs.scenario, &bit::watches(&bs)).unwrap();
    // Watching changes no step: the rows are simulate's, bit for bit.
    let plain = tippetop::simulate(&bs.scenario).unwrap();
    assert_eq!(traj.samples, plain.samples);
    let r = bit::evaluate_run(&bs, 0, &traj, &stays);
    let (phase, hold) = (bs.bit.phase, bs.bit.hold);
    let one = bs.bit.one;
    // The paper's write works (physics.md#bit): θ enters `one` through its
    // lower edge and stays.
    assert!(r.write.success(), "{r:?}");
    let ts = r.write.time.unwrap();
    // The rows agree: every row of the hold is in `one`, and the first row
    // of the last in-window run of rows is the first row at or after the
    // crossing (rows 0.1 us apart).
    let dt = phase * 2.0 / (bs.scenario.solver.samples - 1) as f64;
    let rows: Vec<(f64, f64)> = traj.samples.iter().map(|s| (s.t, s.theta)).collect();
    let inside = |th: f64| one[0] <= th && th <= one[1];
    assert!(
        rows.iter()
            .filter(|r| r.0 >= phase - hold - 1e-12 && r.0 <= phase + 1e-12)
            .all(|r| inside(r.1))
    );
    let last_out = rows
        .iter()
        .rposition(|r| r.0 <= phase + 1e-12 && !inside(r.1))
        .unwrap();
    let t_row = rows[last_out + 1].0;
    assert!(t_row - dt < ts && ts <= t_row, "{ts} vs row {t_row}");
    // θ at the switching time is the window's lower edge (a root of
    // θ − edge located on the dense output, to the root finder's tolerance).
    let mut sim = tippetop::Simulation::new(&bs.scenario).unwrap();
    sim.integrate_to(ts).unwrap();
    let theta = sim.state().theta;
    assert!((theta - one[0]).abs() < 1e-9, "theta(ts) = {theta}");
    // Energy: work_applied at the phase's ends (rows fall on 100 and 200 us).
    let at = |t: f64| {
        traj.samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-12)
            .unwrap()
            .work_applied
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    assert!(close(r.write.energy.unwrap(), at(phase) - at(0.0)));
    assert!(close(r.erase.energy.unwrap(), at(2.0 * phase) - at(phase)));
    // The erase fails by leaving `zero` (physics.md#bit): it came back to
    // θ ≈ 0.2 and fell again; the rows agree that it was in `zero` at some
    // row of the erase and is out at its end.
    assert_eq!(r.erase.failure, Some(Mode::Left), "{r:?}");
    let zero = bs.bit.zero;
    assert!(
        rows.iter()
            .any(|r| r.0 >= phase && zero[0] <= r.1 && r.1 <= zero[1])
    );
    // Independent of the sample spacing: with 10x fewer rows (still 10
    // per hold; the largest step is the row spacing, so the steps differ)
    // the switching time agrees to the solver's tolerance (rtol 1e-10),
    // where a test on the rows would move by up to a row spacing (1 us,
    // 2.5 % of the time).
    let coarse = BitScenario::load(None, Some(&nano), &["solver.samples=201".into()]).unwrap();
    let rc = bit::run_one(&coarse, 0);
    assert!(rc.write.success(), "{rc:?}");
    let tc = rc.write.time.unwrap();
    assert!((tc - ts).abs() < 1e-9 * ts, "{tc} vs {ts}");
    assert_eq!(rc.erase.failure, r.erase.failure);
    let rep = bit::report(&bs, std::slice::from_ref(&r), true);
    assert_eq!(rep.write.successes, 1);
    assert_eq!(rep.erase_given_write.runs, 1);
}

#[test]
fn bit_text_round_trips() {
    let nano = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/bit/nano.toml"
    ))
    .unwrap();
    let hot = [
        "solver.method=\"langevin\"",
        "solver.dt=1e-14",
        "surface.friction=0",
    ]
    .iter()
    .chain(&[
        "thermal.temperature=300",
        "thermal.damping_translational=1e11",
        "thermal.damping_rotational=1e11",
        "thermal.seed=3",
        "thermal.run=5",
        "bit.phase=1e-11",
        "bit.hold=2e-12",
        "bit.one=[0.9, 3.0]",
        "write.0.stop=5e-12",
        "erase.0.stop=5e-12",
        "erase.0.start=1e-12",
    ])
    .map(|s| s.to_string())
    .collect::<Vec<_>>();
    for (text, sets) in [
        (FILE, vec![]),
        (nano.as_str(), vec![]),
        (nano.as_str(), hot),
    ] {
        let bs = BitScenario::load(None, Some(text), &sets).unwrap();
        let again = bs.to_toml_string();
        assert!(!again.contains("[[force]]"), "{again}");
        let back = BitScenario::load(None, Some(&again), &[]).unwrap();
        assert_eq!(back, bs, "{again}");
        assert_eq!(back.to_toml_string(), again);
    }
}

/// The watch events never change a step, in every model and in a Langevin
/// run: the watched trajectory is the plain one bit for bit, and the
/// stochastic run's judgement agrees with its rows where the rows decide
/// (a Langevin path crosses its window edges many times).
#[test]
fn watching_changes_no_step_in_any_model() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/bit/");
    let nano = std::fs::read_to_string(format!("{root}nano.toml")).unwrap();
    let hot = std::fs::read_to_string(format!("{root}nano_300K.toml")).unwrap();
    let cases: [(&str, Vec<String>); 4] = [
        (&nano, vec!["solver.model=\"reduced\"".into()]),
        (&nano, vec!["solver.model=\"rigid\"".into()]),
        (
            &nano,
            vec![
                "bit.phase=2e-5".into(),
                "bit.hold=4e-6".into(),
                "write.0.stop=2e-5".into(),
                "erase.0.stop=2e-5".into(),
            ],
        ),
        (&hot, vec!["thermal.run=3".into()]),
    ];
    for (text, sets) in cases {
        let bs = BitScenario::load(None, Some(text), &sets).unwrap();
        let (watched, stays) =
            tippetop::simulate_watching(&bs.scenario, &bit::watches(&bs)).unwrap();
        let plain = tippetop::simulate(&bs.scenario).unwrap();
        assert_eq!(watched.samples, plain.samples, "{sets:?}");
        assert_eq!(watched.summary.steps, plain.summary.steps, "{sets:?}");
        let r = bit::evaluate_run(&bs, 0, &watched, &stays);
        // Necessary conditions the rows can check: success needs every row
        // of the hold inside; a row inside during the phase means the
        // phase was entered.
        for (p, w, t0) in [
            (&r.write, bs.bit.one, 0.0),
            (&r.erase, bs.bit.zero, bs.bit.phase),
        ] {
            let t1 = t0 + bs.bit.phase;
            let tol = 1e-9 * bs.bit.phase;
            let inside = |th: f64| w[0] <= th && th <= w[1];
            let phase_rows: Vec<_> = watched
                .samples
                .iter()
                .filter(|s| s.t >= t0 - tol && s.t <= t1 + tol)
                .collect();
            if p.success() {
                assert!(
                    phase_rows
                        .iter()
                        .filter(|s| s.t >= t1 - bs.bit.hold - tol)
                        .all(|s| inside(s.theta)),
                    "{sets:?}: {p:?}"
                );
            }
            if phase_rows.iter().any(|s| inside(s.theta)) {
                assert_ne!(p.failure, Some(Mode::NeverEntered), "{sets:?}");
            }
        }
        if text == hot {
            assert!(stays.iter().any(|s| s.crossings > 0), "{stays:?}");
        }
    }
}
