//! The fold rule over the command line's parameter space: seeded random scenes (taper 0.1..1,
//! pre-curvature |A|, |B| <= 3, rigid or elastic base k = 0.1..30, DP or AP tip forces up to
//! 20 at any angle, flows up to 15 at any angle). For every scene `accurate` answers:
//!
//! - without a load path, a shooting answer is on the unfolded side, `dR/dphi1 > 0` in an
//!   independent shot at 1e-12 (the rule's own criterion, checked by another integration;
//!   an answer of the FDM fallback is not: where it falls back the shots are too
//!   ill-conditioned to tell);
//! - with one, every fold is a fold (`R = 0` and `dR/dphi1 = 0` there, independent shots),
//!   their number is even, and the equilibrium returned is the path's arrival;
//! - `fdm-richardson` (its own grids; on a fold it follows the same path) either agrees
//!   within the two error estimates or refuses (its two grids disagree, its continuation
//!   stalls): it never returns another equilibrium.
//!
//! `folds_subset` (60 scenes) runs in CI; `folds_full` (300 scenes, ~10 s in release) with
//! `cargo test --release -p beam-model --test it -- folds:: --ignored --nocapture`.

use beam_model::shot::base_residual;
use beam_model::{solve, Loads, Method, Scene, TipForce, Whisker};

/// xorshift64: a seeded uniform stream in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn scene(r: &mut Rng) -> Scene {
    use std::f64::consts::PI;
    let theta = 0.1 + 0.9 * r.next();
    let (a, b) = (-3.0 + 6.0 * r.next(), -3.0 + 6.0 * r.next());
    let k = if r.next() < 0.3 {
        f64::INFINITY
    } else {
        10f64.powf(-1.0 + 2.5 * r.next())
    };
    let (f, beta) = (20.0 * r.next(), PI * (2.0 * r.next() - 1.0));
    let q = if r.next() < 0.5 { 0.0 } else { 15.0 * r.next() };
    let alpha = PI * (2.0 * r.next() - 1.0);
    let tip = if r.next() < 0.3 {
        TipForce::ap(f, beta)
    } else {
        TipForce::dp(f, beta)
    };
    Scene::new(Whisker::new(theta, a, b, k), Loads::combined(tip, q, alpha))
}

/// `(R, dR/dphi1)` at `(phi1, lambda)` by a shot at 1e-12 from the loaded end.
fn residual_at(scene: &Scene, phi1: f64, lambda: f64) -> (f64, f64) {
    base_residual(&scene.whisker, &scene.loads, phi1, lambda, 1e-12).expect("a shot")
}

#[derive(Debug, Default)]
struct Tally {
    answered: usize,
    folded: usize,
    folds: usize,
    fdm_agree: usize,
    fdm_refused: usize,
    failures: Vec<String>,
}

fn run(scenes: usize) -> Tally {
    let mut rng = Rng(0x5eed_f01d);
    let mut t = Tally::default();
    for i in 0..scenes {
        let scene = scene(&mut rng);
        let Ok(acc) = solve(&scene, &Method::accurate()) else {
            continue;
        };
        t.answered += 1;
        let mut fail = |what: String| t.failures.push(format!("#{i} {scene:?}: {what}"));
        let shooting = acc.stats.method_used == beam_model::MethodKind::Accurate;
        let Some(path) = &acc.load_path else {
            if shooting {
                // the residual as the tip-angle error it implies (|dR/dphi1| reaches 1e6)
                let (r, dr) = residual_at(&scene, acc.loaded_end.phi, 1.0);
                if (r / dr).abs() > 1e-10 || dr <= 0.0 {
                    fail(format!("no load path, but R {r:e}, dR/dphi1 {dr:e}"));
                }
            }
            continue;
        };
        t.folded += usize::from(!path.folds.is_empty());
        t.folds += path.folds.len();
        if path.folds.len() % 2 != 0 {
            fail(format!("{} folds before the arrival", path.folds.len()));
        }
        for f in &path.folds {
            let (r, dr) = residual_at(&scene, f.phi1, f.lambda);
            if r.abs() > 1e-6 || dr.abs() > 1e-2 {
                fail(format!("fold {f:?}: R {r:e}, dR/dphi1 {dr:e}"));
            }
        }
        if shooting && (acc.loaded_end.phi - path.arrival.phi1).abs() > 1e-9 {
            fail(format!(
                "returned phi1 {} is not the arrival {:?}",
                acc.loaded_end.phi, path.arrival
            ));
        }
        match solve(&scene, &Method::FdmRichardson { n: 100 }) {
            Ok(fdm) => {
                let d = fdm.difference(&acc);
                if d <= fdm.stats.error_estimate + acc.stats.error_estimate + 1e-9 {
                    t.fdm_agree += 1;
                } else {
                    fail(format!("fdm-richardson {d:e} from accurate"));
                }
            }
            // a refusal (two grids disagree, an estimate too large, a stalled path) is an
            // answer too; only another equilibrium is not
            Err(_) => t.fdm_refused += 1,
        }
    }
    eprintln!("{t:?}");
    t
}

#[test]
fn folds_subset() {
    let t = run(60);
    assert!(t.failures.is_empty(), "{:#?}", t.failures);
    assert!(t.answered >= 55, "{t:?}");
}

#[test]
#[ignore = "300 scenes; run with --ignored"]
fn folds_full() {
    let t = run(300);
    assert!(t.failures.is_empty(), "{:#?}", t.failures);
    // the space holds folding load paths, or the battery tests nothing
    assert!(t.folded >= 3, "{t:?}");
}
