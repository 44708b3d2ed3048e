//! Issue 26, "finite or failed": a run never reports `ok` with an output
//! row that holds a value that is not a finite number in any column. The
//! driver checks every row it records (every model, every command: `run`,
//! sweeps, ensembles, bit runs, `Simulation`, Python) and fails the run at
//! the first such row (`failure = "non_finite"` for a NaN), keeping the
//! rows before it. No input is known to produce such a row any more (the
//! vector model's attitude did, from spin × t ≈ 1.5e6 rad), so the check is
//! tested by planting a NaN in the `qw` column with
//! `tippetop::testing::plant_nan_row`, which is process-wide: the tests of
//! this binary take [`PLANT`] so that none runs while another has a NaN
//! planted.

use tippetop::analysis::{ensemble::Ensemble, sweep::Axis, sweep::Sweep};
use tippetop::{Error, Failure, ModelKind, Scenario, Simulation, simulate, testing};

/// Held by each test of this binary (the plant is process-wide).
static PLANT: std::sync::Mutex<()> = std::sync::Mutex::new(());

const LANGEVIN: &str = r#"preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
t_end = 1e-11
samples = 11
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 1
"#;

/// Check a trajectory that met the planted NaN at `at` \[s\]: failed with
/// `non_finite` at `at`, its rows those before `at`, all finite.
fn failed_at(tr: &tippetop::Trajectory, at: f64, what: &str) {
    match &tr.error {
        Some(Error::Runtime { t, kind, why }) => {
            assert_eq!(*kind, Failure::NonFinite, "{what}: {why}");
            assert_eq!(*t, at, "{what}: failed at {t} s");
            assert!(why.contains("column qw"), "{what}: {why}");
        }
        other => panic!("{what}: not a run-time failure: {other:?}"),
    }
    assert_eq!(tr.summary.failure, Some("non_finite"), "{what}");
    assert_ne!(tr.summary.status, "ok", "{what}");
    assert!(!tr.samples.is_empty(), "{what}: no rows kept");
    assert!(
        tr.samples.iter().all(|s| s.t < at && s.is_finite()),
        "{what}: a kept row is at or after the NaN, or not finite"
    );
    // The rows are evenly spaced from 0: those before `at` are all there.
    let last = tr.samples.last().unwrap().t;
    let dt = tr.samples[1].t - tr.samples[0].t;
    assert!(
        at - last <= dt * (1.0 + 1e-9),
        "{what}: rows end at {last} s"
    );
}

#[test]
fn a_planted_nan_row_fails_every_kind_of_run() {
    let _one_at_a_time = PLANT.lock().unwrap_or_else(|e| e.into_inner());
    // Classical top, 1 s, 1001 rows: the NaN from the row at 0.5 s.
    let mut sc = Scenario::classical();
    sc.solver.t_end = 1.0;
    let at = 0.5;
    // Without the plant every model's run is ok and finite (the reference).
    for m in [ModelKind::Reduced, ModelKind::Vector, ModelKind::Rigid] {
        sc.solver.model = m;
        let tr = simulate(&sc).unwrap();
        assert!(tr.error.is_none() && tr.samples.iter().all(|s| s.is_finite()));
    }
    testing::plant_nan_row(Some(at));
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        for m in [ModelKind::Reduced, ModelKind::Vector, ModelKind::Rigid] {
            sc.solver.model = m;
            let tr = simulate(&sc).unwrap();
            failed_at(&tr, at, &format!("{m:?}"));
            assert_eq!(tr.samples.len(), 500, "{m:?}");
            // Paused and resumed (`Simulation`): the same.
            let mut sim = Simulation::new(&sc).unwrap();
            sim.integrate_to(0.3).unwrap();
            assert!(sim.error().is_none());
            sim.integrate_to(1.0).unwrap();
            assert!(sim.is_finished());
            let tr2 = sim.into_trajectory();
            assert_eq!(tr2.samples, tr.samples, "{m:?}: Simulation");
            assert_eq!(tr2.summary.failure, Some("non_finite"));
        }
        // A NaN in the very first row (t = 0): no row kept, failed at 0.
        testing::plant_nan_row(Some(0.0));
        sc.solver.model = ModelKind::Vector;
        let tr = simulate(&sc).unwrap();
        assert!(tr.samples.is_empty());
        assert_eq!(tr.summary.failure, Some("non_finite"));
        testing::plant_nan_row(Some(at));
        // Sweep rows: each case failed, its status the error (a sweep's
        // runs compute no pose: the NaN is planted in `J`).
        let sweep = Sweep {
            preset: Some("classical".into()),
            toml_text: None,
            sets: vec!["solver.t_end=1".into()],
            axes: vec![Axis::parse("surface.friction=0.1:0.2:2").unwrap()],
        };
        let rows = sweep.run(0..2, Some(2), &|| {}).unwrap();
        for r in &rows {
            assert!(r.status.contains("became NaN in column J"), "{}", r.status);
            assert_eq!(r.summary.as_ref().unwrap().failure, Some("non_finite"));
        }
        // Ensemble rows (Langevin, t_end 1e-11 s): NaN from 5e-12 s.
        testing::plant_nan_row(Some(5e-12));
        let ens = Ensemble::new(None, Some(LANGEVIN.into()), Vec::new(), 2).unwrap();
        for i in 0..2 {
            let row = ens.run(i);
            assert!(
                row.status.contains("became NaN in column qw"),
                "{}",
                row.status
            );
            let finals = row.finals.expect("the rows before the NaN");
            assert!(finals.iter().all(|v| v.is_finite()));
            assert!(finals[0] < 5e-12);
        }
    }));
    testing::plant_nan_row(None);
    if let Err(e) = outcome {
        std::panic::resume_unwind(e);
    }
}

/// A run that fails at its start (a Painlevé case at t = 0: no consistent
/// normal force) writes the state there as its one row: N is undefined
/// (NaN, as docs/guide.md says of undefined values), the velocity and the
/// energy are not: `u_Z = a sin θ θ̇` and `E = ½ m |u|² + ½ A θ̇² + ½ C ω² +
/// m g (R − a cos θ)` (here Ω = 0 and the centre at rest horizontally).
/// Both were NaN in the vector and reduced models (`ux = (v·x̂)` read the
/// NaN `v_Z` through `0 × NaN`), found by `fuzz_cli`.
#[test]
fn the_row_at_a_painleve_start_has_its_velocity_and_energy() {
    let _one_at_a_time = PLANT.lock().unwrap_or_else(|e| e.into_inner());
    let mut sc = Scenario::classical();
    sc.top.mass = 1e3;
    sc.initial.theta_dot = -1e3;
    for m in [ModelKind::Reduced, ModelKind::Vector] {
        sc.solver.model = m;
        let tr = simulate(&sc).unwrap();
        assert_eq!(tr.summary.failure, Some("painleve"), "{m:?}");
        assert_eq!(tr.samples.len(), 1, "{m:?}");
        let s = &tr.samples[0];
        assert!(s.normal.is_nan(), "{m:?}: N = {}", s.normal);
        let (top, th, thd, w) = (
            &sc.top,
            sc.initial.theta,
            sc.initial.theta_dot,
            sc.initial.spin,
        );
        let uz = top.offset * th.sin() * thd;
        let e = 0.5 * top.mass * uz * uz
            + 0.5 * top.inertia_transverse * thd * thd
            + 0.5 * top.inertia_axial * w * w
            + top.mass * sc.surface.gravity * (top.radius - top.offset * th.cos());
        assert_eq!((s.ux, s.uy), (0.0, 0.0), "{m:?}");
        assert!(
            (s.uz - uz).abs() <= 1e-15 * uz.abs(),
            "{m:?}: uz {} vs {uz}",
            s.uz
        );
        assert!(
            (s.energy - e).abs() <= 1e-14 * e,
            "{m:?}: E {} vs {e}",
            s.energy
        );
    }
}
