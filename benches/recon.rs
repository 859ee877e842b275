//! Reconstruction of the 200-point sweep of g1 under q = 5 (uniform rigid whisker) with the
//! accurate method: identification plus one contact point per row. Target: < 10 ms.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use vibrissa::beam_model::Whisker;
use vibrissa::contact_sim::{sweep, Profile, SweepSettings};
use vibrissa::profile_recon::{from_sweep, reconstruct, ReconSettings};

fn recon_g1(c: &mut Criterion) {
    let whisker = Whisker::uniform();
    let truth = match sweep(
        &whisker,
        beam_model::FluidLoad { q: 5.0, alpha: 0.0 },
        &Profile::g1(),
        &SweepSettings::default(),
    ) {
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
    group.finish();
}

criterion_group!(benches, recon_g1);
criterion_main!(benches);
