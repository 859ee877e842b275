//! The frictional stream (`FrictionalStreamer`) against the batch frictional reconstruction
//! (`reconstruct_frictional`) on contact-sim's frictional sweeps: what a row gives on its own
//! (the point, s1, the phase, a phase-B row's force split) equal row by row; a tip contact's
//! `ft` (causal tangent) within its error estimates of the batch's and of the truth; the end
//! of the stream the batch's answer (points, slip states, mu with its standard error).

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, ContactLaw, Phase, Profile, SweepResult, SweepSettings};
use profile_recon::stream::STREAM_NOISE;
use profile_recon::{
    from_sweep, reconstruct_frictional, FrictionalPoint, FrictionalStreamer, KnownFlow,
    ReconSettings,
};

fn frictional_sweep(w: Whisker, flow: FluidLoad, profile: &str, mu: f64) -> SweepResult {
    let s = SweepSettings {
        points: 30,
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    };
    sweep(&w, flow, &Profile::parse(profile).unwrap(), &s).unwrap()
}

/// Streams `truth`'s log and compares it with the batch; returns (rows streamed, phase-B
/// rows, worst on-the-fly phase-A `|ft - batch| / (sigma_ft + batch sigma_ft)`).
fn compare(w: &Whisker, truth: &SweepResult, known: KnownFlow, mu: f64) -> (usize, usize, f64) {
    let settings = ReconSettings {
        noise: Some(STREAM_NOISE),
        consistency_tol: None,
        ..Default::default()
    };
    let rows = from_sweep(truth);
    let batch = reconstruct_frictional(w, &rows, known, &settings, None).unwrap();
    let mut s = FrictionalStreamer::new(w, known, &settings, None).unwrap();
    let mut live: Vec<FrictionalPoint> = Vec::new();
    for r in &rows {
        live.extend(s.push(*r).unwrap());
    }
    let end = s.finish().unwrap();
    live.extend(end.held.iter().copied());
    assert_eq!(live.len(), batch.points.len());
    let (mut nb, mut worst_a) = (0, 0.0f64);
    for p in &live {
        let b = batch.points.iter().find(|b| b.row == p.row).unwrap();
        let t = &truth.points[p.row];
        assert_eq!(
            (p.phase, p.s1, p.x, p.y),
            (b.phase, b.s1, b.x, b.y),
            "row {}",
            p.row
        );
        assert!((p.x - t.xc).hypot(p.y - t.yc) < 1e-9, "row {}", p.row);
        if p.phase == Phase::B {
            nb += 1;
            assert_eq!((p.f, p.ft, p.psi), (b.f, b.ft, b.psi), "row {}", p.row);
        } else if p.ft.is_finite() {
            let z = (p.ft - b.ft).abs() / (p.sigma_ft + b.sigma_ft);
            worst_a = worst_a.max(z);
            assert!(z <= 6.0, "row {}: {p:?} vs {b:?}", p.row);
            assert!(
                (p.ft - t.ft).abs() <= 6.0 * p.sigma_ft + 1e-9,
                "row {}: live ft {:e} vs the truth's {:e}, sigma_ft {:e} at x {}",
                p.row,
                p.ft,
                t.ft,
                p.sigma_ft,
                p.x
            );
        }
    }
    // the end of the stream: the batch's answer
    assert_eq!(end.points.len(), batch.points.len());
    let (mut worst_sigma, mut worst_value) = (0.0f64, 0.0f64);
    for (p, b) in end.points.iter().zip(&batch.points) {
        assert_eq!((p.row, p.phase, p.slip), (b.row, b.phase, b.slip));
        assert_eq!((p.x, p.y, p.s1), (b.x, b.y, b.s1), "row {}", p.row);
        // a tip contact's tangent is a least-squares fit weighted by the points' error
        // estimates, which the stream's central differences took at other steps (the noise
        // scales of the rows so far): within half of those error estimates
        for (u, v, e) in [
            (p.f, b.f, b.sigma_f),
            (p.ft, b.ft, b.sigma_ft),
            (p.psi, b.psi, b.sigma_psi),
        ] {
            worst_value = worst_value.max((u - v).abs() / e);
            assert!(
                (u - v).abs() <= 0.5 * e,
                "row {}: {u} vs {v} ({e:e})",
                p.row
            );
        }
        // error estimates: central differences at other steps (see above)
        for (u, v) in [(p.sigma_ft, b.sigma_ft), (p.sigma, b.sigma)] {
            worst_sigma = worst_sigma.max((u - v).abs() / v);
        }
    }
    // an identified flow: the stream's is one free row's (its deviation one row's), the
    // batch's the mean of every pre-contact row, so the shared flow term of the error
    // estimates differs; a given flow has none. Within 25 % (was 10 %, docs/friction-recon.md
    // "The traced tangent's error"): a traced tangent's estimate is its fits' distance to
    // the fits of other degrees, and the top degrees' fits move by up to two of their own
    // deviations with the points' weights (row 11: 2.6e-8 in the slope against 1.3e-7)
    let given = known.q.is_some() && known.alpha.is_some();
    assert!(
        !given || worst_sigma < 0.25,
        "error estimates {worst_sigma:e} apart"
    );
    let (ms, mb) = (end.mu.unwrap(), batch.mu.unwrap());
    assert_eq!(ms.rows, mb.rows);
    assert!(
        (ms.value - mb.value).abs() <= 0.5 * mb.stderr,
        "{ms:?} vs {mb:?}"
    );
    assert!(
        !given || (ms.stderr - mb.stderr).abs() <= 0.1 * mb.stderr,
        "{ms:?} vs {mb:?}"
    );
    assert!((ms.value - mu).abs() <= 1e-8, "{ms:?}");
    eprintln!(
        "end of stream: f, ft, psi within {worst_value:.1e} of their error estimates of the \
         batch's, the estimates within {worst_sigma:.1e}; mu {ms:?} vs {mb:?}"
    );
    (live.len(), nb, worst_a)
}

// Was ignored on branch fslip: rows moved by 2.8e-11 (the sweep's faster path) flipped the
// traced tangent's choice of degree and its error estimate (row 36's live ft missed by
// 1.6e-8 against 6 sigma_ft = 1.5e-8). The tangent is now a smooth mean over the degrees
// with an error estimate that two agreeing degrees cannot fool (friction/contour.rs;
// docs/friction-recon.md, "The traced tangent's error").
#[test]
fn frec_stream_gives_the_batch_frictional_points_row_by_row() {
    // tip contact sliding throughout (phase A): the tangent read from the points so far
    let w = Whisker::new(0.5, 0.0, 0.0, 10.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let truth = frictional_sweep(w, flow, "circle:0.3,1.5,0.6", 0.4);
    let given = KnownFlow {
        q: Some(flow.q),
        alpha: Some(flow.alpha),
    };
    let (n, nb, worst) = compare(&w, &truth, given, 0.4);
    eprintln!("sliding tip, flow given: {n} rows, {nb} in phase B, worst phase-A ft {worst:.2} deviations");
    assert!(n >= 25);
}

#[test]
fn frec_stream_through_phase_b_with_the_flow_identified() {
    // g1 under q = 5, mu = 0.5: the contact rolls through phase B; the stream's flow is
    // fixed by the first free row
    let w = Whisker::new(0.75, 0.0, 0.0, 20.0);
    let flow = FluidLoad { q: 5.0, alpha: 0.0 };
    let truth = frictional_sweep(w, flow, "g1", 0.5);
    let (n, nb, worst) = compare(&w, &truth, KnownFlow::default(), 0.5);
    eprintln!("g1 q 5 mu 0.5, flow identified: {n} rows, {nb} in phase B, worst phase-A ft {worst:.2} deviations");
    assert!(nb >= 5, "{nb}");
}
