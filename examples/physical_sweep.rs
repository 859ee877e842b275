//! A physical sweep from a scene file, and its contour reconstructed from the base
//! observables alone, through the facade `vibrissa` (no command-line types).
//!
//! ```sh
//! cargo run --release --example physical_sweep [SCENE.ron]
//! ```
//!
//! The scene defaults to `scenes/physical-beta-g1.ron` (a rat beta whisker, mm / N / N mm).
//! Every number is in the scene's units and equals what `vibrissa sweep` writes for the
//! same scene, bit for bit. The example checks itself: each reconstructed contact point
//! must lie on the sweep's own contact point (an independent route: the sweep solved the
//! contact, the reconstruction integrates from the logged base observables [6.5-6.9]).

use vibrissa::{Error, Scene};

/// The scene swept when none is given.
const DEFAULT_SCENE: &str = "scenes/physical-beta-g1.ron";

fn main() -> Result<(), Error> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| DEFAULT_SCENE.into());
    run(&path)
}

/// Sweeps the scene file `path`, reconstructs its log and checks the points.
fn run(path: &str) -> Result<(), Error> {
    let scene = Scene::load(path)?;
    let sweep = scene.sweep()?;
    let rows = sweep.rows();
    let (first, _) = sweep.first_contact();
    let (separation, _) = sweep.separation();
    println!(
        "{path}: {} rows, first contact {first:?}, separation {separation:?}",
        rows.len()
    );
    for row in rows.iter().step_by(25) {
        println!(
            "  x0 {:+.6}  Ax {:+.4e}  Ay {:+.4e}  MA {:+.4e}  phi0 {:.6}  phase {:?}",
            row.x0, row.ax, row.ay, row.ma, row.phi0, row.phase
        );
    }

    // Each reconstructed point carries its row's x0 exactly; rows where the contact force
    // is zero (first touch, release) look like the free whisker and give no point.
    let rec = scene.reconstruct(&sweep)?;
    let mut worst = 0.0f64;
    for p in &rec.rows {
        let row = rows
            .iter()
            .find(|r| r.x0 == p.x0)
            .expect("every point names a row of the sweep");
        worst = worst.max((p.x - row.xc).hypot(p.y - row.yc));
    }
    let contact = rows.iter().filter(|r| r.xc.is_finite()).count();
    println!(
        "reconstructed {} of {contact} contact rows, q = {:.6e}; worst distance to the sweep's contact points {worst:.3e}",
        rec.rows.len(),
        rec.q
    );
    assert!(rec.rows.len() + 2 >= contact, "rows lost");
    assert!(worst < 1e-6, "reconstruction off by {worst:e}");
    Ok(())
}

#[test]
fn example_checks_pass() {
    run(DEFAULT_SCENE).expect("the example's checks");
}
