//! What the frictional sweep is told by the sweep's settings.

/// Settings of the frictional sweep handed down from [`crate::sweep::SweepSettings`].
pub(crate) struct FrictionSettings {
    pub mu: f64,
    /// The base motion's frame (a path's: its segment's).
    pub frame: crate::motion::Frame,
    pub points: usize,
    pub integration_tol: f64,
    pub solve_tol: f64,
    pub event_tol: f64,
    pub check_penetration: bool,
    pub max_steps: usize,
    pub max_step: f64,
    /// Rows' integrator and residual tolerances and the estimate's integrator tolerance,
    /// with an accuracy asked for.
    pub rows_at: Option<(f64, f64, f64)>,
}

impl FrictionSettings {
    /// The frictional sweep's settings from the sweep's `settings`, the coefficient `mu` and
    /// the motion's frame `frame` (the rows' tolerances from the accuracy asked for).
    pub fn of(
        settings: &crate::sweep::SweepSettings,
        mu: f64,
        frame: crate::motion::Frame,
    ) -> Self {
        use crate::accuracy::{row_integration_tol, row_solve_tol, ESTIMATE_FACTOR};
        FrictionSettings {
            mu,
            frame,
            points: settings.points,
            integration_tol: settings.integration_tol,
            solve_tol: settings.solve_tol,
            event_tol: settings.event_tol,
            check_penetration: settings.check_penetration,
            max_steps: settings.max_steps,
            max_step: settings.max_step,
            rows_at: settings.accuracy.map(|t| {
                (
                    row_integration_tol(t),
                    row_solve_tol(t),
                    row_integration_tol(t) * ESTIMATE_FACTOR,
                )
            }),
        }
    }
}
