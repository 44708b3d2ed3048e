//! Issue 12 (hardening): every input bounded, every run bounded. Regression
//! tests for the library side of defects 1, 2, 3, 7, 8 and 10.

use tippetop::{Error, Scenario, Trajectory, limits, simulate, simulate_with_progress};

fn sets(s: &[&str]) -> Vec<String> {
    s.iter().map(|x| x.to_string()).collect()
}

fn load(preset: &str, set: &[&str]) -> Result<Scenario, Error> {
    Scenario::load(Some(preset), None, &sets(set))
}

/// `set` on `preset` must be rejected as bad input naming `key`.
fn rejected(preset: &str, set: &[&str], key: &str) {
    match load(preset, set) {
        Err(Error::Invalid {
            key: k,
            what,
            range,
        }) => {
            assert_eq!(k, key, "{preset} {set:?}: {what} ({range})");
            assert!(!range.is_empty());
        }
        Err(e) => panic!("{preset} {set:?}: not an input error: {e}"),
        Ok(_) => panic!("{preset} {set:?}: accepted"),
    }
}

fn run(preset: &str, set: &[&str]) -> Trajectory {
    let sc = load(preset, set).unwrap_or_else(|e| panic!("{set:?}: {e}"));
    simulate(&sc).unwrap()
}

const MODELS: [&str; 3] = ["vector", "reduced", "rigid"];
const METHODS: [&str; 3] = ["adaptive", "rk4", "stiff"];

/// Defect 1: finite values that used to pass validation and then panicked
/// in the solver ("solve needs finite t0 <= t_end", "h_max ... inf") are
/// bad input, for every model and method, with the key to change.
#[test]
fn extreme_finite_values_are_input_errors_naming_the_key() {
    let cases: &[(&str, &str, &str)] = &[
        ("classical", "solver.t_end=1e308", "solver.t_end"),
        ("nano", "solver.t_end=1e308", "solver.t_end"),
        ("classical", "solver.t_end=1e20", "solver.t_end"),
        ("classical", "solver.t_end=1e-320", "solver.t_end"),
        ("classical", "surface.gravity=1e308", "surface.gravity"),
        ("classical", "top.mass=1e-320", "top.mass"),
        // The key that caused the overflow (issue 26): the mass makes the
        // applied force's rate sqrt(|H| / (m R)) infinite, the radius the
        // inertia unit m R^2.
        ("nano", "top.mass=1e-320", "top.mass"),
        ("nano", "top.radius=1e308", "top.radius"),
        ("classical", "top.radius=1e200", "top.radius"),
        ("classical", "top.mass=1e308", "top.mass"),
        ("classical", "initial.spin=1e308", "solver.t_end"),
        ("nano", "initial.spin=-1e308", "solver.t_end"),
        ("classical", "initial.theta_dot=1e308", "solver.t_end"),
        ("classical", "force.0.hx=1e308", "force.0.hx"),
        ("nano", "force.0.hy=-1e308", "force.0.hy"),
        (
            "classical",
            "top.inertia_transverse=1e308",
            "top.inertia_transverse",
        ),
        ("classical", "top.inertia_axial=1e-320", "top.inertia_axial"),
        ("classical", "initial.ux=1e200", "initial.ux"),
        ("nano", "initial.uy=1e308", "initial.uy"),
    ];
    for &(preset, set, key) in cases {
        for model in MODELS {
            for method in METHODS {
                let m = format!("solver.model={model}");
                let me = format!("solver.method={method}");
                let theta = "initial.theta=0.1";
                rejected(preset, &[set, &m, &me, theta], key);
            }
        }
    }
}

/// Defect 1: the bound on t_end / T_ref is stated in the message, with the
/// time unit and what sets it.
#[test]
fn t_end_bound_is_stated() {
    let e = load("classical", &["initial.spin=1e9"])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("solver.t_end: 10 s is 10000000000 time units"),
        "{e}"
    );
    assert!(e.contains("T_ref = 1/(|spin|)"), "{e}");
    assert!(e.contains("t_end <= 1e9 T_ref = 1 s"), "{e}");
    // Just inside the bound: valid.
    load("classical", &["initial.spin=1e8"]).unwrap();
}

/// Defect 2: `solver.samples` has an upper bound; the memory of a valid run
/// is within `MAX_RUN_BYTES`.
#[test]
fn samples_are_bounded_by_memory() {
    for n in ["1000000000", "4611686018427387904", "5000001"] {
        rejected(
            "classical",
            &[&format!("solver.samples={n}")],
            "solver.samples",
        );
    }
    let sc = load("classical", &["solver.samples=5000000"]).unwrap();
    let bytes = limits::run_memory_bytes(&sc.solver);
    assert!(bytes <= limits::MAX_RUN_BYTES, "{bytes}");
    // One row is the size of a Sample and its time: at most a few hundred bytes.
    const { assert!(limits::BYTES_PER_SAMPLE <= 256) };
}

/// Memory per sample is stated once, and correctly (issue 26: the README
/// said 144 bytes, the error message 216): a row is one `f64` per
/// trajectory.csv column but `rolling`, a `u8` padded to 8 (208 bytes),
/// plus its sample time and a stochastic run's ∫N dt (8 bytes each); the
/// user guide (docs/guide.md, "Limits") and the error message give that figure.
#[test]
fn bytes_per_sample_is_derived_from_the_row() {
    use tippetop::trajectory::COLUMNS;
    let row = (COLUMNS.len() - 1) * 8 + 8;
    assert_eq!(std::mem::size_of::<tippetop::Sample>(), row);
    assert_eq!(limits::BYTES_PER_SAMPLE, (row + 16) as u64);
    assert_eq!(limits::BYTES_PER_SAMPLE, 224);
    let readme = include_str!("../../../docs/guide.md");
    let stated = format!("{} bytes per output row", limits::BYTES_PER_SAMPLE);
    assert!(readme.contains(&stated), "docs/guide.md: {stated:?}");
    for wrong in ["144 bytes", "216 bytes"] {
        assert!(!readme.contains(wrong), "docs/guide.md still says {wrong}");
    }
    let e = load("classical", &["solver.samples=5000001"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("each row keeps 224 bytes in memory"), "{e}");
    // The largest run: 5e6 rows of 224 bytes (1.12 GB) and 100 000 events.
    let sc = load("classical", &["solver.samples=5000000"]).unwrap();
    let bytes = limits::run_memory_bytes(&sc.solver);
    assert!((1_120_000_000..1_140_000_000).contains(&bytes), "{bytes}");
}

/// How many runs fit at once in the memory bound (3 GiB): all asked for
/// when small; at 5e6 samples two (3 GiB / 1.12 GB = 2.9), one for 1.2 GB
/// besides; an error naming the key when not even one fits.
#[test]
fn threads_fit_the_memory_bound() {
    let sc = load("classical", &["solver.samples=5000000"]).unwrap();
    let big = limits::run_memory_bytes(&sc.solver);
    assert_eq!(limits::MEMORY_BUDGET, 3 * 1024 * 1024 * 1024);
    assert_eq!(limits::fit_threads("k", 64, big, 0).unwrap(), 2);
    assert_eq!(limits::fit_threads("k", 64, big, 1_200_000_000).unwrap(), 1);
    assert_eq!(limits::fit_threads("k", 1, big, 0).unwrap(), 1);
    assert_eq!(limits::fit_threads("k", 8, 1_000_000, 0).unwrap(), 8);
    let e = limits::fit_threads("solver.samples", 4, big, 2_500_000_000)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("solver.samples: needs 3.6"), "{e}");
    assert!(e.contains("at most 3.221 GB"), "{e}");
    // A sweep of such runs: two at once, whatever is asked.
    let sw = tippetop::analysis::sweep::Sweep {
        preset: Some("classical".into()),
        toml_text: None,
        sets: sets(&["solver.samples=5000000"]),
        axes: vec![tippetop::analysis::sweep::Axis::parse("top.offset=1e-3:2e-3:4").unwrap()],
    };
    assert_eq!(sw.max_samples(), 5_000_000);
    assert_eq!(sw.threads_within_memory(1024).unwrap(), 2);
    // Varied samples: the largest value counts.
    let sw = tippetop::analysis::sweep::Sweep {
        axes: vec![
            tippetop::analysis::sweep::Axis::parse("solver.samples=1001:4000001:3").unwrap(),
        ],
        sets: Vec::new(),
        ..sw
    };
    assert_eq!(sw.max_samples(), 4_000_001);
    assert_eq!(sw.threads_within_memory(1024).unwrap(), 3);
}

/// Defect 3: the step limit fires on every model and method, counted over
/// the whole run (every `solve` call), with exit-3 style error and the
/// message naming the limit (`solver.max_steps`).
#[test]
fn step_limit_fires_on_every_model_and_method() {
    for model in MODELS {
        for method in ["adaptive", "stiff"] {
            let m = format!("solver.model={model}");
            let me = format!("solver.method={method}");
            let tr = run("classical", &[&m, &me, "solver.max_steps=300"]);
            let e = tr
                .error
                .as_ref()
                .unwrap_or_else(|| panic!("{model} {method}"));
            let msg = e.to_string();
            assert!(!e.is_input());
            assert_eq!(e.failure(), Some(tippetop::Failure::StepLimit));
            assert!(
                msg.contains("step limit 300 reached (solver.max_steps"),
                "{msg}"
            );
            assert!(
                tr.summary.steps <= 300,
                "{model} {method}: {}",
                tr.summary.steps
            );
            // Coulomb already: no advice to switch to it.
            assert!(!msg.contains("try friction_law = \"coulomb\""), "{msg}");
        }
        // RK4: 1000 steps over the run, but three force switches off its
        // grid add a step each; a limit of 1000 stops it.
        let m = format!("solver.model={model}");
        let tr = run(
            "nano",
            &[
                &m,
                "solver.method=rk4",
                "solver.max_steps=1000",
                "force.1.start=1.23e-5",
                "force.1.stop=3.21e-5",
                "force.2.start=5.55e-5",
            ],
        );
        let msg = tr.error.as_ref().expect(model).to_string();
        assert!(msg.contains("step limit 1000 reached"), "{msg}");
        assert!(tr.summary.steps <= 1000);
    }
}

/// Defect 3: with many integration segments (force switches) the limit is
/// the run's, not each segment's.
#[test]
fn step_limit_counts_all_segments() {
    let mut s = vec!["solver.max_steps=400".to_string()];
    for k in 1..40 {
        s.push(format!("force.{k}.start={}", k as f64 * 2.5e-6));
        s.push(format!("force.{k}.stop={}", k as f64 * 2.5e-6 + 1e-6));
        s.push(format!("force.{k}.hx=1e-23"));
    }
    let refs: Vec<&str> = s.iter().map(String::as_str).collect();
    let tr = run("nano", &refs);
    assert!(tr.summary.steps <= 400, "{}", tr.summary.steps);
    assert!(tr.error.unwrap().to_string().contains("step limit 400"));
}

/// Defect 3: `solver.max_steps` has a documented range; RK4's steps must fit.
#[test]
fn max_steps_range() {
    for v in ["0", "-1", "1000000001", "1.5", "\"x\""] {
        rejected(
            "nano",
            &[&format!("solver.max_steps={v}")],
            "solver.max_steps",
        );
    }
    rejected(
        "nano",
        &["solver.method=rk4", "solver.max_steps=999"],
        "solver.steps",
    );
    let sc = load("nano", &["solver.max_steps=20000000"]).unwrap();
    assert_eq!(sc.solver.step_limit(), 20_000_000);
    // Defaults: 2e7, a tenth for the stiff method.
    assert_eq!(
        load("nano", &[]).unwrap().solver.step_limit(),
        limits::MAX_STEPS
    );
    assert_eq!(
        load("nano", &["solver.method=stiff"])
            .unwrap()
            .solver
            .step_limit(),
        limits::MAX_STEPS / 10
    );
    // Written back only when given.
    let text = load("nano", &["solver.max_steps=1234"])
        .unwrap()
        .to_toml_string();
    assert!(text.contains("max_steps = 1234"), "{text}");
    assert!(
        !load("nano", &[])
            .unwrap()
            .to_toml_string()
            .contains("max_steps")
    );
}

/// Defect 3: the progress callback reports the fraction of t_end done,
/// non-decreasing, in [0, 1], every PROGRESS_EVERY steps, with the time,
/// the step count and the spin there (issue 29: what a runaway warning
/// reads).
#[test]
fn progress_is_reported() {
    for model in MODELS {
        let m = format!("solver.model={model}");
        let sc = load("classical", &[&m, "solver.samples=40001"]).unwrap();
        let mut seen = Vec::new();
        let mut reports = Vec::new();
        let tr = simulate_with_progress(&sc, &mut |p| reports.push(*p)).unwrap();
        let t_end = sc.solver.t_end;
        let mut sim = tippetop::Simulation::new(&sc).unwrap();
        for (k, p) in reports.iter().enumerate() {
            // Every PROGRESS_EVERY-th accepted step, its time t = fraction
            // t_end, and the spin there between the run's extremes.
            assert_eq!(p.steps, (k as u64 + 1) * tippetop::simulate::PROGRESS_EVERY);
            assert!((p.t - p.fraction * t_end).abs() <= 1e-12 * t_end, "{p:?}");
            // The spin there: the same run paused at t reads it from the
            // dense output of the step that ends at t.
            sim.integrate_to(p.t).unwrap();
            let spin = sim.state().spin;
            assert!(
                (p.spin - spin).abs() <= 1e-9 * spin.abs(),
                "{p:?} vs {spin}"
            );
            seen.push(p.fraction);
        }
        assert!(tr.error.is_none());
        let expected = tr.summary.steps / tippetop::simulate::PROGRESS_EVERY;
        assert!(expected >= 2, "{model}: {}", tr.summary.steps);
        assert_eq!(seen.len() as u64, expected, "{model}");
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        assert!(seen.iter().all(|f| (0.0..=1.0).contains(f)), "{seen:?}");
    }
}

/// Defect 7a: a failed RK4 run of the reduced model still records the
/// events before its failure (θ passed π/2, N < 0).
#[test]
fn failed_run_keeps_its_events() {
    let tr = run(
        "nano",
        &[
            "solver.method=rk4",
            "solver.steps=500",
            "solver.samples=501",
            "solver.model=reduced",
            "surface.contact=paper",
            "surface.friction_law=coulomb_sliding",
        ],
    );
    assert!(tr.error.is_some());
    let kinds: Vec<&str> = tr.events.iter().map(|e| e.kind.as_str()).collect();
    assert!(kinds.contains(&"theta_above_half_pi"), "{kinds:?}");
    assert!(kinds.contains(&"contact_lost"), "{kinds:?}");
    let half = tr.summary.first_time_theta_above_half_pi.unwrap();
    let lost = tr.summary.contact_lost_at.unwrap();
    // The samples agree: θ > π/2 and N < 0 do occur in the rows after them.
    assert!(
        tr.samples
            .iter()
            .any(|s| s.t > half && s.theta > std::f64::consts::FRAC_PI_2)
    );
    assert!(tr.samples.iter().any(|s| s.t > lost && s.normal < 0.0));
    assert!(tr.summary.negative_normal_fraction > 0.0);
    // The RK4 blow-up is reported as such, not as the physics' Painlevé case.
    assert_eq!(tr.summary.failure, Some("unstable"));
    let msg = tr.error.unwrap().to_string();
    assert!(msg.contains("the RK4 solution became unstable"), "{msg}");
}

/// Defect 7b: the reduced model stops (exit 3) when θ passes π, as it does
/// at 0, instead of continuing with meaningless angles.
#[test]
fn reduced_model_stops_at_the_pole_at_pi() {
    let tr = run(
        "classical",
        &[
            "solver.model=reduced",
            "initial.spin=0",
            "initial.theta=3.0",
            "initial.theta_dot=5",
        ],
    );
    assert_eq!(tr.summary.failure, Some("pole"));
    let msg = tr.error.expect("must fail at theta = pi").to_string();
    assert!(msg.contains("pole of the Euler angles"), "{msg}");
    let pi = std::f64::consts::PI;
    assert!(tr.samples.iter().all(|s| s.theta > 0.0 && s.theta < pi));
    assert!(tr.summary.theta_max < pi);
    // θ rises at 5 rad/s from 3.0: π is reached after about 0.03 s.
    assert!(tr.summary.t_end < 0.2, "{}", tr.summary.t_end);
    // The vector model goes through the pole.
    let tr = run(
        "classical",
        &["initial.spin=0", "initial.theta=3.0", "initial.theta_dot=5"],
    );
    assert!(tr.error.is_none(), "{:?}", tr.error);
}

/// Defect 7c: a spin that makes every row NaN is bad input.
#[test]
fn spin_1e308_is_rejected() {
    for p in ["nano", "classical"] {
        rejected(p, &["initial.spin=1e308"], "solver.t_end");
    }
}

/// Defect 8: a Painlevé failure names the run's friction law.
#[test]
fn painleve_message_names_the_law() {
    let tr = run(
        "classical",
        &[
            "surface.friction_law=viscous",
            "surface.friction_eps=1e-3",
            "surface.friction=1e3",
            "solver.t_end=1",
        ],
    );
    let msg = tr.error.unwrap().to_string();
    assert!(msg.contains("Painleve paradox"), "{msg}");
    assert!(msg.contains("viscous friction"), "{msg}");
    assert!(!msg.contains("Coulomb"), "{msg}");
}

/// Defect 10: `--set solver.method=rk4` alone is valid on both presets
/// (steps defaults to samples - 1), and stays valid when samples changes.
#[test]
fn rk4_runs_on_both_presets() {
    for p in ["nano", "classical"] {
        let sc = load(p, &["solver.method=rk4"]).unwrap();
        assert_eq!(sc.solver.steps, sc.solver.samples - 1);
        let tr = simulate(&sc).unwrap();
        assert!(tr.error.is_none(), "{p}: {:?}", tr.error);
        let sc = load(p, &["solver.method=rk4", "solver.samples=201"]).unwrap();
        assert_eq!(sc.solver.steps, 200);
    }
}

/// Defect 8: an RK4 run whose fixed step is far too long blows up; that is
/// reported as such (it used to read as a Painlevé paradox at θ = π/2).
#[test]
fn rk4_blow_up_is_not_reported_as_painleve() {
    for (preset, samples) in [("classical", "51"), ("nano", "51")] {
        let tr = run(
            preset,
            &["solver.method=rk4", &format!("solver.samples={samples}")],
        );
        assert_eq!(tr.summary.failure, Some("unstable"), "{preset}");
        let msg = tr.error.expect(preset).to_string();
        assert!(
            msg.contains("the RK4 solution became unstable (energy balance error"),
            "{msg}"
        );
        assert!(msg.contains("raise solver.steps"), "{msg}");
    }
    // A failure whose balance is unknown still names the fixed step.
    let tr = run(
        "nano",
        &[
            "solver.method=rk4",
            "solver.samples=21",
            "solver.model=reduced",
        ],
    );
    // Not unstable: the kind is the failure's own.
    assert!(
        tr.summary.failure.is_some_and(|f| f != "unstable"),
        "{:?}",
        tr.summary.failure
    );
    let msg = tr.error.unwrap().to_string();
    assert!(msg.contains("method = \"rk4\" with a fixed step"), "{msg}");
}

/// The reduced model cannot start within its pole guard (|sin θ| < 1e-8):
/// that is bad input (it used to fail at t = 0 with exit 3); the vector
/// model starts there.
#[test]
fn reduced_model_rejects_a_start_at_the_pole_guard() {
    for theta in ["1e-9", "3.14159265", "3.141592653589793"] {
        rejected(
            "classical",
            &["solver.model=reduced", &format!("initial.theta={theta}")],
            "initial.theta",
        );
        load("classical", &[&format!("initial.theta={theta}")]).unwrap();
    }
    load("classical", &["solver.model=reduced", "initial.theta=2e-8"]).unwrap();
}
