//! The whole chain through the facade: forward model in physical units, a sweep, the
//! observables alone, identification and reconstruction, against the simulation's truth.

use vibrissa::beam_model::{solve, Loads, Method, Preset, Scene, Support, TipForce, Whisker};
use vibrissa::contact_sim::{sweep, Phase, Profile, SweepSettings};
use vibrissa::profile_recon::{contour_error, from_sweep, reconstruct, ReconSettings};

#[test]
fn physical_units_round_trip_through_the_dimensionless_model() {
    let w = Preset::Beta.whisker();
    // Table 4.2, f = 1: the thesis's model gives x1 = 19.921 mm; the exact elastica
    // (Mattiasson 0.30172 L) gives 19.974 mm.
    let force_n = 1.0 * w.force_scale();
    let f = w.dimensionless_force(force_n);
    assert!((f - 1.0).abs() < 1e-14);
    let sol = solve(
        &Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(f, 0.0))),
        &Method::accurate(),
    )
    .unwrap();
    let x1_mm = w.length_of(sol.tip.x) * 1e3;
    assert!((x1_mm - 0.30172 * 66.2).abs() < 1e-3, "{x1_mm}");
    assert!((x1_mm - 19.921).abs() / 19.921 < 0.005);
}

#[test]
fn demo_scene_chain_recovers_flow_and_contour() {
    let w = Whisker {
        theta: 0.75,
        a: 0.0,
        b: 0.0,
        support: Support::Spring { k: 20.0 },
    };
    let g1 = Profile::g1();
    let truth = sweep(
        &w,
        beam_model::FluidLoad { q: 5.0, alpha: 0.0 },
        &g1,
        &SweepSettings {
            points: 60,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(truth.phase_pattern(), "ABA");
    let rows = from_sweep(&truth);
    let rec = reconstruct(&w, &rows, None, &ReconSettings::default()).unwrap();
    assert!((rec.identification.q - 5.0).abs() < 1e-12);
    let e = contour_error(&rec.points, &g1);
    assert!(
        e.iter().all(|&v| v < 1e-9),
        "max e = {:e}",
        e.iter().cloned().fold(0.0, f64::max)
    );
    // the hidden truth: contact force and s1 of each row
    for p in &rec.points {
        let t = &truth.points[p.row];
        assert!(
            (p.f - t.f).abs() < 1e-8 * (1.0 + t.f),
            "f {} vs {}",
            p.f,
            t.f
        );
        if t.phase == Phase::B && t.s1 < 1.0 - 1e-6 {
            assert!((p.s1 - t.s1).abs() < 1e-8);
        }
    }
    // The base angle is observed, so the follicle stiffness is not needed: a rigid whisker
    // model reconstructs the same contour.
    let rigid = Whisker {
        support: Support::Rigid,
        ..w
    };
    let rec_rigid = reconstruct(&rigid, &rows, None, &ReconSettings::default()).unwrap();
    for (a, b) in rec.points.iter().zip(&rec_rigid.points) {
        assert_eq!((a.x, a.y), (b.x, b.y));
    }
    // A wrong taper is detected as inconsistent, not silently used.
    let wrong = Whisker { theta: 0.7, ..w };
    assert!(reconstruct(&wrong, &rows, None, &ReconSettings::default()).is_err());
}
