//! # beam-model
//!
//! The whisker (vibrissa) as a tapered, pre-curved, elastically supported Euler-Bernoulli
//! beam with large deflections (thesis ch. 3-4), dimensionless with length 1:
//!
//! | module | concept |
//! |---|---|
//! | [`whisker`] | conicity theta, Cesaro pre-curvature `A s + B` |
//! | [`support`] | rigid clamp or torsional spring k |
//! | [`loads`] | tip force f at beta (DP or AP), fluid load q at alpha, loaded length s1 |
//! | [`scene`] | a whisker with its loads |
//! | [`balance`] | the force balance: loads to base reactions and back [5.1, 6.1, 6.8, 6.9] |
//! | [`units`] | physical units <-> dimensionless form [3.16-3.19], rat whisker presets (Table 2.2) |
//! | [`equations`] | the system [3.25] and its Jacobian [3.27] plugged into `bvp-solvers` |
//! | [`linear`] | linear small-deflection theory about the unloaded shape (the continuation's first predictor; `auto`'s cheapest model where its a-priori bound meets the tolerance, [`ModelKind::Linear`]) |
//! | [`shot`] | shooting from the loaded end (observables as initial values) |
//! | [`methods`] | `fdm`, `rk4`, `accurate`, `auto` and [`solve`] |
//! | [`scenarios`] | the thesis's load scenarios 1-18 as reference problems |
//! | [`accuracy`] | the report of an accuracy asked for: one error estimate per item of a result (sweep rows, reconstructed points) |
//!
//! ```
//! use beam_model::{solve, Loads, Method, Scene, TipForce, Whisker};
//! let scene = Scene::new(Whisker::uniform(), Loads::tip(TipForce::dp(1.0, 0.0)));
//! let sol = solve(&scene, &Method::accurate()).unwrap();
//! // Mattiasson (1981): x1 = 0.30172, y1 = 0.94357 for f = 1
//! assert!((sol.tip.x - 0.30172).abs() < 1e-5 && (sol.tip.y - 0.94357).abs() < 1e-5);
//! ```

pub mod accuracy;
pub mod balance;
pub mod equations;
pub mod error;
pub mod linear;
pub mod loads;
pub mod methods;
pub mod path;
pub mod scenarios;
pub mod scene;
pub mod shot;
pub mod solution;
pub mod support;
pub mod trig;
pub mod units;
pub mod whisker;

pub use accuracy::AccuracyReport;
pub use balance::Reactions;
pub use error::{ModelError, Result};
pub use loads::{FluidLoad, LoadKind, Loads, TipForce};
pub use methods::{shape_from_tip_angle, solve, Method};
pub use scene::Scene;
pub use solution::{
    BaseObservables, Elastica, EndState, LoadFold, LoadPath, MethodKind, ModelKind,
    PathEquilibrium, Solution, SolveStats,
};
pub use support::Support;
pub use units::{PhysicalWhisker, Preset};
pub use whisker::Whisker;
