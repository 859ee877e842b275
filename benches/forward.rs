//! Forward solves of the three reference scenes (`scenarios::reference_scenes`) by each
//! method: `forward/<method>/<scene>`. The target: one `accurate` solve of the
//! pre-curved combined-load scene in < 200 µs.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use vibrissa::beam_model::{scenarios, solve, Method};

fn forward(c: &mut Criterion) {
    let methods = [
        Method::accurate(),
        Method::Rk4 { n: 100 },
        Method::Fdm { n: 100 },
    ];
    for method in methods {
        for (name, scene) in scenarios::reference_scenes() {
            // A scene that does not solve is a bug elsewhere; report it and skip the bench.
            if let Err(e) = solve(&scene, &method) {
                eprintln!("forward/{}/{name}: {e}", method.name());
                continue;
            }
            c.bench_function(&format!("forward/{}/{name}", method.name()), |b| {
                b.iter(|| solve(black_box(&scene), black_box(&method)))
            });
        }
    }
}

criterion_group!(benches, forward);
criterion_main!(benches);
