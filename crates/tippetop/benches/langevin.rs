//! Langevin dynamics of the vector model (`solver.method = "langevin"`,
//! docs/physics.md#langevin), on one core, reported in steps per second:
//!
//! - `langevin_run`: whole runs in process (`tippetop::simulate`, no
//!   files) of 10 000 steps of 4 fs (40 ps, 41 samples, the
//!   `nano-physical` preset's density of samples):
//!   - `nano_physical`: the preset (C60 on graphene at 300 K: adhesion, the
//!     stem's lying well, γ_t = γ_r = 2.2e12 /s);
//!   - `nano_physical_contact`: the same with contact damping
//!     `thermal.damping_contact = 1e-13` N s/m (the coupled Ornstein–Uhlenbeck
//!     step, a 5×5 symmetric eigendecomposition per half step);
//!   - `simple`: the preset without adhesion and well (gravity and the
//!     applied force only), and `simple_contact` with contact damping;
//!   - `nano_physical_rigid`, `simple_rigid`: the same with the rigid
//!     model (its Langevin scheme in bilateral contact: the same
//!     Ornstein–Uhlenbeck step, RK4 of the 3D body with the contact
//!     constraint); whole runs only;
//! - `langevin_engine`: the same steps through `integrate::solve` alone (no
//!   samples, no events, no diagnostics): what the splitting costs without
//!   the driver;
//! - `langevin_parts`: the pieces of one step, each per step: the 10
//!   normals (`Stream::normals`, one call), the two half-step
//!   Ornstein–Uhlenbeck updates (`OdeSystem::thermostat` twice on one
//!   state, then the next state: the pattern of a run, where the second half
//!   of step n and the first half of step n + 1 see the same axis), and
//!   RK4's 4 evaluations of the right-hand side.
//!
//! `cargo bench -p tippetop --bench langevin`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use tippetop::{
    Adhesion, ModelKind, Scenario,
    integrate::{self, OdeSystem, Options, Stepper},
    model::vector::{DIM, Vector},
    random::Stream,
    simulate,
};

/// Steps per benchmarked run.
const STEPS: u64 = 10_000;

/// The `nano-physical` preset cut to [`STEPS`] steps of its 4 fs.
fn nano_physical() -> Scenario {
    let mut sc = Scenario::nano_physical();
    let dt = sc.solver.dt.expect("the preset has a step");
    sc.solver.t_end = STEPS as f64 * dt;
    sc.solver.samples = 41;
    sc
}

/// With contact damping (N s/m).
fn contact(mut sc: Scenario) -> Scenario {
    sc.thermal.damping_contact = 1e-13;
    sc
}

/// Without adhesion and wells.
fn simple() -> Scenario {
    let mut sc = nano_physical();
    sc.set_adhesion(Adhesion::NONE);
    sc.set_wells(&[]);
    sc
}

/// With the rigid model.
fn rigid(mut sc: Scenario) -> Scenario {
    sc.solver.model = ModelKind::Rigid;
    sc
}

fn check(sc: &Scenario) {
    let tr = simulate(sc).expect("valid scenario");
    assert!(tr.error.is_none(), "{:?}", tr.error);
}

/// The model at its initial state, its segment begun, and the engine's
/// options (scaled step, seed 1, run 0).
fn setup(sc: &Scenario) -> (Vector, [f64; DIM], Options, f64) {
    let mut m = Vector::new(sc);
    let h = sc.solver.dt.expect("a step") / m.scales.time;
    let t_end = STEPS as f64 * h;
    let y0 = m.scale_state(&sc.initial);
    m.begin_segment(0.0, &y0);
    let opts = Options {
        stepper: Stepper::Langevin {
            h,
            seed: sc.thermal.seed.unwrap_or(0),
            run: 0,
            first_step: 0,
        },
        max_steps: 10 * STEPS,
        h0: None,
        h_max: None,
    };
    (m, y0, opts, t_end)
}

/// `STEPS` steps through `integrate::solve` alone; the final state.
fn bare(m: &mut Vector, y0: [f64; DIM], opts: &Options, t_end: f64) -> [f64; DIM] {
    integrate::solve(
        m,
        opts,
        0.0,
        y0,
        t_end,
        &[],
        &[],
        &[],
        &mut |_, _, _| {},
        &mut |_, _, _| {},
    )
    .expect("bare Langevin solve")
    .y
}

fn cases() -> [(&'static str, Scenario); 4] {
    [
        ("nano_physical", nano_physical()),
        ("nano_physical_contact", contact(nano_physical())),
        ("simple", simple()),
        ("simple_contact", contact(simple())),
    ]
}

fn bench_runs(c: &mut Criterion) {
    let mut g = c.benchmark_group("langevin_run");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(STEPS));
    let rigid_cases = [
        ("nano_physical_rigid", rigid(nano_physical())),
        ("simple_rigid", rigid(simple())),
    ];
    for (name, sc) in cases().iter().chain(&rigid_cases) {
        check(sc);
        g.bench_function(*name, |b| b.iter(|| simulate(black_box(sc))));
    }
    g.finish();

    let mut g = c.benchmark_group("langevin_engine");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(STEPS));
    for (name, sc) in &cases() {
        let (m, y0, opts, t_end) = setup(sc);
        g.bench_function(*name, |b| {
            b.iter(|| {
                let mut m = m.clone();
                bare(&mut m, black_box(y0), &opts, t_end)
            })
        });
    }
    g.finish();
}

fn bench_parts(c: &mut Criterion) {
    let mut g = c.benchmark_group("langevin_parts");
    g.throughput(Throughput::Elements(1));

    // The 10 normals of a step, one call.
    let stream = Stream::new(1, 0);
    let mut xi = [0.0; 10];
    let mut step = 0u64;
    g.bench_function("normals_10", |b| {
        b.iter(|| {
            step += 1;
            stream.normals(black_box(step), &mut xi);
            black_box(&xi);
        })
    });

    for (name, sc) in &cases() {
        // Two states of a run (after 1 000 and 1 001 steps), so the axis
        // changes between the pairs of half steps as in a run.
        let (mut m, y0, opts, _) = setup(sc);
        let Stepper::Langevin { h, .. } = opts.stepper else {
            unreachable!()
        };
        let ya = bare(&mut m.clone(), y0, &opts, 1000.0 * h);
        let yb = bare(&mut m.clone(), y0, &opts, 1001.0 * h);
        let states = [ya, yb];
        let mut xi = [0.0; 10];
        stream.normals(7, &mut xi);
        let (first, second) = xi.split_at(5);
        let mut i = 0usize;
        g.bench_function(format!("ou_2_half_steps_{name}"), |b| {
            b.iter(|| {
                i += 1;
                let mut y = states[i & 1];
                m.thermostat(&mut y, black_box(0.5 * h), second);
                m.thermostat(&mut y, black_box(0.5 * h), first);
                black_box(y)
            })
        });
        // RK4's 4 evaluations, at 4 states with 4 different axes (four
        // states of the run, 1 000 … 1 003 steps), as RK4's stages have:
        // the wells' torque is cached on the axis bits, so 4 evaluations
        // at one state would measure one `atan2` instead of four.
        let lane_states: [[f64; DIM]; 4] =
            std::array::from_fn(|j| bare(&mut m.clone(), y0, &opts, (1000 + j) as f64 * h));
        let mut dy = [0.0; DIM];
        g.bench_function(format!("rhs_4_{name}"), |b| {
            b.iter(|| {
                for y in black_box(&lane_states) {
                    m.rhs(0.0, y, &mut dy).expect("rhs");
                    black_box(&dy);
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_runs, bench_parts);
criterion_main!(benches);
