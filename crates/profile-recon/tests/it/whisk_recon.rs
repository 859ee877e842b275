//! Reconstruction of logs of any base motion (issue 38, item 3), against truth the
//! reconstruction does not compute: `contact_sim` sweeps (rotations about any base from any
//! start, translations past pegs and discs; flows at angles; springs) whose rows carry the
//! contact point, and the obstacles they were swept against.
//!
//! Per scene: every contact row's point equals the sweep's contact point and lies on the
//! obstacle (exact logs, <= 1e-10); a peg's position from all rows (<= 1e-10), a disc's centre
//! and radius from its points (a least-squares circle, within a tolerance its standard errors
//! scale); the log reversed, and thinned to every third row, gives the same point per row
//! (<= 1e-10, the integrator's level: the flow is identified from other rows); streamed row by row
//! gives the batch's points (<= 1e-10); noised (relative
//! 1e-4, seeded) the peg within 3 standard errors.
//!
//! `cargo test -p profile-recon --test it -- wrec --ignored --nocapture` runs the
//! full seeded battery and prints its figures; the default run takes a small subset.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{sweep, BaseMotion, Phase, Profile, SweepResult, SweepSettings};
use profile_recon::{
    add_noise, estimate_disc, estimate_peg, from_sweep, poses_of_sweep, reconstruct_posed,
    reconstruct_with, KnownFlow, ObservableRow, ReconPoint, ReconSettings, RowPose, Streamer,
};

/// Consistency residual below which a row of a sweep counts as exact: the reconstructed
/// point must then be the sweep's to 1e-10. The sweep's rows are exact to its own
/// re-integration bound (1.5e-9 in contact-sim's whisking battery, docs/whisking.md): rows
/// beyond this (its event rows where a tangential contact reaches the tip) are held to their
/// error estimate instead.
const CONSISTENT: f64 = 1e-10;

// the scenes of contact-sim's whisking battery, drawn by its own generator
use crate::whisking::{random_whisking_scene as random_scene, Rng, Scene};

/// Worst figures of a battery, each with the scene where it occurred.
#[derive(Debug, Default)]
struct Figures {
    scenes: usize,
    swept: usize,
    rows: usize,
    missed: usize,
    /// Swept scenes whose every contact force stays below 1e-9 (read as free).
    faint: usize,
    /// The reconstructed point against the sweep's contact point.
    point: (f64, String),
    /// The reconstructed point's clearance from the obstacle.
    on_obstacle: (f64, String),
    /// Rows whose consistency residual exceeds [`CONSISTENT`] (the log's own inaccuracy).
    loose: usize,
    /// Their worst distance from the sweep's point or the obstacle, and relative to their
    /// error estimate.
    loose_point: (f64, String),
    loose_ratio: (f64, String),
    /// A peg's position from all rows.
    peg: (f64, String),
    pegs: usize,
    /// A disc's centre and radius: the worst error, and the worst beyond 1e-10 in standard
    /// errors.
    disc: (f64, String),
    disc_z: (f64, String),
    discs: usize,
    /// Reversed and thinned against the batch.
    reorder: (f64, String),
    /// Streamed against the batch.
    stream: (f64, String),
    /// Noised logs of pegs: within 3 standard errors, out of.
    noisy_pegs: (usize, usize),
    noisy_worst: (f64, String),
}

fn worse(slot: &mut (f64, String), v: f64, name: &str) {
    if v > slot.0 || v.is_nan() {
        *slot = (v, name.to_string());
    }
}

fn by_row(points: &[ReconPoint]) -> std::collections::HashMap<usize, ReconPoint> {
    points.iter().map(|p| (p.row, *p)).collect()
}

/// Reconstructs one swept scene and checks it (module docs); returns false when the scene
/// swept without a contact row.
fn check_scene(scene: &Scene, res: &SweepResult, fig: &mut Figures, seed: u64) {
    let rows = from_sweep(res);
    let poses = poses_of_sweep(res);
    let settings = ReconSettings::default();
    let known = KnownFlow::default();
    let fmax = res.contact_points().map(|p| p.f).fold(0.0, f64::max);
    let rec = match reconstruct_posed(&scene.whisker, &rows, &poses, known, &settings) {
        Ok(rec) => rec,
        // a touch whose force never leaves the noise floor reads as the free whisker
        Err(profile_recon::ReconError::NoContactRows { .. }) if fmax < 1e-9 => {
            fig.faint += 1;
            return;
        }
        Err(e) => panic!("{}: {e} (largest contact force {fmax:e})", scene.name),
    };
    let got = by_row(&rec.points);
    let name = &scene.name;
    for (i, p) in res.points.iter().enumerate() {
        if p.phase == Phase::None {
            continue;
        }
        fig.rows += 1;
        let Some(r) = got.get(&i) else {
            // a contact row read as free: only with a force at the noise floor
            assert!(
                p.f < 1e-9,
                "{name}: contact row {i} (f = {}) gave no point",
                p.f
            );
            fig.missed += 1;
            continue;
        };
        assert_eq!(r.x0, p.x0, "{name}: x0 copied");
        let err = (r.x - p.xc).hypot(r.y - p.yc);
        if err > 1e-10 && std::env::var_os("WREC_DEBUG").is_some() {
            println!(
                "{name} row {i}: {err:.2e} phase {:?}/{:?} s1 {:.6}/{:.6} f {:.3e} sigma {:.2e} residual {:.2e} clearance {:.2e}",
                p.phase, r.phase, p.s1, r.s1, p.f, r.sigma, r.residual,
                scene.profile.clearance(r.x, r.y)
            );
        }
        let off = scene.profile.clearance(r.x, r.y).abs();
        if r.residual <= CONSISTENT {
            worse(&mut fig.point, err, name);
            worse(&mut fig.on_obstacle, off, name);
        } else {
            // a row the log itself holds to less than 1e-10 (the sweep's event rows where
            // tangential contact reaches the tip): the point within its error estimate
            fig.loose += 1;
            worse(&mut fig.loose_point, err.max(off), name);
            worse(&mut fig.loose_ratio, err.max(off) / r.sigma, name);
        }
    }
    match scene.profile {
        Profile::Peg { x, y } => {
            let e = estimate_peg(&rec.points).unwrap();
            worse(&mut fig.peg, (e.x - x).hypot(e.y - y), name);
            fig.pegs += 1;
        }
        Profile::Disc { x, y, r } if rec.points.len() >= 3 => {
            if let Ok(e) = estimate_disc(&rec.points) {
                // an arc of a few rows determines the circle poorly: the error relative to
                // 1e-10 times the condition its standard errors show (they are the points'
                // own error over sqrt(J^T J))
                // within 1e-10, or within 3 standard errors (a short arc, or points as
                // inexact as the log's event rows, determines the circle less well)
                let z = [(e.x - x), (e.y - y), (e.r - r)]
                    .iter()
                    .zip(e.stderr)
                    .map(|(d, se)| if d.abs() <= 1e-10 { 0.0 } else { d.abs() / se })
                    .fold(0.0, f64::max);
                let err = (e.x - x).abs().max((e.y - y).abs()).max((e.r - r).abs());
                worse(&mut fig.disc, err, name);
                worse(&mut fig.disc_z, z, name);
                fig.discs += 1;
            }
        }
        _ => {}
    }
    // reversed and thinned: the same point per row
    let n = rows.len();
    let rev: Vec<usize> = (0..n).rev().collect();
    let thin: Vec<usize> = (0..n)
        .filter(|i| i % 3 == 0 || res.points[*i].phase == Phase::None)
        .collect();
    for order in [rev, thin] {
        let r2: Vec<ObservableRow> = order.iter().map(|&i| rows[i]).collect();
        let p2: Vec<RowPose> = order.iter().map(|&i| poses[i]).collect();
        let Ok(rec2) = reconstruct_posed(&scene.whisker, &r2, &p2, known, &settings) else {
            panic!("{name}: reordered log failed");
        };
        for p in &rec2.points {
            let orig = order[p.row];
            if let Some(a) = got.get(&orig) {
                worse(&mut fig.reorder, (a.x - p.x).hypot(a.y - p.y), name);
            }
        }
    }
    // streamed: the batch's points row by row
    let mut st = Streamer::new(&scene.whisker, known, &settings).unwrap();
    let mut streamed = Vec::new();
    for (r, p) in rows.iter().zip(&poses) {
        streamed.extend(st.push_posed(*r, *p).unwrap());
    }
    streamed.extend(st.finish().unwrap());
    for p in &streamed {
        if let Some(a) = got.get(&p.row) {
            worse(&mut fig.stream, (a.x - p.x).hypot(a.y - p.y), name);
        }
    }
    // noised: the peg within 3 standard errors
    if let Profile::Peg { x, y } = scene.profile {
        let noisy = add_noise(&rows, 1e-4, seed);
        let loose = ReconSettings {
            consistency_tol: None,
            ..settings
        };
        if let Ok(rn) = reconstruct_posed(&scene.whisker, &noisy, &poses, known, &loose) {
            if let Ok(e) = estimate_peg(&rn.points) {
                fig.noisy_pegs.1 += 1;
                let z = ((e.x - x) / e.stderr_x)
                    .abs()
                    .max(((e.y - y) / e.stderr_y).abs());
                if z <= 3.0 {
                    fig.noisy_pegs.0 += 1;
                }
                worse(&mut fig.noisy_worst, z, name);
            }
        }
    }
}

fn battery(n: usize, seed: u64) -> Figures {
    let mut rng = Rng(seed);
    let mut fig = Figures::default();
    for i in 0..n {
        let scene = random_scene(&mut rng, i);
        fig.scenes += 1;
        let Ok(res) = sweep(&scene.whisker, scene.flow, &scene.profile, &scene.settings) else {
            continue;
        };
        if res.contact_points().count() == 0 {
            continue;
        }
        fig.swept += 1;
        check_scene(&scene, &res, &mut fig, seed ^ i as u64);
    }
    fig
}

fn assert_figures(fig: &Figures) {
    println!("{fig:#?}");
    assert!(fig.point.0 <= 1e-10, "point {:?}", fig.point);
    assert!(
        fig.on_obstacle.0 <= 1e-10,
        "on obstacle {:?}",
        fig.on_obstacle
    );
    assert!(fig.peg.0 <= 1e-10, "peg {:?}", fig.peg);
    assert!(fig.disc.0 <= 1e-10, "disc {:?}", fig.disc);
    assert!(fig.disc_z.0 <= 3.0, "disc {:?} {:?}", fig.disc, fig.disc_z);
    assert!(fig.loose_ratio.0 <= 3.0, "loose rows {:?}", fig.loose_ratio);
    assert!(fig.reorder.0 <= 1e-10, "reordered {:?}", fig.reorder);
    assert!(fig.stream.0 <= 1e-10, "streamed {:?}", fig.stream);
    let (inside, of) = fig.noisy_pegs;
    assert!(
        10 * inside >= 9 * of,
        "noisy pegs within 3 se: {inside} of {of}"
    );
}

/// The subset of the seeded battery in the default suite.
#[test]
fn wrec_battery_subset() {
    let fig = battery(8, 0x5EED_0038);
    assert!(fig.swept >= 4, "{fig:?}");
    assert_figures(&fig);
}

/// The full seeded battery (module docs).
#[test]
#[ignore = "the full battery: cargo test -p profile-recon --test it -- wrec --ignored --nocapture"]
fn wrec_battery_full() {
    let fig = battery(300, 0x5EED_0038);
    assert_figures(&fig);
}

/// Whisking the linear-limit scene of contact-sim (a straight uniform rigid whisker, no
/// flow, the base at the origin) against the peg (-0.2, 0.6): every contact row gives the
/// peg, the flow given as none; a translate log (no poses) is reconstructed bit for bit as
/// before.
#[test]
fn wrec_a_whisking_log_gives_the_peg_and_a_translate_log_is_unchanged() {
    let whisker = Whisker::new(1.0, 0.0, 0.0, f64::INFINITY);
    let flow = FluidLoad { q: 0.0, alpha: 0.0 };
    let peg = Profile::parse("peg:-0.2,0.6").unwrap();
    let settings = SweepSettings {
        points: 40,
        motion: BaseMotion::Rotate {
            x0: 0.0,
            y0: 0.0,
            gamma0: 0.0,
        },
        ..SweepSettings::default()
    };
    let res = sweep(&whisker, flow, &peg, &settings).unwrap();
    let rows = from_sweep(&res);
    let poses = poses_of_sweep(&res);
    let rec = reconstruct_posed(
        &whisker,
        &rows,
        &poses,
        KnownFlow::default(),
        &ReconSettings::default(),
    )
    .unwrap();
    let contact = res.contact_points().count();
    assert!(
        rec.points.len() + 1 >= contact && contact >= 40,
        "{} points of {contact} contact rows",
        rec.points.len()
    );
    let e = estimate_peg(&rec.points).unwrap();
    assert!(
        (e.x + 0.2).abs() < 1e-10 && (e.y - 0.6).abs() < 1e-10,
        "{e:?}"
    );
    assert!(e.spread < 1e-10 && e.stderr_x < 1e-10, "{e:?}");
    // a translate log: the posed reconstruction is the plain one, bit for bit
    let g2 = sweep(
        &Whisker::uniform(),
        FluidLoad { q: 3.0, alpha: 0.2 },
        &Profile::g2(),
        &SweepSettings {
            points: 15,
            ..SweepSettings::default()
        },
    )
    .unwrap();
    let rows = from_sweep(&g2);
    let plain = reconstruct_with(
        &Whisker::uniform(),
        &rows,
        KnownFlow::default(),
        &ReconSettings::default(),
    )
    .unwrap();
    let posed = reconstruct_posed(
        &Whisker::uniform(),
        &rows,
        &poses_of_sweep(&g2),
        KnownFlow::default(),
        &ReconSettings::default(),
    )
    .unwrap();
    assert_eq!(plain, posed);
}

/// A translate log turned as a whole: every row's reactions turned by `delta` and its base
/// angle by `delta` about its base, the base lifted by `y0` (the flow turned with them, as a
/// turned experiment records it). The reconstruction is covariant: the points are the
/// original ones turned by `delta` about each row's base and lifted by `y0`, the flow angle
/// `alpha - delta` (spec/model.md: the load vector `q (cos alpha, -sin alpha)`), `psi + delta`.
#[test]
fn wrec_a_turned_and_lifted_log_gives_the_turned_and_lifted_points() {
    let w = Whisker::new(0.7, 0.3, -0.2, 25.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.3 };
    let res = sweep(
        &w,
        flow,
        &Profile::g2(),
        &SweepSettings {
            points: 20,
            ..SweepSettings::default()
        },
    )
    .unwrap();
    let rows = from_sweep(&res);
    let plain =
        reconstruct_with(&w, &rows, KnownFlow::default(), &ReconSettings::default()).unwrap();
    for (delta, y0) in [(0.4, 0.25), (-0.7, -0.1), (1.1, 0.0)] {
        let (sd, cd) = f64::sin_cos(delta);
        let turned: Vec<ObservableRow> = rows
            .iter()
            .map(|r| ObservableRow {
                ax: cd * r.ax - sd * r.ay,
                ay: sd * r.ax + cd * r.ay,
                phi0: r.phi0 + delta,
                ..*r
            })
            .collect();
        let poses = vec![RowPose::new(y0, delta); rows.len()];
        let rec = reconstruct_posed(
            &w,
            &turned,
            &poses,
            KnownFlow::default(),
            &ReconSettings::default(),
        )
        .unwrap();
        assert!(
            (rec.identification.alpha - (flow.alpha - delta)).abs() < 1e-12,
            "alpha {} at delta {delta}",
            rec.identification.alpha
        );
        assert_eq!(rec.points.len(), plain.points.len());
        let mut worst: f64 = 0.0;
        for (p, q) in plain.points.iter().zip(&rec.points) {
            assert_eq!((p.row, p.phase), (q.row, q.phase));
            let (dx, dy) = (p.x - p.x0, p.y);
            let (ex, ey) = (p.x0 + cd * dx - sd * dy, y0 + sd * dx + cd * dy);
            worst = worst.max((q.x - ex).hypot(q.y - ey));
            worst = worst.max((q.s1 - p.s1).abs()).max((q.f - p.f).abs());
            let dpsi = (q.psi - p.psi - delta + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            worst = worst.max(dpsi.abs());
        }
        assert!(worst < 1e-10, "delta {delta}: {worst:e}");
        println!(
            "delta {delta}, y0 {y0}: worst {worst:.2e} over {} points",
            rec.points.len()
        );
    }
}
