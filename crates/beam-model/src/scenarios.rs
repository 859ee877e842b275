//! The thesis's load scenarios 1-18 (Tables 3.1-3.3, ch. 4) as reference problems shared by
//! tests, benchmarks and the figure reproduction. Parameters are those of the thesis's
//! figures (Figs. 4.3-4.29); where a figure does not list its load values, a representative
//! range is used and documented on the scenario.

use crate::loads::{Loads, TipForce};
use crate::scene::Scene;
use crate::whisker::Whisker;

/// One case of a scenario: a label for legends and the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Legend label, e.g. `"f=5 beta=30deg k=20"`.
    pub label: String,
    /// The scene.
    pub scene: Scene,
}

/// A load scenario of the thesis.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Scenario number 1-18.
    pub id: u8,
    /// Short title (thesis section heading).
    pub title: &'static str,
    /// Thesis figures showing it.
    pub figures: &'static str,
    /// The cases.
    pub cases: Vec<Case>,
}

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn whisker(theta: f64, a: f64, b: f64, k: f64) -> Whisker {
    Whisker::new(theta, a, b, k)
}

fn fmt_k(k: f64) -> String {
    if k.is_finite() {
        format!(" k={k}")
    } else {
        String::new()
    }
}

/// Tip-load magnitudes of Fig. 4.5.
pub const TIP_LOADS: [f64; 8] = [0.01, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 40.0];
/// Fluid-load magnitudes used for the distributed-load scenarios (Figs. 4.11-4.17).
pub const FLUID_LOADS: [f64; 7] = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 40.0];
/// AP tip-load magnitudes of Fig. 4.9 (0..30).
pub const AP_LOADS: [f64; 7] = [1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0];
/// The combined-load scenarios' tip forces (Table 4.1, q = 5, lambda = 0.5, 1, 2).
pub const COMBINED_F: [f64; 3] = [10.0, 5.0, 2.5];

/// Combined-load cases of scenarios 11-18: q = 5, alpha = 0, f in Table 4.1, beta = 30 deg.
fn combined(label: &str, w: Whisker, beta_deg: f64) -> Vec<Case> {
    COMBINED_F
        .iter()
        .map(|&f| Case {
            label: format!("{label} f={f} beta={beta_deg}deg"),
            scene: Scene::new(w, Loads::combined(TipForce::dp(f, deg(beta_deg)), 5.0, 0.0)),
        })
        .collect()
}

fn fluid_cases(label: &str, w: Whisker, qs: &[f64], alpha_deg: f64) -> Vec<Case> {
    qs.iter()
        .map(|&q| Case {
            label: format!("{label} q={q} alpha={alpha_deg}deg"),
            scene: Scene::new(w, Loads::fluid(q, deg(alpha_deg))),
        })
        .collect()
}

const INF: f64 = f64::INFINITY;

/// Scenario `id` (1-18), or `None`.
pub fn scenario(id: u8) -> Option<Scenario> {
    let mut cases = Vec::new();
    let (title, figures) = match id {
        1 => {
            for beta in [0.0, 45.0] {
                for f in TIP_LOADS {
                    cases.push(Case {
                        label: format!("f={f} beta={beta}deg"),
                        scene: Scene::new(
                            Whisker::uniform(),
                            Loads::tip(TipForce::dp(f, deg(beta))),
                        ),
                    });
                }
            }
            ("DP tip load, rigid support", "4.3-4.7")
        }
        2 => {
            for f in AP_LOADS {
                cases.push(Case {
                    label: format!("AP f={f}"),
                    scene: Scene::new(Whisker::uniform(), Loads::tip(TipForce::ap(f, 0.0))),
                });
            }
            ("AP tip load, rigid support", "4.9-4.10")
        }
        3 => {
            for alpha in [0.0, 45.0] {
                cases.extend(fluid_cases("", Whisker::uniform(), &FLUID_LOADS, alpha));
            }
            ("distributed load, rigid, uniform, straight", "4.11-4.13")
        }
        4 => {
            for k in [INF, 20.0, 10.0, 5.0, 1.0, 0.5] {
                cases.extend(fluid_cases(
                    &fmt_k(k),
                    whisker(1.0, 0.0, 0.0, k),
                    &[10.0, 20.0],
                    0.0,
                ));
            }
            ("distributed load, elastic support", "4.14-4.15")
        }
        5 => {
            for theta in [1.0, 0.75, 0.5, 0.25] {
                cases.extend(fluid_cases(
                    &format!("theta={theta}"),
                    whisker(theta, 0.0, 0.0, INF),
                    &FLUID_LOADS,
                    0.0,
                ));
            }
            ("distributed load, rigid, conical", "4.16")
        }
        6 => {
            for k in [20.0, 10.0, 5.0, 1.0] {
                for theta in [1.0, 0.75, 0.5, 0.25] {
                    cases.extend(fluid_cases(
                        &format!("theta={theta}{}", fmt_k(k)),
                        whisker(theta, 0.0, 0.0, k),
                        &[5.0, 10.0, 20.0],
                        0.0,
                    ));
                }
            }
            ("distributed load, elastic, conical", "4.17")
        }
        7 => {
            for (a, b) in [
                (0.0, 0.5),
                (0.0, -0.5),
                (2.0, 0.0),
                (-2.0, 0.0),
                (3.0, -0.5),
                (-3.0, 0.5),
            ] {
                cases.extend(fluid_cases(
                    &format!("A={a} B={b}"),
                    whisker(1.0, a, b, INF),
                    &[5.0, 10.0, 20.0, 40.0],
                    0.0,
                ));
            }
            ("distributed load, rigid, pre-curved", "4.18")
        }
        8 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0), (2.0, -1.0)] {
                for k in [INF, 20.0, 10.0, 5.0, 1.0] {
                    cases.extend(fluid_cases(
                        &format!("A={a} B={b}{}", fmt_k(k)),
                        whisker(1.0, a, b, k),
                        &[10.0, 20.0],
                        0.0,
                    ));
                }
            }
            ("distributed load, elastic, pre-curved", "4.19")
        }
        9 => {
            for (a, b) in [(0.0, -0.5), (-2.0, 0.0), (1.0, -0.5)] {
                for theta in [1.0, 0.75, 0.5, 0.25] {
                    cases.extend(fluid_cases(
                        &format!("A={a} B={b} theta={theta}"),
                        whisker(theta, a, b, INF),
                        &[10.0],
                        0.0,
                    ));
                }
            }
            ("distributed load, rigid, conical, pre-curved", "4.20")
        }
        10 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0), (2.0, -1.0)] {
                for theta in [0.5, 0.25] {
                    for k in [INF, 20.0, 10.0, 5.0, 1.0] {
                        cases.extend(fluid_cases(
                            &format!("A={a} B={b} theta={theta}{}", fmt_k(k)),
                            whisker(theta, a, b, k),
                            &[10.0],
                            0.0,
                        ));
                    }
                }
            }
            ("distributed load, elastic, conical, pre-curved", "4.21")
        }
        11 => {
            for beta in [30.0, 45.0] {
                cases.extend(combined("", Whisker::uniform(), beta));
            }
            ("combined load, uniform, straight, rigid", "4.22")
        }
        12 => {
            for k in [20.0, 10.0, 5.0, 1.0] {
                cases.extend(combined(&fmt_k(k), whisker(1.0, 0.0, 0.0, k), 30.0));
            }
            ("combined load, uniform, straight, elastic", "4.23")
        }
        13 => {
            for theta in [0.75, 0.5] {
                cases.extend(combined(
                    &format!("theta={theta}"),
                    whisker(theta, 0.0, 0.0, INF),
                    30.0,
                ));
            }
            ("combined load, tapered, straight, rigid", "4.24")
        }
        14 => {
            for theta in [0.75, 0.5] {
                for k in [20.0, 5.0] {
                    cases.extend(combined(
                        &format!("theta={theta}{}", fmt_k(k)),
                        whisker(theta, 0.0, 0.0, k),
                        30.0,
                    ));
                }
            }
            ("combined load, tapered, straight, elastic", "4.25")
        }
        15 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0), (2.0, -0.5), (2.0, 1.0)] {
                cases.extend(combined(
                    &format!("A={a} B={b}"),
                    whisker(1.0, a, b, INF),
                    30.0,
                ));
            }
            ("combined load, uniform, pre-curved, rigid", "4.26")
        }
        16 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0)] {
                for k in [20.0, 5.0] {
                    cases.extend(combined(
                        &format!("A={a} B={b}{}", fmt_k(k)),
                        whisker(1.0, a, b, k),
                        30.0,
                    ));
                }
            }
            ("combined load, uniform, pre-curved, elastic", "4.27")
        }
        17 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0), (2.0, -1.0)] {
                for theta in [0.75, 0.5] {
                    cases.extend(combined(
                        &format!("A={a} B={b} theta={theta}"),
                        whisker(theta, a, b, INF),
                        30.0,
                    ));
                }
            }
            ("combined load, tapered, pre-curved, rigid", "4.28")
        }
        18 => {
            for (a, b) in [(0.0, -0.5), (2.0, 0.0), (2.0, -1.0)] {
                for k in [20.0, 10.0] {
                    cases.extend(combined(
                        &format!("A={a} B={b} theta=0.5{}", fmt_k(k)),
                        whisker(0.5, a, b, k),
                        30.0,
                    ));
                }
            }
            ("combined load, tapered, pre-curved, elastic", "4.29")
        }
        _ => return None,
    };
    for c in &mut cases {
        c.label = c.label.trim().to_string();
    }
    Some(Scenario {
        id,
        title,
        figures,
        cases,
    })
}

/// All 18 scenarios.
pub fn all() -> Vec<Scenario> {
    (1..=18).filter_map(scenario).collect()
}

/// The three reference scenes of the accuracy-against-speed study: a uniform tip load
/// (f = 5, beta = 0); a conical whisker on a spring under a fluid load (theta = 0.5, k = 10,
/// q = 10); a pre-curved, conical, elastic whisker under a combined load (theta = 0.75,
/// A = 2, B = -1, k = 20, f = 5 at 30 deg, q = 5).
pub fn reference_scenes() -> [(&'static str, Scene); 3] {
    [
        (
            "uniform-tip",
            Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(5.0, 0.0))),
        ),
        (
            "conical-spring-fluid",
            Scene::new(whisker(0.5, 0.0, 0.0, 10.0), Loads::fluid(10.0, 0.0)),
        ),
        (
            "precurved-combined",
            Scene::new(
                whisker(0.75, 2.0, -1.0, 20.0),
                Loads::combined(TipForce::dp(5.0, deg(30.0)), 5.0, 0.0),
            ),
        ),
    ]
}
