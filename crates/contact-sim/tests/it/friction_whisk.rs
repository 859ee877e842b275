//! Coulomb friction against pegs and discs and with whisking (issues 38 and 39 at their
//! seam, docs/friction-whisk.md), checked against truths the sweep does not compute:
//! - `mu = 0` is the frictionless sweep bit for bit (rotate, peg, disc);
//! - the limit `mu -> 0`: at `mu = 1e-8` the frictional solver gives the frictionless rows of a
//!   whisking sweep against a peg and a translation past a disc, row for row;
//! - a peg in stick: the contact point is the peg and the touching material point does not
//!   move, `s1` constant from row to row;
//! - a turn written as a path (one segment, and three with two corners in the contact) is
//!   `rotate` with friction;
//! - a seeded battery over the whisking battery's scenes (rotations about a base anywhere
//!   near the origin past pegs, discs and parabolas, translations past pegs and discs) and,
//!   one in four, the path battery's (random polylines of poses, k along half of them) with
//!   `mu` in `[0, 1.5]`: every row re-integrated from its own pose and base observables by
//!   the friction battery's RK4 elastica (not beam-model's): equilibrium (free-end moment, the
//!   loaded end on the contact point), the contact point on the obstacle, tangency in
//!   tangential contact and the tip steeper than the boundary in tip contact, the turned
//!   follicle law `phi0 = pi/2 + gamma - MA/k` (k the path's where it sets it), the observables as the balance of
//!   `F = fn n + ft t`, the force in the cone (on its edge in slip), the slip law between
//!   consecutive rows (the material point's displacement `d sigma - d s1` zero from a stuck
//!   row, against `ft` from a sliding one; `sigma` the contour's arc length, `r dpsi` on a
//!   disc, none on a peg), no penetration, and the motion advancing.
//!
//! `cargo test -p contact-sim --release --test it -- friction_whisk:: --ignored --nocapture`
//! runs the full battery and prints its figures; the default run takes a seeded subset.

use crate::friction::{contour_arc, elastica_to, Scene as Bare};
use crate::whisking::{random_whisking_scene as random_scene, Rng, Scene};
use beam_model::{FluidLoad, Whisker};
use contact_sim::{
    sweep, BaseMotion, ContactError, ContactLaw, Phase, Pose, Poses, Profile, SlipState,
    SweepPoint, SweepResult, SweepSettings,
};
use std::f64::consts::{FRAC_PI_2, PI};

/// The force on the whisker `fn n + ft t`, `n = (sin psi, -cos psi)`, `t = (cos psi, sin psi)`.
fn force(p: &SweepPoint) -> (f64, f64) {
    let (sp, cp) = p.psi.sin_cos();
    (p.f * sp + p.ft * cp, -p.f * cp + p.ft * sp)
}

/// An angle difference wrapped into `[-pi, pi)` (a disc's contour angle runs over all reals).
fn wrap(d: f64) -> f64 {
    (d + PI).rem_euclid(2.0 * PI) - PI
}

/// The contour's arc length from row `a`'s contact point to `b`'s, oriented with the
/// contour's tangent `(cos psi, sin psi)`: none on a peg, `r dpsi` on a disc, the graph's
/// polyline length towards +x otherwise.
fn dsigma(profile: &Profile, a: &SweepPoint, b: &SweepPoint) -> f64 {
    match *profile {
        Profile::Peg { .. } => 0.0,
        Profile::Disc { r, .. } => r * wrap(b.psi - a.psi),
        _ => contour_arc(profile, a.xc, b.xc),
    }
}

/// Worst deviations of a battery: (value, where).
#[derive(Debug, Default)]
struct Figures {
    rows: usize,
    stick_rows: usize,
    slip_rows: usize,
    b_rows: usize,
    events: usize,
    /// intervals between two stuck rows on a peg, and the largest change of s1 over them
    peg_stick_intervals: usize,
    equilibrium: (f64, String),
    on_obstacle: (f64, String),
    phase: (f64, String),
    tangency: (f64, String),
    follicle: (f64, String),
    balance: (f64, String),
    cone: (f64, String),
    edge: (f64, String),
    stuck: (f64, String),
    peg_stuck: (f64, String),
    against: (f64, String),
    penetration: (f64, String),
}

fn worse(slot: &mut (f64, String), v: f64, at: impl Fn() -> String) {
    if v > slot.0 || v.is_nan() {
        *slot = (v, at());
    }
}

/// Checks every row of a frictional sweep (any motion, any obstacle) independently of the
/// sweep's solver.
fn check(s: &Scene, mu: f64, r: &SweepResult, fig: &mut Figures) -> Result<(), String> {
    for w in r.points.windows(2) {
        // (a path may turn back: its parameter is not in the rows; the path battery's own)
        let advancing = match s.settings.motion {
            BaseMotion::Translate => w[1].x0 < w[0].x0,
            BaseMotion::Rotate { .. } => w[1].gamma > w[0].gamma,
            BaseMotion::Path(_) => true,
        };
        if !advancing {
            return Err(format!(
                "{}: the motion does not advance: {:?} then {:?}",
                s.name, w[0], w[1]
            ));
        }
    }
    fig.events += r.friction_events.len();
    let bare = Bare {
        whisker: s.whisker,
        flow: s.flow,
        profile: s.profile.clone(),
    };
    let (sa, ca) = s.flow.alpha.sin_cos();
    let q = s.flow.q;
    let compliance = s.whisker.support.compliance();
    let mut prev: Option<&SweepPoint> = None;
    for (i, p) in r.points.iter().enumerate() {
        let at = || {
            format!(
                "{} mu={mu:.3} row {i} (x0 {:.6}, gamma {:.6}, phase {}, {:?})",
                s.name, p.x0, p.gamma, p.phase, p.slip
            )
        };
        // the follicle law turned by gamma (and tensed where a path sets k), every row
        let c = p.k.map_or(compliance, |k| 1.0 / k);
        let law = (p.phi0 - (FRAC_PI_2 + p.gamma - p.ma * c)).abs();
        worse(&mut fig.follicle, law, at);
        if p.phase == Phase::None {
            if p.slip != SlipState::None {
                return Err(format!("{}: a free row with a slip state", at()));
            }
            continue;
        }
        fig.rows += 1;
        match p.slip {
            SlipState::Stick => fig.stick_rows += 1,
            SlipState::Slip => fig.slip_rows += 1,
            SlipState::None => return Err(format!("{}: a contact row without a slip state", at())),
        }
        let tangential = p.phase == Phase::B;
        if tangential {
            fig.b_rows += 1;
            // (s1 = 1 where the tip passes a peg; a snap where the tip would leave a disc's
            // tangential contact ends on the phase's end located to the event tolerance)
            if !(p.s1 > 0.0 && p.s1 <= 1.0 + 1e-9) {
                return Err(format!("{}: s1 {} outside (0, 1]", at(), p.s1));
            }
        } else if p.s1 != 1.0 {
            return Err(format!("{}: tip contact at s1 {}", at(), p.s1));
        }
        if p.f < -1e-12 {
            return Err(format!("{}: fn = {}", at(), p.f));
        }
        let scale = 1f64.max(p.f.hypot(p.ft)).max(p.ma.abs());
        let (fx, fy) = force(p);
        let bal = (p.ax + fx + q * p.s1 * ca)
            .abs()
            .max((p.ay + fy - q * p.s1 * sa).abs());
        worse(&mut fig.balance, bal / scale, at);
        // equilibrium from the base pose and observables: the loaded end s1 carries no
        // moment and lies on the contact point
        let n = 4000;
        let tr = elastica_to(&bare, (fx, fy), [p.phi0, -p.ma, p.x0, p.y0], n, p.s1);
        let e = tr[n];
        let eq = e[2].abs().max((e[3] - p.xc).abs()).max((e[4] - p.yc).abs());
        worse(&mut fig.equilibrium, eq / scale, at);
        worse(
            &mut fig.on_obstacle,
            s.profile.clearance(p.xc, p.yc).abs(),
            at,
        );
        if tangential {
            worse(&mut fig.tangency, wrap(e[1] - p.psi).abs(), at);
        } else {
            worse(&mut fig.phase, wrap(p.psi - e[1]).max(0.0), at);
        }
        worse(&mut fig.cone, (p.ft.abs() - mu * p.f).max(0.0) / scale, at);
        if p.slip == SlipState::Slip {
            worse(&mut fig.edge, (p.ft.abs() - mu * p.f).abs() / scale, at);
        }
        // the slip law between consecutive contact rows
        if let Some(a) = prev {
            let ds = dsigma(&s.profile, a, p);
            let chord = ds - (p.s1 - a.s1);
            let dsd = p.slip_distance - a.slip_distance;
            if (dsd - chord).abs() > 1e-6 * ds.abs() + 1e-9 {
                return Err(format!(
                    "{}: slip displacement {dsd:e} against the material point's {chord:e}",
                    at()
                ));
            }
            match a.slip {
                SlipState::Stick => {
                    worse(&mut fig.stuck, chord.abs(), at);
                    if s.profile.is_peg() && p.slip == SlipState::Stick {
                        fig.peg_stick_intervals += 1;
                        worse(&mut fig.peg_stuck, (p.s1 - a.s1).abs(), at);
                    }
                }
                _ => {
                    let ft = if p.ft.abs() > a.ft.abs() { p.ft } else { a.ft };
                    worse(&mut fig.against, chord * ft.signum() / scale, at);
                }
            }
        }
        prev = Some(p);
        // no other point inside the obstacle (nothing enters a peg)
        if !s.profile.is_peg() {
            for v in tr.iter().filter(|v| (v[0] - p.s1).abs() >= 2e-3) {
                worse(&mut fig.penetration, -s.profile.clearance(v[3], v[4]), at);
            }
        }
    }
    Ok(())
}

fn assert_figures(f: &Figures) {
    assert!(f.equilibrium.0 < 1e-7, "{f:#?}");
    assert!(f.on_obstacle.0 < 1e-10, "{f:#?}");
    assert!(f.phase.0 < 1e-9, "{f:#?}");
    assert!(f.tangency.0 < 1e-8, "{f:#?}");
    assert!(f.follicle.0 < 1e-9, "{f:#?}");
    assert!(f.balance.0 < 1e-12, "{f:#?}");
    assert!(f.cone.0 < 1e-9, "{f:#?}");
    assert!(f.edge.0 < 1e-9, "{f:#?}");
    assert!(f.stuck.0 < 1e-9, "{f:#?}");
    assert!(f.peg_stuck.0 < 1e-9, "{f:#?}");
    assert!(f.against.0 < 1e-12, "{f:#?}");
    assert!(f.penetration.0 < 1e-9, "{f:#?}");
}

/// How a battery's scenes ended.
#[derive(Debug, Default)]
struct Tally {
    swept: usize,
    /// the frictionless sweep of the scene refuses too (no contact within the turn, ...)
    refused_both: usize,
    /// no quasi-static continuation ([`ContactError::FrictionIndeterminate`])
    indeterminate: usize,
    /// other refusals of a scene the frictionless sweep follows
    other: Vec<String>,
}

/// Runs `count` scenes of the whisking battery from `seed`, each with `mu` drawn in
/// `[0, 1.5]` and `points` rows; prints the figures.
fn battery(count: usize, seed: u64, points: usize) -> (Figures, Tally) {
    let mut rng = Rng(seed);
    let mut fig = Figures::default();
    let mut tally = Tally::default();
    for i in 0..count {
        // one scene in four along a random path of poses (the path battery's scenes)
        let mut sc = if i % 4 == 3 {
            crate::path::random_scene(&mut rng, i)
        } else {
            random_scene(&mut rng, i)
        };
        let mu = rng.range(0.0, 1.5);
        // `FW_SCENE=N` runs scene N alone (its rows printed)
        let only = std::env::var("FW_SCENE")
            .ok()
            .and_then(|v| v.parse::<usize>().ok());
        if only.is_some_and(|n| n != i) {
            continue;
        }
        if only.is_some() {
            eprintln!("{} mu={mu}: {:?}", sc.name, sc.settings.motion);
        }
        sc.settings.points = points;
        let plain = sc.settings.clone();
        sc.settings.contact_law = ContactLaw::Coulomb { mu };
        match sweep(&sc.whisker, sc.flow, &sc.profile, &sc.settings) {
            Ok(r) => {
                tally.swept += 1;
                eprintln!(
                    "{} mu={mu:.3}: {} rows {}, {}, {} switches",
                    sc.name,
                    r.phase_pattern(),
                    r.points.len(),
                    r.separation,
                    r.friction_events.len()
                );
                if only.is_some() {
                    for (k, q) in r.points.iter().enumerate() {
                        eprintln!("{k} x0 {:.6} y0 {:.6} g {:.6} {} {:?} s1 {:.9} f {:.4e} ft {:.4e} sd {:.9e}", q.x0, q.y0, q.gamma, q.phase, q.slip, q.s1, q.f, q.ft, q.slip_distance);
                    }
                }
                if let Err(e) = check(&sc, mu, &r, &mut fig) {
                    panic!("{e}");
                }
            }
            Err(e) => {
                let both = sweep(&sc.whisker, sc.flow, &sc.profile, &plain).is_err();
                eprintln!(
                    "{} mu={mu:.3}: refused ({}): {e}",
                    sc.name,
                    if both {
                        "frictionless too"
                    } else {
                        "frictional only"
                    }
                );
                match e {
                    _ if both => tally.refused_both += 1,
                    ContactError::FrictionIndeterminate { .. } => tally.indeterminate += 1,
                    e => tally.other.push(format!("{} mu={mu:.3}: {e}", sc.name)),
                }
            }
        }
    }
    eprintln!("friction-whisk battery (seed {seed:#x}, {count} scenes): {tally:#?}\n{fig:#?}");
    (fig, tally)
}

/// A seeded subset of the battery in the suite.
#[test]
fn battery_subset() {
    let (fig, tally) = battery(12, 0xF1_5C, 12);
    assert!(tally.other.is_empty(), "{tally:#?}");
    assert!(tally.swept >= 8 && fig.rows > 60, "{tally:#?} {fig:#?}");
    assert_figures(&fig);
}

/// The full battery: `cargo test -p contact-sim --release --test it -- friction_whisk::
/// --ignored --nocapture`.
#[test]
#[ignore = "the full battery: cargo test -p contact-sim --release --test it -- friction_whisk:: --ignored --nocapture"]
fn battery_full() {
    let (fig, tally) = battery(300, 0xF1_5C, 30);
    assert!(tally.other.is_empty(), "{tally:#?}");
    assert_figures(&fig);
}

fn rotate(x0: f64, y0: f64, gamma0: f64, points: usize, mu: f64) -> SweepSettings {
    SweepSettings {
        points,
        motion: BaseMotion::Rotate { x0, y0, gamma0 },
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    }
}

fn translate(points: usize, mu: f64) -> SweepSettings {
    SweepSettings {
        points,
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    }
}

/// `mu = 0` runs the frictionless sweep: whisking against a peg and a disc, and a
/// translation past a disc, give the frictionless rows bit for bit, no switches, every row
/// `ft = 0`, `slip = none`.
#[test]
fn mu_zero_is_the_frictionless_sweep_bit_for_bit() {
    let w = Whisker::new(0.5, 0.2, 0.1, 20.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.3 };
    for (spec, law) in [
        ("peg:-0.2,0.6", rotate(0.0, 0.0, 0.0, 15, 0.0)),
        ("disc:-0.3,0.8,0.2", rotate(0.0, 0.0, 0.0, 15, 0.0)),
        ("disc:-0.1,1.0,0.3", translate(15, 0.0)),
    ] {
        let p = Profile::parse(spec).unwrap();
        let plain = SweepSettings {
            contact_law: ContactLaw::Frictionless,
            ..law.clone()
        };
        let a = sweep(&w, flow, &p, &plain).unwrap();
        let b = sweep(&w, flow, &p, &law).unwrap();
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{spec}");
        assert!(b.friction_events.is_empty());
        assert!(b
            .points
            .iter()
            .all(|r| r.ft == 0.0 && r.slip == SlipState::None));
    }
}

/// The limit `mu -> 0`: at `mu = 1e-8` the frictional solver (sliding throughout,
/// `|ft| = mu fn`) gives the frictionless rows at the same coordinate to 1e-6: whisking a
/// tapered spring-mounted whisker under a flow against a peg (tangential contact until the
/// tip passes it) and translating it past a disc.
#[test]
fn mu_to_zero_is_the_frictionless_whisking_sweep() {
    let w = Whisker::new(0.5, 0.2, 0.1, 20.0);
    let flow = FluidLoad { q: 1.0, alpha: 0.3 };
    for (spec, set) in [
        ("peg:-0.2,0.6", rotate(0.0, 0.0, 0.0, 20, 1e-8)),
        ("disc:-0.3,0.8,0.2", rotate(0.0, 0.0, 0.0, 20, 1e-8)),
        ("disc:-0.1,1.0,0.3", translate(20, 1e-8)),
    ] {
        let p = Profile::parse(spec).unwrap();
        let plain = SweepSettings {
            contact_law: ContactLaw::Frictionless,
            ..set.clone()
        };
        let a = sweep(&w, flow, &p, &plain).unwrap();
        let b = sweep(&w, flow, &p, &set).unwrap();
        assert_eq!(a.phase_pattern(), b.phase_pattern(), "{spec}");
        assert_eq!(a.separation, b.separation, "{spec}");
        let coord = |p: &SweepPoint| {
            if set.motion == BaseMotion::Translate {
                p.x0
            } else {
                p.gamma
            }
        };
        let ra: Vec<_> = a.contact_points().collect();
        let (mut worst, mut compared) = (0.0f64, 0);
        for q in b.contact_points() {
            assert_eq!(q.slip, SlipState::Slip, "{spec}");
            assert!((q.ft.abs() - 1e-8 * q.f).abs() <= 1e-20 + 1e-14 * q.f);
            let Some(p) = ra
                .iter()
                .find(|p| (coord(p) - coord(q)).abs() < 1e-6 && p.phase == q.phase)
            else {
                continue;
            };
            let d = [
                coord(p) - coord(q),
                p.ax - q.ax,
                p.ay - q.ay,
                p.ma - q.ma,
                p.phi0 - q.phi0,
                p.f - q.f,
                p.s1 - q.s1,
                p.xc - q.xc,
            ];
            worst = d.iter().fold(worst, |m, v| m.max(v.abs()));
            compared += 1;
        }
        eprintln!("{spec}: mu = 1e-8 against the frictionless rows: {compared} compared, worst {worst:.2e}");
        assert!(compared >= 15, "{spec}: {compared}");
        assert!(worst < 1e-6, "{spec}: {worst:e}");
    }
}

/// A peg in stick: the contact point is the peg itself and the touching material point stays
/// put, `s1` equal in every stuck row and in the row of the stick -> slip switch (to the
/// solver's tolerance) while the force turns inside the cone to its edge. Whisking pins the
/// material point at a fixed distance from the base (the chord of `[0, s1]` cannot change), so
/// the force along the whisker grows fast and the stick is short: a strongly pre-curved
/// whisker at `mu = 5` holds it longest.
#[test]
fn a_stuck_peg_keeps_its_material_point() {
    let mut stuck_rows = 0;
    for (w, flow, spec, mu) in [
        (
            Whisker::new(0.5, 0.2, 0.1, 20.0),
            FluidLoad { q: 0.5, alpha: 0.0 },
            "peg:-0.2,0.6",
            1.5,
        ),
        (
            Whisker::new(0.6, 2.0, 1.0, 10.0),
            FluidLoad { q: 0.5, alpha: 0.0 },
            "peg:-0.3,0.5",
            5.0,
        ),
    ] {
        let p = Profile::parse(spec).unwrap();
        let set = rotate(0.0, 0.0, 0.0, 20, mu);
        let r = sweep(&w, flow, &p, &set).unwrap();
        let rows: Vec<_> = r.contact_points().collect();
        let n = rows
            .iter()
            .take_while(|q| q.slip == SlipState::Stick)
            .count();
        assert!(n >= 1 && n < rows.len(), "{spec}: {n} stuck rows");
        stuck_rows += n;
        let (first, switch) = (rows[0], rows[n]);
        assert_eq!(
            r.friction_events[0].kind,
            contact_sim::FrictionEventKind::StickToSlip
        );
        let mut drift = 0.0f64;
        for q in &rows[..=n] {
            // the peg itself, exactly
            assert_eq!(p.clearance(q.xc, q.yc), 0.0, "{spec}");
            drift = drift
                .max((q.s1 - first.s1).abs())
                .max(q.slip_distance.abs());
        }
        eprintln!(
            "{spec} mu {mu}: stuck over {n} rows, gamma {:.6}..{:.6} (the switch), s1 drift {drift:.2e}, ft/fn {:.3} at the switch",
            first.gamma,
            switch.gamma,
            switch.ft / switch.f
        );
        assert!(drift < 1e-9, "{spec}: {drift:e}");
        assert!((switch.ft.abs() - mu * switch.f).abs() < 1e-9 * switch.f.max(1.0));
        let sc = Scene {
            name: spec.into(),
            whisker: w,
            flow,
            profile: p,
            settings: set,
        };
        let mut fig = Figures::default();
        check(&sc, mu, &r, &mut fig).unwrap();
        assert_figures(&fig);
    }
    assert!(stuck_rows >= 2);
}

fn turn_path(poses: &[(f64, f64, f64)], points: usize, mu: f64) -> SweepSettings {
    let poses = poses
        .iter()
        .map(|&(x0, y0, gamma)| Pose { x0, y0, gamma })
        .collect();
    SweepSettings {
        points,
        motion: BaseMotion::Path(Poses::new(poses, None).unwrap()),
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    }
}

/// The largest difference of two contact rows' observables, slip displacement and force.
fn row_diff(p: &SweepPoint, q: &SweepPoint) -> f64 {
    [
        (p.x0, q.x0),
        (p.y0, q.y0),
        (p.gamma, q.gamma),
        (p.ma, q.ma),
        (p.ax, q.ax),
        (p.ay, q.ay),
        (p.phi0, q.phi0),
        (p.f, q.f),
        (p.ft, q.ft),
        (p.s1, q.s1),
        (p.xc, q.xc),
        (p.slip_distance, q.slip_distance),
    ]
    .iter()
    .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()))
}

/// A turn written as a path is `rotate` with friction: a single segment from the same start
/// gives the same rows (the same grid in gamma, the same switches, slip states and slip
/// displacement); the turn cut in three segments (two corners inside the contact, a row on
/// each) gives rows that pass the battery's checks and the same stick/slip switch rows.
#[test]
fn a_turn_written_as_a_path_is_rotate_with_friction() {
    let w = Whisker::new(0.7, -0.5, 0.3, 15.0);
    let flow = FluidLoad {
        q: 1.5,
        alpha: -0.2,
    };
    for (spec, mu) in [("disc:-0.5,0.8,0.15", 0.5), ("peg:-0.2,0.6", 0.9)] {
        let profile = Profile::parse(spec).unwrap();
        let rot = rotate(0.05, -0.1, -0.2, 25, mu);
        let r = sweep(&w, flow, &profile, &rot).unwrap();
        let one = turn_path(&[(0.05, -0.1, -0.2), (0.05, -0.1, 3.0)], 25, mu);
        let p = sweep(&w, flow, &profile, &one).unwrap();
        assert_eq!(p.separation, r.separation, "{spec}");
        assert_eq!(p.phase_pattern(), r.phase_pattern(), "{spec}");
        let (ra, rb): (Vec<_>, Vec<_>) =
            (r.contact_points().collect(), p.contact_points().collect());
        assert_eq!(ra.len(), rb.len(), "{spec}");
        let mut worst = 0.0f64;
        for (a, b) in ra.iter().zip(&rb) {
            assert_eq!((a.phase, a.slip), (b.phase, b.slip), "{spec}");
            worst = worst.max(row_diff(a, b));
        }
        assert_eq!(r.friction_events.len(), p.friction_events.len(), "{spec}");
        eprintln!(
            "{spec} mu {mu}: {} rows, {} switches; one-segment path against rotate {worst:.2e}",
            ra.len(),
            r.friction_events.len()
        );
        assert!(worst < 1e-8, "{spec}: {worst:e}");
        // three segments, the corners inside the contact
        let (g0, g1) = (ra[0].gamma, ra[ra.len() - 1].gamma);
        let (c1, c2) = (g0 + 0.3 * (g1 - g0), g0 + 0.7 * (g1 - g0));
        let three = turn_path(
            &[
                (0.05, -0.1, -0.2),
                (0.05, -0.1, c1),
                (0.05, -0.1, c2),
                (0.05, -0.1, 3.0),
            ],
            25,
            mu,
        );
        let t = sweep(&w, flow, &profile, &three).unwrap();
        assert_eq!(t.separation, r.separation, "{spec}");
        let rt: Vec<_> = t.contact_points().collect();
        for c in [c1, c2] {
            assert!(
                rt.iter().any(|q| (q.gamma - c).abs() < 1e-12),
                "{spec}: no row on the corner {c}"
            );
        }
        let switches = |rows: &[&SweepPoint]| -> Vec<SweepPoint> {
            rows.windows(2)
                .filter(|w| w[0].slip != w[1].slip)
                .map(|w| *w[1])
                .collect()
        };
        let (sa, st) = (switches(&ra), switches(&rt));
        assert_eq!(sa.len(), st.len(), "{spec}");
        let mut at_switch = 0.0f64;
        for (a, b) in sa.iter().zip(&st) {
            at_switch = at_switch.max(row_diff(a, b));
        }
        eprintln!(
            "{spec}: three segments, {} rows, switch rows against rotate {at_switch:.2e}",
            rt.len()
        );
        assert!(at_switch < 1e-7, "{spec}: {at_switch:e}");
        let sc = Scene {
            name: format!("{spec} three segments"),
            whisker: w,
            flow,
            profile,
            settings: three,
        };
        let mut fig = Figures::default();
        check(&sc, mu, &t, &mut fig).unwrap();
        assert_figures(&fig);
    }
}
