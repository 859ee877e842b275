//! Reconstruction of the 200-point sweep of g1 under q = 5 (uniform rigid whisker) with the
//! accurate method: identification plus one contact point per row (target: no slower than
//! the 5.5 ms of the neighbour-seeded version it replaced; 4.7 ms measured). And the latency
//! of the stream mode: one row in, its contact point out (`Streamer::push`, flow known), the
//! time a robot waits per sensor row.
//!
//! Issue #21 (targets 2 ms and 8 us a row): on the shared 2-core machine, side by side with
//! the version before it, 2.85-2.94 ms -> 1.95-2.09 ms, phase A 11.4-11.9 -> 6.8-7.9 us,
//! phase B 9.9-10.7 -> 6.3-7.1 us (callgrind: 39.5M -> 24.8M instructions a reconstruction,
//! 152k/138k -> 85k/79k a stream row): the Jacobian carried along the base run's steps,
//! sin/cos of phi by table, fewer divisions off the stepper.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use vibrissa::beam_model::Whisker;
use vibrissa::contact_sim::{sweep, Phase, Profile, SweepSettings};
use vibrissa::profile_recon::{from_sweep, reconstruct, KnownFlow, ReconSettings, Streamer};

fn recon_g1(c: &mut Criterion) {
    let whisker = Whisker::uniform();
    let flow = beam_model::FluidLoad { q: 5.0, alpha: 0.0 };
    let truth = match sweep(&whisker, flow, &Profile::g1(), &SweepSettings::default()) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("recon/g1: sweep failed: {e}");
            return;
        }
    };
    let rows = from_sweep(&truth);
    let settings = ReconSettings::default();
    let mut group = c.benchmark_group("recon");
    group.sample_size(20);
    group.bench_function("g1/q=5/200-points/accurate", |b| {
        b.iter(|| reconstruct(black_box(&whisker), black_box(&rows), None, &settings))
    });
    // stream latency: one contact row of each phase through a running stream
    let known = KnownFlow {
        q: Some(5.0),
        alpha: Some(0.0),
    };
    for phase in [Phase::A, Phase::B] {
        let Some(k) = truth.points.iter().position(|p| p.phase == phase) else {
            continue;
        };
        let Ok(mut stream) = Streamer::new(&whisker, known, &settings) else {
            continue;
        };
        // the rows before it set the stream's column scales
        for r in &rows[..k] {
            let _ = stream.push(*r);
        }
        let row = rows[k];
        group.bench_function(format!("stream/row-latency/phase-{}", phase.label()), |b| {
            b.iter(|| stream.push(black_box(row)))
        });
    }
    group.finish();
}

criterion_group!(benches, recon_g1);
criterion_main!(benches);
