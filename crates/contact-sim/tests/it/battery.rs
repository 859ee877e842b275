//! A seeded random battery of sweeps over the parameter space the CLI accepts: every profile
//! kind (g1, g2, ge, parabola, cosh, circle arc, table), theta 0.1..1, pre-curvature A, B of
//! both signs, rigid and elastic follicles, q 0..8, flow angles in (-60, 60) degrees.
//!
//! Every row is checked independently of the sweep's own solver (adaptive shooting):
//! - re-solved by `fdm-richardson` (FDM on three grids + Richardson, a different method) at
//!   the row's contact force (counted: it agrees to 1e-9, or lands on another equilibrium of
//!   the same loads, where `accurate` from scratch lands too);
//! - an RK4 integration from the base with the row's observables as initial values (another
//!   integrator, the other direction): free-end moment zero and the loaded end on the contact
//!   point to 1e-9 relative to the load scale (scaled by the check's own conditioning for
//!   slender tips);
//! - the global moment balance about the base, from the row's contact point and the
//!   integrated shape, holds to 1e-8;
//! - the phase conditions hold on the re-solved shape, and no other part of the whisker lies
//!   inside the obstacle;
//! - x0 falls strictly from row to row;
//! - the first touch lies on the contour, tangent to the free whisker (phase B) or at its tip.
//!
//! `cargo test -p contact-sim --release --test it -- battery:: --ignored --nocapture` runs the
//! full battery and prints its figures; the default run takes a smaller seeded subset.

use beam_model::{solve, FluidLoad, Loads, Method, Scene, Whisker};
use contact_sim::phase::contact_loads;
use contact_sim::{sweep, FirstContact, Phase, Profile, Separation, SweepResult, SweepSettings};

/// SplitMix64: a tiny seeded generator, so the battery needs no extra dependency.
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

#[derive(Debug)]
struct SceneSpec {
    name: String,
    whisker: Whisker,
    flow: FluidLoad,
    profile: Profile,
}

fn random_scene(rng: &mut Rng, i: usize) -> SceneSpec {
    let u = rng.next();
    let theta = if u < 0.1 {
        rng.range(0.03, 0.1)
    } else if u < 0.25 {
        rng.range(0.1, 0.3)
    } else {
        rng.range(0.3, 1.0)
    };
    let (a, b) = if rng.next() < 0.3 {
        (0.0, 0.0)
    } else {
        (rng.range(-1.0, 1.0), rng.range(-0.8, 0.8))
    };
    let k = if rng.next() < 0.35 {
        f64::INFINITY
    } else {
        rng.range(5.0, 50.0)
    };
    let q = if rng.next() < 0.15 {
        0.0
    } else {
        rng.range(0.0, 8.0)
    };
    let alpha = if rng.next() < 0.3 {
        0.0
    } else {
        rng.range(-60.0, 60.0)
    };
    let kind = i % 7;
    let low = rng.range(0.35, 0.85);
    let profile = match kind {
        0 => Profile::g1(),
        1 => Profile::g2(),
        2 => Profile::ge(),
        3 => Profile::Parabola {
            a: rng.range(0.3, 3.0),
            xv: rng.range(-0.5, 0.5),
            yv: low,
        },
        4 => {
            let (amp, c) = (rng.range(0.3, 1.5), rng.range(0.7, 3.0));
            Profile::Cosh {
                a: amp,
                c,
                xv: rng.range(-0.5, 0.5),
                d: low - amp,
            }
        }
        5 => {
            let r = rng.range(0.6, 3.0);
            Profile::Circle {
                xc: rng.range(-0.5, 0.5),
                yc: low + r,
                r,
            }
        }
        _ => {
            let (ac, xv) = (rng.range(0.3, 2.0), rng.range(-0.4, 0.4));
            let xs: Vec<f64> = (0..=50).map(|j| -2.5 + 0.1 * j as f64).collect();
            let ys = xs.iter().map(|x| ac * (x - xv).powi(2) + low).collect();
            Profile::points(xs, ys).unwrap()
        }
    };
    SceneSpec {
        name: format!(
            "#{i} {} theta={theta:.3} A={a:.3} B={b:.3} k={k:.2} q={q:.3} alpha={alpha:.1}",
            profile.name()
        ),
        whisker: Whisker::new(theta, a, b, k),
        flow: FluidLoad {
            q,
            alpha: alpha.to_radians(),
        },
        profile,
    }
}

/// Worst deviations over the rows of one sweep.
#[derive(Default, Debug, Clone, Copy)]
struct Figures {
    rows: usize,
    resolve: f64,
    moment: f64,
    penetration: f64,
    phase: f64,
    fdm_agree: usize,
    fdm_near: usize,
    fdm_other: usize,
    fdm_fail: usize,
}

/// The whisker integrated from the base with the row's observables as initial values
/// `(phi0, m(0) = -MA, x0, 0)` by classical RK4 on 4000 steps (a different integrator, in the
/// other direction than the sweep's shots): `(s, phi, m, x, y)` samples to `s = 1`.
fn from_base(s: &SceneSpec, p: &contact_sim::SweepPoint) -> Vec<[f64; 5]> {
    // finer for slender tips, whose boundary layer the check must resolve too
    let n = if s.whisker.theta < 0.1 { 20_000 } else { 4000 };
    crate::whisking::from_base(&s.whisker, s.flow, p, 0.0, n)
}

/// Checks every contact row of `r` independently of the sweep's solver.
fn check_rows(s: &SceneSpec, r: &SweepResult) -> Result<Figures, String> {
    let mut fig = Figures::default();
    let n = if s.whisker.theta < 0.3 { 200 } else { 100 };
    for w in r.points.windows(2) {
        if w[1].x0.is_nan() || w[1].x0 >= w[0].x0 {
            return Err(format!("x0 does not fall: {} then {}", w[0].x0, w[1].x0));
        }
    }
    let (sa, ca) = s.flow.alpha.sin_cos();
    for (i, p) in r.points.iter().enumerate() {
        if p.phase == Phase::None {
            if (p.ax + s.flow.q * ca).abs() > 1e-12 || (p.ay - s.flow.q * sa).abs() > 1e-12 {
                return Err(format!("pre-contact row {i}: Ax, Ay are not the flow's"));
            }
            continue;
        }
        fig.rows += 1;
        if p.f < 0.0 {
            return Err(format!("row {i}: negative contact force {}", p.f));
        }
        // (1) the initial-value check from the base: free-end moment zero at s1, the loaded
        // end on the contact point, the phase condition there
        let tr = from_base(s, p);
        // relative to the load scale max(1, f, |MA|) (`loaded_end_misfit`)
        let (d, ph) = crate::whisking::loaded_end_misfit(&tr, p);
        let k1 = tr.iter().position(|v| v[0] >= p.s1 - 1e-15).unwrap();
        let scale = 1f64.max(p.f).max(p.ma.abs());
        fig.resolve = fig.resolve.max(d);
        fig.phase = fig.phase.max(ph);
        // (2) a second method from scratch: fdm-richardson at the row's loads; it may land on
        // another equilibrium of the same loads (counted, see the note of issue 12)
        let loads = contact_loads(s.flow, p.psi, p.f, p.s1);
        let scene = Scene::new(s.whisker, loads);
        // phase B ends the loads between grid nodes: a finer grid keeps the FDM's order
        let n = if p.phase == Phase::B { 4 * n } else { n };
        if let Ok(sol) = solve(&scene, &Method::FdmRichardson { n }) {
            let d2 = [sol.base.ma - p.ma, sol.base.phi0 - p.phi0]
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            if d2 <= 1e-9 {
                fig.fdm_agree += 1;
            } else if d2 <= 1e-6 {
                fig.fdm_near += 1;
            } else {
                // another equilibrium of the same loads when `accurate` from scratch lands
                // on the fdm-richardson one too
                let other = solve(&scene, &Method::accurate())
                    .map(|a| (a.base.ma - sol.base.ma).abs() < 1e-6)
                    .unwrap_or(false);
                if other {
                    fig.fdm_other += 1;
                } else {
                    fig.fdm_fail += 1;
                }
            }
        } else {
            fig.fdm_fail += 1;
        }
        // (3) global moment balance about the base [6.7]:
        // MA = (Fx Y1 - Fy X1) + int_0^s1 (Qx y - Qy x) ds on the integrated shape (Simpson)
        let (fx, fy) = (p.f * p.psi.sin(), -p.f * p.psi.cos());
        let (qx, qy) = (s.flow.q * ca, -s.flow.q * sa);
        let g = |v: &[f64; 5]| qx * v[4] - qy * (v[3] - p.x0);
        let mut integral = 0.0;
        let mut j = 0;
        while j + 2 <= k1 {
            let h = tr[j + 2][0] - tr[j][0];
            integral += h / 6.0 * (g(&tr[j]) + 4.0 * g(&tr[j + 1]) + g(&tr[j + 2]));
            j += 2;
        }
        if j < k1 {
            integral += 0.5 * (tr[k1][0] - tr[j][0]) * (g(&tr[j]) + g(&tr[k1]));
        }
        let moment = fx * p.yc - fy * (p.xc - p.x0) + integral;
        fig.moment = fig.moment.max((moment - p.ma).abs() / scale);
        // (4) no penetration away from the contact point
        for v in &tr {
            if (v[0] - p.s1).abs() < 2e-3 {
                continue;
            }
            let (x, y) = (v[3], v[4]);
            let gy = s.profile.y(x);
            if gy.is_finite() {
                let mut depth = y - gy;
                if let Profile::Circle { xc, r, .. } = s.profile {
                    depth = depth.min(r - (x - xc).abs());
                }
                fig.penetration = fig.penetration.max(depth);
            }
        }
    }
    Ok(fig)
}

/// The first touch against the free whisker re-solved by `fdm-richardson`.
fn check_first_touch(s: &SceneSpec, r: &SweepResult) -> Result<f64, String> {
    let t = r.first_touch;
    let on = (t.yc - s.profile.y(t.xc)).abs();
    let sol = solve(
        &Scene::new(s.whisker, Loads::fluid(s.flow.q, s.flow.alpha)),
        &Method::FdmRichardson { n: 200 },
    )
    .map_err(|e| format!("free re-solve failed: {e}"))?;
    let err = match t.kind {
        FirstContact::Tip => {
            let dx = (t.x0 + sol.tip.x - t.xc).abs();
            let dy = (sol.tip.y - t.yc).abs();
            if sol.tip.phi <= t.psi - 1e-9 {
                return Err("tip contact with phi1 <= psi".into());
            }
            dx.max(dy)
        }
        FirstContact::Tangential => {
            // the touching point: the re-solved elastica sampled at s, tangent there
            let el = &sol.elastica;
            let j = el.s.iter().position(|&v| v >= t.s).unwrap_or(el.len() - 1);
            let h = el.s[1] - el.s[0];
            // a sampling bound only: the exact tangency is checked below on the contour
            let d = (t.x0 + el.x[j] - t.xc).hypot(el.y[j] - t.yc);
            if d > 2.0 * h {
                return Err(format!(
                    "tangential touch {d:.3e} away from the free whisker"
                ));
            }
            0.0
        }
    };
    // no point of the free whisker is beyond the contour at the first-touch base position
    let shape = beam_model::shape_from_tip_angle(
        &Scene::new(s.whisker, Loads::fluid(s.flow.q, s.flow.alpha)),
        t.phi1,
        1e-12,
        2000,
    )
    .map_err(|e| e.to_string())?;
    let el = &shape.elastica;
    let mut depth = f64::NEG_INFINITY;
    for j in 0..el.len() {
        let x = t.x0 + el.x[j];
        let g = s.profile.y(x);
        if g.is_finite() {
            depth = depth.max(el.y[j] - g);
        }
    }
    if depth > 1e-9 {
        return Err(format!(
            "the free whisker is {depth:.3e} inside the contour at first touch"
        ));
    }
    Ok(on.max(err))
}

/// Named scenes a researcher brings that the thesis never had.
fn named_scenes() -> Vec<SceneSpec> {
    let table: Vec<f64> = (0..=50).map(|j| -2.5 + 0.1 * j as f64).collect();
    let ys = table.iter().map(|x| 0.6 * x * x + 0.5).collect();
    let mk = |name: &str, w: Whisker, q: f64, alpha_deg: f64, profile: Profile| SceneSpec {
        name: name.to_string(),
        whisker: w,
        flow: FluidLoad {
            q,
            alpha: alpha_deg.to_radians(),
        },
        profile,
    };
    vec![
        mk(
            "bent back (A = -3, B = 1.5) on a parabola",
            Whisker::new(0.5, -3.0, 1.5, f64::INFINITY),
            0.5,
            0.0,
            Profile::parse("parabola:1,0,0.45").unwrap(),
        ),
        mk(
            "circle post r = 0.6",
            Whisker::new(0.75, 0.0, 0.0, 20.0),
            2.0,
            0.0,
            Profile::parse("circle:0,1.1,0.6").unwrap(),
        ),
        mk(
            "table over [-2.5, 2.5]",
            Whisker::new(0.6, 0.0, 0.0, 20.0),
            3.0,
            0.0,
            Profile::points(table, ys).unwrap(),
        ),
        mk(
            "slender theta = 0.05 on g1",
            Whisker::new(0.05, 0.0, 0.0, f64::INFINITY),
            0.3,
            0.0,
            Profile::g1(),
        ),
        mk(
            "slender theta = 0.05, elastic, flow at 30 degrees on g2",
            Whisker::new(0.05, 0.0, 0.0, 20.0),
            0.5,
            30.0,
            Profile::g2(),
        ),
        mk(
            "a contour down to the base's path (cosh:1,2,0,-1)",
            Whisker::uniform(),
            1.0,
            0.0,
            Profile::parse("cosh:1,2,0,-1").unwrap(),
        ),
        mk(
            "an almost flat parabola (parabola:1e-3,0.4,0.7)",
            Whisker::uniform(),
            1.0,
            0.0,
            Profile::parse("parabola:1e-3,0.4,0.7").unwrap(),
        ),
        mk(
            "flow at 45 degrees on g2",
            Whisker::new(0.75, -0.5, 0.2, 20.0),
            4.0,
            45.0,
            Profile::g2(),
        ),
        mk(
            "flow at -45 degrees on ge",
            Whisker::new(0.4, 0.0, 0.0, 10.0),
            2.0,
            -45.0,
            Profile::ge(),
        ),
    ]
}

/// What a battery has seen so far.
#[derive(Default)]
struct Tally {
    failures: Vec<String>,
    refused: Vec<String>,
    stopped: Vec<String>,
    worst: Figures,
    worst_at: [String; 3],
    seps: std::collections::BTreeMap<String, usize>,
    firsts: [usize; 2],
    touch_worst: f64,
}

/// The tolerances of a sweep's checks `(position, phase, penetration)`.
///
/// The check integrates from the base towards the tip: errors of the recorded base values
/// (the shots' ~1e-11) grow by cond = int_0^1 e^-4 ds, which is 1 for a uniform whisker and
/// ~2500 at theta = 0.05; the tolerances grow with it. The row where a second contact is
/// located touches the contour to within the sweep's shape check (RK4 on 200 steps, ~1e-7).
fn tolerances(s: &SceneSpec, r: &SweepResult) -> (f64, f64, f64) {
    let th = s.whisker.theta;
    let cond = if th < 1.0 {
        (th.powi(-3) - 1.0) / (3.0 * (1.0 - th))
    } else {
        1.0
    };
    let tol_pen = if matches!(r.separation, Separation::MultiContact { .. }) {
        2e-7
    } else {
        5e-8
    };
    (1e-9 + 1e-11 * cond, 1e-8 + 1e-10 * cond, tol_pen)
}

impl Tally {
    /// Records the sweep `r` of scene `s` (taking `ms` milliseconds) and checks it.
    fn record(&mut self, s: &SceneSpec, r: &SweepResult, ms: f64) {
        *self
            .seps
            .entry(match r.separation {
                Separation::MultiContact { .. } => "multi-contact".to_string(),
                Separation::NotReached { .. } => "not-reached".to_string(),
                Separation::ContactAtBase => "contact-at-base".to_string(),
                ref x => format!("{x:?}").to_lowercase(),
            })
            .or_default() += 1;
        self.firsts[(r.first_contact == FirstContact::Tangential) as usize] += 1;
        match check_first_touch(s, r) {
            Ok(e) => self.touch_worst = self.touch_worst.max(e),
            Err(e) => self.failures.push(format!("{}: first touch: {e}", s.name)),
        }
        let f = match check_rows(s, r) {
            Ok(f) => f,
            Err(e) => return self.failures.push(format!("{}: {e}", s.name)),
        };
        println!(
            "{} -> {} {:?} rows {} resolve {:.1e} moment {:.1e} pen {:.1e} ({ms:.0} ms)",
            s.name,
            r.phase_pattern(),
            r.separation,
            f.rows,
            f.resolve,
            f.moment,
            f.penetration
        );
        let w = &mut self.worst;
        for (k, (new, old)) in [
            (f.resolve, &mut w.resolve),
            (f.moment, &mut w.moment),
            (f.penetration, &mut w.penetration),
        ]
        .into_iter()
        .enumerate()
        {
            if new > *old {
                *old = new;
                self.worst_at[k] = s.name.clone();
            }
        }
        w.phase = w.phase.max(f.phase);
        w.rows += f.rows;
        w.fdm_agree += f.fdm_agree;
        w.fdm_other += f.fdm_other;
        w.fdm_near += f.fdm_near;
        w.fdm_fail += f.fdm_fail;
        let (tol_pos, tol_phase, tol_pen) = tolerances(s, r);
        if f.resolve > tol_pos || f.moment > 1e-8 || f.penetration > tol_pen || f.phase > tol_phase
        {
            self.failures.push(format!("{}: {f:?}", s.name));
        }
    }

    /// Prints the battery's figures.
    fn report(&self, total: usize) {
        let w = &self.worst;
        println!(
            "battery: {total} scenes, {} refused (no contact), {} stopped with an error, {} contact rows; first contact tip {} tangential {}; separations {:?}",
            self.refused.len(),
            self.stopped.len(),
            w.rows,
            self.firsts[0],
            self.firsts[1],
            self.seps
        );
        println!(
            "fdm-richardson from scratch: {} rows agree to 1e-9, {} to 1e-6, {} land on another equilibrium (where accurate from scratch lands too), {} otherwise",
            w.fdm_agree, w.fdm_near, w.fdm_other, w.fdm_fail
        );
        println!(
            "worst re-solve {:.2e} ({}), moment {:.2e} ({}), penetration {:.2e} ({}), phase {:.2e}, first touch {:.2e}",
            w.resolve, self.worst_at[0], w.moment, self.worst_at[1], w.penetration, self.worst_at[2], w.phase, self.touch_worst
        );
        for r in &self.refused {
            println!("refused: {r}");
        }
        for r in &self.stopped {
            println!("stopped with an error: {r}");
        }
    }
}

fn run_battery(count: usize, seed: u64, max_stopped: usize) {
    let mut rng = Rng(seed);
    let named = named_scenes();
    let settings = SweepSettings {
        points: 30,
        pre_contact_rows: 3,
        ..SweepSettings::default()
    };
    let mut tally = Tally::default();
    let total = named.len() + count;
    let mut named = named.into_iter();
    for i in 0..total {
        let s = match named.next() {
            Some(s) => s,
            None => random_scene(&mut rng, i),
        };
        let t0 = std::time::Instant::now();
        match sweep(&s.whisker, s.flow, &s.profile, &settings) {
            Ok(r) => tally.record(&s, &r, t0.elapsed().as_secs_f64() * 1e3),
            Err(e @ contact_sim::ContactError::NoContact { .. }) => {
                tally.refused.push(format!("{}: {e}", s.name));
            }
            // a typed error is an honest outcome, never a wrong row: counted and listed
            Err(e) => tally.stopped.push(format!("{}: {e}", s.name)),
        }
    }
    tally.report(total);
    // Known limit: very slender tips (theta < 0.06) under strong flow, where the shots' noise
    // floor (~1e-9) stops the corrector; anything more is a regression.
    assert!(
        tally.stopped.len() <= max_stopped,
        "{} scenes stopped with an error (at most {max_stopped} expected)",
        tally.stopped.len()
    );
    assert!(
        tally.failures.is_empty(),
        "{} failures:\n{}",
        tally.failures.len(),
        tally.failures.join("\n")
    );
}

#[test]
fn battery_subset() {
    run_battery(14, 0x5EED_0010, 0);
}

#[test]
#[ignore = "the full battery (about a minute in release); run with --ignored"]
fn battery_full() {
    run_battery(56, 0x5EED_0010, 1);
}

/// The slender rigid whisker under a strong flow of issue "Speed to the floor" (g1,
/// theta = 0.1, k = inf, q = 8, a tangential first contact) had stopped with a stalled
/// corrector near the fold of its contact point: it sweeps through, every row passing the
/// battery's independent checks. (Kept out of `named_scenes`, which would shift the seeded
/// random scenes.)
#[test]
fn a_slender_rigid_whisker_under_a_strong_flow_sweeps_through() {
    let s = SceneSpec {
        name: "slender rigid theta = 0.1, q = 8 on g1".into(),
        whisker: Whisker::new(0.1, 0.0, 0.0, f64::INFINITY),
        flow: FluidLoad { q: 8.0, alpha: 0.0 },
        profile: Profile::g1(),
    };
    let settings = SweepSettings {
        points: 30,
        pre_contact_rows: 3,
        ..SweepSettings::default()
    };
    let r = sweep(&s.whisker, s.flow, &s.profile, &settings).expect("the sweep goes through");
    assert_eq!(r.first_contact, FirstContact::Tangential);
    assert_eq!(r.separation, Separation::Release);
    let mut tally = Tally::default();
    tally.record(&s, &r, 0.0);
    assert!(tally.failures.is_empty(), "{:?}", tally.failures);
}

/// The full battery on another seed (hexadecimal in `VIBRISSA_BATTERY_SEED`, 5EED0011 by
/// default): new scenes for a change that the usual seed has seen too often. Known to fail
/// on 5EED0012 (two slender tips whose phase-B corrector stalls) and 5EED0013 (transient
/// second contacts between traced nodes: rows inside the contour by up to 4e-6).
#[test]
#[ignore = "another seed of the full battery; run with --ignored"]
fn battery_other_seed() {
    let seed = std::env::var("VIBRISSA_BATTERY_SEED").map_or(0x5EED_0011, |s| {
        u64::from_str_radix(s.trim_start_matches("0x"), 16).expect("a hexadecimal seed")
    });
    run_battery(56, seed, 1);
}
