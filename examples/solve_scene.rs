//! One equilibrium of a scene file through the facade `vibrissa`: the tip and the base
//! observables in the scene's units, with the solver's error estimate.
//!
//! ```sh
//! cargo run --release --example solve_scene [SCENE.ron]
//! ```
//!
//! The scene defaults to `scenes/s18-combined-tapered-precurved-elastic.ron` (the thesis's
//! scenario 18: tip force and fluid load on a tapered, pre-curved whisker on a spring); the
//! first-order system [3.25] is solved by the scene's method, and every answer carries the
//! estimate of its error, which the example requires below 1e-6.

use vibrissa::{Error, Scene};

/// The scene solved when none is given.
const DEFAULT_SCENE: &str = "scenes/s18-combined-tapered-precurved-elastic.ron";

fn main() -> Result<(), Error> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| DEFAULT_SCENE.into());
    run(&path)
}

/// Solves the scene file `path` and prints its tip and base observables.
fn run(path: &str) -> Result<(), Error> {
    let scene = Scene::load(path)?;
    let sol = scene.solve()?;
    println!(
        "{path}: tip ({:.10}, {:.10}), phi1 {:.10}",
        sol.tip.x, sol.tip.y, sol.tip.phi
    );
    println!(
        "base: Ax {:.10e}  Ay {:.10e}  MA {:.10e}  phi0 {:.10}",
        sol.base.ax, sol.base.ay, sol.base.ma, sol.base.phi0
    );
    println!(
        "method {}, error estimate {:.2e}",
        sol.stats.method_used.name(),
        sol.stats.error_estimate
    );
    let est = sol.stats.error_estimate;
    assert!(est.is_finite() && est < 1e-6, "error estimate {est:e}");
    Ok(())
}

#[test]
fn example_checks_pass() {
    run(DEFAULT_SCENE).expect("the example's checks");
}
