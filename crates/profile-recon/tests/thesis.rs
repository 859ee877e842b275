//! Round trips of the thesis's method [6.5-6.10] on chapter-5 cases: sweep -> observables ->
//! reconstruction, against the contour and the simulation's hidden truth.

use contact_sim::{cases, sweep, Phase, SweepSettings};
use profile_recon::{contour_error, from_sweep, reconstruct, ReconMethod, ReconSettings};
use std::time::Instant;

fn case(name: &str, profile: &str, label: &str) -> cases::SweepCase {
    cases::chapter5()
        .into_iter()
        .find(|c| c.case == name && c.profile_name == profile && c.label == label)
        .unwrap_or_else(|| panic!("no case {name} {profile} {label}"))
}

#[test]
fn thesis_method_round_trips_at_the_fdm_level() {
    let thesis = ReconSettings {
        method: ReconMethod::Thesis,
        consistency_tol: None,
        ..ReconSettings::default()
    };
    for (name, profile, label) in [
        ("1", "g1", "q=5"),
        ("3", "g2", "k=10"),
        ("4B", "g2", "A=2 B=0"),
        ("2", "g1", "theta=0.5"),
    ] {
        let c = case(name, profile, label);
        let s = SweepSettings {
            points: 30,
            ..SweepSettings::default()
        };
        let truth = sweep(&c.whisker, c.q, &c.profile, &s).unwrap();
        let rows = from_sweep(&truth);
        let acc = reconstruct(&c.whisker, &rows, None, &ReconSettings::default()).unwrap();
        let t0 = Instant::now();
        let rec = reconstruct(&c.whisker, &rows, None, &thesis)
            .unwrap_or_else(|e| panic!("case {name} {profile} {label}: {e}"));
        let dt = t0.elapsed().as_secs_f64();
        assert_eq!(rec.identification.q, acc.identification.q);
        assert_eq!(rec.points.len(), acc.points.len());
        let e = contour_error(&rec.points, &c.profile);
        let e_acc = contour_error(&acc.points, &c.profile);
        let max_e = e.iter().copied().fold(0.0, f64::max);
        let max_acc = e_acc.iter().copied().fold(0.0, f64::max);
        let max_res = rec.points.iter().map(|p| p.residual).fold(0.0, f64::max);
        let its: usize = rec.points.iter().map(|p| p.evaluations).sum();
        let mut same = 0;
        let mut max_dx: f64 = 0.0;
        for (p, e) in rec.points.iter().zip(&e) {
            let t = &truth.points[p.row];
            let ok =
                p.phase == t.phase || (t.s1 - 1.0).abs() < 1e-6 && (t.phi1 - t.psi).abs() < 1e-6;
            if ok {
                same += 1;
            }
            max_dx = max_dx.max((p.x - t.xc).abs());
            eprintln!(
                "  row {:3} {:?}/{:?} x {:.6} e {:.2e} res {:.2e} it {} s1 {:.4}/{:.4}",
                p.row, p.phase, t.phase, p.x, e, p.residual, p.evaluations, p.s1, t.s1
            );
        }
        eprintln!(
            "case {name} {profile} {label}: {} points, max e {max_e:.2e} (accurate {max_acc:.2e}), max |dx| {max_dx:.2e}, max res {max_res:.2e}, phases {same}/{}, iterations {its}, {dt:.3} s",
            rec.points.len(),
            rec.points.len()
        );
    }
}
