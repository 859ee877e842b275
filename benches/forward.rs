//! Forward solves of the three reference scenes (`scenarios::reference_scenes`) by each
//! method: `forward/<method>/<scene>`; `auto` (accuracy on demand) at 1e-8 on the same
//! scenes, and a weak flow (q = 0.5 on a conical whisker on a spring, the regime of a
//! flow sensor) at 1e-4 and 1e-8: `forward/auto-1e-4/weak-flow`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use vibrissa::beam_model::{scenarios, solve, Loads, Method, Scene, Whisker};

fn forward(c: &mut Criterion) {
    let methods = [
        Method::accurate(),
        Method::Rk4 { n: 100 },
        Method::Fdm { n: 100 },
        Method::Auto {
            tol: 1e-8,
            samples: 100,
        },
    ];
    let weak = Scene::new(Whisker::new(0.5, 0.0, 0.0, 10.0), Loads::fluid(0.5, 0.0));
    for tol in [1e-4, 1e-8] {
        let method = Method::Auto { tol, samples: 100 };
        for (m, label) in [(method, "auto"), (Method::accurate(), "accurate")] {
            let id = format!("forward/{label}-{tol:e}/weak-flow");
            if label == "accurate" && tol > 1e-8 {
                continue;
            }
            c.bench_function(&id, |b| b.iter(|| solve(black_box(&weak), black_box(&m))));
        }
    }
    for method in methods {
        for (name, scene) in scenarios::reference_scenes() {
            // A scene that does not solve is a bug elsewhere; report it and skip the bench.
            if let Err(e) = solve(&scene, &method) {
                eprintln!("forward/{}/{name}: {e}", method.name());
                continue;
            }
            let label = match method {
                Method::Auto { tol, .. } => format!("auto-{tol:e}"),
                m => m.name().to_string(),
            };
            c.bench_function(&format!("forward/{label}/{name}"), |b| {
                b.iter(|| solve(black_box(&scene), black_box(&method)))
            });
        }
    }
}

criterion_group!(benches, forward);
criterion_main!(benches);
