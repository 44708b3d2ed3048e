//! Coulomb–Contensou friction (docs/physics.md#contensou): one evaluation of the
//! exact law (Gauss–Legendre over the contact disc, elliptic integrals by the
//! AGM) at a few ratios `d = |v|/(r_c |n_Z|)`, of the Padé form, and of the
//! stick test's gauge (a root-find on the law's limit curve), Hertz pressure.
//!
//! `cargo bench -p tippetop --bench contensou`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use tippetop::physics::contensou::{self, Pressure};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("contensou");
    for d in [1e-3, 0.3, 0.653, 2.0, 100.0] {
        g.bench_function(format!("exact_d_{d}"), |b| {
            b.iter(|| contensou::exact(Pressure::Hertz, black_box(d)))
        });
    }
    g.bench_function("pade_d_0.653", |b| {
        b.iter(|| contensou::pade(Pressure::Hertz, black_box(0.653)))
    });
    g.bench_function("gauge_exact", |b| {
        b.iter(|| contensou::gauge(Pressure::Hertz, false, black_box(0.3), black_box(0.2)))
    });
    g.bench_function("gauge_pade", |b| {
        b.iter(|| contensou::gauge(Pressure::Hertz, true, black_box(0.3), black_box(0.2)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
