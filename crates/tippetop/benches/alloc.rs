//! Heap allocations in the inner loop, counted with a global allocator
//! wrapper (not a criterion benchmark: it prints counts and exits non-zero
//! if the inner loop allocates).
//!
//! 1. `Reduced::eval` and `OdeSystem::rhs`, 1 000 000 calls each.
//! 2. `integrate::solve` (DOP853, rtol 1e-8) on the classical top with the
//!    regularised law, with the same three event functions the simulator
//!    uses (θ = π/2, θ maxima, N = 0), 1 001 samples pushed into a
//!    pre-sized vector and a no-op `on_step`: allocations counted between
//!    accepted step 100 (after warm-up) and the last step.
//! 3. `tippetop::simulate` of the same scenario as a whole (all allocations,
//!    with the number of steps): the fixed cost of a run.
//! 4. The vector model: `Vector::eval` and `OdeSystem::rhs` (1 000 000 calls
//!    each), and whole runs of 10 s and 20 s.
//!
//! `cargo bench -p tippetop --bench alloc`

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};

use tippetop::{
    FrictionLaw, Scenario,
    integrate::{self, Direction, Event, OdeSystem, Options, Stepper},
    model::reduced::{DIM, Reduced, TH, THD},
    simulate,
};

struct Counting;

static ALLOCS: AtomicU64 = AtomicU64::new(0);
static BYTES: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(layout.size() as u64, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(layout.size() as u64, Ordering::Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        BYTES.fetch_add(new_size as u64, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocs() -> u64 {
    ALLOCS.load(Ordering::Relaxed)
}

/// The regularised classical run with the Euler-angle model (the vector
/// model, the default since session 3, has its own section below).
fn scenario() -> Scenario {
    let mut sc = Scenario::classical();
    sc.solver.model = tippetop::ModelKind::Reduced;
    sc.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
    sc.solver.rtol = 1e-8;
    sc
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` runs this too.
    let sc = scenario();
    let mut failed = false;

    // 1. One evaluation.
    let mut m = Reduced::new(&sc);
    let y = m.scale_state(&sc.initial);
    let mut dy = [0.0; DIM];
    let n_eval = 1_000_000u64;
    let a0 = allocs();
    for _ in 0..n_eval {
        let e = black_box(&m).eval(black_box(&y)).expect("eval");
        black_box(e);
    }
    let a1 = allocs();
    for _ in 0..n_eval {
        m.rhs(0.0, black_box(&y), &mut dy).expect("rhs");
        black_box(&dy);
    }
    let a2 = allocs();
    println!(
        "Reduced::eval: {} allocations in {n_eval} calls; OdeSystem::rhs: {} allocations in {n_eval} calls",
        a1 - a0,
        a2 - a1
    );
    failed |= a2 != a0;

    // 2. integrate::solve, counted from accepted step 100 to the end.
    let mut m = Reduced::new(&sc);
    let t_end = sc.solver.t_end / m.scales.time;
    let ns = sc.solver.samples;
    let sample_times: Vec<f64> = (0..ns)
        .map(|i| t_end * i as f64 / (ns - 1) as f64)
        .collect();
    let opts = Options {
        stepper: Stepper::Dop853 {
            rtol: 1e-8,
            atol: 1e-8,
            beta: 0.0,
            stability_cap: false,
        },
        max_steps: 20_000_000,
        h0: None,
        h_max: Some(t_end / (ns - 1) as f64),
    };
    let events: Vec<Event<Reduced, DIM>> = vec![
        Event {
            g: Box::new(|_, _, y| y[TH] - std::f64::consts::FRAC_PI_2),
            direction: Direction::Rising,
            terminal: false,
            step_to_event: false,
        },
        Event {
            g: Box::new(|_, _, y| y[THD]),
            direction: Direction::Falling,
            terminal: false,
            step_to_event: false,
        },
        Event {
            g: Box::new(|m, _, y| m.eval(y).map(|e| e.normal).unwrap_or(f64::NAN)),
            direction: Direction::Either,
            terminal: false,
            step_to_event: false,
        },
    ];
    let mut samples: Vec<(f64, [f64; DIM])> = Vec::with_capacity(ns);
    let mut steps = 0u64;
    let mut at_warm = 0u64;
    let mut at_last = 0u64;
    let y0 = m.scale_state(&sc.initial);
    let out = integrate::solve(
        &mut m,
        &opts,
        0.0,
        y0,
        t_end,
        &[],
        &sample_times,
        &events,
        &mut |_, t, y| samples.push((t, *y)),
        &mut |_, _, _| {
            steps += 1;
            if steps == 100 {
                at_warm = allocs();
            }
            at_last = allocs();
        },
    )
    .expect("solve");
    let per_step = at_last - at_warm;
    println!(
        "integrate::solve (DOP853 rtol 1e-8, classical 10 s, regularised): {} allocations over accepted steps 100..{} ({} RHS evaluations, {} events fired, {} samples)",
        per_step,
        out.stats.steps,
        out.stats.rhs_evals,
        out.fired.len(),
        samples.len()
    );
    // The only allowed growth: the `fired` vector of event records
    // (amortised doubling, O(log events)).
    let allowed = 2 * (out.fired.len().max(1) as f64).log2().ceil() as u64 + 2;
    failed |= per_step > allowed;

    // 3. A whole simulate().
    let a0 = allocs();
    let tr = simulate(&sc).expect("simulate");
    let a1 = allocs();
    println!(
        "simulate (same scenario): {} allocations in total for {} accepted steps, {} RHS evaluations, {} samples, {} events",
        a1 - a0,
        tr.summary.steps,
        tr.summary.rhs_evaluations,
        tr.samples.len(),
        tr.events.len()
    );

    // 4. The vector model: eval and rhs, and whole runs of 10 s and 20 s
    //    (the fixed cost of a run must not grow with its length).
    {
        use tippetop::{ModelKind, model::vector::Vector};
        let mut sv = sc.clone();
        sv.solver.model = ModelKind::Vector;
        let mut m = Vector::new(&sv);
        let y = m.scale_state(&sv.initial);
        let mut dy = [0.0; tippetop::model::vector::DIM];
        let a0 = allocs();
        for i in 0..n_eval {
            let mut yi = y;
            yi[0] += 1e-12 * i as f64;
            black_box(m.eval(black_box(&yi)).ok());
            black_box(m.rhs(0.0, black_box(&yi), &mut dy).ok());
        }
        let a1 = allocs();
        println!(
            "Vector::eval + OdeSystem::rhs: {} allocations in {n_eval} calls each",
            a1 - a0
        );
        failed |= a1 != a0;
        for t_end in [10.0, 20.0] {
            let mut s2 = sv.clone();
            s2.solver.t_end = t_end;
            s2.solver.samples = 1001;
            let a0 = allocs();
            let tr = simulate(&s2).expect("simulate");
            let a1 = allocs();
            println!(
                "simulate (vector model, {t_end} s): {} allocations in total for {} accepted steps, {} events",
                a1 - a0,
                tr.summary.steps,
                tr.events.len()
            );
        }
    }

    if failed {
        eprintln!("FAIL: the inner loop allocates");
        std::process::exit(1);
    }
}
