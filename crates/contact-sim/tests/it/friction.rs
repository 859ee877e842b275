//! Frictional sweeps (`contact_sim::friction`, tip contact) against independent truth:
//! - `mu = 0` is the frictionless sweep bit for bit;
//! - `mu` large: the tip stays pinned where it touched, and every row equals a pinned-tip
//!   elastica solved here from scratch (RK4 from the base, Newton on `(m0, Fx, Fy)` with
//!   finite differences);
//! - the linear limit: a straight uniform clamped whisker pushed along a near-flat inclined
//!   wall slides from the start (its chord cannot grow), and the force lies on the cone's
//!   edge with `Fx = 3 (xc - x0)`, so `fn = 3 (xc - x0) / (sin psi + mu cos psi)` to first order;
//! - a seeded battery: every row re-integrated from its own base observables by the elastica
//!   written out here (not beam-model's), checked for equilibrium (free-end moment, the tip on
//!   the contact point), the contact point on the contour, the tip contact's phase condition,
//!   the follicle law, the observables as the force balance of `F = fn n + ft t`, the force in
//!   the cone (on its edge in slip), the slip law between consecutive rows, and no penetration.
//!
//! `cargo test -p contact-sim --release --test it -- friction:: --ignored --nocapture` runs the full
//! battery and prints its figures; the default run takes a seeded subset.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{
    sweep, ContactError, ContactLaw, Phase, Profile, SlipState, SweepPoint, SweepResult,
    SweepSettings,
};
use std::f64::consts::FRAC_PI_2;

pub(crate) struct Scene {
    pub(crate) whisker: Whisker,
    pub(crate) flow: FluidLoad,
    pub(crate) profile: Profile,
}

fn settings(mu: f64, points: usize) -> SweepSettings {
    SweepSettings {
        points,
        contact_law: ContactLaw::Coulomb { mu },
        ..SweepSettings::default()
    }
}

/// The force on the whisker `fn n + ft t`, `n = (sin psi, -cos psi)`, `t = (cos psi, sin psi)`.
fn force(p: &SweepPoint) -> (f64, f64) {
    let (sp, cp) = p.psi.sin_cos();
    (p.f * sp + p.ft * cp, -p.f * cp + p.ft * sp)
}

/// The elastica written out: `phi' = m / e(s)^4 + A s + B`, `m' = Fx sin phi - Fy cos phi +
/// q (s1 - s) sin(phi + alpha)` on `[0, s1]`, `x' = cos phi`, `y' = sin phi` (spec/model.md),
/// the force `(fx, fy)` at `s = 1`, integrated by classical RK4 on `n` steps from the base
/// values `(phi0, m0, x0, 0)`: samples `(s, phi, m, x, y)`.
fn elastica(sc: &Scene, (fx, fy): (f64, f64), base: [f64; 4], n: usize) -> Vec<[f64; 5]> {
    elastica_to(sc, (fx, fy), base, n, 1.0)
}

/// [`elastica`] with the force at `s1 <= 1` (the flow on `[0, s1]`), then the unloaded segment
/// beyond it (`m' = 0`) on `n - n s1` more steps: the sample at `s1` is the `n`-th.
pub(crate) fn elastica_to(
    sc: &Scene,
    (fx, fy): (f64, f64),
    base: [f64; 4],
    n: usize,
    s1: f64,
) -> Vec<[f64; 5]> {
    let w = &sc.whisker;
    let (q, al) = (sc.flow.q, sc.flow.alpha);
    let rhs = |s: f64, u: &[f64; 4], loaded: bool| -> [f64; 4] {
        let e = 1.0 + (w.theta - 1.0) * s;
        let (sp, cp) = u[0].sin_cos();
        let dm = if loaded {
            fx * sp - fy * cp + q * (s1 - s) * (u[0] + al).sin()
        } else {
            0.0
        };
        [u[1] / (e * e * e * e) + w.a * s + w.b, dm, cp, sp]
    };
    let beyond = ((1.0 - s1) * n as f64).ceil() as usize;
    let mut u = base;
    let mut out = vec![[0.0, u[0], u[1], u[2], u[3]]];
    for i in 0..n + beyond {
        let (s, h) = if i < n {
            (s1 * i as f64 / n as f64, s1 / n as f64)
        } else {
            let h = (1.0 - s1) / beyond as f64;
            (s1 + (i - n) as f64 * h, h)
        };
        let add = |a: &[f64; 4], k: &[f64; 4], c: f64| {
            [
                a[0] + c * k[0],
                a[1] + c * k[1],
                a[2] + c * k[2],
                a[3] + c * k[3],
            ]
        };
        let k1 = rhs(s, &u, i < n);
        let k2 = rhs(s + 0.5 * h, &add(&u, &k1, 0.5 * h), i < n);
        let k3 = rhs(s + 0.5 * h, &add(&u, &k2, 0.5 * h), i < n);
        let k4 = rhs(s + h, &add(&u, &k3, h), i < n);
        for j in 0..4 {
            u[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
        if i + 1 == n {
            // the unloaded segment carries no moment: m(s1) = 0 is checked on the sample
            out.push([s1, u[0], u[1], u[2], u[3]]);
            u[1] = 0.0;
        } else {
            out.push([s + h, u[0], u[1], u[2], u[3]]);
        }
    }
    out
}

/// The row's base values `(phi0, m0 = -MA, x0, 0)`.
fn base_of(p: &SweepPoint) -> [f64; 4] {
    [p.phi0, -p.ma, p.x0, 0.0]
}

#[derive(Debug, Default, Clone)]
struct Figures {
    rows: usize,
    stick_rows: usize,
    slip_rows: usize,
    /// rows in tangential contact, and of those stuck
    b_rows: usize,
    b_stick_rows: usize,
    /// sweeps whose first touch is tangential
    tangential_touch: usize,
    events: usize,
    /// intervals between two stuck rows in tangential contact, the largest change of s1 and
    /// of the contact point's arc length over one of them (the rolling moves both)
    b_stick_intervals: usize,
    rolled_s1: f64,
    rolled_sigma: f64,
    /// worst (value, scene, row) of each check
    equilibrium: (f64, usize, usize),
    on_contour: (f64, usize, usize),
    phase: (f64, usize, usize),
    tangency: (f64, usize, usize),
    follicle: (f64, usize, usize),
    balance: (f64, usize, usize),
    cone: (f64, usize, usize),
    edge: (f64, usize, usize),
    stuck: (f64, usize, usize),
    rolling: (f64, usize, usize),
    against: (f64, usize, usize),
    penetration: (f64, usize, usize),
}

fn worst(slot: &mut (f64, usize, usize), v: f64, scene: usize, row: usize) {
    if v > slot.0 || v.is_nan() {
        *slot = (v, scene, row);
    }
}

/// The signed arc length of the contour from `xa` to `xb` (towards +x), as the length of a
/// polyline of 4000 chords on the graph `y(x)` (error ~ kappa^2 h^2 / 24 of the length).
pub(crate) fn contour_arc(profile: &Profile, xa: f64, xb: f64) -> f64 {
    let n = 4000;
    let h = (xb - xa) / n as f64;
    let mut len = 0.0;
    let mut prev = (xa, profile.y(xa));
    for k in 1..=n {
        let x = if k == n { xb } else { xa + k as f64 * h };
        let p = (x, profile.y(x));
        len += (p.0 - prev.0).hypot(p.1 - prev.1);
        prev = p;
    }
    len * (xb - xa).signum()
}

/// Checks every row of a frictional sweep (tip and tangential contact) independently of the
/// sweep's solver.
fn check(sc: &Scene, mu: f64, r: &SweepResult, id: usize, fig: &mut Figures) {
    fig.events += r.friction_events.len();
    if r.first_contact == contact_sim::FirstContact::Tangential {
        fig.tangential_touch += 1;
    }
    let (sa, ca) = sc.flow.alpha.sin_cos();
    let q = sc.flow.q;
    let mut prev: Option<&SweepPoint> = None;
    for (i, p) in r.points.iter().enumerate() {
        if p.phase == Phase::None {
            assert_eq!(p.slip, SlipState::None);
            continue;
        }
        assert!(matches!(p.phase, Phase::A | Phase::B), "scene {id} row {i}");
        let tangential = p.phase == Phase::B;
        assert!(
            tangential || p.s1 == 1.0,
            "scene {id} row {i}: tip contact at s1 {}",
            p.s1
        );
        fig.rows += 1;
        if tangential {
            fig.b_rows += 1;
            if p.slip == SlipState::Stick {
                fig.b_stick_rows += 1;
            }
        }
        match p.slip {
            SlipState::Stick => fig.stick_rows += 1,
            SlipState::Slip => fig.slip_rows += 1,
            SlipState::None => panic!("scene {id} row {i}: a contact row without a slip state"),
        }
        let scale = 1f64.max(p.f.hypot(p.ft)).max(p.ma.abs());
        let (fx, fy) = force(p);
        // the observables are the balance of F and the flow on [0, s1] [6.7-6.9]
        let bal = (p.ax + fx + q * p.s1 * ca)
            .abs()
            .max((p.ay + fy - q * p.s1 * sa).abs());
        worst(&mut fig.balance, bal / scale, id, i);
        // the follicle law phi0 = pi/2 - MA / k
        let k = match sc.whisker.support {
            beam_model::Support::Spring { k } => k,
            _ => f64::INFINITY,
        };
        worst(
            &mut fig.follicle,
            (p.phi0 - FRAC_PI_2 + p.ma / k).abs(),
            id,
            i,
        );
        // equilibrium: from the base, the loaded end s1 carries no moment and lies on the
        // contact point (the force there, the segment beyond unloaded)
        let n = if sc.whisker.theta < 0.3 { 8000 } else { 3000 };
        let tr = elastica_to(sc, (fx, fy), base_of(p), n, p.s1);
        let e = tr[n];
        let eq = e[2].abs().max((e[3] - p.xc).abs()).max((e[4] - p.yc).abs());
        worst(&mut fig.equilibrium, eq / scale, id, i);
        worst(
            &mut fig.on_contour,
            (p.yc - sc.profile.y(p.xc)).abs(),
            id,
            i,
        );
        if tangential {
            // tangency phi(s1) = psi, and the contact point strictly inside the whisker
            worst(&mut fig.tangency, (e[1] - p.psi).abs(), id, i);
            assert!(p.s1 > 0.0 && p.s1 < 1.0, "scene {id} row {i}: s1 {}", p.s1);
        } else {
            // tip contact: the tip steeper than the contour
            worst(&mut fig.phase, (p.psi - e[1]).max(0.0), id, i);
        }
        // the force in the cone, on its edge in slip
        assert!(p.f >= -1e-12, "scene {id} row {i}: fn = {}", p.f);
        worst(
            &mut fig.cone,
            (p.ft.abs() - mu * p.f).max(0.0) / scale,
            id,
            i,
        );
        if p.slip == SlipState::Slip {
            worst(&mut fig.edge, (p.ft.abs() - mu * p.f).abs() / scale, id, i);
        }
        // the slip law between consecutive rows: the touching material point's displacement
        // along the contour, d(sigma) - d(s1) (sigma the contour's arc length towards +x,
        // measured here on the contour's graph; s1 = 1 in tip contact), is zero from a stuck
        // row (in tangential contact: rolling), against ft from a sliding one; the row's slip
        // displacement follows it
        if let Some(a) = prev {
            let dsigma = contour_arc(&sc.profile, a.xc, p.xc);
            let chord = dsigma - (p.s1 - a.s1);
            let dsd = p.slip_distance - a.slip_distance;
            assert!(
                (dsd - chord).abs() <= 1e-6 * dsigma.abs() + 1e-9,
                "scene {id} row {i}: slip displacement {dsd:e} against the material point's {chord:e}"
            );
            match a.slip {
                SlipState::Stick if a.phase == Phase::B && p.phase == Phase::B => {
                    fig.b_stick_intervals += 1;
                    fig.rolled_s1 = fig.rolled_s1.max((p.s1 - a.s1).abs());
                    fig.rolled_sigma = fig.rolled_sigma.max(dsigma.abs());
                    worst(&mut fig.rolling, chord.abs(), id, i);
                    worst(&mut fig.stuck, chord.abs(), id, i);
                }
                SlipState::Stick => worst(&mut fig.stuck, chord.abs(), id, i),
                _ => {
                    // the interval slides with the sign of ft of its slip mode: both rows
                    // carry it (a slip -> stick switch row too, on the cone's edge), but
                    // where one has fn = 0 (the first touch, a release)
                    let ft = if p.ft.abs() > a.ft.abs() { p.ft } else { a.ft };
                    worst(&mut fig.against, chord * ft.signum() / scale, id, i);
                }
            }
        }
        prev = Some(p);
        // no penetration away from the contact point (the whole whisker, the unloaded segment
        // beyond a tangential contact too)
        let near = |v: &[f64; 5]| (v[0] - p.s1).abs() < 2e-3;
        for v in tr.iter().filter(|v| !near(v)) {
            let gy = sc.profile.y(v[3]);
            if gy.is_finite() {
                let mut depth = v[4] - gy;
                if let Profile::Circle { xc, r, .. } = sc.profile {
                    depth = depth.min(r - (v[3] - xc).abs());
                }
                worst(&mut fig.penetration, depth, id, i);
            }
        }
    }
}

/// Asserts the figures of a battery.
fn assert_figures(f: &Figures) {
    assert!(f.equilibrium.0 < 1e-7, "{f:?}");
    assert!(f.on_contour.0 < 1e-10, "{f:?}");
    assert!(f.phase.0 < 1e-9, "{f:?}");
    assert!(f.tangency.0 < 1e-8, "{f:?}");
    assert!(f.rolling.0 < 1e-9, "{f:?}");
    assert!(f.follicle.0 < 1e-9, "{f:?}");
    assert!(f.balance.0 < 1e-12, "{f:?}");
    assert!(f.cone.0 < 1e-9, "{f:?}");
    assert!(f.edge.0 < 1e-9, "{f:?}");
    assert!(f.stuck.0 < 1e-9, "{f:?}");
    assert!(f.against.0 < 1e-12, "{f:?}");
    assert!(f.penetration.0 < 1e-9, "{f:?}");
}

/// `mu = 0` is the frictionless sweep: the same rows bit for bit, no friction events, every
/// row `ft = 0`, `slip = none`.
#[test]
fn mu_zero_is_the_frictionless_sweep_bit_for_bit() {
    let scenes = [
        (
            Whisker::uniform(),
            FluidLoad { q: 5.0, alpha: 0.0 },
            Profile::g1(),
        ),
        (
            Whisker::new(0.6, 0.3, 0.2, 20.0),
            FluidLoad { q: 2.0, alpha: 0.3 },
            Profile::g2(),
        ),
    ];
    for (w, flow, p) in scenes {
        let plain = SweepSettings {
            points: 25,
            ..SweepSettings::default()
        };
        let a = sweep(&w, flow, &p, &plain).unwrap();
        let b = sweep(&w, flow, &p, &settings(0.0, 25)).unwrap();
        // bit for bit (Debug prints the shortest round trip; NaN compares equal here)
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert!(b.friction_events.is_empty());
        assert!(b
            .points
            .iter()
            .all(|r| r.ft == 0.0 && r.slip == SlipState::None && r.slip_distance == 0.0));
    }
}

/// The limit `mu -> 0`: at `mu = 1e-9` a tip-contact sweep (a spring-mounted tapered whisker
/// under a slanted flow past a circle, slipping throughout, ending in a snap) gives the
/// frictionless rows to 1e-7, by a different solver (the frictional one), with `|ft| = mu fn`.
#[test]
fn mu_to_zero_is_the_frictionless_sweep() {
    let sc = Scene {
        whisker: Whisker::new(0.5, 0.0, 0.0, 10.0),
        flow: FluidLoad { q: 1.0, alpha: 0.2 },
        profile: Profile::parse("circle:0.3,1.5,0.6").unwrap(),
    };
    let plain = SweepSettings {
        points: 20,
        ..SweepSettings::default()
    };
    let a = sweep(&sc.whisker, sc.flow, &sc.profile, &plain).unwrap();
    let b = sweep(&sc.whisker, sc.flow, &sc.profile, &settings(1e-9, 20)).unwrap();
    assert_eq!(a.phase_pattern(), "A");
    assert_eq!((a.separation, b.separation), (b.separation, a.separation));
    assert_eq!(a.points.len(), b.points.len());
    let mut worst = 0.0f64;
    for (p, q) in a.points.iter().zip(&b.points) {
        let d = [
            p.x0 - q.x0,
            p.ax - q.ax,
            p.ay - q.ay,
            p.ma - q.ma,
            p.phi0 - q.phi0,
            p.f - q.f,
        ];
        worst = d.iter().fold(worst, |m, v| m.max(v.abs()));
        if q.phase == Phase::A {
            assert_eq!(q.slip, SlipState::Slip);
            assert!((q.ft.abs() - 1e-9 * q.f).abs() <= 1e-20 + 1e-15 * q.f);
        }
    }
    eprintln!("mu = 1e-9 against the frictionless rows: worst {worst:.2e}");
    assert!(worst < 1e-7, "{worst:e}");
}

/// The accuracy asked for holds with friction: at `T = 1e-6` and `1e-8` every contact row of a
/// sliding sweep (the circle scene above at mu = 0.4) carries an estimate at most `T`, and its
/// error against the same sweep at the tightest tolerances (integration 1e-14, rows at the same
/// base positions) is below its estimate.
#[test]
fn the_accuracy_asked_for_holds_with_friction() {
    let sc = Scene {
        whisker: Whisker::new(0.5, 0.0, 0.0, 10.0),
        flow: FluidLoad { q: 1.0, alpha: 0.2 },
        profile: Profile::parse("circle:0.3,1.5,0.6").unwrap(),
    };
    let truth = sweep(
        &sc.whisker,
        sc.flow,
        &sc.profile,
        &SweepSettings {
            integration_tol: 1e-14,
            solve_tol: 1e-12,
            ..settings(0.4, 15)
        },
    )
    .unwrap();
    for tol in [1e-6, 1e-8] {
        let s = SweepSettings {
            accuracy: Some(tol),
            ..settings(0.4, 15)
        };
        let r = sweep(&sc.whisker, sc.flow, &sc.profile, &s).unwrap();
        let acc = r.accuracy.as_ref().unwrap();
        assert_eq!(r.points.len(), truth.points.len());
        for ((p, t), e) in r.points.iter().zip(&truth.points).zip(&acc.estimates) {
            if p.phase == Phase::None {
                continue;
            }
            assert!((p.x0 - t.x0).abs() < 1e-9, "{} vs {}", p.x0, t.x0);
            let err = [
                p.ax - t.ax,
                p.ay - t.ay,
                p.ma - t.ma,
                p.phi0 - t.phi0,
                p.xc - t.xc,
            ]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(
                *e <= tol && err <= e.max(1e-11),
                "T {tol:e}: x0 {}: error {err:e}, estimate {e:e}",
                p.x0
            );
        }
    }
}

/// A pre-curved rigid whisker (A = 1, B = 0.5, theta 0.3) under a weak flow touches g2 with its
/// tip inside the cone; at `mu = 10` it never slides: every row has the tip at the first touch
/// and is the pinned-tip elastica at its base position, solved here from scratch (RK4 from the
/// base on 20,000 steps, Newton on `(m0, Fx, Fy)` against `m(1) = 0` and the tip at the touch
/// point, finite-difference Jacobian) from the frictionless first-touch state.
#[test]
fn a_large_mu_pins_the_tip() {
    let sc = Scene {
        whisker: Whisker::new(0.3, 1.0, 0.5, f64::INFINITY),
        flow: FluidLoad { q: 0.5, alpha: 0.0 },
        profile: Profile::g2(),
    };
    let r = sweep(&sc.whisker, sc.flow, &sc.profile, &settings(10.0, 12)).unwrap();
    assert!(r.friction_events.is_empty());
    let touch = r.first_touch;
    let rows: Vec<_> = r.contact_points().collect();
    assert!(rows.len() >= 12);
    let mut worst_err = 0.0f64;
    // Newton continued row to row from the free whisker's state at the touch
    let first = rows[0];
    let mut u = [-first.ma, 0.0, 0.0];
    for p in &rows {
        assert_eq!(p.slip, SlipState::Stick);
        assert!((p.xc - touch.xc).abs() < 1e-12 && p.slip_distance == 0.0);
        let n = 20_000;
        let res = |u: &[f64; 3]| {
            let tr = elastica(&sc, (u[1], u[2]), [FRAC_PI_2, u[0], p.x0, 0.0], n);
            let e = tr[n];
            [e[2], e[3] - touch.xc, e[4] - touch.yc]
        };
        for _ in 0..20 {
            let r0 = res(&u);
            if r0.iter().all(|v| v.abs() < 1e-12) {
                break;
            }
            let mut j = [[0.0; 3]; 3];
            for k in 0..3 {
                let mut v = u;
                v[k] += 1e-7;
                let r1 = res(&v);
                for i in 0..3 {
                    j[i][k] = (r1[i] - r0[i]) / 1e-7;
                }
            }
            let d = solve3(j, [-r0[0], -r0[1], -r0[2]]);
            for k in 0..3 {
                u[k] += d[k];
            }
        }
        let (fx, fy) = force(p);
        let err = [u[0] + p.ma, u[1] - fx, u[2] - fy]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        if p.x0 == rows[rows.len() - 1].x0 {
            // the snap: a turning point of x0, where the pinned problem's solution moves as
            // the square root of a change in x0 (the row's x0 is located to ~1e-11)
            assert!(err < 1e-5, "{err:e}");
        } else {
            worst_err = worst_err.max(err);
        }
    }
    eprintln!(
        "pinned tip: {} rows, worst difference {worst_err:.2e}",
        rows.len()
    );
    assert!(worst_err < 1e-7, "{worst_err:e}");
    assert_eq!(r.separation, contact_sim::Separation::Snap);
}

fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> [f64; 3] {
    for c in 0..3 {
        let p = (c..3)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..3 {
            let m = a[r][c] / a[c][c];
            let row = a[c];
            for (x, y) in a[r].iter_mut().zip(row) {
                *x -= m * y;
            }
            b[r] -= m * b[c];
        }
    }
    let mut x = [0.0; 3];
    for c in (0..3).rev() {
        let s: f64 = (c + 1..3).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    x
}

/// The linear limit: a straight uniform clamped whisker (no flow) touches a near-flat wall
/// (a circle of radius 50) inclined at psi with its tip. Its chord cannot grow, so the tip
/// slides from the first touch, down the wall (its shortening is second order), with the
/// force on the cone's edge `ft = +mu fn`; to first order the tip deflection is the
/// cantilever's, `Fx = 3 (xc - x0)`, so `fn = 3 (xc - x0) / (sin psi + mu cos psi)` and
/// `Fy = fn (mu sin psi - cos psi)`. Checked at the first rows (deflection up to 4e-3),
/// the relative error below 5 times the deflection.
#[test]
fn the_linear_limit_slides_on_the_cone_edge() {
    for (psi, mu) in [(0.5f64, 0.3), (0.8, 1.0), (0.3, 0.05), (1.0, 1.5)] {
        let r = 50.0;
        let spec = format!("circle:{},{},{}", -r * psi.sin(), 1.0 + r * psi.cos(), r);
        let sc = Scene {
            whisker: Whisker::new(1.0, 0.0, 0.0, f64::INFINITY),
            flow: FluidLoad { q: 0.0, alpha: 0.0 },
            profile: Profile::parse(&spec).unwrap(),
        };
        // 40 steps of at most 0.05: the trace ends a short way from the touch, so that the
        // 2000 rows are dense within the small deflections
        let s = SweepSettings {
            max_steps: 40,
            max_step: 0.05,
            ..settings(mu, 2000)
        };
        let res = sweep(&sc.whisker, sc.flow, &sc.profile, &s);
        let rows: Vec<SweepPoint> = match &res {
            Ok(r) => r.contact_points().copied().collect(),
            Err(e) => panic!("psi {psi} mu {mu}: {e}"),
        };
        let mut checked = 0;
        let mut worst_rel = 0.0f64;
        for p in rows.iter().skip(1) {
            let d = p.xc - p.x0;
            if d > 4e-3 {
                break;
            }
            assert_eq!(p.slip, SlipState::Slip);
            let f_lin = 3.0 * d / (p.psi.sin() + mu * p.psi.cos());
            let rel = (p.f - f_lin).abs() / f_lin;
            assert!(
                rel < 5.0 * d,
                "psi {psi} mu {mu}: fn {} vs {f_lin} at {d:e}",
                p.f
            );
            assert!((p.ft - mu * p.f).abs() < 1e-12 * p.f.max(1e-300) + 1e-15);
            assert!(p.slip_distance < 0.0, "the tip slides down the wall");
            let (_, fy) = force(p);
            let fy_lin = f_lin * (mu * p.psi.sin() - p.psi.cos());
            assert!(
                (fy - fy_lin).abs() < 5.0 * d * fy_lin.abs(),
                "Fy {fy} vs {fy_lin}"
            );
            checked += 1;
            worst_rel = worst_rel.max(rel / d);
        }
        eprintln!(
            "psi {psi} mu {mu}: {checked} rows, worst relative error / deflection {worst_rel:.3}"
        );
        assert!(checked >= 3, "psi {psi} mu {mu}: {checked} rows checked");
    }
}

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// A random scene: theta 0.2..1, pre-curvature of both signs (or none), rigid or a spring,
/// q 0..5 at -45..45 degrees, g1, g2, a random parabola or a circle, and mu in 0.05..1.5.
fn random_scene(rng: &mut Rng) -> (Scene, f64) {
    let theta = rng.range(0.2, 1.0);
    let (a, b) = if rng.next() < 0.3 {
        (0.0, 0.0)
    } else {
        (rng.range(-0.8, 1.2), rng.range(-0.5, 0.8))
    };
    let k = if rng.next() < 0.5 {
        f64::INFINITY
    } else {
        rng.range(5.0, 50.0)
    };
    let q = if rng.next() < 0.2 {
        0.0
    } else {
        rng.range(0.0, 5.0)
    };
    let alpha = rng.range(-45.0, 45.0).to_radians();
    let u = rng.next();
    let profile = if u < 0.15 {
        Profile::g1()
    } else if u < 0.3 {
        Profile::g2()
    } else if u < 0.45 {
        let c = rng.range(0.3, 2.0);
        let x0 = rng.range(-0.5, 0.5);
        let y0 = rng.range(0.4, 0.9);
        Profile::parse(&format!("parabola:{c},{x0},{y0}")).unwrap()
    } else {
        let r = rng.range(0.2, 1.5);
        let cx = rng.range(-0.3, 0.6);
        let cy = rng.range(0.85, 1.2) + r * rng.range(0.3, 0.95);
        Profile::parse(&format!("circle:{cx},{cy},{r}")).unwrap()
    };
    let mu = rng.range(0.05, 1.5);
    (
        Scene {
            whisker: Whisker::new(theta, a, b, k),
            flow: FluidLoad { q, alpha },
            profile,
        },
        mu,
    )
}

/// Runs `count` random scenes from `seed` with `points` rows each; prints the figures.
fn battery(count: usize, seed: u64, points: usize) -> Figures {
    let mut rng = Rng(seed);
    let mut fig = Figures::default();
    let (mut swept, mut with_b, mut indeterminate, mut no_contact, mut other) = (0, 0, 0, 0, 0);
    for id in 0..count {
        let (sc, mu) = random_scene(&mut rng);
        let sweep_result = sweep(&sc.whisker, sc.flow, &sc.profile, &settings(mu, points));
        if let Err(e @ ContactError::FrictionIndeterminate { .. }) = &sweep_result {
            eprintln!("scene {id} (mu {mu:.3}, {}): {e}", sc.profile.name());
        }
        match sweep_result {
            Ok(r) => {
                swept += 1;
                if r.phase_pattern().contains('B') {
                    with_b += 1;
                }
                if !r.friction_events.is_empty() {
                    let kinds: Vec<_> = r.friction_events.iter().map(|e| e.kind).collect();
                    eprintln!(
                        "scene {id} (mu {mu:.3}, {}): {kinds:?}, {}",
                        sc.profile.name(),
                        r.separation
                    );
                }
                check(&sc, mu, &r, id, &mut fig);
            }
            Err(ContactError::FrictionIndeterminate { .. }) => indeterminate += 1,
            Err(ContactError::NoContact { .. }) => no_contact += 1,
            Err(e) => {
                other += 1;
                eprintln!("scene {id}: {e}");
            }
        }
    }
    eprintln!(
        "friction battery (seed {seed:#x}): {count} scenes, {swept} swept ({with_b} reach tangential contact, {} touch tangentially first; {} rows: {} stick, {} slip; {} in tangential contact, {} of them stuck; {} switches), {indeterminate} refused (no quasi-static continuation), {no_contact} without contact, {other} other errors",
        fig.tangential_touch, fig.rows, fig.stick_rows, fig.slip_rows, fig.b_rows, fig.b_stick_rows, fig.events
    );
    eprintln!("worst (value, scene, row): {fig:#?}");
    assert_eq!(other, 0, "sweeps that failed");
    fig
}

/// Thesis case 1 with friction: the uniform rigid whisker under q = 5 past g1 at mu = 0.5
/// reaches tangential contact (its frictionless pattern is ABA), and every row passes the
/// battery's checks (equilibrium, tangency, m(s1) = 0, the cone, the slip law with rolling in
/// a tangential stick, no penetration).
#[test]
fn thesis_case_1_with_friction_passes_the_checks() {
    let sc = Scene {
        whisker: Whisker::uniform(),
        flow: FluidLoad { q: 5.0, alpha: 0.0 },
        profile: Profile::g1(),
    };
    let r = sweep(&sc.whisker, sc.flow, &sc.profile, &settings(0.5, 30)).unwrap();
    let mut fig = Figures::default();
    check(&sc, 0.5, &r, 0, &mut fig);
    eprintln!(
        "g1, q 5, mu 0.5: {} {}, events {:?}; {fig:#?}",
        r.phase_pattern(),
        r.separation,
        r.friction_events
    );
    assert!(r.phase_pattern().contains('B'), "{}", r.phase_pattern());
    assert!(fig.b_rows > 3, "{fig:?}");
    assert_figures(&fig);
}

/// The limit `mu -> 0` through tangential contact: thesis case 1 (ABA) at `mu = 1e-8` gives
/// the frictionless rows to 1e-6 (the frictional solver, slipping throughout, `|ft| = mu fn`),
/// row for row at the same base positions.
#[test]
fn mu_to_zero_in_tangential_contact_is_the_frictionless_sweep() {
    let (w, flow, p) = (
        Whisker::uniform(),
        FluidLoad { q: 5.0, alpha: 0.0 },
        Profile::g1(),
    );
    let plain = SweepSettings {
        points: 20,
        ..SweepSettings::default()
    };
    let a = sweep(&w, flow, &p, &plain).unwrap();
    let b = sweep(&w, flow, &p, &settings(1e-8, 20)).unwrap();
    assert_eq!(a.phase_pattern(), b.phase_pattern());
    assert_eq!(a.separation, b.separation);
    let (ra, rb): (Vec<_>, Vec<_>) = (a.contact_points().collect(), b.contact_points().collect());
    let mut worst = 0.0f64;
    let mut compared = 0;
    for q in &rb {
        assert_eq!(q.slip, SlipState::Slip);
        assert!((q.ft.abs() - 1e-8 * q.f).abs() <= 1e-20 + 1e-14 * q.f);
        // the frictionless row at the same base position (the grids share their ends to
        // ~1e-8; switch rows have no partner)
        let Some(p) = ra
            .iter()
            .find(|p| (p.x0 - q.x0).abs() < 1e-6 && p.phase == q.phase)
        else {
            continue;
        };
        let d = [
            p.x0 - q.x0,
            p.ax - q.ax,
            p.ay - q.ay,
            p.ma - q.ma,
            p.phi0 - q.phi0,
            p.f - q.f,
            p.s1 - q.s1,
        ];
        let dev = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        worst = worst.max(dev);
        compared += 1;
    }
    eprintln!(
        "mu = 1e-8 against the frictionless ABA rows: {compared} compared, worst {worst:.2e}"
    );
    assert!(compared >= 15, "{compared}");
    assert!(worst < 1e-6, "{worst:e}");
}

/// A seeded subset of the battery in the suite (seconds).
#[test]
fn friction_battery_subset() {
    let fig = battery(12, 0xF71C_7100, 16);
    assert!(fig.rows > 40, "{fig:?}");
    assert_figures(&fig);
}

/// The full battery: `cargo test -p contact-sim --release --test it -- friction:: --ignored
/// --nocapture`.
#[test]
#[ignore]
fn friction_battery_full() {
    let fig = battery(200, 0xF71C_7100, 40);
    assert_figures(&fig);
}

/// One scene of the full battery, its rows printed: `FRICTION_SCENE=N cargo test -p
/// contact-sim --release --test it -- friction::one_scene --ignored --nocapture`.
#[test]
#[ignore]
fn one_scene() {
    let id: usize = std::env::var("FRICTION_SCENE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let mut rng = Rng(0xF71C_7100);
    let (mut sc, mut mu) = random_scene(&mut rng);
    for _ in 0..id {
        (sc, mu) = random_scene(&mut rng);
    }
    eprintln!(
        "scene {id}: {:?} {:?} {} mu {mu}",
        sc.whisker,
        sc.flow,
        sc.profile.name()
    );
    if std::env::var("FRICTION_MU").is_ok_and(|v| v == "0") {
        mu = 0.0;
    }
    let r = sweep(&sc.whisker, sc.flow, &sc.profile, &settings(mu, 40)).unwrap();
    eprintln!(
        "{} {:?}; first touch {:?}",
        r.separation, r.friction_events, r.first_touch
    );
    for p in r.contact_points() {
        // the deepest point away from the contact (the battery's penetration check)
        let n = 3000;
        let tr = elastica_to(&sc, force(p), base_of(p), n, p.s1);
        let deepest = tr
            .iter()
            .filter(|v| (v[0] - p.s1).abs() >= 2e-3)
            .map(|v| (v[4] - sc.profile.y(v[3]), v[0]))
            .filter(|d| d.0.is_finite())
            .fold(
                (f64::NEG_INFINITY, 0.0),
                |m, d| if d.0 > m.0 { d } else { m },
            );
        eprintln!("deepest {:.3e} at s {:.4}", deepest.0, deepest.1);
        eprintln!(
            "{} x0 {:.9} f {:.6e} ft {:+.6e} {:5} xc {:.9} s1 {:.6} phi1-psi {:.4} sd {:+.6e}",
            p.phase,
            p.x0,
            p.f,
            p.ft,
            p.slip.label(),
            p.xc,
            p.s1,
            p.phi1 - p.psi,
            p.slip_distance
        );
    }
}

/// `sweep_with_progress` reports a frictional sweep as a frictionless one (fcost): `Coarse`
/// before and after the trace, then `Fine` reports counting up (never down, never past
/// their total) to the last, `done == total`, and the same rows as `sweep`. (The scene
/// slides throughout, so it runs on the frictionless machinery, which reports the rows of
/// its first half one by one and the rest at the end, `friction::slide`.)
#[test]
fn fcost_a_frictional_sweep_reports_its_progress() {
    use contact_sim::{sweep_with_progress, SweepProgress};
    let (whisker, flow, profile) = (
        Whisker::uniform(),
        FluidLoad { q: 5.0, alpha: 0.0 },
        Profile::g1(),
    );
    let s = settings(0.5, 20);
    let mut reports = Vec::new();
    let r = sweep_with_progress(&whisker, flow, &profile, &s, &mut |p| reports.push(p)).unwrap();
    let contact = r.contact_points().count();
    assert_eq!(reports[0], SweepProgress::Coarse { steps: 0 });
    assert!(matches!(reports[1], SweepProgress::Coarse { steps } if steps > 1));
    let fine: Vec<(usize, usize)> = reports[2..]
        .iter()
        .map(|p| match *p {
            SweepProgress::Fine { done, total } => (done, total),
            other => panic!("{other:?} after the trace"),
        })
        .collect();
    assert!(fine.len() > 2 && contact > 2);
    let total = fine[0].1;
    for w in fine.windows(2) {
        assert!(
            w[0].0 <= w[1].0 && w[1].0 <= total && w[1].1 == total,
            "{w:?}"
        );
    }
    assert_eq!(fine.last(), Some(&(total, total)));
    let plain = sweep(&whisker, flow, &profile, &s).unwrap();
    assert_eq!(format!("{:?}", plain.points), format!("{:?}", r.points));
}
