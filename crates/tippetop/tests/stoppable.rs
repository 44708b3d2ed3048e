//! `simulate::stoppable`: runs in progress end soon after the flag is set,
//! on the calling thread and on the workers of a sweep (the way Python's
//! Ctrl-C stops a long call within a second).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use tippetop::analysis::sweep::{Axis, Sweep};
use tippetop::simulate::stoppable;

/// The classical top spun at 1e7 rad/s for 10 s: millions of steps, about
/// a minute of integration.
const LONG: [&str; 2] = ["initial.spin=1e7", "solver.t_end=10"];

/// Set `flag` after `after`, from a thread of its own.
fn set_later(flag: &Arc<AtomicBool>, after: Duration) -> std::thread::JoinHandle<()> {
    let flag = flag.clone();
    std::thread::spawn(move || {
        std::thread::sleep(after);
        flag.store(true, Ordering::Relaxed);
    })
}

#[test]
fn a_run_ends_interrupted_soon_after_the_flag_is_set() {
    let sets: Vec<String> = LONG.iter().map(|s| s.to_string()).collect();
    let sc = tippetop::Scenario::load(Some("classical"), None, &sets).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let setter = set_later(&flag, Duration::from_millis(300));
    let start = Instant::now();
    let traj = stoppable(&flag, || tippetop::simulate(&sc)).unwrap();
    let took = start.elapsed();
    setter.join().unwrap();
    let err = traj.error.expect("the run ends failed").to_string();
    assert!(err.contains("interrupted"), "{err}");
    assert!(took < Duration::from_secs(5), "{took:?} to stop");
    assert!(traj.summary.steps > 0);
}

#[test]
fn a_sweep_stops_its_runs_in_progress() {
    let sw = Sweep {
        preset: Some("classical".into()),
        toml_text: None,
        sets: LONG.iter().map(|s| s.to_string()).collect(),
        axes: vec![Axis::parse("top.offset=3e-4:6e-3:4").unwrap()],
    };
    let flag = Arc::new(AtomicBool::new(false));
    let setter = set_later(&flag, Duration::from_millis(300));
    let start = Instant::now();
    let mut rows = 0;
    let complete = stoppable(&flag, || {
        sw.run_streaming(0..sw.total(), Some(2), &mut |row| {
            rows += 1;
            assert!(row.status.contains("interrupted"), "{}", row.status);
            !flag.load(Ordering::Relaxed)
        })
    })
    .unwrap();
    let took = start.elapsed();
    setter.join().unwrap();
    assert!(!complete);
    assert_eq!(rows, 1);
    assert!(took < Duration::from_secs(5), "{took:?} to stop");
}

#[test]
fn outside_stoppable_and_with_the_flag_down_a_run_is_the_same_bits() {
    let sets = vec!["solver.t_end=0.2".to_string()];
    let sc = tippetop::Scenario::load(Some("classical"), None, &sets).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let inside = stoppable(&flag, || tippetop::simulate(&sc)).unwrap();
    let outside = tippetop::simulate(&sc).unwrap();
    assert!(inside.error.is_none());
    assert_eq!(inside.samples, outside.samples);
    assert_eq!(inside.summary, outside.summary);
}

#[test]
fn a_run_integrated_in_pieces_shorter_than_a_check_ends_interrupted_too() {
    // The direct rare-event runs integrate 512 steps at a time: fewer
    // than the CHECK_EVERY steps between two looks inside a call.
    let sets = vec!["solver.t_end=10".to_string()];
    let sc = tippetop::Scenario::load(Some("classical"), None, &sets).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    let mut sim = tippetop::Simulation::new(&sc).unwrap();
    let step = 1e-4;
    let (mut t, mut pieces) = (0.0_f64, 0);
    stoppable(&flag, || {
        while !sim.is_finished() && t < 10.0 {
            pieces += 1;
            if pieces == 10 {
                flag.store(true, Ordering::Relaxed);
            }
            t = (t + step).min(10.0);
            sim.integrate_to(t).unwrap();
        }
    });
    assert_eq!(pieces, 10, "the run went on after the flag");
    let err = sim.error().expect("the run ends failed").to_string();
    assert!(err.contains("interrupted"), "{err}");
}
