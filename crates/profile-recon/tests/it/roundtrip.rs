//! Round trips sweep -> observables -> reconstruction against the simulation's hidden truth.

use contact_sim::{cases, sweep, Phase, SweepSettings};
use profile_recon::{contour_error, from_sweep, reconstruct, ReconSettings};

#[test]
fn every_chapter5_case_round_trips_with_the_accurate_method() {
    let mut worst_e: f64 = 0.0;
    let mut worst_q: f64 = 0.0;
    for c in cases::chapter5() {
        let s = SweepSettings {
            points: 40,
            ..SweepSettings::default()
        };
        let truth = sweep(
            &c.whisker,
            beam_model::FluidLoad { q: c.q, alpha: 0.0 },
            &c.profile,
            &s,
        )
        .unwrap();
        let rows = from_sweep(&truth);
        let rec = reconstruct(&c.whisker, &rows, None, &ReconSettings::default())
            .unwrap_or_else(|e| panic!("case {} {} {}: {e}", c.case, c.profile_name, c.label));
        let dq = (rec.identification.q - c.q).abs();
        worst_q = worst_q.max(dq);
        assert!(dq < 1e-9, "case {} {}: dq = {dq:e}", c.case, c.label);
        // Every contact row with a force is reconstructed; a first tip contact with f = 0 looks
        // exactly like the flow alone and stays a pre-contact row.
        let with_force = truth
            .points
            .iter()
            .filter(|p| p.phase != Phase::None && p.f > 1e-9)
            .count();
        assert!(
            rec.points.len() >= with_force,
            "case {} {} {}",
            c.case,
            c.profile_name,
            c.label
        );
        let errs = contour_error(&rec.points, &c.profile);
        for (p, e) in rec.points.iter().zip(&errs) {
            let t = &truth.points[p.row];
            assert_eq!(p.x0, t.x0);
            // phases recovered, except exactly at a switch where both hold
            if (t.s1 - 1.0).abs() > 1e-6 && (t.phase == Phase::B) {
                assert_eq!(p.phase, Phase::B, "case {} {} x0={}", c.case, c.label, t.x0);
            }
            assert!(
                (p.x - t.xc).abs() < 1e-8,
                "case {} {} {}: x {} vs {}",
                c.case,
                c.profile_name,
                c.label,
                p.x,
                t.xc
            );
            worst_e = worst_e.max(*e);
        }
    }
    assert!(worst_e <= 1e-9, "max e = {worst_e:e}");
    eprintln!("worst e = {worst_e:e}, worst dq = {worst_q:e}");
}
