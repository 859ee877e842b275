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
