//! Whole runs, in process (`tippetop::simulate`, no output files):
//!
//! - the classical preset, 10 s, adaptive DOP853 at rtol 1e-8, with the
//!   regularised law (ε = 1e-3 m/s) and with the exact Coulomb law;
//! - the classical preset, 10 s, RK4 (the paper's 500 steps blow up): the
//!   exact law on 100 000 steps (dt = 1e-4 s); the regularised law on
//!   1 000 000 steps (dt = 1e-5 s: at 100 000 steps it blows up at 2.96 s,
//!   at 200 000 it stays finite but wrongly inverts, at 500 000 θ(10 s) is
//!   off by 7e-4 rad);
//! - the nano preset, 100 µs, adaptive at rtol 1e-10 (Euler angles, vector
//!   form, rigid body);
//! - `bare_solve`: the regularised classical run through `integrate::solve`
//!   alone (same options, no samples, no events, no diagnostics), to measure
//!   what the driver's diagnostics and events cost;
//!
//! The paper's reproduction as a whole is benchmarked in the
//! `tippetop-paper` crate (`cargo bench -p tippetop-paper`).
//!
//! `cargo bench -p tippetop --bench simulate`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use tippetop::{
    FrictionLaw, Method, ModelKind, Scenario,
    integrate::{self, Options, Stepper},
    model::reduced::{DIM, Reduced},
    simulate,
};

/// The classical preset at rtol 1e-8 with the given law, Euler-angle
/// model (the cases without the `_vector` suffix; the default model is the
/// vector form since session 3).
pub fn classical(law: FrictionLaw) -> Scenario {
    let mut sc = Scenario::classical();
    sc.solver.model = ModelKind::Reduced;
    sc.surface.law = law;
    sc.solver.rtol = 1e-8;
    sc
}

/// The same scenario with the vector-form model.
fn vector(mut sc: Scenario) -> Scenario {
    sc.solver.model = ModelKind::Vector;
    sc
}

fn regularized() -> FrictionLaw {
    FrictionLaw::Regularized { eps: 1e-3 }
}

fn rk4(law: FrictionLaw, steps: usize) -> Scenario {
    let mut sc = classical(law);
    sc.solver.method = Method::Rk4;
    sc.solver.steps = steps;
    sc
}

fn check(sc: &Scenario) {
    let tr = simulate(sc).expect("valid scenario");
    assert!(tr.error.is_none(), "{:?}", tr.error);
}

/// The regularised classical run through `integrate::solve` only.
fn bare_solve(sc: &Scenario) -> [f64; DIM] {
    let mut m = Reduced::new(sc);
    let t_end = sc.solver.t_end / m.scales.time;
    let opts = Options {
        stepper: Stepper::Dop853 {
            rtol: sc.solver.rtol,
            atol: sc.solver.rtol,
            beta: 0.0,
            stability_cap: false,
        },
        max_steps: 20_000_000,
        h0: None,
        h_max: Some(t_end / (sc.solver.samples - 1) as f64),
    };
    let y0 = m.scale_state(&sc.initial);
    integrate::solve(
        &mut m,
        &opts,
        0.0,
        y0,
        t_end,
        &[],
        &[],
        &[],
        &mut |_, _, _| {},
        &mut |_, _, _| {},
    )
    .expect("bare solve")
    .y
}

fn bench_runs(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulate");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(5));
    let cases = [
        (
            "classical_10s_regularized_rtol1e-8",
            classical(regularized()),
        ),
        (
            "classical_10s_coulomb_rtol1e-8",
            classical(FrictionLaw::Coulomb),
        ),
        (
            "classical_10s_rk4_100k_coulomb",
            rk4(FrictionLaw::Coulomb, 100_000),
        ),
        (
            "classical_10s_rk4_1M_regularized",
            rk4(regularized(), 1_000_000),
        ),
        ("nano_100us_rtol1e-10", {
            let mut sc = Scenario::nano();
            sc.solver.model = ModelKind::Reduced;
            sc
        }),
        (
            "classical_10s_regularized_rtol1e-8_vector",
            vector(classical(regularized())),
        ),
        (
            "classical_10s_coulomb_rtol1e-8_vector",
            vector(classical(FrictionLaw::Coulomb)),
        ),
        ("nano_100us_rtol1e-10_vector", vector(Scenario::nano())),
        ("nano_100us_rtol1e-10_rigid", {
            let mut sc = Scenario::nano();
            sc.solver.model = ModelKind::Rigid;
            sc
        }),
    ];
    for (name, sc) in &cases {
        check(sc);
        g.bench_function(*name, |b| b.iter(|| simulate(black_box(sc))));
    }
    // The same runs without the pose (`simulate_with_pose(.., false, ..)`:
    // the on-plane models integrate the motion alone, the same bits in
    // every other column; docs/performance.md#pose).
    for (name, sc) in cases
        .iter()
        .filter(|(n, _)| !n.contains("rk4") && !n.contains("rigid"))
    {
        g.bench_function(format!("{name}_nopose"), |b| {
            b.iter(|| tippetop::simulate_with_pose(black_box(sc), false, &mut |_| {}))
        });
    }
    let sc = classical(regularized());
    g.bench_function("classical_10s_regularized_rtol1e-8_bare_solve", |b| {
        b.iter(|| bare_solve(black_box(&sc)))
    });
    g.finish();
}

criterion_group!(benches, bench_runs);
criterion_main!(benches);
