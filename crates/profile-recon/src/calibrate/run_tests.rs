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
