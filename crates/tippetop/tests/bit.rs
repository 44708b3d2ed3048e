//! The bit scenario (issue #16): the run built from `[bit]`, `[[write]]`,
//! `[[erase]]` (times, windows, the preset's force replaced), `--set` of
//! the new keys, and a run evaluated against its own rows.

use tippetop::analysis::bit::{self, Mode};
use tippetop::scenario::bit::BitScenario;

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

#[test]
fn run_results_follow_the_rows() {
    let bs = BitScenario::load(None, Some(FILE), &[]).unwrap();
    let traj = tippetop::simulate(&bs.scenario).unwrap();
    let r = bit::evaluate_run(&bs, 0, &traj);
    // The write judged on the rows directly: in `one` at every row of
    // [phase - hold, phase].
    let (phase, hold) = (1e-4, 2e-5);
    let one = bs.bit.one;
    let held = traj
        .samples
        .iter()
        .filter(|s| s.t >= phase - hold - 1e-12 && s.t <= phase + 1e-12)
        .all(|s| one[0] <= s.theta && s.theta <= one[1]);
    assert_eq!(r.write.success(), held);
    // Energy: work_applied at 100 us minus at 0.
    let at = |t: f64| {
        traj.samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-12)
            .unwrap()
            .work_applied
    };
    assert_eq!(r.write.energy, Some(at(phase) - at(0.0)));
    assert_eq!(r.erase.energy, Some(at(2.0 * phase) - at(phase)));
    if !r.write.success() {
        assert!(matches!(
            r.write.failure,
            Some(Mode::Left | Mode::NeverEntered | Mode::TooLate)
        ));
    }
    let rep = bit::report(&bs, std::slice::from_ref(&r), true);
    assert_eq!(rep.write.successes, usize::from(r.write.success()));
    assert_eq!(rep.erase_given_write.runs, usize::from(r.write.success()));
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
