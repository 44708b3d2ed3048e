//! A parameter sweep of short runs on 1 and 2 threads (rayon), at 100 and
//! 1 000 cases, with the Euler-angle (`reduced`) and the vector model, to
//! measure the parallel speed-up and whether the cost per case stays flat as
//! the number of cases grows: the pattern of `tippetop::analysis::sweep`
//! (independent `simulate` calls mapped over a grid with rayon) without its
//! CSV and plot output.
//!
//! Each case: the classical preset, 0.5 s, regularised law ε = 1e-3 m/s,
//! adaptive at rtol 1e-8, 101 samples, with θ0 and ω0 on a grid
//! (θ0 in [0.05, 1.5] rad, ω0 in [60, 200] rad/s).
//!
//! `cargo bench -p tippetop --bench sweep`

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use tippetop::{FrictionLaw, ModelKind, Scenario, simulate};

/// `n` cases on a 2D grid of (θ0, ω0) covering the same ranges for every n.
fn cases(n: usize, model: ModelKind) -> Vec<Scenario> {
    let side = (n as f64).sqrt().ceil() as usize;
    (0..n)
        .map(|k| {
            let (i, j) = (k / side, k % side);
            let fi = i as f64 / (side - 1).max(1) as f64;
            let fj = j as f64 / (side - 1).max(1) as f64;
            let mut sc = Scenario::classical();
            sc.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
            sc.solver.rtol = 1e-8;
            sc.solver.t_end = 0.5;
            sc.solver.samples = 101;
            sc.solver.model = model;
            sc.initial.theta = 0.05 + 1.45 * fi;
            sc.initial.spin = 60.0 + 140.0 * fj;
            sc
        })
        .collect()
}

/// Run all cases; returns the sum of final θ (so nothing is optimised away).
fn run_all(cases: &[Scenario]) -> f64 {
    cases
        .par_iter()
        .with_max_len(1)
        .map(|sc| simulate(sc).map_or(f64::NAN, |t| t.summary.theta_final))
        .sum()
}

fn bench_sweep(c: &mut Criterion) {
    let mut g = c.benchmark_group("sweep");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(15));
    for (name, model) in [
        ("reduced", ModelKind::Reduced),
        ("vector", ModelKind::Vector),
    ] {
        for n in [100usize, 1000] {
            let cs = cases(n, model);
            g.throughput(Throughput::Elements(n as u64));
            for threads in [1usize, 2] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("thread pool");
                g.bench_with_input(
                    BenchmarkId::new(format!("{name}_{threads}_threads"), n),
                    &cs,
                    |b, cs| b.iter(|| pool.install(|| run_all(black_box(cs)))),
                );
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench_sweep);
criterion_main!(benches);
