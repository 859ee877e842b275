//! The reconstruction battery (issue 11): random seeded scenes, each log also shuffled,
//! reversed, thinned to every fifth row and cut to one pre-contact row, and with seeded noise
//! 1e-6 and 1e-4, against independent truth:
//!
//! - `forward_logs`: logs built row by row from forward solves of the whisker (beam-model's
//!   `accurate` shooting from the free end under `contact_loads`), independent of any sweep:
//!   a pre-contact row (the flow alone) and contact rows with a random phase, force, contact
//!   angle (phase A: `phi(1) > psi`) or contact arc length (phase B: `psi = phi(s1)`, solved by
//!   a secant), at random base positions; the truth is `x0 + r(s1)`.
//! - `sweep_logs` (ignored: minutes): sweeps of contact-sim over random scenes; the truth is
//!   the sweep's hidden contact point. Scenes where the sweep itself fails are counted and
//!   printed, not hidden.
//!
//! Figures are printed (`cargo test --release -p profile-recon --test it -- battery:: --skip calibrate_battery:: --nocapture
//! --include-ignored`).

use beam_model::{solve, FluidLoad, Loads, Method, Scene, Whisker};
use contact_sim::phase::contact_loads;
use contact_sim::{sweep, Phase, Profile, SweepSettings};
use profile_recon::{
    add_noise, from_sweep, reconstruct_with, KnownFlow, ObservableRow, ReconPoint, ReconSettings,
    Reconstruction,
};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};

/// A random whisker and flow.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Setup {
    pub(crate) whisker: Whisker,
    pub(crate) flow: FluidLoad,
}

pub(crate) fn random_setup(rng: &mut StdRng, i: usize) -> Setup {
    // every tenth scene slender (theta = 0.05), else 0.1..1
    let theta = if i % 10 == 7 {
        0.05
    } else {
        rng.gen_range(0.1..=1.0)
    };
    let a = rng.gen_range(-1.5..1.5);
    let b = rng.gen_range(-0.8..0.8);
    let k = if rng.gen_bool(0.3) {
        f64::INFINITY
    } else {
        rng.gen_range(5.0..50.0)
    };
    // q = 0 now and then; alpha in (-60, 60) degrees
    let q = if i % 9 == 4 {
        0.0
    } else {
        rng.gen_range(0.2..8.0)
    };
    let alpha = rng.gen_range(-60.0f64..60.0).to_radians();
    Setup {
        whisker: Whisker::new(theta, a, b, k),
        flow: FluidLoad { q, alpha },
    }
}

/// Relative distance of two points of a contour.
fn dist(p: &ReconPoint, x: f64, y: f64) -> f64 {
    (p.x - x).hypot(p.y - y)
}

/// The flow error of a reconstruction: (|dq|, |dalpha| in degrees; 0 for q = 0, where alpha
/// is not defined).
fn flow_error(rec: &Reconstruction, flow: FluidLoad) -> (f64, f64) {
    let dq = (rec.identification.q - flow.q).abs();
    let da = if flow.q > 0.0 {
        (rec.identification.alpha - flow.alpha).abs().to_degrees()
    } else {
        0.0
    };
    (dq, da)
}

/// Variants of a log: (name, rows, index map new -> original).
fn variants(rows: &[ObservableRow], pre: usize, rng: &mut StdRng) -> Vec<(String, Vec<usize>)> {
    let n = rows.len();
    let mut out = vec![("original".to_string(), (0..n).collect::<Vec<_>>())];
    let mut sh: Vec<usize> = (0..n).collect();
    sh.shuffle(rng);
    out.push(("shuffled".into(), sh));
    out.push(("reversed".into(), (0..n).rev().collect()));
    // thinned: every fifth contact row, the pre-contact rows kept (the first of them)
    let mut th: Vec<usize> = (0..pre.min(1)).collect();
    th.extend((pre..n).step_by(5));
    out.push(("thinned".into(), th));
    // one pre-contact row
    if pre > 1 {
        out.push(("one-pre".into(), (pre - 1..n).collect()));
    }
    out
}

/// Statistics over a battery.
#[derive(Default, Debug)]
struct Stats {
    logs: usize,
    points: usize,
    worst: f64,
    worst_at: String,
    worst_dq: f64,
    worst_da: f64,
    failures: Vec<String>,
    noisy_medians: Vec<(f64, f64, String, f64)>,
    worst_sigma_ratio: f64,
    spurious: usize,
    reported: Vec<String>,
}

impl Stats {
    fn point(&mut self, e: f64, at: impl FnOnce() -> String) {
        self.points += 1;
        // a NaN error counts as the worst
        if e.is_nan() || e > self.worst {
            self.worst = e;
            self.worst_at = at();
        }
    }
}

fn settings() -> ReconSettings {
    ReconSettings {
        consistency_tol: None,
        ..ReconSettings::default()
    }
}

/// Checks one exact log variant: every contact row (truth `Some((x, y, f))`) reconstructed,
/// no pre-contact row reconstructed, the flow identified.
fn check_exact(
    stats: &mut Stats,
    name: &str,
    setup: &Setup,
    rows: &[ObservableRow],
    truth: &[Option<(f64, f64, f64)>],
) {
    stats.logs += 1;
    let rec = match reconstruct_with(&setup.whisker, rows, KnownFlow::default(), &settings()) {
        Ok(r) => r,
        Err(e) => {
            stats.failures.push(format!("{name}: {e}"));
            return;
        }
    };
    if std::env::var("BATTERY_DEBUG").is_ok() {
        let id = &rec.identification;
        eprintln!(
            "{name}: q {} alpha {} noise {:e} pre {:?}",
            id.q, id.alpha, id.noise, id.pre_contact
        );
        for p in &rec.points {
            eprintln!(
                "  row {} {:?} s1 {:.5} f {:.3e} res {:.2e} sigma {:.2e} alt {} truth {:?}",
                p.row, p.phase, p.s1, p.f, p.residual, p.sigma, p.alternatives, truth[p.row]
            );
        }
    }
    let (dq, da) = flow_error(&rec, setup.flow);
    stats.worst_dq = stats.worst_dq.max(dq);
    stats.worst_da = stats.worst_da.max(da);
    if dq > 1e-9 || da > 1e-7 {
        stats
            .failures
            .push(format!("{name}: flow dq = {dq:e}, dalpha = {da:e} deg"));
    }
    let mut seen = vec![false; rows.len()];
    for p in &rec.points {
        seen[p.row] = true;
        match truth[p.row] {
            Some((x, y, _)) => {
                let e = dist(p, x, y);
                stats.point(e, || {
                    format!(
                        "{name} row {} ({:?}, s1 = {:.4}, f = {:.3e}, alternatives {})",
                        p.row, p.phase, p.s1, p.f, p.alternatives
                    )
                });
                if e > 1e-9 {
                    stats.failures.push(format!(
                        "{name} row {}: error {e:.3e} ({:?} s1 {:.6} f {:.3e} sigma {:.2e} alt {})",
                        p.row, p.phase, p.s1, p.f, p.sigma, p.alternatives
                    ));
                }
            }
            None => stats.failures.push(format!(
                "{name} row {}: a pre-contact row reconstructed",
                p.row
            )),
        }
    }
    // every contact row with a force above the noise floor's reach
    for (i, t) in truth.iter().enumerate() {
        if let Some((_, _, f)) = t {
            if *f > 1e-8 && !seen[i] {
                stats.failures.push(format!(
                    "{name} row {i}: contact row (f = {f:.3e}) not reconstructed"
                ));
            }
        }
    }
}

/// Checks a noisy copy: no failure, median point error within 10x the noise level.
fn check_noisy(
    stats: &mut Stats,
    name: &str,
    setup: &Setup,
    rows: &[ObservableRow],
    truth: &[Option<(f64, f64, f64)>],
    level: f64,
    seed: u64,
) {
    stats.logs += 1;
    let noisy = add_noise(rows, level, seed);
    // Slender tips (theta < 0.1) at noise 1e-4 are reported, not asserted: the integration
    // from the base to a tip with e^4 ~ 1e-5 amplifies the noise of MA by 1e5 (the free
    // whisker can wind off), and the noise moves the identification itself (q by ~4 % in
    // sweep#37), beyond a linear error estimate.
    let slender_loud = setup.whisker.theta < 0.1 && level >= 1e-4;
    let rec = match reconstruct_with(&setup.whisker, &noisy, KnownFlow::default(), &settings()) {
        Ok(r) => r,
        Err(e) => {
            let list = if slender_loud {
                &mut stats.reported
            } else {
                &mut stats.failures
            };
            list.push(format!("{name} noise {level:e}: {e}"));
            return;
        }
    };
    if std::env::var("BATTERY_DEBUG").is_ok() {
        let id = &rec.identification;
        eprintln!(
            "{name} noise {level:e}: q {} alpha {} noise {:e} pre {:?}",
            id.q, id.alpha, id.noise, id.pre_contact
        );
        for p in &rec.points {
            let e = truth[p.row].map(|(x, y, _)| dist(p, x, y));
            eprintln!(
                "  row {} {:?} s1 {:.5} f {:.3e} res {:.2e} sigma {:.2e} alt {} err {:?}",
                p.row, p.phase, p.s1, p.f, p.residual, p.sigma, p.alternatives, e
            );
        }
    }
    let mut errs: Vec<f64> = rec
        .points
        .iter()
        .filter_map(|p| truth[p.row].map(|(x, y, _)| dist(p, x, y)))
        .collect();
    let mut ratios: Vec<f64> = rec
        .points
        .iter()
        .filter_map(|p| truth[p.row].map(|(x, y, _)| dist(p, x, y) / p.sigma.max(1e-300)))
        .collect();
    stats.spurious += rec.points.iter().filter(|p| truth[p.row].is_none()).count();
    for &r in &ratios {
        if r.is_finite() {
            stats.worst_sigma_ratio = stats.worst_sigma_ratio.max(r);
        }
    }
    if errs.is_empty() {
        stats
            .failures
            .push(format!("{name} noise {level:e}: no contact point"));
        return;
    }
    errs.sort_by(f64::total_cmp);
    ratios.sort_by(f64::total_cmp);
    let med = errs[errs.len() / 2];
    let med_ratio = ratios[ratios.len() / 2];
    stats
        .noisy_medians
        .push((level, med, name.to_string(), med_ratio));
    // The target: a median error within 10x the relative noise (the error estimates are
    // checked point by point at the end: no point beyond 10 of its sigmas).
    if med > 10.0 * level {
        let list = if slender_loud {
            &mut stats.reported
        } else {
            &mut stats.failures
        };
        list.push(format!(
            "{name} noise {level:e}: median error {med:.3e}, median error/sigma {med_ratio:.2} (q {} vs {})",
            rec.identification.q, setup.flow.q
        ));
    }
}

/// One log of the battery: its name, scene, rows, the true contact point of each row and
/// the number of pre-contact rows.
struct Log<'a> {
    name: &'a str,
    setup: &'a Setup,
    rows: &'a [ObservableRow],
    truth: &'a [Option<(f64, f64, f64)>],
    pre: usize,
}

/// Runs every variant of one log.
fn run_log(stats: &mut Stats, log: &Log<'_>, rng: &mut StdRng, seed: u64) {
    let Log {
        name,
        setup,
        rows,
        truth,
        pre,
    } = *log;
    for (vname, idx) in variants(rows, pre, rng) {
        let r: Vec<ObservableRow> = idx.iter().map(|&i| rows[i]).collect();
        let t: Vec<Option<(f64, f64, f64)>> = idx.iter().map(|&i| truth[i]).collect();
        check_exact(stats, &format!("{name}/{vname}"), setup, &r, &t);
    }
    for level in [1e-6, 1e-4] {
        check_noisy(stats, name, setup, rows, truth, level, seed);
    }
}

fn report(what: &str, s: &Stats) {
    eprintln!(
        "{what}: {} logs, {} points, worst error {:.3e} at {}, worst dq {:.2e}, worst dalpha {:.2e} deg",
        s.logs, s.points, s.worst, s.worst_at, s.worst_dq, s.worst_da
    );
    for level in [1e-6, 1e-4] {
        let mut m: Vec<&(f64, f64, String, f64)> =
            s.noisy_medians.iter().filter(|v| v.0 == level).collect();
        m.sort_by(|a, b| a.1.total_cmp(&b.1));
        let within = m.iter().filter(|v| v.1 <= 10.0 * level).count();
        if let Some(w) = m.last() {
            eprintln!(
                "{what}: noise {level:e}: {} logs, {within} with median error <= 10x noise; middle median {:.3e}; worst median {:.3e} (error/sigma {:.2}) at {}",
                m.len(),
                m[m.len() / 2].1,
                w.1,
                w.3,
                w.2
            );
            for v in m.iter().filter(|v| v.1 > 10.0 * level) {
                eprintln!(
                    "    over 10x: median {:.3e}, error/sigma {:.2}: {}",
                    v.1, v.3, v.2
                );
            }
        }
    }
    eprintln!(
        "{what}: worst |error| / sigma over the noisy points {:.2}; pre-contact rows reconstructed in noisy logs: {}",
        s.worst_sigma_ratio, s.spurious
    );
    for f in &s.reported {
        eprintln!("  REPORTED (slender, noise 1e-4) {f}");
    }
    for f in s.failures.iter().take(40) {
        eprintln!("  FAIL {f}");
    }
}

// ---------------------------------------------------------------------------------------
// forward logs

/// One forward solve under contact loads: (observables row at x0, contact point, phi(s1)).
fn forward(
    setup: &Setup,
    x0: f64,
    psi: f64,
    f: f64,
    s1: f64,
) -> Option<(ObservableRow, (f64, f64), f64)> {
    let loads = contact_loads(setup.flow, psi, f, s1);
    let sol = solve(&Scene::new(setup.whisker, loads), &Method::accurate()).ok()?;
    let b = sol.base;
    let e = sol.loaded_end;
    Some((
        ObservableRow {
            x0,
            ax: b.ax,
            ay: b.ay,
            ma: b.ma,
            phi0: b.phi0,
        },
        (x0 + e.x, e.y),
        e.phi,
    ))
}

/// Solves `phi(s1; psi) - offset = psi` for psi by a secant from the unloaded tip angle.
fn consistent_psi(setup: &Setup, f: f64, s1: f64, offset: f64) -> Option<f64> {
    let g = |psi: f64| forward(setup, 0.0, psi, f, s1).map(|(_, _, phi)| phi - offset - psi);
    let mut p0 = setup.whisker.phi_unloaded(s1) - offset;
    let mut g0 = g(p0)?;
    let mut p1 = p0 + g0;
    for _ in 0..40 {
        let g1 = g(p1)?;
        if g1.abs() < 1e-13 {
            return Some(p1);
        }
        let d = g1 - g0;
        if d == 0.0 {
            return None;
        }
        let next = p1 - g1 * (p1 - p0) / d;
        (p0, g0, p1) = (p1, g1, next);
    }
    None
}

#[test]
fn forward_logs() {
    let mut stats = Stats::default();
    let mut skipped = 0;
    let scenes = 48;
    for i in 0..scenes {
        let seed = 1000 + i as u64;
        let mut rng = StdRng::seed_from_u64(seed);
        let setup = random_setup(&mut rng, i);
        // pre-contact row(s): the flow alone
        let Ok(free) = solve(
            &Scene::new(setup.whisker, Loads::fluid(setup.flow.q, setup.flow.alpha)),
            &Method::accurate(),
        ) else {
            skipped += 1;
            continue;
        };
        let mut rows = Vec::new();
        let mut truth = Vec::new();
        for k in 0..3 {
            let b = free.base;
            rows.push(ObservableRow {
                x0: 2.0 - 0.1 * k as f64,
                ax: b.ax,
                ay: b.ay,
                ma: b.ma,
                phi0: b.phi0,
            });
            truth.push(None);
        }
        let fmax = if setup.whisker.theta < 0.1 { 1.0 } else { 6.0 };
        let mut tries = 0;
        while truth.len() < 3 + 12 && tries < 60 {
            tries += 1;
            let x0 = rng.gen_range(-1.0..1.5);
            let f = rng.gen_range(0.05..fmax);
            let row = if rng.gen_bool(0.5) {
                // phase A: tip contact with phi(1) - psi = offset > 0
                let off = rng.gen_range(0.05..0.6);
                consistent_psi(&setup, f, 1.0, off).and_then(|psi| forward(&setup, x0, psi, f, 1.0))
            } else {
                let s1 = rng.gen_range(0.3..0.97);
                consistent_psi(&setup, f, s1, 0.0).and_then(|psi| forward(&setup, x0, psi, f, s1))
            };
            if let Some((r, (x, y), _)) = row {
                rows.push(r);
                truth.push(Some((x, y, f)));
            }
        }
        if truth.len() < 3 + 6 {
            skipped += 1;
            continue;
        }
        let name = format!(
            "forward#{i} theta {:.2} A {:.2} B {:.2} k {:.1} q {:.2} alpha {:.1}",
            setup.whisker.theta,
            setup.whisker.a,
            setup.whisker.b,
            setup.whisker.support.stiffness(),
            setup.flow.q,
            setup.flow.alpha.to_degrees()
        );
        let log = Log {
            name: &name,
            setup: &setup,
            rows: &rows,
            truth: &truth,
            pre: 3,
        };
        run_log(&mut stats, &log, &mut rng, seed);
    }
    eprintln!("forward logs: {scenes} scenes, {skipped} skipped (forward solve failed)");
    report("forward", &stats);
    assert!(skipped <= scenes / 6, "{skipped} scenes skipped");
    assert!(
        stats.failures.is_empty(),
        "{} failures",
        stats.failures.len()
    );
    assert!(
        stats.worst_sigma_ratio <= 10.0,
        "a noisy point {:.1} of its sigmas off",
        stats.worst_sigma_ratio
    );
}

// ---------------------------------------------------------------------------------------
// sweep logs

/// A random convex contour of each kind in turn, above the free tip region.
pub(crate) fn random_profile(rng: &mut StdRng, i: usize) -> (String, Profile) {
    let vy = rng.gen_range(0.35..0.75);
    let vx = rng.gen_range(-0.4..0.4);
    match i % 7 {
        0 => ("g1".into(), Profile::g1()),
        1 => ("g2".into(), Profile::g2()),
        2 => ("ge".into(), Profile::ge()),
        3 => {
            let a = rng.gen_range(0.3..2.5);
            (
                format!("parabola:{a:.3},{vx:.3},{vy:.3}"),
                Profile::Parabola { a, xv: vx, yv: vy },
            )
        }
        4 => {
            let (a, c) = (rng.gen_range(0.3..1.5), rng.gen_range(0.8..3.0));
            (
                format!("cosh:{a:.3},{c:.3},{vx:.3},{:.3}", vy - a),
                Profile::Cosh {
                    a,
                    c,
                    xv: vx,
                    d: vy - a,
                },
            )
        }
        5 => {
            let r = rng.gen_range(1.0..3.0);
            (
                format!("circle:{vx:.3},{:.3},{r:.3}", vy + r),
                Profile::Circle {
                    xc: vx,
                    yc: vy + r,
                    r,
                },
            )
        }
        _ => {
            let a = rng.gen_range(0.3..2.0);
            let x: Vec<f64> = (0..=60).map(|k| -3.0 + 0.1 * k as f64).collect();
            let y: Vec<f64> = x.iter().map(|x| a * (x - vx).powi(2) + vy).collect();
            (
                format!("points(parabola {a:.3},{vx:.3},{vy:.3})"),
                Profile::points(x, y).unwrap_or_else(|_| Profile::g2()),
            )
        }
    }
}

#[test]
#[ignore = "minutes: sweeps of 48 random scenes (run with --include-ignored)"]
fn sweep_logs() {
    let mut stats = Stats::default();
    let mut sweep_failures = Vec::new();
    let scenes = 48;
    let only: Option<usize> = std::env::var("BATTERY_SCENE")
        .ok()
        .and_then(|v| v.parse().ok());
    for i in 0..scenes {
        if only.is_some_and(|o| o != i) {
            continue;
        }
        let seed = 5000 + i as u64;
        let mut rng = StdRng::seed_from_u64(seed);
        let setup = random_setup(&mut rng, i);
        let (pname, profile) = random_profile(&mut rng, i);
        let name = format!(
            "sweep#{i} {pname} theta {:.2} A {:.2} B {:.2} k {:.1} q {:.2} alpha {:.1}",
            setup.whisker.theta,
            setup.whisker.a,
            setup.whisker.b,
            setup.whisker.support.stiffness(),
            setup.flow.q,
            setup.flow.alpha.to_degrees()
        );
        let s = SweepSettings {
            points: 60,
            ..SweepSettings::default()
        };
        let res = match sweep(&setup.whisker, setup.flow, &profile, &s) {
            Ok(r) => r,
            Err(e) => {
                sweep_failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        if !res
            .points
            .iter()
            .any(|p| p.phase != Phase::None && p.f > 1e-8)
        {
            sweep_failures.push(format!(
                "{name}: degenerate sweep, no row with a contact force (all f <= 1e-8)"
            ));
            continue;
        }
        let rows = from_sweep(&res);
        let truth: Vec<Option<(f64, f64, f64)>> = res
            .points
            .iter()
            .map(|p| (p.phase != Phase::None).then_some((p.xc, p.yc, p.f)))
            .collect();
        if std::env::var("BATTERY_DEBUG").is_ok() {
            for p in &res.points {
                eprintln!(
                    "truth x0 {:.4} {:?} f {:.3e} s1 {:.4} Ax {:.6} Ay {:.6} MA {:.6} phi0 {:.6}",
                    p.x0, p.phase, p.f, p.s1, p.ax, p.ay, p.ma, p.phi0
                );
            }
        }
        let pre = res
            .points
            .iter()
            .take_while(|p| p.phase == Phase::None)
            .count();
        let log = Log {
            name: &name,
            setup: &setup,
            rows: &rows,
            truth: &truth,
            pre,
        };
        run_log(&mut stats, &log, &mut rng, seed);
    }
    eprintln!(
        "sweep logs: {scenes} scenes, {} sweeps failed (contact-sim):",
        sweep_failures.len()
    );
    for f in &sweep_failures {
        eprintln!("  SWEEP {f}");
    }
    report("sweep", &stats);
    assert!(
        stats.failures.is_empty(),
        "{} failures",
        stats.failures.len()
    );
    assert!(
        stats.worst_sigma_ratio <= 10.0,
        "a noisy point {:.1} of its sigmas off",
        stats.worst_sigma_ratio
    );
}
