//! The small records of a result, as typed values with serde `Serialize`: what `solve
//! --json` and `sweep --json` print (the CLI serialises them) and the dicts the Python
//! package returns (built from the same values).
//!
//! Every number is written as JSON writes it: a non-finite one (a rigid support's
//! `k = inf`, a NaN estimate) is `null` (Python's `None`), through [`finite`] and its
//! siblings, so that the CLI's JSON and the Python dicts say the same thing.
//!
//! - [`SolveSummary`]: one configuration [3.25-3.27]: method, ends, base observables
//!   [3.31], statistics, the scene's values, the load path's folds, the physical values;
//! - [`SweepSummary`]: a sweep [ch. 5]: first contact, separation, phases, row counts,
//!   events, the flow and the accuracy asked for;
//! - [`ReconSummary`]: a reconstruction [ch. 6]: the flow, the noise, counts, accuracy.

use beam_model::{EndState, LoadKind, Solution};
use contact_sim::{ContactLaw, SweepResult};
use serde::{Serialize, Serializer};

use crate::resolve::Resolved;
use crate::sweep_events::{friction_label, friction_switches, sweep_events, RowCounts};
use crate::units::{Quantity, UnitSystem};

/// Serialises a number, `None` (JSON `null`) when it is NaN or infinite.
pub fn finite<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

/// Serialises an optional number: `None` when absent, else as [`finite`].
pub fn finite_opt<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(x) => finite(x, s),
        None => s.serialize_none(),
    }
}

/// A number that serialises as [`finite`] (in lists and matrices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Finite(pub f64);

impl Serialize for Finite {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        finite(&self.0, s)
    }
}

/// The words of a unit system in the summaries: `physical` or `dimensionless`.
pub fn units_word(units: &UnitSystem) -> &'static str {
    if units.is_physical() {
        "physical"
    } else {
        "dimensionless"
    }
}

/// An end of the whisker: position and tangent angle (rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EndSummary {
    /// x.
    #[serde(serialize_with = "finite")]
    pub x: f64,
    /// y.
    #[serde(serialize_with = "finite")]
    pub y: f64,
    /// Tangent angle (rad).
    #[serde(serialize_with = "finite")]
    pub phi: f64,
}

impl From<&EndState> for EndSummary {
    fn from(e: &EndState) -> Self {
        EndSummary {
            x: e.x,
            y: e.y,
            phi: e.phi,
        }
    }
}

/// The base observables [3.31], named as the CSV columns.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BaseSummary {
    /// Base force Ax.
    #[serde(rename = "Ax", serialize_with = "finite")]
    pub ax: f64,
    /// Base force Ay.
    #[serde(rename = "Ay", serialize_with = "finite")]
    pub ay: f64,
    /// Base moment MA.
    #[serde(rename = "MA", serialize_with = "finite")]
    pub ma: f64,
    /// Base angle phi0 (rad).
    #[serde(serialize_with = "finite")]
    pub phi0: f64,
}

/// A solve's statistics (`beam_model::SolveStats`): iterations, residual, error estimate
/// against the tolerance, the method and model that answered.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StatsSummary {
    /// Newton (or Picard) iterations.
    pub iterations: usize,
    /// The final residual.
    #[serde(serialize_with = "finite")]
    pub residual: f64,
    /// Load continuation steps.
    pub continuation_steps: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
    /// The error estimate of the answer (dimensionless).
    #[serde(serialize_with = "finite")]
    pub error_estimate: f64,
    /// The tolerance it was held to.
    #[serde(serialize_with = "finite")]
    pub tolerance: f64,
    /// The method that answered.
    pub method_used: &'static str,
    /// The model that answered (linear theory or the elastica).
    pub model_used: &'static str,
    /// Branch jumps met along the load path.
    pub branch_jumps: usize,
}

/// The scene's dimensionless values as solved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneSummary {
    /// Taper theta.
    #[serde(serialize_with = "finite")]
    pub theta: f64,
    /// Pre-curvature slope A.
    #[serde(serialize_with = "finite")]
    pub a: f64,
    /// Pre-curvature offset B.
    #[serde(serialize_with = "finite")]
    pub b: f64,
    /// Base stiffness k (`None`: rigid).
    #[serde(serialize_with = "finite")]
    pub k: f64,
    /// Tip force f.
    #[serde(serialize_with = "finite")]
    pub f: f64,
    /// Tip force angle (degrees).
    #[serde(serialize_with = "finite")]
    pub beta_deg: f64,
    /// `dp` (direction-preserving) or `ap` (angle-preserving).
    pub load: &'static str,
    /// Fluid load q.
    #[serde(serialize_with = "finite")]
    pub q: f64,
    /// Fluid load angle (degrees).
    #[serde(serialize_with = "finite")]
    pub alpha_deg: f64,
}

/// A fold of the load path from zero: load scale and angles there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FoldSummary {
    /// Load scale lambda.
    #[serde(serialize_with = "finite")]
    pub lambda: f64,
    /// Loaded-end angle.
    #[serde(serialize_with = "finite")]
    pub phi1: f64,
    /// Base angle.
    #[serde(serialize_with = "finite")]
    pub phi0: f64,
}

/// An equilibrium at full load on the load path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EquilibriumSummary {
    /// Loaded-end angle.
    #[serde(serialize_with = "finite")]
    pub phi1: f64,
    /// Base angle.
    #[serde(serialize_with = "finite")]
    pub phi0: f64,
}

/// The load path from zero where it folds (`beam_model::LoadPath`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoadPathSummary {
    /// Its folds.
    pub folds: Vec<FoldSummary>,
    /// The first arrival at full load (the equilibrium returned).
    pub arrival: EquilibriumSummary,
    /// Other equilibria at full load on the path.
    pub other_equilibria: Vec<EquilibriumSummary>,
    /// Continuation steps.
    pub steps: usize,
}

/// A physical end position (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TipMetres {
    /// x (m).
    #[serde(serialize_with = "finite")]
    pub x: f64,
    /// y (m).
    #[serde(serialize_with = "finite")]
    pub y: f64,
}

/// The base observables in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BaseSi {
    /// Ax (N).
    #[serde(rename = "Ax_N", serialize_with = "finite")]
    pub ax_n: f64,
    /// Ay (N).
    #[serde(rename = "Ay_N", serialize_with = "finite")]
    pub ay_n: f64,
    /// MA (N m).
    #[serde(rename = "MA_Nm", serialize_with = "finite")]
    pub ma_nm: f64,
}

/// A physical whisker's values and the solve in SI units [3.16-3.19].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhysicalSummary {
    /// Length (m).
    #[serde(serialize_with = "finite")]
    pub length_m: f64,
    /// Base diameter (m).
    #[serde(serialize_with = "finite")]
    pub base_diameter_m: f64,
    /// Young's modulus (Pa).
    #[serde(serialize_with = "finite")]
    pub youngs_modulus_pa: f64,
    /// The tip (m).
    pub tip_m: TipMetres,
    /// The base observables (N, N m).
    pub base: BaseSi,
    /// The tip force (N).
    #[serde(rename = "f_N", serialize_with = "finite")]
    pub f_n: f64,
    /// The fluid load (N/m).
    #[serde(rename = "q_N_per_m", serialize_with = "finite")]
    pub q_n_per_m: f64,
}

/// One configuration solved (`solve --json`): the model's dimensionless values, with the
/// SI values of a physical whisker under `physical`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolveSummary {
    /// The method asked for.
    pub method: &'static str,
    /// Its grid intervals.
    pub n: usize,
    /// The free end s = 1.
    pub tip: EndSummary,
    /// The loaded end s = s1.
    pub loaded_end: EndSummary,
    /// The base observables [3.31].
    pub base: BaseSummary,
    /// The solver's statistics.
    pub stats: StatsSummary,
    /// The scene as solved.
    pub scene: SceneSummary,
    /// `physical` or `dimensionless`.
    pub units: &'static str,
    /// The load path from zero, where it folds or meets other equilibria.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_path: Option<LoadPathSummary>,
    /// The SI values of a physical whisker.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physical: Option<PhysicalSummary>,
}

impl SolveSummary {
    /// The summary of the solution `sol` of the resolved scene `r`.
    pub fn of(r: &Resolved, sol: &Solution) -> Self {
        let s = &r.scene;
        let st = &sol.stats;
        SolveSummary {
            method: r.method.name(),
            n: r.method.intervals(),
            tip: (&sol.tip).into(),
            loaded_end: (&sol.loaded_end).into(),
            base: BaseSummary {
                ax: sol.base.ax,
                ay: sol.base.ay,
                ma: sol.base.ma,
                phi0: sol.base.phi0,
            },
            stats: StatsSummary {
                iterations: st.iterations,
                residual: st.residual,
                continuation_steps: st.continuation_steps,
                evaluations: st.evaluations,
                error_estimate: st.error_estimate,
                tolerance: st.tolerance,
                method_used: st.method_used.name(),
                model_used: st.model_used.name(),
                branch_jumps: st.branch_jumps,
            },
            scene: SceneSummary {
                theta: s.whisker.theta,
                a: s.whisker.a,
                b: s.whisker.b,
                k: s.whisker.support.stiffness(),
                f: s.loads.tip.f,
                beta_deg: s.loads.tip.beta.to_degrees(),
                load: match s.loads.tip.kind {
                    LoadKind::Dp => "dp",
                    LoadKind::Ap => "ap",
                },
                q: s.loads.fluid.q,
                alpha_deg: s.loads.fluid.alpha.to_degrees(),
            },
            units: if r.physical.is_some() {
                "physical"
            } else {
                "dimensionless"
            },
            load_path: sol.load_path.as_ref().map(|p| LoadPathSummary {
                folds: p
                    .folds
                    .iter()
                    .map(|f| FoldSummary {
                        lambda: f.lambda,
                        phi1: f.phi1,
                        phi0: f.phi0,
                    })
                    .collect(),
                arrival: EquilibriumSummary {
                    phi1: p.arrival.phi1,
                    phi0: p.arrival.phi0,
                },
                other_equilibria: p
                    .others
                    .iter()
                    .map(|e| EquilibriumSummary {
                        phi1: e.phi1,
                        phi0: e.phi0,
                    })
                    .collect(),
                steps: p.steps,
            }),
            physical: r.physical.as_ref().map(|p| PhysicalSummary {
                length_m: p.length,
                base_diameter_m: p.base_diameter,
                youngs_modulus_pa: p.youngs_modulus,
                tip_m: TipMetres {
                    x: p.length_of(sol.tip.x),
                    y: p.length_of(sol.tip.y),
                },
                base: BaseSi {
                    ax_n: sol.base.ax * p.force_scale(),
                    ay_n: sol.base.ay * p.force_scale(),
                    ma_nm: sol.base.ma * p.moment_scale(),
                },
                f_n: s.loads.tip.f * p.force_scale(),
                q_n_per_m: s.loads.fluid.q * p.line_load_scale(),
            }),
        }
    }
}

/// An event of a sweep: what happens, its 1-based row and base position.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventSummary {
    /// What happens (`first contact (tip)`, `A→B`, `snap`, ...).
    pub event: String,
    /// The 1-based row.
    pub row: usize,
    /// The base position x0 (the scene's length unit).
    #[serde(serialize_with = "finite")]
    pub x0: f64,
}

/// A stick/slip switch of a frictional sweep: which, its 1-based row, base position, contact
/// point and the contact force's normal and tangential parts there (the scene's units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrictionEventSummary {
    /// `stick→slip` or `slip→stick`.
    pub event: &'static str,
    /// The 1-based row.
    pub row: usize,
    /// The base position x0.
    #[serde(serialize_with = "finite")]
    pub x0: f64,
    /// The contact point's x.
    #[serde(serialize_with = "finite")]
    pub xc: f64,
    /// The normal force fn.
    #[serde(serialize_with = "finite")]
    pub f: f64,
    /// The tangential force ft (along `(cos psi, sin psi)`).
    #[serde(serialize_with = "finite")]
    pub ft: f64,
}

impl FrictionEventSummary {
    /// The stick/slip switches of the sweep `res` in the order of the motion, in `units`
    /// (empty without friction).
    pub fn of(res: &SweepResult, units: &UnitSystem) -> Vec<Self> {
        let (l, fs) = (units.scale(Quantity::Length), units.scale(Quantity::Force));
        friction_switches(res)
            .into_iter()
            .map(|s| FrictionEventSummary {
                event: friction_label(s.event.kind),
                row: s.index + 1,
                x0: s.event.x0 * l,
                xc: s.event.xc * l,
                f: s.event.f * fs,
                ft: s.event.ft * fs,
            })
            .collect()
    }
}

/// The range `[least, greatest]` of the base pose over a sweep's contact rows (all its rows
/// if none touched): `x0`, `y0` in the scene's length unit, the turn `gamma_deg` in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PoseRange {
    /// Base x.
    pub x0: [f64; 2],
    /// Base y.
    pub y0: [f64; 2],
    /// The turn of the follicle (degrees).
    pub gamma_deg: [f64; 2],
}

impl PoseRange {
    /// The range over the rows of `res` in `units`.
    pub fn of(res: &SweepResult, units: &UnitSystem) -> Self {
        let l = units.scale(Quantity::Length);
        let contact: Vec<_> = res.contact_points().collect();
        let rows: Vec<_> = if contact.is_empty() {
            res.points.iter().collect()
        } else {
            contact
        };
        let range = |f: &dyn Fn(&contact_sim::SweepPoint) -> f64| {
            let (lo, hi) = rows
                .iter()
                .map(|p| f(p))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
            if lo <= hi {
                [lo, hi]
            } else {
                [0.0, 0.0]
            }
        };
        PoseRange {
            x0: range(&|p| p.x0 * l),
            y0: range(&|p| p.y0 * l),
            gamma_deg: range(&|p| p.gamma.to_degrees()),
        }
    }
}

/// A sweep (`sweep --json`, the Python `summary`): how the contact began and ended, the
/// phases, the row counts and the events (rows numbered from 1 as in [`RowCounts`]), the
/// flow, positions and loads in the scene's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepSummary {
    /// How the contact began (`tip` or `tangential`).
    pub first_contact: &'static str,
    /// Its row.
    pub first_contact_row: Option<usize>,
    /// Its base position.
    #[serde(serialize_with = "finite_opt")]
    pub first_contact_x0: Option<f64>,
    /// How the contact ended.
    pub separation: String,
    /// The last contact row.
    pub separation_row: Option<usize>,
    /// Its base position.
    #[serde(serialize_with = "finite_opt")]
    pub separation_x0: Option<f64>,
    /// The phases in order (`AB`, `BAB`, ...).
    pub phases: String,
    /// All rows.
    pub rows: usize,
    /// Rows before contact.
    pub pre_contact_rows: usize,
    /// Rows in contact.
    pub contact_rows: usize,
    /// Contact rows asked for.
    pub points_requested: usize,
    /// Rows added at events.
    pub event_rows: usize,
    /// The events in row order.
    pub events: Vec<EventSummary>,
    /// The friction coefficient of the contact (0: frictionless).
    #[serde(serialize_with = "finite")]
    pub mu: f64,
    /// The stick/slip switches in the order of the motion (empty without friction).
    pub friction_events: Vec<FrictionEventSummary>,
    /// How the base moved: `translate`, `rotate` or `path` (spec/cli.md `--motion`; set by
    /// [`SweepSummary::with_motion`], `translate` otherwise).
    pub motion: &'static str,
    /// The range of the base pose over the contact rows (all rows if none touched).
    pub pose: PoseRange,
    /// The fluid load (the scene's line-load unit).
    #[serde(serialize_with = "finite")]
    pub q: f64,
    /// The flow angle (degrees).
    #[serde(serialize_with = "finite")]
    pub alpha_deg: f64,
    /// `physical` or `dimensionless`.
    pub units: &'static str,
    /// The length unit.
    pub length_unit: &'static str,
    /// The force unit.
    pub force_unit: &'static str,
    /// The moment unit.
    pub moment_unit: &'static str,
    /// The accuracy asked for of every row, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tol: Option<Finite>,
    /// The model of the rows held to it (always the elastica).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_used: Option<&'static str>,
    /// The worst row's error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_estimate: Option<Finite>,
    /// Its 1-based row.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_estimate_row: Option<usize>,
}

impl SweepSummary {
    /// The summary naming the base motion `motion` (its [`contact_sim::BaseMotion::label`]).
    pub fn with_motion(mut self, motion: &contact_sim::BaseMotion) -> Self {
        self.motion = motion.label();
        self
    }

    /// The summary of the sweep `res` of `requested` contact rows under the contact law
    /// `law` in `units`.
    pub fn of(res: &SweepResult, requested: usize, law: ContactLaw, units: &UnitSystem) -> Self {
        let n = RowCounts::of(res, requested);
        let l = units.scale(Quantity::Length);
        let x0_of = |row: Option<usize>| row.map(|r| res.points[r - 1].x0 * l);
        let worst = res.accuracy.as_ref().and_then(|a| a.worst());
        SweepSummary {
            first_contact: res.first_contact.label(),
            first_contact_row: n.first_contact_row,
            first_contact_x0: x0_of(n.first_contact_row),
            separation: res.separation.to_string(),
            separation_row: n.separation_row,
            separation_x0: x0_of(n.separation_row),
            phases: res.phase_pattern(),
            rows: n.rows,
            pre_contact_rows: n.pre_contact,
            contact_rows: n.contact,
            points_requested: n.requested,
            event_rows: n.event_rows,
            events: sweep_events(res)
                .into_iter()
                .map(|e| EventSummary {
                    row: e.index + 1,
                    x0: res.points[e.index].x0 * l,
                    event: e.label,
                })
                .collect(),
            mu: law.mu(),
            friction_events: FrictionEventSummary::of(res, units),
            motion: "translate",
            pose: PoseRange::of(res, units),
            q: res.q * units.scale(Quantity::LineLoad),
            alpha_deg: res.alpha.to_degrees(),
            units: units_word(units),
            length_unit: units.unit(Quantity::Length),
            force_unit: units.unit(Quantity::Force),
            moment_unit: units.unit(Quantity::Moment),
            tol: res.accuracy.as_ref().map(|a| Finite(a.tol)),
            // the contact rows are always the elastica's (no linear rung): spec/cli.md's
            // `model_used` of the accuracy asked for
            model_used: res
                .accuracy
                .as_ref()
                .map(|_| beam_model::ModelKind::Elastica.name()),
            max_estimate: worst.map(|(_, e)| Finite(e)),
            max_estimate_row: worst.map(|(row, _)| row + 1),
        }
    }
}

/// A reconstruction [ch. 6] (the Python package's `summary`): the flow identified or given,
/// the noise, the counts and the accuracy asked for, in the scene's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReconSummary {
    /// The fluid load (the scene's line-load unit).
    #[serde(serialize_with = "finite")]
    pub q: f64,
    /// The fluid load, dimensionless.
    #[serde(serialize_with = "finite")]
    pub q_dimensionless: f64,
    /// Whether q was given (not identified).
    pub q_given: bool,
    /// The flow angle (degrees).
    #[serde(serialize_with = "finite")]
    pub alpha_deg: f64,
    /// Whether the flow angle was given.
    pub alpha_given: bool,
    /// The relative noise level.
    #[serde(serialize_with = "finite")]
    pub noise: f64,
    /// Whether it was estimated from the log.
    pub noise_estimated: bool,
    /// The pre-contact rows' misfit to the free whisker's model.
    #[serde(serialize_with = "finite")]
    pub model_mismatch: f64,
    /// Contact points.
    pub points: usize,
    /// Rows of the log.
    pub rows: usize,
    /// The first contact row (1-based).
    pub first_contact_row: usize,
    /// The method (`accurate` or `thesis`).
    pub method: &'static str,
    /// `physical` or `dimensionless`.
    pub units: &'static str,
    /// The length unit.
    pub length_unit: &'static str,
    /// The force unit.
    pub force_unit: &'static str,
    /// The accuracy asked for of every point, if any (dimensionless).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tol: Option<Finite>,
    /// The worst point's error estimate (dimensionless).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_estimate: Option<Finite>,
    /// Its 1-based row.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_estimate_row: Option<usize>,
}

/// The obstacle a log's contact points give (issue 38), in the scene's units: a peg's
/// position or a disc's centre and radius, each with its standard errors
/// ([`profile_recon::obstacle`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum ObstacleSummary {
    /// A peg: the mean of the points.
    Peg {
        /// Peg x.
        x: f64,
        /// Peg y.
        y: f64,
        /// Standard error of x.
        stderr_x: f64,
        /// Standard error of y.
        stderr_y: f64,
        /// Largest distance of a point from (x, y).
        spread: f64,
        /// Points used.
        rows: usize,
    },
    /// A disc: the least-squares circle of the points.
    Disc {
        /// Centre x.
        x: f64,
        /// Centre y.
        y: f64,
        /// Radius.
        r: f64,
        /// Standard errors of x, y, r.
        stderr: [f64; 3],
        /// Root mean square distance of the points from the circle.
        rms: f64,
        /// Points used.
        rows: usize,
    },
}

/// Points closer together than this (relative to the largest point's error estimate, plus
/// an absolute 1e-9) read as one peg when no profile says what the obstacle is.
pub const PEG_SPREAD_SIGMAS: f64 = 6.0;

impl ObstacleSummary {
    /// The obstacle of `rec`'s points: the kind the true profile names (`peg:`, `disc:`), or
    /// without a profile a peg when every point is the same point (their spread within
    /// [`PEG_SPREAD_SIGMAS`] of their error estimates); `None` otherwise (a graph's contour
    /// is the points themselves) or when the points determine nothing.
    pub fn of(
        rec: &profile_recon::Reconstruction,
        truth: Option<&contact_sim::Profile>,
        units: &UnitSystem,
    ) -> Option<Self> {
        use contact_sim::Profile;
        let l = units.scale(Quantity::Length);
        let peg = |e: profile_recon::PegEstimate| ObstacleSummary::Peg {
            x: e.x * l,
            y: e.y * l,
            stderr_x: e.stderr_x * l,
            stderr_y: e.stderr_y * l,
            spread: e.spread * l,
            rows: e.rows,
        };
        match truth {
            Some(Profile::Peg { .. }) => profile_recon::estimate_peg(&rec.points).ok().map(peg),
            Some(Profile::Disc { .. }) => {
                profile_recon::estimate_disc(&rec.points)
                    .ok()
                    .map(|e| ObstacleSummary::Disc {
                        x: e.x * l,
                        y: e.y * l,
                        r: e.r * l,
                        stderr: e.stderr.map(|v| v * l),
                        rms: e.rms * l,
                        rows: e.rows,
                    })
            }
            Some(_) => None,
            None => {
                let e = profile_recon::estimate_peg(&rec.points).ok()?;
                let sigma = rec.points.iter().map(|p| p.sigma).fold(0.0, f64::max);
                (e.rows >= 2 && e.spread <= PEG_SPREAD_SIGMAS * sigma + 1e-9).then(|| peg(e))
            }
        }
    }
}

impl ReconSummary {
    /// The summary of `rec` from a log of `rows` rows by `method`, in `units`.
    pub fn of(
        rec: &profile_recon::Reconstruction,
        method: profile_recon::ReconMethod,
        rows: usize,
        units: &UnitSystem,
    ) -> Self {
        let id = &rec.identification;
        let worst = rec.accuracy.as_ref().and_then(|a| a.worst());
        ReconSummary {
            q: id.q * units.scale(Quantity::LineLoad),
            q_dimensionless: id.q,
            q_given: rec.q_given,
            alpha_deg: id.alpha.to_degrees(),
            alpha_given: rec.alpha_given,
            noise: id.noise,
            noise_estimated: id.noise_estimated,
            model_mismatch: id.model_mismatch,
            points: rec.points.len(),
            rows,
            first_contact_row: id.first_contact_row + 1,
            method: method.name(),
            units: units_word(units),
            length_unit: units.unit(Quantity::Length),
            force_unit: units.unit(Quantity::Force),
            tol: rec.accuracy.as_ref().map(|a| Finite(a.tol)),
            max_estimate: worst.map(|(_, e)| Finite(e)),
            max_estimate_row: worst.map(|(k, _)| rec.points[k].row + 1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resolve::{resolve_model, ModelFlags, Value};

    fn solved(flags: &ModelFlags) -> (Resolved, Solution) {
        let r = resolve_model(flags, None).unwrap();
        let sol = beam_model::solve(&r.scene, &r.method).unwrap();
        (r, sol)
    }

    #[test]
    fn solve_summary_holds_the_published_cantilever() {
        // Mattiasson (1981), f = 1 on a uniform rigid cantilever [Table 4.1]: the tip moves
        // 0.30172 L across and 0.05643 L back; the base holds the load, Ax = -f
        let mut flags = ModelFlags::default();
        flags.tip.f = Some(Value::Number(1.0));
        let (r, sol) = solved(&flags);
        let s = SolveSummary::of(&r, &sol);
        assert!((s.tip.x - 0.30172).abs() < 1e-5, "{}", s.tip.x);
        assert!((s.tip.y - 0.94357).abs() < 1e-5, "{}", s.tip.y);
        assert!((s.base.ax + 1.0).abs() < 1e-9 && s.base.ay.abs() < 1e-9);
        // the moment balance about the base: the force f across the whisker's axis (x) acts
        // at the tip's height, |MA| = f * y_tip
        assert!(
            (s.base.ma.abs() - s.tip.y).abs() < 1e-9,
            "{} vs {}",
            s.base.ma,
            s.tip.y
        );
        assert!(s.stats.error_estimate <= s.stats.tolerance);
        let v = serde_json::to_value(&s).unwrap();
        // a rigid support's k = inf is null, as JSON has no infinity; keys as the CLI's
        assert_eq!(v["scene"]["k"], serde_json::Value::Null);
        assert_eq!(v["base"]["Ax"], serde_json::json!(s.base.ax));
        assert_eq!(v["units"], "dimensionless");
        assert!(v.get("physical").is_none() && v.get("load_path").is_none());
        assert_eq!(v["method"], "accurate");
    }

    #[test]
    fn non_finite_numbers_are_null_and_finite_ones_exact() {
        #[derive(Serialize)]
        struct R {
            #[serde(serialize_with = "finite")]
            a: f64,
            #[serde(serialize_with = "finite_opt")]
            b: Option<f64>,
            c: Vec<Finite>,
        }
        let mut seed = 0x35_u64;
        for _ in 0..2000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = f64::from_bits(seed);
            let v = serde_json::to_value(R {
                a: x,
                b: Some(x),
                c: vec![Finite(x)],
            })
            .unwrap();
            if x.is_finite() {
                // float_roundtrip: the number parses back to the same bits
                let back: f64 = serde_json::from_str(&v["a"].to_string()).unwrap();
                assert_eq!(back.to_bits(), x.to_bits());
                assert_eq!(v["b"], v["a"]);
                assert_eq!(v["c"][0], v["a"]);
            } else {
                assert!(v["a"].is_null() && v["b"].is_null() && v["c"][0].is_null());
            }
        }
        let v = serde_json::to_value(R {
            a: 0.0,
            b: None,
            c: vec![],
        })
        .unwrap();
        assert!(v["b"].is_null());
    }
}
