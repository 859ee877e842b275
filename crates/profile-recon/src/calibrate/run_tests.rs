//! Unit tests of [`run`](super)'s starting values: the pre-contact rows, the start flow and
//! the start compliance on an exact log.

use super::super::residual::tip_force;
use super::super::test_log::exact;
use super::*;

#[test]
fn the_free_rows_give_the_start_flow() {
    let e = exact(4, 12);
    let pre = pre_contact(&e.log.rows, false);
    // the rows before contact, and the contact rows without force (at the first contact
    // and the separation), which have the free whisker's observables
    let (sa, ca) = e.flow.alpha.sin_cos();
    let model = Model::of(&e.truth);
    let force = |r: &ObservableRow| tip_force(&model, (e.flow.q * ca, e.flow.q * sa), r);
    let truth: Vec<bool> = e
        .kinds
        .iter()
        .zip(&e.log.rows)
        .map(|(k, r)| *k == RowKind::Pre || force(r) < 1e-9)
        .collect();
    assert_eq!(truth.iter().filter(|p| **p).count(), 6);
    assert_eq!(pre, truth);
    // the mean base forces of the free whisker are the flow's [6.1]
    let (qc, qs) = start_flow(&e.log, &pre);
    assert!((qc - e.flow.q * ca).abs() < 1e-9 && (qs - e.flow.q * sa).abs() < 1e-9);
    // a given q keeps the rows' direction
    let given = CalibLog {
        flow: KnownFlow {
            q: Some(3.0),
            alpha: None,
        },
        ..e.log.clone()
    };
    let (gc, gs) = start_flow(&given, &pre);
    assert!((gc - 3.0 * ca).abs() < 1e-9 && (gs - 3.0 * sa).abs() < 1e-9);
    // a given flow is the flow
    let fixed = CalibLog {
        flow: KnownFlow {
            q: Some(3.0),
            alpha: Some(-0.5),
        },
        ..e.log.clone()
    };
    assert_eq!(
        start_flow(&fixed, &pre),
        (3.0 * (-0.5f64).cos(), 3.0 * (-0.5f64).sin())
    );
}

#[test]
fn the_follicle_law_gives_the_start_compliance() {
    // every row of an exact log satisfies phi0 - pi/2 = -MA / k [3.21, 3.22] (k = 20)
    let e = exact(2, 12);
    let c = start_compliance(std::slice::from_ref(&e.log)).unwrap();
    assert!((c - 0.05).abs() < 1e-10, "{c}");
    // no moment, no compliance; a law of the wrong sign clamps at rigid
    let flat = |phi0: f64, ma: f64| CalibLog {
        rows: vec![ObservableRow {
            x0: 0.0,
            ax: 0.0,
            ay: 0.0,
            ma,
            phi0,
        }],
        ..e.log.clone()
    };
    assert_eq!(start_compliance(&[flat(1.6, 0.0)]), None);
    assert_eq!(start_compliance(&[flat(FRAC_PI_2 + 0.1, 1.0)]), Some(0.0));
}

/// The free whisker without flow is the row of zero reactions and moment at an end of the
/// motion, even where the contact branch leaves it without a kink of the slope and the
/// other end has one (docs/whisking-recon.md, "The no-flow disc scene").
#[test]
fn an_unloaded_end_row_is_the_free_whisker_without_flow() {
    // the contact branch linear from zero at the first end, a kink before the last row
    let mut rows: Vec<ObservableRow> = (0..12)
        .map(|i| {
            let t = i as f64;
            ObservableRow {
                x0: -0.1 * t,
                ax: -0.2 * t,
                ay: 0.01 * t * t,
                ma: 0.15 * t,
                phi0: 1.45 + 0.05 * t,
            }
        })
        .collect();
    let last = rows.last_mut().unwrap();
    last.ax += 0.8;
    last.ay += 0.9;
    for posed in [true, false] {
        let pre = pre_contact(&rows, posed);
        assert_eq!(
            pre.iter().position(|p| *p),
            Some(0),
            "posed {posed}: {pre:?}"
        );
        assert_eq!(pre.iter().filter(|p| **p).count(), 1);
    }
    // a start flow of zero from it
    let log = CalibLog {
        rows: rows.clone(),
        profile: contact_sim::Profile::g2(),
        flow: KnownFlow::default(),
        poses: Vec::new(),
    };
    assert_eq!(start_flow(&log, &pre_contact(&rows, true)), (0.0, 0.0));
}
