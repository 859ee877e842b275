//! Sweeps along a path of poses (issue 38, `BaseMotion::Path`), checked against truths the
//! path's sweep does not compute:
//! - a translation written as a path is `translate` (the rows at the same base positions);
//! - a pure turn written as a path is `rotate`;
//! - a constant k given along the path is the whisker's own spring;
//! - the linear limit with a follicle that stiffens along the turn: a straight uniform
//!   whisker whisked against a peg at distance r, its follicle of compliance c(p): the beam
//!   turns by `d_eff = phi0 - pi/2 - gamma_t` and `MA = 3 d_eff / r` (the cantilever of
//!   length r), so `MA = 3 (gamma - gamma_t) / (r + 3 c)` in closed form;
//! - a seeded battery of random polylines (2-6 rows) mixing turn and translation, past pegs,
//!   discs and graphs, flows at angles, springs and a stiffening or softening k(p): every
//!   row re-integrated from its own pose and observables by RK4 from the base (another
//!   integrator, the other direction), the base law `phi0 = pi/2 + gamma - MA/k(p)` row by
//!   row, the rows' poses on the path and advancing along it.
//!
//! `cargo test -p contact-sim --test it -- path:: --ignored --nocapture` runs the full seeded
//! battery and prints its figures; the default run takes a small subset.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{
    sweep, BaseMotion, ContactLaw, Phase, Pose, Poses, Profile, Separation, SweepPoint,
    SweepResult, SweepSettings,
};
use std::f64::consts::FRAC_PI_2;

// the battery's scene, generator, first draws, obstacle, worst-case slot and RK4 checker,
// shared with the whisking battery
use crate::whisking::{check_contact_row, obstacle, worse, ContactSlots, Rng, Scene, Start};

fn pose(x0: f64, y0: f64, gamma: f64) -> Pose {
    Pose { x0, y0, gamma }
}

fn along(poses: Vec<Pose>, k: Option<Vec<f64>>, points: usize) -> SweepSettings {
    SweepSettings {
        points,
        motion: BaseMotion::Path(Poses::new(poses, k).unwrap()),
        ..SweepSettings::default()
    }
}

/// The largest difference of the contact rows' observables of two sweeps with as many rows.
fn max_row_diff(a: &SweepResult, b: &SweepResult) -> f64 {
    let (ra, rb): (Vec<_>, Vec<_>) = (a.contact_points().collect(), b.contact_points().collect());
    assert_eq!(ra.len(), rb.len(), "{} vs {} rows", ra.len(), rb.len());
    let mut worst: f64 = 0.0;
    for (p, q) in ra.iter().zip(&rb) {
        assert_eq!(p.phase, q.phase);
        for (u, v) in [
            (p.x0, q.x0),
            (p.y0, q.y0),
            (p.gamma, q.gamma),
            (p.ma, q.ma),
            (p.ax, q.ax),
            (p.ay, q.ay),
            (p.phi0, q.phi0),
            (p.f, q.f),
            (p.s1, q.s1),
            (p.xc, q.xc),
        ] {
            worst = worst.max((u - v).abs());
        }
    }
    worst
}

/// A translation written as a 2-row path (x0 from beyond the touch to beyond the
/// separation) is `translate`: the same first touch (the scan's against the flank's exact
/// one), the same separation, the same rows (evenly spaced in p is evenly spaced in x0).
#[test]
fn wpath_a_translation_written_as_a_path_is_translate() {
    let whisker = Whisker::new(0.6, 0.3, 0.2, 20.0);
    let flow = FluidLoad { q: 2.0, alpha: 0.3 };
    for spec in ["g2", "disc:0.1,1.3,0.45", "peg:-0.1,0.8"] {
        let profile = Profile::parse(spec).unwrap();
        let settings = SweepSettings {
            points: 30,
            ..SweepSettings::default()
        };
        let t = sweep(&whisker, flow, &profile, &settings).unwrap();
        let x_touch = t.first_touch.x0;
        let path = along(
            vec![pose(x_touch + 0.4, 0.0, 0.0), pose(x_touch - 5.0, 0.0, 0.0)],
            None,
            30,
        );
        let p = sweep(&whisker, flow, &profile, &path).unwrap();
        assert!(
            (p.first_touch.x0 - x_touch).abs() < 1e-9,
            "{spec}: {}",
            p.first_touch.x0 - x_touch
        );
        assert_eq!(p.separation, t.separation, "{spec}");
        assert_eq!(p.phase_pattern(), t.phase_pattern(), "{spec}");
        let d = max_row_diff(&t, &p);
        println!("{spec}: rows differ by {d:.2e}");
        assert!(d < 1e-9, "{spec}: {d:e}");
    }
}

/// A pure turn written as a path is `rotate` from the same start.
#[test]
fn wpath_a_turn_written_as_a_path_is_rotate() {
    let whisker = Whisker::new(0.7, -0.5, 0.3, 15.0);
    let flow = FluidLoad {
        q: 1.5,
        alpha: -0.2,
    };
    for spec in ["disc:-0.5,0.8,0.15", "peg:-0.2,0.6"] {
        let profile = Profile::parse(spec).unwrap();
        let rot = SweepSettings {
            points: 25,
            motion: BaseMotion::Rotate {
                x0: 0.05,
                y0: -0.1,
                gamma0: -0.2,
            },
            ..SweepSettings::default()
        };
        let r = sweep(&whisker, flow, &profile, &rot).unwrap();
        let path = along(
            vec![pose(0.05, -0.1, -0.2), pose(0.05, -0.1, 3.0)],
            None,
            25,
        );
        let p = sweep(&whisker, flow, &profile, &path).unwrap();
        assert!((p.first_touch.gamma - r.first_touch.gamma).abs() < 1e-9);
        assert_eq!(p.separation, r.separation, "{spec}");
        let d = max_row_diff(&r, &p);
        println!("{spec}: rows differ by {d:.2e}");
        assert!(d < 1e-9, "{spec}: {d:e}");
    }
}

/// A constant k given along the path is the whisker's own spring: the same rows.
#[test]
fn wpath_a_constant_k_along_the_path_is_the_plain_spring() {
    let flow = FluidLoad { q: 1.0, alpha: 0.1 };
    let disc = Profile::parse("disc:-0.4,0.75,0.2").unwrap();
    let poses = vec![pose(0.1, 0.0, -0.1), pose(0.0, 0.1, 0.9)];
    let sprung = Whisker::new(0.6, 0.3, 0.2, 20.0);
    let rigid = Whisker::new(0.6, 0.3, 0.2, f64::INFINITY);
    let a = sweep(&sprung, flow, &disc, &along(poses.clone(), None, 30)).unwrap();
    let b = sweep(
        &rigid,
        flow,
        &disc,
        &along(poses, Some(vec![20.0, 20.0]), 30),
    )
    .unwrap();
    assert_eq!(a.separation, b.separation);
    let d = max_row_diff(&a, &b);
    assert!(d < 1e-10, "{d:e}");
    assert!(b.points.iter().all(|p| p.k == Some(20.0)));
    assert!(a.points.iter().all(|p| p.k.is_none()));
}

/// The linear limit with a follicle that stiffens along the turn (k from 10 to 80 over a
/// turn of 2 rad, linear in the compliance): a straight uniform whisker (no flow) turned about the origin against
/// the peg (-0.2, 0.6) at `r = sqrt(0.4)`. The touch comes at the peg's angle
/// `gamma_t = atan(1/3)` (no load before it: the follicle does not matter); the beam, a
/// cantilever of length r, turns by `d_eff = phi0 - pi/2 - gamma_t` and carries
/// `MA = 3 d_eff / r`; the follicle yields `MA/k`, so `MA = 3 (gamma - gamma_t) / (r + 3/k)`
/// in closed form; both to second order in the turn. The base law holds row by row.
#[test]
fn wpath_linear_limit_with_a_stiffening_follicle() {
    let whisker = Whisker::new(1.0, 0.0, 0.0, f64::INFINITY);
    let flow = FluidLoad { q: 0.0, alpha: 0.0 };
    let peg = Profile::parse("peg:-0.2,0.6").unwrap();
    let r = 0.4f64.sqrt();
    let gamma_t = 0.2f64.atan2(0.6);
    let (k0, k1) = (10.0, 80.0);
    let settings = along(
        vec![pose(0.0, 0.0, 0.0), pose(0.0, 0.0, 2.0)],
        Some(vec![k0, k1]),
        200,
    );
    let res = sweep(&whisker, flow, &peg, &settings).unwrap();
    assert!((res.first_touch.gamma - gamma_t).abs() < 1e-9);
    assert!((res.first_touch.s - r).abs() < 1e-7);
    println!("separation: {}", res.separation);
    let (mut checked, mut worst_beam, mut worst_closed, mut worst_law) =
        (0, 0.0f64, 0.0f64, 0.0f64);
    for p in res.contact_points() {
        let k = p.k.unwrap();
        // k along the path: the compliance linear in p = gamma / 2
        let c = (1.0 - p.gamma / 2.0) / k0 + p.gamma / 2.0 / k1;
        assert!((1.0 / k - c).abs() < 1e-14, "{k} at gamma {}", p.gamma);
        worst_law = worst_law.max((p.phi0 - (FRAC_PI_2 + p.gamma - p.ma / k)).abs());
        let d = p.gamma - gamma_t;
        let d_eff = p.phi0 - FRAC_PI_2 - gamma_t;
        if d <= 0.0 || d > 0.05 {
            continue;
        }
        checked += 1;
        let beam = (p.ma.abs() - 3.0 * d_eff / r) / (3.0 * d_eff / r);
        let closed = 3.0 * d / (r + 3.0 / k);
        let rel = (p.ma.abs() - closed) / closed;
        assert!(beam.abs() < 0.5 * d * d, "beam at d = {d}: {beam:e}");
        assert!(rel.abs() < 0.5 * d * d, "closed form at d = {d}: {rel:e}");
        assert!(d_eff < d, "the follicle yields: {d_eff} vs {d}");
        worst_beam = worst_beam.max(beam.abs() / (d * d));
        worst_closed = worst_closed.max(rel.abs() / (d * d));
    }
    assert!(checked >= 5, "{checked}");
    assert!(worst_law < 1e-12, "{worst_law:e}");
    println!(
        "stiffening follicle: {checked} rows, |rel. dev.|/d^2 <= {worst_beam:.3} (beam), {worst_closed:.3} (closed form); base law {worst_law:.1e}"
    );
}

/// A polyline: a translation then a turn about the corner's base. A row lands exactly on
/// the corner (its pose the corner's to rounding), the rows advance along the path, the
/// grid is even in p (the gaps between the grid's rows equal, the corner and switch rows
/// extra), and the rows pass the independent check.
#[test]
fn wpath_rows_land_on_the_corners() {
    let whisker = Whisker::new(0.6, 0.3, 0.2, 20.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let disc = Profile::parse("disc:-0.1,0.85,0.15").unwrap();
    let corner = pose(-0.3, 0.0, 0.0);
    let path = vec![pose(0.3, 0.0, 0.0), corner, pose(-0.3, 0.05, 0.9)];
    let scene = Scene {
        name: "corner".into(),
        whisker,
        flow,
        profile: disc,
        settings: along(path, None, 40),
    };
    let r = sweep(&scene.whisker, scene.flow, &scene.profile, &scene.settings).unwrap();
    let BaseMotion::Path(poses) = &scene.settings.motion else {
        unreachable!()
    };
    let ps: Vec<f64> = r.contact_points().map(|p| param_of(poses, p).0).collect();
    assert!(ps[0] < 1.0 && *ps.last().unwrap() > 1.0, "{ps:?}");
    let on = r
        .contact_points()
        .filter(|p| (p.x0 - corner.x0).abs() + p.y0.abs() + p.gamma.abs() < 1e-12)
        .count();
    assert_eq!(on, 1, "rows on the corner");
    // the grid: (points - 1) equal gaps from the first to the last contact row
    let h = (ps.last().unwrap() - ps[0]) / 39.0;
    let on_grid = ps
        .iter()
        .filter(|p| {
            let k = (*p - ps[0]) / h;
            (k - k.round()).abs() < 1e-9
        })
        .count();
    assert!(on_grid >= 40, "{on_grid} rows on the grid of {}", ps.len());
    let mut fig = Figures::default();
    check_rows(&scene, &r, &mut fig).unwrap();
    assert!(fig.resolve.0 < 1e-8 && fig.base_law.0 < 2e-11, "{fig:?}");
}

/// A path that ends while the whisker still touches ends the sweep at its last row, with
/// the reason said; with friction too.
#[test]
fn wpath_a_path_ending_in_contact_ends_the_sweep_there() {
    let whisker = Whisker::new(0.6, 0.3, 0.2, 20.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.0 };
    let disc = Profile::parse("disc:-0.4,0.75,0.2").unwrap();
    let settings = along(vec![pose(0.0, 0.0, 0.0), pose(0.0, 0.0, 0.5)], None, 20);
    let full = sweep(
        &whisker,
        flow,
        &disc,
        &along(vec![pose(0.0, 0.0, 0.0), pose(0.0, 0.0, 3.0)], None, 20),
    )
    .unwrap();
    assert!(
        full.contact_points().last().unwrap().gamma > 0.5,
        "the contact goes on past 0.5"
    );
    let r = sweep(&whisker, flow, &disc, &settings).unwrap();
    assert_eq!(r.separation, Separation::PathEnd);
    assert_eq!(r.separation.to_string(), "end of the path");
    let last = r.points.last().unwrap();
    assert!((last.gamma - 0.5).abs() < 1e-12 && last.f > 0.0, "{last:?}");
    let s = SweepSettings {
        contact_law: ContactLaw::Coulomb { mu: 0.3 },
        ..settings
    };
    let f = sweep(&whisker, flow, &disc, &s).unwrap();
    assert_eq!(f.separation, Separation::PathEnd);
    let last = f.points.last().unwrap();
    assert!((last.gamma - 0.5).abs() < 1e-12 && last.f > 0.0, "{last:?}");
    assert!(last.ft.abs() <= 0.3 * last.f + 1e-12, "{last:?}");
}

/// A random scene: a whisker (theta 0.3..1, pre-curvature of both signs, rigid or a spring),
/// a flow (q 0..3 at -45..45 degrees), a random polyline of 2-6 poses from near the origin
/// (each segment turning by -0.1..0.9 rad and moving by up to 0.3 in x (mostly towards -x)
/// and 0.15 in y), half of them with k along the path (5..60, a tenth of the rows rigid:
/// stiffening and softening), and an obstacle (peg 40 %, disc 40 %, parabola 20 %) placed
/// ahead of the start as in the whisking battery.
pub(crate) fn random_scene(rng: &mut Rng, i: usize) -> Scene {
    let st = Start::draw(rng);
    let (bx, by, gamma0) = (st.bx, st.by, st.gamma0);
    let rows = 2 + (rng.next() * 5.0) as usize;
    let mut poses = vec![pose(bx, by, gamma0)];
    for _ in 1..rows {
        let last = *poses.last().unwrap();
        poses.push(pose(
            last.x0 + rng.range(-0.3, 0.1),
            last.y0 + rng.range(-0.15, 0.15),
            last.gamma + rng.range(-0.1, 0.9),
        ));
    }
    let ks = (rng.next() < 0.5).then(|| {
        (0..rows)
            .map(|_| {
                if rng.next() < 0.1 {
                    f64::INFINITY
                } else {
                    rng.range(5.0, 60.0)
                }
            })
            .collect::<Vec<_>>()
    });
    let d = rng.range(0.35, 0.85);
    let ang = gamma0 + rng.range(0.25, 0.9);
    let kind = rng.next();
    let profile = obstacle(rng, kind, (bx, by), d, ang);
    let settings = SweepSettings {
        points: 20,
        motion: BaseMotion::Path(Poses::new(poses, ks.clone()).unwrap()),
        ..SweepSettings::default()
    };
    Scene {
        name: format!(
            "#{i} path of {rows} from ({bx:.3}, {by:.3}, {gamma0:.3}) k {} past {} {}",
            if ks.is_some() { "along" } else { "fixed" },
            profile.name(),
            st.describe()
        ),
        whisker: st.whisker,
        flow: st.flow,
        profile,
        settings,
    }
}

/// Worst deviations of a battery.
#[derive(Debug, Default)]
struct Figures {
    rows: usize,
    /// Free-end moment and contact point of the RK4 integration from the base.
    resolve: (f64, String),
    /// The contact point's clearance from the obstacle.
    on_obstacle: (f64, String),
    /// The phase condition (tangency in B; tip steeper than the boundary in A).
    phase: (f64, String),
    /// The base law phi0 = pi/2 + gamma - MA/k(p).
    base_law: (f64, String),
    /// The row's pose off the path.
    off_path: (f64, String),
    /// The deepest point of the rest of the whisker inside the obstacle.
    penetration: (f64, String),
}

/// The path parameter of a row's pose (the nearest point of the polyline in `(x0, y0,
/// gamma)`) and the pose's distance from it.
fn param_of(path: &Poses, p: &SweepPoint) -> (f64, f64) {
    let mut best = (f64::NAN, f64::INFINITY);
    for (i, w) in path.poses.windows(2).enumerate() {
        let d = [
            w[1].x0 - w[0].x0,
            w[1].y0 - w[0].y0,
            w[1].gamma - w[0].gamma,
        ];
        let e = [p.x0 - w[0].x0, p.y0 - w[0].y0, p.gamma - w[0].gamma];
        let dd: f64 = d.iter().map(|v| v * v).sum();
        let t = (d.iter().zip(&e).map(|(a, b)| a * b).sum::<f64>() / dd).clamp(0.0, 1.0);
        let off = (0..3)
            .map(|j| (e[j] - t * d[j]).powi(2))
            .sum::<f64>()
            .sqrt();
        if off < best.1 {
            best = (i as f64 + t, off);
        }
    }
    best
}

/// Checks every row of `r` independently of the sweep's solver: on the path and advancing
/// along it, k the path's at the row's p, the base law with it, and in contact the
/// re-integration from the base, the contact point on the obstacle, the phase condition, the
/// force balance and no other point inside the obstacle.
fn check_rows(s: &Scene, r: &SweepResult, fig: &mut Figures) -> Result<(), String> {
    let BaseMotion::Path(path) = &s.settings.motion else {
        return Err("not a path".into());
    };
    let mut before = f64::NEG_INFINITY;
    for (i, p) in r.points.iter().enumerate() {
        let at = || {
            format!(
                "{} row {i} (pose {:.6}, {:.6}, {:.6}, phase {})",
                s.name, p.x0, p.y0, p.gamma, p.phase
            )
        };
        let (param, off) = param_of(path, p);
        worse(&mut fig.off_path, off, at);
        if param <= before {
            return Err(format!("{}: p {param} after {before}", at()));
        }
        before = param;
        let compliance = match (path.k(param), p.k) {
            (Some(k), Some(row_k)) => {
                if ((1.0 / k) - (1.0 / row_k)).abs() > 1e-9 {
                    return Err(format!("{}: k {row_k} vs the path's {k}", at()));
                }
                1.0 / row_k
            }
            (None, None) => s.whisker.support.compliance(),
            _ => return Err(format!("{}: k {:?}", at(), p.k)),
        };
        let law = (p.phi0 - (FRAC_PI_2 + p.gamma - p.ma * compliance)).abs();
        worse(&mut fig.base_law, law, at);
        if p.phase == Phase::None {
            continue;
        }
        fig.rows += 1;
        let slots = ContactSlots {
            resolve: &mut fig.resolve,
            on_obstacle: &mut fig.on_obstacle,
            phase: &mut fig.phase,
            penetration: &mut fig.penetration,
        };
        check_contact_row(s, p, slots, at)?;
    }
    Ok(())
}

/// Runs `count` random scenes from `seed`; refusals are counted by kind ("no contact" along
/// the path is the draw's doing; any other refusal fails the battery unless allowed).
fn run_battery(count: usize, seed: u64) {
    let mut rng = Rng(seed);
    let mut fig = Figures::default();
    let (mut swept, mut refused) = (0, Vec::new());
    let mut separations = std::collections::BTreeMap::new();
    let only = std::env::var("VIBRISSA_PATH_SCENE").ok();
    for i in 0..count {
        let s = random_scene(&mut rng, i);
        if only.as_ref().is_some_and(|o| *o != i.to_string()) {
            continue;
        }
        match sweep(&s.whisker, s.flow, &s.profile, &s.settings) {
            Ok(r) => {
                swept += 1;
                *separations.entry(r.separation.to_string()).or_insert(0) += 1;
                if let Err(e) = check_rows(&s, &r, &mut fig) {
                    panic!("{e}");
                }
            }
            Err(e) => refused.push(format!("{}: {e}", s.name)),
        }
    }
    let mut kinds = std::collections::BTreeMap::new();
    for r in &refused {
        let kind = if r.contains("does not touch") {
            "no contact along the path"
        } else if r.contains("starts inside") {
            "starts inside"
        } else {
            "other"
        };
        *kinds.entry(kind).or_insert(0) += 1;
    }
    println!(
        "{count} scenes: {swept} swept, {} refused {kinds:?}; separations {separations:?}",
        refused.len()
    );
    for r in refused
        .iter()
        .filter(|r| !r.contains("does not touch") && !r.contains("starts inside"))
    {
        println!("  refused {r}");
    }
    println!("{} contact rows; worst:", fig.rows);
    for (name, v) in [
        ("re-integration from the base", &fig.resolve),
        ("contact point off the obstacle", &fig.on_obstacle),
        ("phase condition", &fig.phase),
        ("base law", &fig.base_law),
        ("pose off the path", &fig.off_path),
        ("penetration", &fig.penetration),
    ] {
        println!("  {name} {:.2e} at {}", v.0, v.1);
    }
    let other: Vec<_> = refused
        .iter()
        .filter(|r| !r.contains("no contact"))
        .collect();
    assert!(other.is_empty(), "{other:?}");
    assert!(fig.resolve.0 < 1e-8, "{:?}", fig.resolve);
    assert!(fig.on_obstacle.0 < 1e-9, "{:?}", fig.on_obstacle);
    assert!(fig.phase.0 < 1e-8, "{:?}", fig.phase);
    assert!(fig.base_law.0 < 2e-11, "{:?}", fig.base_law);
    // a row at a corner or the path's end is solved there to the corrector's tolerance
    assert!(fig.off_path.0 < 1e-10, "{:?}", fig.off_path);
    assert!(fig.penetration.0 < 1e-6, "{:?}", fig.penetration);
}

#[test]
fn wpath_battery_subset() {
    run_battery(8, 0x5EED_0038_0002);
}

#[test]
#[ignore = "the full path battery: cargo test -p contact-sim --test it -- wpath_battery_full --ignored --nocapture"]
fn wpath_battery_full() {
    run_battery(1000, 0x5EED_0038_0002);
}

/// `--tol` along a path with a corner and a tensing follicle: with the accuracy T asked for
/// every row carries an estimate below T, and its true error (against the default sweep at
/// 1e-12, the same pose to 1e-9) stays below its estimate.
#[test]
fn wpath_rows_carry_error_estimates_that_bound_their_errors() {
    let whisker = Whisker::new(0.6, 0.3, 0.2, f64::INFINITY);
    let flow = FluidLoad { q: 1.0, alpha: 0.2 };
    let disc = Profile::parse("disc:-0.1,0.85,0.15").unwrap();
    let path = vec![
        pose(0.3, 0.0, 0.0),
        pose(-0.3, 0.0, 0.0),
        pose(-0.3, 0.05, 0.9),
    ];
    let ks = Some(vec![15.0, 30.0, 60.0]);
    let exact = sweep(&whisker, flow, &disc, &along(path.clone(), ks.clone(), 25)).unwrap();
    let mut checked = 0;
    for tol in [1e-4, 1e-7] {
        let s = SweepSettings {
            accuracy: Some(tol),
            ..along(path.clone(), ks.clone(), 25)
        };
        let r = sweep(&whisker, flow, &disc, &s).unwrap();
        let acc = r.accuracy.as_ref().unwrap();
        assert_eq!(acc.estimates.len(), r.points.len());
        for (p, e) in r.points.iter().zip(&acc.estimates) {
            assert!(*e <= tol, "estimate {e:e} above {tol:e}");
            let Some(q) = exact.points.iter().find(|q| {
                (q.x0 - p.x0).abs() + (q.y0 - p.y0).abs() + (q.gamma - p.gamma).abs() < 1e-9
                    && q.phase == p.phase
            }) else {
                continue;
            };
            let err = [p.ma - q.ma, p.ax - q.ax, p.ay - q.ay, p.phi0 - q.phi0]
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(err <= e.max(1e-11), "T {tol:e}: {err:e} > {e:e}");
            checked += 1;
        }
    }
    assert!(checked >= 40, "{checked}");
}
