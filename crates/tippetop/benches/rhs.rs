//! One right-hand-side evaluation of the reduced model, as the integrator
//! makes it (`OdeSystem::rhs`, which always computes: `Reduced::eval` keeps
//! its last result and would return it for a repeated state), at typical
//! states: the classical top sliding (regularised law, t = 1 s),
//! the classical top rolling (exact law, after it sticks) and the nano top
//! (exact law, sliding, t = 50 µs). The states are taken from real runs.
//! `eval_cache_hit`: `Reduced::eval` at the state it last evaluated (what
//! the driver's diagnostics pay at a step end).
//!
//! `cargo bench -p tippetop --bench rhs`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use tippetop::{
    FrictionLaw, Initial, Scenario,
    integrate::OdeSystem,
    model::reduced::{DIM, Mode, Reduced},
    simulate,
};

/// The scaled state and model of `sc` at SI time `t` of a run of `sc`.
fn state_at(sc: &Scenario, t: f64, mode: Mode) -> (Reduced, [f64; DIM]) {
    let traj = simulate(sc).expect("valid scenario");
    let s = traj
        .samples
        .iter()
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        .expect("samples");
    let mut m = Reduced::new(sc);
    m.latch_force(t / m.scales.time);
    m.plane.mode = mode;
    let y = m.scale_state(&Initial {
        theta: s.theta,
        theta_dot: s.theta_dot,
        precession: s.precession,
        spin: s.spin,
        ux: s.ux,
        uy: s.uy,
        heading: 0.0,
    });
    (m, y)
}

fn bench_rhs(c: &mut Criterion) {
    let mut classical = Scenario::classical();
    classical.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
    classical.solver.rtol = 1e-8;
    classical.solver.t_end = 1.0;
    let (m_cl, y_cl) = state_at(&classical, 1.0, Mode::Sliding);

    let mut rolling = Scenario::classical();
    rolling.solver.t_end = 1.0;
    let (m_ro, y_ro) = state_at(&rolling, 1.0, Mode::Rolling);

    let nano = Scenario::nano();
    let (m_na, y_na) = state_at(&nano, 5e-5, Mode::Sliding);

    let mut g = c.benchmark_group("rhs");
    for (name, m, y) in [
        ("classical_regularized_sliding", &m_cl, &y_cl),
        ("classical_exact_rolling", &m_ro, &y_ro),
        ("nano_exact_sliding", &m_na, &y_na),
    ] {
        assert!(m.eval(y).is_ok(), "{name}: state not evaluable");
        let mut m = m.clone();
        let mut dy = [0.0; DIM];
        g.bench_function(name, |b| {
            b.iter(|| {
                let r = m.rhs(0.0, black_box(y), &mut dy);
                black_box(&r);
                black_box(&dy);
            })
        });
    }
    let _ = m_cl.eval(&y_cl);
    g.bench_function("classical_regularized_sliding_eval_cache_hit", |b| {
        b.iter(|| black_box(&m_cl).eval(black_box(&y_cl)).map(|e| e.dy))
    });
    g.finish();
}

/// The vector-form model's `OdeSystem::rhs` at the same three physical
/// states (the Euler-angle state converted with the precessing x along X).
fn bench_rhs_vector(c: &mut Criterion) {
    use tippetop::model::vector::{self, Vector};
    let mut classical = Scenario::classical();
    classical.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
    classical.solver.rtol = 1e-8;
    classical.solver.t_end = 1.0;
    let mut rolling = Scenario::classical();
    rolling.solver.t_end = 1.0;
    let nano = Scenario::nano();
    let mut g = c.benchmark_group("rhs_vector");
    for (name, sc, t, mode) in [
        (
            "classical_regularized_sliding",
            &classical,
            1.0,
            Mode::Sliding,
        ),
        ("classical_exact_rolling", &rolling, 1.0, Mode::Rolling),
        ("nano_exact_sliding", &nano, 5e-5, Mode::Sliding),
    ] {
        let (r, yr) = state_at(sc, t, mode);
        let mut m = Vector::new(sc);
        m.latch_force(t / m.scales.time);
        m.plane.mode = mode;
        let s = r.scales;
        let y = m.scale_state(&Initial {
            theta: yr[0],
            theta_dot: yr[1] / s.time,
            precession: yr[2] / s.time,
            spin: yr[3] / s.time,
            ux: yr[4] * s.velocity(),
            uy: yr[5] * s.velocity(),
            heading: 0.0,
        });
        assert!(m.eval(&y).is_ok(), "{name}: state not evaluable");
        let mut dy = [0.0; vector::DIM];
        g.bench_function(name, |b| {
            b.iter(|| {
                let r = m.rhs(0.0, black_box(&y), &mut dy);
                black_box(&r);
                black_box(&dy);
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_rhs, bench_rhs_vector);
criterion_main!(benches);
