//! `tippetop_paper::reproduce` as a whole (every run, figure and claim of the
//! paper, default options; no output files).
//!
//! `cargo bench -p tippetop-paper --bench reproduce`

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use tippetop_paper::{Options, reproduce};

fn bench_reproduce(c: &mut Criterion) {
    let mut g = c.benchmark_group("reproduce");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    g.bench_function("paper_reproduce", |b| {
        b.iter(|| reproduce(Options::default(), &mut |_| {}).expect("reproduce"))
    });
    g.finish();
}

criterion_group!(benches, bench_reproduce);
criterion_main!(benches);
