//! Reconstruction under sensor noise degrades gracefully: no failure, error growing with the
//! noise level.

use beam_model::Whisker;
use contact_sim::{sweep, Profile, SweepSettings};
use profile_recon::{from_sweep, noise_study};

#[test]
fn error_grows_with_noise_without_failures() {
    let w = Whisker::uniform();
    let truth = sweep(
        &w,
        beam_model::FluidLoad { q: 5.0, alpha: 0.0 },
        &Profile::g1(),
        &SweepSettings {
            points: 60,
            ..Default::default()
        },
    )
    .unwrap();
    let rows = from_sweep(&truth);
    let levels = [0.0, 1e-6, 1e-4, 1e-2];
    let res = noise_study(&w, &rows, 5.0, &Profile::g1(), &levels, 7).unwrap();
    for r in &res {
        eprintln!("{r:?}");
        assert!(r.points > 40, "{r:?}");
        assert!(r.max_error.is_finite());
    }
    assert!(res[0].max_error < 1e-9);
    // roughly proportional to the noise: within two decades of the level, growing with it
    for r in &res[1..] {
        assert!(r.median_error < 100.0 * r.level, "{r:?}");
    }
    assert!(res[1].median_error < res[2].median_error && res[2].median_error < res[3].median_error);
}
