//! The sweep cases of thesis chapter 5 (eqs. 5.4-5.10, 5.12) as reference problems shared by
//! tests, benchmarks and the figure reproduction.

use crate::profile::Profile;
use beam_model::Whisker;

/// One sweep case: a whisker, a fluid load and a contour.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepCase {
    /// Thesis case, e.g. `"1"`, `"4A"`, `"5"`, `"exp"`.
    pub case: &'static str,
    /// Legend label, e.g. `"q=5"`.
    pub label: String,
    /// Profile name (`g1`, `g2`, `ge`).
    pub profile_name: &'static str,
    /// The contour.
    pub profile: Profile,
    /// The whisker.
    pub whisker: Whisker,
    /// Fluid load q (alpha = 0).
    pub q: f64,
}

fn whisker(theta: f64, a: f64, b: f64, k: f64) -> Whisker {
    Whisker::new(theta, a, b, k)
}

fn profiles(names: &[&'static str]) -> Vec<(&'static str, Profile)> {
    names
        .iter()
        .map(|&n| {
            let p = match n {
                "g1" => Profile::g1(),
                "g2" => Profile::g2(),
                _ => Profile::ge(),
            };
            (n, p)
        })
        .collect()
}

const INF: f64 = f64::INFINITY;

/// All chapter-5 cases in thesis order (cases 1, 2, 3, 4A, 4B, 5 on their contours, and the
/// experimental contour ge with q = 0).
pub fn chapter5() -> Vec<SweepCase> {
    let mut out = Vec::new();
    let mut push = |case, label: String, (pn, p): &(&'static str, Profile), w, q| {
        out.push(SweepCase {
            case,
            label,
            profile_name: pn,
            profile: p.clone(),
            whisker: w,
            q,
        })
    };
    for p in profiles(&["g1", "g2"]) {
        for q in [0.0, 1.0, 5.0, 10.0] {
            push("1", format!("q={q}"), &p, whisker(1.0, 0.0, 0.0, INF), q);
        }
    }
    for p in profiles(&["g1", "g2"]) {
        for theta in [1.0, 0.75, 0.5, 0.25] {
            push(
                "2",
                format!("theta={theta}"),
                &p,
                whisker(theta, 0.0, 0.0, INF),
                5.0,
            );
        }
    }
    for p in profiles(&["g1", "g2"]) {
        for k in [INF, 20.0, 10.0, 5.0] {
            push("3", format!("k={k}"), &p, whisker(1.0, 0.0, 0.0, k), 5.0);
        }
    }
    for p in profiles(&["g1", "g2"]) {
        for (a, b) in [
            (0.0, 0.0),
            (0.0, -0.5),
            (0.0, -1.0),
            (-1.0, 0.0),
            (-2.0, 0.0),
        ] {
            push(
                "4A",
                format!("A={a} B={b}"),
                &p,
                whisker(1.0, a, b, INF),
                5.0,
            );
        }
    }
    for p in profiles(&["g2"]) {
        for (a, b) in [(0.0, 0.0), (0.0, 0.5), (0.0, 1.0), (1.0, 0.0), (2.0, 0.0)] {
            push(
                "4B",
                format!("A={a} B={b}"),
                &p,
                whisker(1.0, a, b, INF),
                5.0,
            );
        }
    }
    for (theta, k) in [(0.75, 20.0), (0.5, 20.0), (0.75, 10.0), (0.5, 10.0)] {
        push(
            "5",
            format!("theta={theta} k={k}"),
            &profiles(&["g1"])[0],
            whisker(theta, -1.0, -0.5, k),
            5.0,
        );
    }
    for (theta, k) in [(0.75, 20.0), (0.5, 20.0), (0.75, 10.0), (0.5, 10.0)] {
        push(
            "5",
            format!("theta={theta} k={k}"),
            &profiles(&["g2"])[0],
            whisker(theta, 2.0, 0.0, k),
            5.0,
        );
    }
    push(
        "exp",
        "q=0".into(),
        &profiles(&["ge"])[0],
        whisker(1.0, 0.0, 0.0, INF),
        0.0,
    );
    out
}
