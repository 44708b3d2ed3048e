//! The counter-based random stream (`tippetop::random`): normals per
//! second on one core, as a Langevin step would draw them (6 normals: the
//! rigid model's 3 force and 3 torque components, one call per step), in
//! bulk (1 024 per call), one at a time (`Stream::normal`, which pays a whole
//! block for one normal), the uniforms alone and the raw Philox blocks (what
//! the normals cost beyond the generator). Throughput is reported in elements
//! (normals, uniforms or blocks) per second.
//!
//! `cargo bench -p tippetop --bench random`

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use tippetop::random::Stream;

fn bench(c: &mut Criterion) {
    let stream = Stream::new(0x5eed, 7);
    let mut g = c.benchmark_group("random");

    g.throughput(Throughput::Elements(6));
    let mut six = [0.0; 6];
    let mut step = 0u64;
    g.bench_function("normals_6_per_step", |b| {
        b.iter(|| {
            step += 1;
            stream.normals(black_box(step), &mut six);
            black_box(&six);
        })
    });

    g.throughput(Throughput::Elements(1024));
    let mut bulk = vec![0.0; 1024];
    g.bench_function("normals_1024_per_call", |b| {
        b.iter(|| {
            step += 1;
            stream.normals(black_box(step), &mut bulk);
            black_box(&bulk);
        })
    });
    g.bench_function("uniforms_1024_per_call", |b| {
        b.iter(|| {
            step += 1;
            stream.uniforms(black_box(step), &mut bulk);
            black_box(&bulk);
        })
    });

    g.throughput(Throughput::Elements(1));
    g.bench_function("normal_one_at_a_time", |b| {
        b.iter(|| {
            step += 1;
            black_box(stream.normal(black_box(step), 3))
        })
    });
    g.bench_function("philox_block", |b| {
        b.iter(|| {
            step += 1;
            black_box(stream.block(black_box(step), 0))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
