//! Scenes and references the methods' unit tests share (test builds only): each method is
//! checked against a solver it does not use, on the same scenes.

use crate::{solve, Loads, Method, ModelError, Scene, Solution, TipForce, Whisker};

/// Moderate whiskers single shooting (`accurate`) answers: DP and AP tip forces, a flow,
/// spring and rigid bases, pre-curvature (theta 0.2..1).
pub(crate) fn moderate() -> Vec<Scene> {
    vec![
        Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(3.0, 0.0))),
        Scene::new(
            Whisker::new(0.2, 2.0, -1.0, 20.0),
            Loads::combined(TipForce::dp(5.0, 0.5), 5.0, 0.0),
        ),
        Scene::new(
            Whisker::new(0.5, 0.0, 0.0, 10.0),
            Loads::tip(TipForce::ap(5.0, 0.0)),
        ),
        Scene::new(
            Whisker::new(0.3, 0.0, 0.0, f64::INFINITY),
            Loads::fluid(20.0, 0.0),
        ),
    ]
}

/// `scene` solved by `method` and by `accurate` (single shooting, an independent
/// discretisation), with their difference; `method`'s error where it fails.
pub(crate) fn against_accurate(
    scene: &Scene,
    method: &Method,
) -> Result<(Solution, Solution, f64), ModelError> {
    let sol = solve(scene, method)?;
    let acc = solve(scene, &Method::accurate()).unwrap();
    let d = sol.difference(&acc);
    Ok((sol, acc, d))
}

/// The slender scene `accurate`'s shooting refuses (theta = 0.01, rigid, f = 5) solved by
/// `method`, and FDM + two Richardson levels on 3200..12800 intervals (an independent
/// discretisation), with their difference.
pub(crate) fn slender_against_fdm_richardson(method: &Method) -> (Solution, Solution, f64) {
    let scene = Scene::new(
        Whisker::new(0.01, 0.0, 0.0, f64::INFINITY),
        Loads::tip(TipForce::dp(5.0, 0.0)),
    );
    let sol = solve(&scene, method).unwrap();
    let r = solve(&scene, &Method::FdmRichardson { n: 3200 }).unwrap();
    let d = sol.difference(&r);
    (sol, r, d)
}
