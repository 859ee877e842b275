//! A 200-point sweep of the uniform, straight, rigid whisker past the contour g1 under the
//! flow q = 5 (thesis ch. 5, case 1) with the default settings. The target: < 50 ms.
//! And the same whisker and flow whisked (rotated about its base at the origin from
//! gamma = 0) against the peg (-0.2, 0.6), 200 points (issue 38: as fast per row as the
//! translating sweep), and the same rotation written as a 2-row path of poses, `(0, 0, 0)`
//! to `(0, 0, 3)` (issue 38: a path costs what the rotation does). And the g1 sweep with Coulomb friction mu = 0.5 (issue 39: at most
//! 1.5x the frictionless).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use vibrissa::beam_model::Whisker;
use vibrissa::contact_sim::{sweep, BaseMotion, ContactLaw, Profile, SweepSettings};

fn sweep_g1(c: &mut Criterion) {
    let whisker = Whisker::uniform();
    let profile = Profile::g1();
    let settings = SweepSettings::default(); // 200 contact points
    if let Err(e) = sweep(
        &whisker,
        beam_model::FluidLoad { q: 5.0, alpha: 0.0 },
        &profile,
        &settings,
    ) {
        eprintln!("sweep/g1/q=5: {e}");
        return;
    }
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("g1/q=5/200-points", |b| {
        b.iter(|| {
            sweep(
                black_box(&whisker),
                beam_model::FluidLoad { q: 5.0, alpha: 0.0 },
                black_box(&profile),
                &settings,
            )
        })
    });
    group.finish();
}

fn whisk_peg(c: &mut Criterion) {
    let whisker = Whisker::uniform();
    let profile = Profile::parse("peg:-0.2,0.6").expect("a peg");
    let settings = SweepSettings {
        motion: BaseMotion::Rotate {
            x0: 0.0,
            y0: 0.0,
            gamma0: 0.0,
        },
        ..SweepSettings::default() // 200 contact points
    };
    let flow = beam_model::FluidLoad { q: 5.0, alpha: 0.0 };
    if let Err(e) = sweep(&whisker, flow, &profile, &settings) {
        eprintln!("sweep/rotate/peg: {e}");
        return;
    }
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("rotate/peg:-0.2,0.6/q=5/200-points", |b| {
        b.iter(|| sweep(black_box(&whisker), flow, black_box(&profile), &settings))
    });
    group.finish();
}

fn whisk_peg_path(c: &mut Criterion) {
    use vibrissa::contact_sim::{Pose, Poses};
    let whisker = Whisker::uniform();
    let profile = Profile::parse("peg:-0.2,0.6").expect("peg");
    let poses = vec![
        Pose::default(),
        Pose {
            x0: 0.0,
            y0: 0.0,
            gamma: 3.0,
        },
    ];
    let settings = SweepSettings {
        motion: BaseMotion::Path(Poses::new(poses, None).expect("path")),
        ..SweepSettings::default()
    };
    let flow = beam_model::FluidLoad { q: 5.0, alpha: 0.0 };
    if let Err(e) = sweep(&whisker, flow, &profile, &settings) {
        eprintln!("sweep/path/peg: {e}");
        return;
    }
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("path/peg:-0.2,0.6/q=5/200-points", |b| {
        b.iter(|| sweep(black_box(&whisker), flow, black_box(&profile), &settings))
    });
    group.finish();
}

fn sweep_g1_friction(c: &mut Criterion) {
    let whisker = Whisker::uniform();
    let profile = Profile::g1();
    let settings = SweepSettings {
        contact_law: ContactLaw::Coulomb { mu: 0.5 },
        ..SweepSettings::default()
    };
    let flow = beam_model::FluidLoad { q: 5.0, alpha: 0.0 };
    if let Err(e) = sweep(&whisker, flow, &profile, &settings) {
        eprintln!("sweep/g1/q=5/mu=0.5: {e}");
        return;
    }
    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("g1/q=5/mu=0.5/200-points", |b| {
        b.iter(|| sweep(black_box(&whisker), flow, black_box(&profile), &settings))
    });
    group.finish();
}

criterion_group!(
    benches,
    sweep_g1,
    whisk_peg,
    whisk_peg_path,
    sweep_g1_friction
);
criterion_main!(benches);
