//! The resumable driver (`Simulation`, issue #13 item 5): stepping to t1
//! then t2 gives the same run, bit for bit, as one run to t2; snapshot,
//! restore, continue equals an uninterrupted run; the state at a time is
//! the dense output there. Every case runs on every model it applies to and
//! covers the discrete changes a pause must not disturb: force switches,
//! stick/slip switches, the latched normal-force branch, flights and
//! impacts, failures part-way.

use tippetop::{ModelKind, Scenario, Simulation, Trajectory, simulate};

const MODELS: [ModelKind; 3] = [ModelKind::Reduced, ModelKind::Vector, ModelKind::Rigid];

fn scenario(path: &str) -> Scenario {
    let p = format!("{}/../../scenarios/{path}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(p).expect("scenario file");
    Scenario::from_toml_str(&text).expect("scenario")
}

/// The cases: (name, scenario), each also run with every model.
fn cases() -> Vec<(String, Scenario)> {
    let mut base: Vec<(&str, Scenario)> = vec![
        // 275 sign changes of N: the latched branch flips at each.
        ("nano", Scenario::nano()),
        // Exact Coulomb law: sliding, then stick (rolling).
        ("classical", Scenario::classical()),
        // A force switch, N < 0 half the time.
        ("fig06", scenario("fig06_reversal.toml")),
        // A force step that breaks rolling.
        ("fig14", scenario("fig14_step_1us.toml")),
    ];
    let mut rk4 = Scenario::nano();
    rk4.solver.method = tippetop::Method::Rk4;
    base.push(("nano_rk4", rk4));
    let mut stiff = Scenario::nano();
    stiff.solver.method = tippetop::Method::Stiff;
    stiff.solver.t_end = 20e-6;
    base.push(("nano_stiff", stiff));
    let mut out = Vec::new();
    for (name, sc) in base {
        for model in MODELS {
            let mut s = sc.clone();
            s.solver.model = model;
            out.push((format!("{name}/{model:?}"), s));
        }
    }
    // Flights and impacts (rigid model, unilateral contact).
    let mut fl = scenario("fig06_reversal.toml");
    fl.solver.model = ModelKind::Rigid;
    fl.surface.contact = tippetop::ContactMode::Unilateral;
    out.push(("fig06/rigid-unilateral".into(), fl));
    // A run that fails part-way (the sliding-only law chatters).
    let mut ch = Scenario::classical();
    ch.surface.law = tippetop::FrictionLaw::CoulombSliding;
    assert!(
        simulate(&ch).unwrap().error.is_some(),
        "the chatter case fails"
    );
    out.push(("classical-chatter/Vector".into(), ch));
    out
}

/// Bit-for-bit equality of two trajectories (`{:?}` prints every float
/// with the shortest representation that reads back to the same bits).
fn assert_same(name: &str, a: &Trajectory, b: &Trajectory) {
    assert_eq!(a.samples.len(), b.samples.len(), "{name}: sample count");
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert_eq!(format!("{x:?}"), format!("{y:?}"), "{name}: sample");
    }
    assert_eq!(
        format!("{:?}", a.events),
        format!("{:?}", b.events),
        "{name}: events"
    );
    assert_eq!(
        format!("{:?}", a.summary),
        format!("{:?}", b.summary),
        "{name}: summary"
    );
    assert_eq!(
        format!("{:?}", a.error),
        format!("{:?}", b.error),
        "{name}: error"
    );
}

#[test]
fn stepping_in_pieces_equals_one_run() {
    for (name, sc) in cases() {
        let whole = simulate(&sc).expect("valid");
        let t_end = sc.solver.t_end;
        // Uneven pieces: some inside steps, some on sample times, some
        // repeated.
        let mut sim = Simulation::new(&sc).expect("valid");
        for f in [0.0, 0.013, 0.013, 0.25, 0.5, 0.50001, 0.77, 0.999_999] {
            sim.integrate_to(f * t_end).expect("in range");
        }
        sim.integrate_to(t_end).expect("in range");
        assert!(sim.is_finished(), "{name}");
        assert_eq!(
            sim.error().map(|e| e.to_string()),
            whole.error.as_ref().map(|e| e.to_string()),
            "{name}"
        );
        assert_same(&name, &sim.into_trajectory(), &whole);
        // One call to t_end.
        let mut sim = Simulation::new(&sc).expect("valid");
        sim.integrate_to(t_end).expect("in range");
        assert_same(&name, &sim.into_trajectory(), &whole);
    }
}

#[test]
fn snapshot_restore_continue_equals_an_uninterrupted_run() {
    for (name, sc) in cases() {
        let whole = simulate(&sc).expect("valid");
        let t_end = sc.solver.t_end;
        let mut sim = Simulation::new(&sc).expect("valid");
        sim.integrate_to(0.6 * t_end).expect("in range");
        if whole.error.is_none() {
            // Paused, not finished, and the state is at the time asked for.
            assert!(!sim.is_finished(), "{name}");
            assert!((sim.time() - 0.6 * t_end).abs() <= 1e-15 * t_end, "{name}");
            assert!(
                (sim.state().t - 0.6 * t_end).abs() <= 1e-15 * t_end,
                "{name}"
            );
        }
        let snap = sim.snapshot();
        let at = sim.state();
        // Go on somewhere else first (to the end), then back.
        sim.integrate_to(t_end).expect("in range");
        sim.restore(&snap);
        assert_eq!(
            format!("{:?}", sim.state()),
            format!("{at:?}"),
            "{name}: state"
        );
        sim.integrate_to(0.8 * t_end).expect("in range");
        sim.integrate_to(t_end).expect("in range");
        assert_same(&name, &sim.into_trajectory(), &whole);
        // A second simulation restored from the snapshot.
        let mut other = Simulation::new(&Scenario::classical()).expect("valid");
        other.restore(&snap);
        other.integrate_to(t_end).expect("in range");
        assert_same(&name, &other.into_trajectory(), &whole);
    }
}

/// The state at a sample time is that sample (the same dense output), to
/// the rounding of converting the time to SI and back.
#[test]
fn state_at_sample_times_is_the_sample() {
    for (name, sc) in cases().into_iter().filter(|(n, _)| !n.contains("chatter")) {
        let whole = simulate(&sc).expect("valid");
        let mut sim = Simulation::new(&sc).expect("valid");
        let n = whole.samples.len();
        for k in [0, 1, n / 3, n / 2, n - 2, n - 1] {
            let s = whole.samples[k];
            sim.integrate_to(s.t).expect("in range");
            let got = sim.state();
            assert!((got.t - s.t).abs() <= 1e-15 * s.t.abs(), "{name}: t");
            // θ moves by |θ̇| dt over the time rounding (~1e-16 relative);
            // 1e-12 rad is far below any integration error here.
            assert!(
                (got.theta - s.theta).abs() <= 1e-12,
                "{name} sample {k}: theta {} vs {}",
                got.theta,
                s.theta
            );
            assert_eq!(got.rolling, s.rolling, "{name}: mode");
        }
    }
}

#[test]
fn integrate_to_rejects_bad_times() {
    let sc = Scenario::nano();
    let mut sim = Simulation::new(&sc).expect("valid");
    for t in [f64::NAN, f64::INFINITY, -1e-9, 2.0 * sc.solver.t_end] {
        let e = sim.integrate_to(t).expect_err("out of range");
        assert!(e.is_input(), "{t}");
        assert!(e.to_string().starts_with("t: "), "{e}");
    }
    sim.integrate_to(0.5 * sc.solver.t_end).expect("in range");
    let e = sim
        .integrate_to(0.25 * sc.solver.t_end)
        .expect_err("backwards");
    assert!(e.to_string().contains("last time integrated to"), "{e}");
    // Bad scenarios are rejected at `new`, as by `simulate`.
    let mut bad = Scenario::nano();
    bad.solver.t_end = -1.0;
    assert!(Simulation::new(&bad).is_err());
}

/// The observer sees every accepted step, in time order, for every model.
#[test]
fn observer_sees_every_accepted_step() {
    for model in MODELS {
        let mut sc = Scenario::classical();
        sc.solver.model = model;
        let whole = simulate(&sc).expect("valid");
        let mut sim = Simulation::new(&sc).expect("valid");
        let seen = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let s2 = seen.clone();
        sim.set_observer(move |s| s2.lock().unwrap().push(s.t));
        sim.integrate_to(sc.solver.t_end).expect("in range");
        let seen = seen.lock().unwrap();
        assert_eq!(seen.len() as u64, whole.summary.steps, "{model:?}");
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{model:?}: order");
        assert_eq!(
            *seen.last().unwrap(),
            sc.solver.t_end,
            "{model:?}: last step"
        );
    }
}

/// The user guide's Rust example (docs/guide.md, "From Rust") is the doc
/// test of `Simulation` (which `cargo test` runs), line for line.
#[test]
fn guide_example_is_the_doc_test() {
    let root = env!("CARGO_MANIFEST_DIR");
    let readme = std::fs::read_to_string(format!("{root}/../../docs/guide.md")).unwrap();
    let start = readme.find("```rust\n").expect("a rust block") + "```rust\n".len();
    let block: Vec<&str> = readme[start..]
        .split("\n```")
        .next()
        .unwrap()
        .lines()
        .collect();
    let src = std::fs::read_to_string(format!("{root}/src/simulate.rs")).unwrap();
    let doc: Vec<&str> = src
        .lines()
        .map(|l| l.trim_start())
        .filter_map(|l| l.strip_prefix("///"))
        .map(|l| l.strip_prefix(' ').unwrap_or(l))
        .collect();
    let at = doc.windows(block.len()).position(|w| w == block.as_slice());
    assert!(
        at.is_some(),
        "docs/guide.md's example not found in Simulation's doc test"
    );
}

/// A `Simulation` and its snapshots can move to another thread (a Python
/// binding releases the GIL while it runs; a sweep runs one per thread).
#[test]
fn simulation_is_send() {
    fn send<T: Send>() {}
    send::<Simulation>();
    send::<tippetop::Snapshot>();
    let mut sc = Scenario::nano();
    sc.solver.t_end = 1e-6;
    let mut sim = Simulation::new(&sc).expect("valid");
    let handle = std::thread::spawn(move || {
        sim.integrate_to(1e-6).expect("in range");
        sim.into_trajectory()
    });
    let tr = handle.join().expect("no panic");
    assert_same("thread", &tr, &simulate(&sc).expect("valid"));
}

/// `integrate_to_while` (Python's Ctrl-C, issue 26): stopped by its
/// callback every few thousand steps and called again each time, the run
/// is the uninterrupted run, bit for bit; the callback is asked every
/// `CHECK_EVERY` accepted steps (so a long call can be interrupted), the
/// run stands at an accepted step before the target each time it stops,
/// and a callback that always agrees stops nothing.
#[test]
fn interrupted_integration_continues_bit_for_bit() {
    let mut all_stops = 0;
    for (name, sc) in cases() {
        let whole = simulate(&sc).unwrap();
        let mut sim = Simulation::new(&sc).unwrap();
        let t_end = sc.solver.t_end;
        let mut stops = 0u64;
        let mut asked = 0u64;
        loop {
            let before = sim.time();
            let mut n = 0;
            let done = sim
                .integrate_to_while(t_end, &mut || {
                    n += 1;
                    asked += 1;
                    n < 3
                })
                .unwrap();
            if done {
                break;
            }
            stops += 1;
            assert!(sim.time() > before && sim.time() < t_end, "{name}");
            assert!(!sim.is_finished(), "{name}");
        }
        let steps = whole.summary.steps;
        // Stopped at every third question, each question after
        // CHECK_EVERY more steps (a segment's end may add one).
        assert!(
            asked >= steps / tippetop::simulate::CHECK_EVERY / 2,
            "{name}: {asked} questions for {steps} steps"
        );
        assert!(
            stops + 1 >= asked / 3 && stops <= asked / 3,
            "{name}: {stops} stops, {asked} questions"
        );
        assert_same(&name, &whole, &sim.into_trajectory());
        let mut free = Simulation::new(&sc).unwrap();
        assert!(free.integrate_to_while(t_end, &mut || true).unwrap());
        assert_same(&name, &whole, &free.into_trajectory());
        all_stops += stops;
    }
    assert!(
        all_stops >= 10,
        "{all_stops} stops: the cases are too short"
    );
}
