//! The stream mode gives the batch reconstruction's points, row by row, whatever the order of
//! the rows, with the flow given or identified from the first free row.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, Profile, SweepSettings};
use profile_recon::{from_sweep, reconstruct_with, KnownFlow, ReconPoint, ReconSettings, Streamer};

fn stream(rows: &[profile_recon::ObservableRow], w: &Whisker, known: KnownFlow) -> Vec<ReconPoint> {
    let mut s = Streamer::new(w, known, &ReconSettings::default()).unwrap();
    let mut out = Vec::new();
    for r in rows {
        out.extend(s.push(*r).unwrap());
    }
    out.extend(s.finish().unwrap());
    out
}

#[test]
fn stream_equals_batch_under_an_oblique_flow() {
    let w = Whisker::new(0.6, 0.0, 0.0, 20.0);
    let flow = FluidLoad { q: 3.0, alpha: 0.3 };
    let truth = sweep(
        &w,
        flow,
        &Profile::g2(),
        &SweepSettings {
            points: 30,
            ..Default::default()
        },
    )
    .unwrap();
    let rows = from_sweep(&truth);
    let batch =
        reconstruct_with(&w, &rows, KnownFlow::default(), &ReconSettings::default()).unwrap();
    assert!((batch.identification.q - 3.0).abs() < 1e-9);
    assert!((batch.identification.alpha - 0.3).abs().to_degrees() < 1e-7);
    assert!(batch.points.len() >= 25, "{}", batch.points.len());
    let mut reversed = rows.clone();
    reversed.reverse();
    let n = rows.len();
    for (name, input, known, index) in [
        (
            "given",
            rows.clone(),
            KnownFlow {
                q: Some(3.0),
                alpha: Some(0.3),
            },
            false,
        ),
        ("identified", rows.clone(), KnownFlow::default(), false),
        // reversed, flow given: every row decided on arrival
        (
            "reversed",
            reversed.clone(),
            KnownFlow {
                q: Some(3.0),
                alpha: Some(0.3),
            },
            true,
        ),
        // reversed, flow identified: every contact row comes before the free rows, held
        // until the first free row fixes the flow (issue #34: it failed on row 0 with "no
        // consistent contact point")
        ("reversed identified", reversed, KnownFlow::default(), true),
    ] {
        let pts = stream(&input, &w, known);
        assert_eq!(pts.len(), batch.points.len(), "{name}");
        for p in &pts {
            let row = if index { n - 1 - p.row } else { p.row };
            let b = batch
                .points
                .iter()
                .find(|b| b.row == row)
                .unwrap_or_else(|| panic!("{name}: row {row} not in the batch"));
            let t = &truth.points[row];
            let d = (p.x - b.x).hypot(p.y - b.y);
            assert!(d < 1e-10, "{name} row {row}: {d:e} from the batch point");
            assert!((p.x - t.xc).hypot(p.y - t.yc) < 1e-9, "{name} row {row}");
            // at a phase switch (s1 = 1 in phase B) both phases are right
            if (t.s1 - 1.0).abs() > 1e-6 {
                assert_eq!(p.phase, t.phase, "{name} row {row}");
            }
        }
    }
}
