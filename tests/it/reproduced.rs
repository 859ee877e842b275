//! Snapshots (insta) of the key reproduced numbers of the thesis, rounded: the tip of every
//! scenario's middle case (Tables 4.2/4.3 are in `xtask/tests/ansys.rs`), and the identification
//! and reconstruction quality of a chapter-6 case. Exact floats are checked elsewhere with
//! tolerances; these catch any drift in what the report shows.

use vibrissa::beam_model::{scenarios, solve, Method};
use vibrissa::contact_sim::{cases, sweep, SweepSettings};
use vibrissa::profile_recon::{contour_error, from_sweep, reconstruct, ReconSettings};

#[test]
fn scenario_tips() {
    let mut out = String::new();
    for sc in scenarios::all() {
        let c = &sc.cases[sc.cases.len() / 2];
        let s = solve(&c.scene, &Method::accurate()).unwrap();
        out.push_str(&format!(
            "{:>2} {:<36} tip ({:.6}, {:.6}) phi1 {:.6} MA {:.6}\n",
            sc.id, c.label, s.tip.x, s.tip.y, s.tip.phi, s.base.ma
        ));
    }
    insta::assert_snapshot!(out);
}

#[test]
fn chapter6_case_quality() {
    let mut out = String::new();
    for c in cases::chapter5().iter().filter(|c| c.case == "5") {
        let truth = sweep(
            &c.whisker,
            beam_model::FluidLoad { q: c.q, alpha: 0.0 },
            &c.profile,
            &SweepSettings {
                points: 40,
                ..Default::default()
            },
        )
        .unwrap();
        let rows = from_sweep(&truth);
        let rec = reconstruct(&c.whisker, &rows, None, &ReconSettings::default()).unwrap();
        let e = contour_error(&rec.points, &c.profile)
            .into_iter()
            .fold(0.0, f64::max);
        out.push_str(&format!(
            "{} {:<18} q={:.9} points={} max_e<1e-10: {}\n",
            c.profile_name,
            c.label,
            rec.identification.q,
            rec.points.len(),
            e < 1e-10
        ));
    }
    insta::assert_snapshot!(out);
}
