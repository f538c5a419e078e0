//! Eigendecomposition + glyph derivation throughput on the grid40 demo field (64,000 tensors).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use tensorglyph::field::synthetic;
use tensorglyph::glyph::derive_glyphs;
use tensorglyph::tensor::eigen::{nalgebra_eigen, symmetric_eigen, symmetrise};

fn bench(c: &mut Criterion) {
    let field = synthetic::grid40();
    let n = field.len() as u64;
    let mut g = c.benchmark_group("grid40");
    g.throughput(Throughput::Elements(n));
    g.bench_function("derive_glyphs (parallel)", |b| {
        b.iter(|| {
            black_box(derive_glyphs(
                black_box(&field),
                &tensorglyph::progress::Silent,
            ))
        })
    });
    g.bench_function("symmetric_eigen Jacobi (1 thread)", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for t in field.tensors.iter() {
                let e = symmetric_eigen(&symmetrise(black_box(&t)).0);
                acc += e.values[0] + e.vectors[2][0];
            }
            black_box(acc)
        })
    });
    g.bench_function("nalgebra SymmetricEigen (1 thread, reference)", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for t in field.tensors.iter() {
                let e = nalgebra_eigen(&symmetrise(black_box(&t)).0);
                acc += e.values[0] + e.vectors[2][0];
            }
            black_box(acc)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
