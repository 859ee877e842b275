//! Criterion benches of `collocation::solve_bvp` on two of scipy's test problems: the shock
//! layer (eps = 1e-3, tol 1e-3: 5 -> ~100 nodes, scipy's `test_shock_layer`) and the
//! boundary layer `y'' = 1e4 y` at tol 1e-6 (5 -> 345 nodes), and scipy's `big_problem`
//! (`n = 60` states, 5 nodes, separated boundary rows: the elimination and the buffers,
//! `docs/bvp20.md`).
//!
//! `cargo bench -p bvp-solvers --bench collocation`

use bvp_solvers::collocation::{solve_bvp, BvpOptions};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::f64::consts::PI;

fn linspace(a: f64, b: f64, m: usize) -> Vec<f64> {
    (0..m)
        .map(|i| a + (b - a) * i as f64 / (m - 1) as f64)
        .collect()
}

fn bench(c: &mut Criterion) {
    let x = linspace(-1.0, 1.0, 5);
    let y = vec![vec![0.0; 2]; 5];
    c.bench_function("collocation shock eps=1e-3 tol=1e-3", |b| {
        b.iter(|| {
            let sol = solve_bvp(
                |x, y, _, d| {
                    let eps = 1e-3;
                    d[0] = y[1];
                    d[1] = -(x * y[1] + eps * PI * PI * (PI * x).cos() + PI * x * (PI * x).sin())
                        / eps;
                },
                |ya, yb, _, r| {
                    r[0] = ya[0] + 2.0;
                    r[1] = yb[0];
                },
                black_box(&x),
                &y,
                &[],
                &BvpOptions::default(),
            )
            .unwrap();
            black_box(sol.x.len())
        })
    });
    let x = linspace(0.0, 1.0, 5);
    let opts = BvpOptions {
        tol: 1e-6,
        ..Default::default()
    };
    c.bench_function("collocation layer k=100 tol=1e-6", |b| {
        b.iter(|| {
            let sol = solve_bvp(
                |_, y, _, d| {
                    d[0] = y[1];
                    d[1] = 1e4 * y[0];
                },
                |ya, yb, _, r| {
                    r[0] = ya[0] - 1.0;
                    r[1] = yb[0];
                },
                black_box(&x),
                &y,
                &[],
                &opts,
            )
            .unwrap();
            black_box(sol.x.len())
        })
    });
    let y60 = vec![vec![0.0; 60]; 5];
    c.bench_function("collocation big_problem n=60 tol=1e-3", |b| {
        b.iter(|| {
            let sol = solve_bvp(
                |_, y, _, d| {
                    for i in 0..30 {
                        d[2 * i] = y[2 * i + 1];
                        d[2 * i + 1] = 0.0;
                    }
                },
                |ya, yb, _, r| {
                    for i in 0..30 {
                        r[i] = ya[2 * i];
                        r[30 + i] = yb[2 * i] - 1.0;
                    }
                },
                black_box(&x),
                &y60,
                &[],
                &BvpOptions::default(),
            )
            .unwrap();
            black_box(sol.x.len())
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
