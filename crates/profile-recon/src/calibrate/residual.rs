//! The residuals of a calibration: what each row of a log says about the whisker.
//!
//! Every row's observables are the initial values of the first-order system at the base
//! (method `accurate`'s `BaseOde`, [`base_shot`](crate::base_shot), spec/model.md), so one integration from the
//! base per row gives the whole whisker of that row for trial parameters. With the log in
//! the units of a nominal stiffness, the model's observables are `(Ax, Ay, MA) / lambda`
//! (`lambda = EI / EI_nominal`, [`Model::lambda`]) and `phi0`. Four residuals per row, all zero
//! for the true whisker:
//!
//! - every row: the follicle law [3.21, 3.22], `phi0 - pi/2 + MA c` (`c = 1/k`, 0 rigid);
//! - a pre-contact row (the free whisker under the flow [6.1]): `Ax + q cos alpha`,
//!   `Ay - q sin alpha` and the free-tip moment `m(1)`;
//! - a tip contact (phase A, `s1 = 1`): `m(1)` [6.6], the signed normal distance of the
//!   reconstructed point `r(1)` to the known contour, and `f sin(psi_f - psi_c)` (the contact
//!   force `f (sin psi_f, -cos psi_f)` of [6.8, 6.9] normal to the contour, frictionless);
//! - a tangential contact (phase B, `s1` the root of `m(s1) = 0` tracked from the previous
//!   parameters): the normal distance of `r(s1)`, `f sin(psi_f - psi_c)` and the tangency
//!   `f sin(phi(s1) - psi_f)`.
//!
//! With friction (issue 39, `mu` fitted) the force-direction residual `f sin(psi_f - psi_c)`
//! becomes the row's contact law ([`ContactLaw`]: `ft + sign mu fn` on a sliding row, none on
//! a sticking one), and phase B's tangency the angle `sin(phi(s1) - psi_c)`.
//!
//! Four residuals of four observables: the row's map from observables to residuals is locally
//! invertible, so the residuals whitened by their covariance under the sensor noise
//! ([`Whitener`](super::whiten::Whitener), the noise of [`add_noise`](crate::add_noise):
//! independent per column, standard deviation proportional to the column's full scale) have,
//! to first order, the squared norm of the Mahalanobis distance between the measured
//! observables and those the trial whisker predicts at that base position: least squares on
//! them is the maximum-likelihood fit of the output error, without one forward contact solve
//! per row.

use crate::base_shot::base_ivp;
use crate::common::force_components;
use crate::observables::ObservableRow;
use crate::pose::RowPose;
use beam_model::{FluidLoad, Support, Whisker};
use bvp_solvers::integrator::{Dop853, OdeSolution};
use bvp_solvers::roots::{brent, RootOptions};
use contact_sim::Profile;

/// Residuals per row.
pub const RESIDUALS_PER_ROW: usize = 4;

/// The whisker's own parameters in the form the fit works with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// Conicity theta [3.8].
    pub theta: f64,
    /// Cesaro slope A [3.5].
    pub a: f64,
    /// Cesaro offset B [3.5].
    pub b: f64,
    /// Base compliance `c = 1/k` (0: rigid) [3.21, 3.22].
    pub c: f64,
    /// Stiffness ratio `lambda = EI_b / EI_nominal` (1 in a dimensionless log): the log's
    /// forces and moments, in units of the nominal stiffness, are `lambda` times the model's.
    pub lambda: f64,
    /// Coulomb friction coefficient at the contact (spec/model.md, "Friction at the
    /// contact"); used only by the rows whose [`ContactLaw`] is [`ContactLaw::Slip`].
    pub mu: f64,
}

impl Model {
    /// The model of a whisker at the nominal stiffness.
    pub fn of(w: &Whisker) -> Self {
        Model {
            theta: w.theta,
            a: w.a,
            b: w.b,
            c: w.support.compliance(),
            lambda: 1.0,
            mu: 0.0,
        }
    }

    /// The follicle (`k = 1/c`, rigid for `c <= 0`).
    pub fn support(&self) -> Support {
        if self.c > 0.0 {
            Support::Spring { k: 1.0 / self.c }
        } else {
            Support::Rigid
        }
    }

    /// The whisker (`k = 1/c`, rigid for `c <= 0`).
    pub fn whisker(&self) -> Whisker {
        Whisker::new(self.theta, self.a, self.b, self.support().stiffness())
    }
}

/// A flow in Cartesian form `(q cos alpha, q sin alpha)`, fitted per log.
pub(crate) fn flow_of(qc: f64, qs: f64) -> FluidLoad {
    let q = qc.hypot(qs);
    FluidLoad {
        q,
        alpha: if q > 0.0 { qs.atan2(qc) } else { 0.0 },
    }
}

/// What a row is and, for phase B, where its contact currently sits on the whisker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RowKind {
    /// The free whisker under the flow.
    Pre,
    /// Tip contact, `s1 = 1`.
    A,
    /// Tangential contact at `s1` (the root of `m` followed from one evaluation to the next).
    B {
        /// The contact arc length.
        s1: f64,
    },
    /// Left out of the fit (a contact force below [`F_MIN_REL`] of the log's largest: a
    /// touch that carries no information on the contour, and a near-double root of `m`).
    Skipped,
}

/// The law the contact force of a contact row obeys (issue 39; spec/model.md, "Friction at
/// the contact": `F = fn n + ft t` with `t = (cos psi_c, sin psi_c)` the known contour's
/// tangent, `n = (sin psi_c, -cos psi_c)`): the residual that replaces the frictionless
/// `ft = 0` of [6.8, 6.9] ([`ContactLaw::residual`]). The contact point on the known
/// contour, the moment `m(1)` and the tangency need no law, so only this one residual of a
/// row changes. Decided per row from the motion of its material point
/// (`CalibProblem::decide_laws`); a peg has no tangent (its rows stay [`ContactLaw::Normal`],
/// which there constrains nothing).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ContactLaw {
    /// Frictionless: `ft = 0` (every row of a calibration that does not fit `mu`).
    #[default]
    Normal,
    /// Stick, or a row where sliding starts, stops or turns: the force anywhere in the cone
    /// `|ft| <= mu fn`, an inequality: no residual on its direction (the row's other three
    /// residuals stay; the whitener gives the fourth a unit direction orthogonal to them,
    /// `whiten::whitener`).
    Stick,
    /// Slip, the material point moving relative to the obstacle along `sign t`
    /// (`sign = +-1`): `ft = -mu fn sign`, residual `ft + sign mu fn`.
    Slip {
        /// `+1` or `-1`: the direction of the sliding along `t`.
        sign: f64,
    },
}

impl ContactLaw {
    /// The law's residual of a contact force with normal part `fnn` and tangential part `ft`
    /// at friction coefficient `mu`: `ft` (normal), 0 (stick), `ft + sign mu fn` (slip).
    pub fn residual(&self, ft: f64, fnn: f64, mu: f64) -> f64 {
        match *self {
            ContactLaw::Normal => ft,
            ContactLaw::Stick => 0.0,
            ContactLaw::Slip { sign } => ft + sign * mu * fnn,
        }
    }

    /// The index of the law's residual among a row's four (phase A: the fourth, phase B:
    /// the third; module docs), None for other kinds.
    pub fn index(kind: RowKind) -> Option<usize> {
        match kind {
            RowKind::A => Some(3),
            RowKind::B { .. } => Some(2),
            _ => None,
        }
    }
}

/// Contact rows with a force below this fraction of the log's largest contact force are
/// left out of the fit ([`RowKind::Skipped`]).
pub const F_MIN_REL: f64 = 1e-3;

/// Rows whose whitener's [`Whitener::degeneracy`](super::whiten::Whitener::degeneracy) falls
/// below this are left out of the fit (a fold of the contact branch: the snap row).
pub const DEGENERATE: f64 = 1e-6;

/// Largest distance in arc length over which a phase-B root is followed from one evaluation
/// to the next.
const TRACK_SPAN: f64 = 0.25;

/// The evaluation of one row: its residuals, the contact point and the tracked kind.
#[derive(Clone, Copy, Debug)]
pub struct RowResult {
    /// The four residuals (module docs).
    pub r: [f64; RESIDUALS_PER_ROW],
    /// The kind, with `s1` moved to the root found.
    pub kind: RowKind,
    /// Reconstructed contact point `(x, y)` (NaN for pre-contact rows).
    pub point: (f64, f64),
    /// Signed normal distance of the point to the contour (positive inside the obstacle;
    /// NaN for pre-contact rows).
    pub distance: f64,
    /// The contact force's component along the contour's normal out of the obstacle,
    /// `f cos(psi_f - psi_c)` (NaN for pre-contact rows): positive for the push of a
    /// frictionless contact, negative for a pull, which no contact exerts.
    pub compression: f64,
    /// The whisker's angle at the contact (`phi(1)` in phase A, `phi(s1)` in phase B; NaN
    /// for pre-contact rows): the direction in which the contact moves along the whisker.
    pub phi: f64,
}

/// Everything a row's evaluation needs besides the row and its kind.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowCtx<'a> {
    pub model: &'a Model,
    /// The flow `(q cos alpha, q sin alpha)` of the row's log.
    pub flow: (f64, f64),
    pub profile: &'a Profile,
    pub integrator: &'a Dop853,
    /// The row's pose (a turning or lifted base, issue 38; [`RowPose::TRANSLATE`] for the
    /// thesis's sweep).
    pub pose: RowPose,
    /// The lab x of a point minus its x integrated from the row's `x0` (a log of a rotation
    /// is calibrated with `x0` replaced by its motion coordinate, [`motion_coordinate`](crate::pose::motion_coordinate); 0 otherwise).
    pub shift: f64,
    /// The law of the row's contact force ([`ContactLaw::Normal`] without friction).
    pub law: ContactLaw,
}

impl RowCtx<'_> {
    /// The lab point of a point `(x, y)` integrated from the row's base: `x + shift`,
    /// `y + y0` ([`RowPose::lift`]); exactly `(x, y)` for the translating sweep.
    fn lab(&self, x: f64, y: f64) -> (f64, f64) {
        let x = if self.shift != 0.0 { x + self.shift } else { x };
        (x, self.pose.lift(y))
    }
}

/// Signed normal distance of `(x, y)` to the contour `y = g(x)` (first order:
/// `(y - g) / sqrt(1 + g'^2)`, positive inside the obstacle) and the contour angle there.
fn contour_distance(profile: &Profile, x: f64, y: f64) -> (f64, f64) {
    let (g, d, _) = profile.eval(x);
    ((y - g) / (1.0 + d * d).sqrt(), d.atan())
}

/// Where a reconstructed point lies relative to the known contour.
#[derive(Clone, Copy, Debug)]
enum Touch {
    /// A graph or a disc: the signed normal distance (positive inside the obstacle) and the
    /// contour's tangent angle `psi_c` there (the normal out of the obstacle is
    /// `(sin psi_c, -cos psi_c)`).
    Line { dist: f64, psi_c: f64 },
    /// A peg: the point's offset from it (a point has no normal: the force's direction is
    /// free, frictionless or not).
    Point { dx: f64, dy: f64 },
}

/// The point `(x, y)` (lab frame) against `profile`: a graph to first order
/// ([`contour_distance`]); a disc exactly, `r - |p - c|` with the normal `(p - c) / |p - c|`
/// (the distance of [`contour_error`](crate::contour_error), `Profile::clearance`, signed);
/// a peg by the offset `p - peg`.
fn touch(profile: &Profile, x: f64, y: f64) -> Touch {
    match *profile {
        Profile::Peg { x: px, y: py } => Touch::Point {
            dx: x - px,
            dy: y - py,
        },
        Profile::Disc { x: cx, y: cy, .. } => {
            let (nx, ny) = (x - cx, y - cy);
            Touch::Line {
                dist: -profile.clearance(x, y),
                psi_c: nx.atan2(-ny),
            }
        }
        _ => {
            let (dist, psi_c) = contour_distance(profile, x, y);
            Touch::Line { dist, psi_c }
        }
    }
}

/// The contour's tangent angle `psi_c` at the point `(x, y)` (lab frame) of `profile`
/// (`t = (cos psi_c, sin psi_c)`, as the residuals use it); NaN for a peg.
pub(crate) fn contour_angle(profile: &Profile, x: f64, y: f64) -> f64 {
    match touch(profile, x, y) {
        Touch::Line { psi_c, .. } => psi_c,
        Touch::Point { .. } => f64::NAN,
    }
}

/// The residuals of `row` of kind `kind` (module docs) whose base has the pose
/// [`RowCtx::pose`] (a turning or lifted base, issue 38): in the lab frame, where the system integrated from the base is covariant
/// (docs/whisking-recon.md), the pose enters only
/// - the follicle law turned by `gamma`, `phi0 - gamma - pi/2 + MA c` [3.21, 3.22]
///   ([`RowPose::unturned`]),
/// - the contact point lifted by `y0` ([`RowPose::lift`], as [`point_to_lab`](crate::pose::point_to_lab)),
///
/// and the flow stays the log's one lab-frame flow (`Ax + q cos alpha`, `Ay - q sin alpha`
/// of a free row hold at any turn [6.1]). Against a peg the distance residual is the pair
/// `x - px`, `y - py` and the force's direction is free (the normal-force residual is
/// dropped); against a disc the distance is exact. `None` where the trial whisker admits
/// no such row (the integration stopped short, the phase-B root was lost, the point left the
/// contour's domain). With [`RowPose::TRANSLATE`] and no shift this is bit for bit the
/// translating sweep's residual.
pub(crate) fn row_residuals(
    ctx: &RowCtx<'_>,
    row: &ObservableRow,
    kind: RowKind,
) -> Option<RowResult> {
    let pose = &ctx.pose;
    let m = ctx.model;
    let obs = ObservableRow {
        x0: row.x0,
        ax: row.ax / m.lambda,
        ay: row.ay / m.lambda,
        ma: row.ma / m.lambda,
        phi0: row.phi0,
    };
    // the follicle law [3.21, 3.22] with m(0) = -MA, turned by gamma (a path's row: its own k)
    let follicle = pose
        .support_or(m.support())
        .residual(pose.unturned(obs.phi0), -obs.ma);
    let whisker = Whisker {
        theta: m.theta,
        a: m.a,
        b: m.b,
        ..Whisker::default()
    };
    let flow = flow_of(ctx.flow.0, ctx.flow.1);
    let nan = (f64::NAN, f64::NAN);
    match kind {
        RowKind::Skipped => Some(RowResult {
            r: [0.0; RESIDUALS_PER_ROW],
            kind,
            point: nan,
            distance: f64::NAN,
            compression: f64::NAN,
            phi: f64::NAN,
        }),
        RowKind::Pre | RowKind::A => {
            let sol = base_ivp(&whisker, flow, &obs, ctx.integrator).ok()?;
            if sol.s_end < 1.0 {
                return None;
            }
            let u = &sol.u_end;
            let (phi1, m1) = (u[0], u[1]);
            let (x1, y1) = ctx.lab(u[2], u[3]);
            if !(phi1.is_finite() && m1.is_finite()) {
                return None;
            }
            // the point force at the tip that the reactions balance with the flow [6.8, 6.9]
            let (fa, fb) = force_components(&obs, flow, 1.0);
            if kind == RowKind::Pre {
                // none on the free whisker [6.1]
                return Some(RowResult {
                    r: [follicle, -fa, fb, m1],
                    kind,
                    point: nan,
                    distance: f64::NAN,
                    compression: f64::NAN,
                    phi: f64::NAN,
                });
            }
            let (r, distance, compression) = match touch(ctx.profile, x1, y1) {
                Touch::Line { dist, psi_c } => {
                    // F = (fa, -fb): ft = F.t, fn = F.n [6.8, 6.9]
                    let (ft, fnn) = (
                        fa * psi_c.cos() - fb * psi_c.sin(),
                        fa * psi_c.sin() + fb * psi_c.cos(),
                    );
                    (
                        [follicle, m1, dist, ctx.law.residual(ft, fnn, m.mu)],
                        dist,
                        fnn,
                    )
                }
                Touch::Point { dx, dy } => ([follicle, m1, dx, dy], dx.hypot(dy), fa.hypot(fb)),
            };
            r.iter().all(|v| v.is_finite()).then_some(RowResult {
                r,
                kind,
                point: (x1, y1),
                distance,
                compression,
                phi: phi1,
            })
        }
        RowKind::B { s1 } => {
            let dense = Dop853 {
                dense: true,
                ..ctx.integrator.clone()
            };
            let sol = base_ivp(&whisker, flow, &obs, &dense).ok()?;
            let root = track_root(&sol, s1)?;
            let mut u = [0.0; 4];
            if !sol.eval_into(root, &mut u) {
                return None;
            }
            let phi = u[0];
            let (x, y) = ctx.lab(u[2], u[3]);
            let (fa, fb) = force_components(&obs, flow, root);
            let tangency = fb * phi.sin() - fa * phi.cos();
            let (r, distance, compression) = match touch(ctx.profile, x, y) {
                Touch::Line { dist, psi_c } => {
                    let (ft, fnn) = (
                        fa * psi_c.cos() - fb * psi_c.sin(),
                        fa * psi_c.sin() + fb * psi_c.cos(),
                    );
                    // with friction the force is not normal to the whisker: the tangency
                    // is the whisker's angle against the contour's (model.md: phi(s1) = psi)
                    let tangency = match ctx.law {
                        ContactLaw::Normal => tangency,
                        _ => (phi - psi_c).sin(),
                    };
                    (
                        [follicle, dist, ctx.law.residual(ft, fnn, m.mu), tangency],
                        dist,
                        fnn,
                    )
                }
                // the force normal to the whisker (tangency); its side is not checked
                Touch::Point { dx, dy } => {
                    ([follicle, dx, dy, tangency], dx.hypot(dy), fa.hypot(fb))
                }
            };
            r.iter().all(|v| v.is_finite()).then_some(RowResult {
                r,
                kind: RowKind::B { s1: root },
                point: (x, y),
                distance,
                compression,
                phi,
            })
        }
    }
}

/// Options of the root searches on the dense output.
const ROOT_OPTS: RootOptions = RootOptions {
    xtol: 1e-15,
    ftol: 0.0,
    max_iter: 200,
};

/// `m` on the dense output (NaN outside).
fn m_at(sol: &OdeSolution, s: f64) -> f64 {
    let mut u = [0.0; 4];
    if sol.eval_into(s, &mut u) {
        u[1]
    } else {
        f64::NAN
    }
}

/// The root of `m` on `(0, 1)` nearest to `guess`, within [`TRACK_SPAN`]: brackets grown
/// outwards from the guess on both sides, by widths `1e-4 * 2^k`
/// ([`grow_brackets`](bvp_solvers::roots::grow_brackets)), the nearer sign change first.
fn track_root(sol: &OdeSolution, guess: f64) -> Option<f64> {
    use bvp_solvers::roots::{grow_brackets, Growth};
    let end = sol.s_end.min(1.0);
    let g = guess.clamp(1e-9, end - 1e-12);
    let mg = m_at(sol, g);
    if mg == 0.0 {
        return Some(g);
    }
    if !mg.is_finite() {
        return None;
    }
    let sign = |s: f64| {
        let m = m_at(sol, s);
        m.is_finite().then_some(m.is_sign_positive())
    };
    let growth = Growth::within(1e-4, 2.0, TRACK_SPAN);
    let m = |s| Ok::<_, bvp_solvers::BvpError>(m_at(sol, s));
    let root = grow_brackets(sign, g, mg.is_sign_positive(), (1e-12, end), growth)
        .find_map(|(a, b)| brent(m, a, b, &ROOT_OPTS).ok())?;
    (root.x > 0.0 && root.x < 1.0).then_some(root.x)
}

/// Every root of `m` on `(0, 1)` of one base integration (sign changes on each step cut in
/// four, then Brent): the phase-B hypotheses of a row.
pub(crate) fn all_roots(sol: &OdeSolution) -> Vec<f64> {
    let mut roots = Vec::new();
    let pts = sol.step_points();
    let mut prev: Option<(f64, f64)> = None;
    for w in pts.windows(2) {
        for k in 0..4 {
            let s = w[0] + (w[1] - w[0]) * (k + 1) as f64 / 4.0;
            let m = m_at(sol, s);
            if let Some((sp, mp)) = prev {
                if mp != 0.0 && m.is_finite() && m.signum() != mp.signum() {
                    if let Ok(r) = brent(
                        |t| Ok::<_, bvp_solvers::BvpError>(m_at(sol, t)),
                        sp,
                        s,
                        &ROOT_OPTS,
                    ) {
                        if r.x > 0.0 && r.x < 1.0 {
                            roots.push(r.x);
                        }
                    }
                }
            }
            prev = Some((s, m));
        }
    }
    roots
}

/// The hypotheses of a contact row at `ctx`: tip contact (if the integration reaches the tip)
/// and every root of `m` (phase B) whose contact force pushes (positive
/// [`RowResult::compression`]), each with its residuals; the phase of the row is the
/// hypothesis with the smallest whitened residual
/// ([`judge`](super::whiten::judge)).
pub(crate) fn hypotheses(ctx: &RowCtx<'_>, row: &ObservableRow) -> Vec<RowResult> {
    let m = ctx.model;
    let obs = ObservableRow {
        ax: row.ax / m.lambda,
        ay: row.ay / m.lambda,
        ma: row.ma / m.lambda,
        ..*row
    };
    let whisker = Whisker {
        theta: m.theta,
        a: m.a,
        b: m.b,
        ..Whisker::default()
    };
    let dense = Dop853 {
        dense: true,
        ..ctx.integrator.clone()
    };
    let Ok(sol) = base_ivp(&whisker, flow_of(ctx.flow.0, ctx.flow.1), &obs, &dense) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if sol.s_end >= 1.0 {
        out.extend(row_residuals(ctx, row, RowKind::A));
    }
    for s in all_roots(&sol) {
        out.extend(row_residuals(ctx, row, RowKind::B { s1: s }));
    }
    // a contact pushes: a hypothesis whose force pulls the whisker towards the obstacle is
    // none (the normal-force residual alone admits both directions)
    out.retain(|h| h.compression > 0.0);
    out
}

/// The contact force of `row` at the tip under the flow, `|(-Ax - qc, Ay - qs)|` (model
/// units, [`force_components`]): what decides [`RowKind::Skipped`].
pub(crate) fn tip_force(model: &Model, flow: (f64, f64), row: &ObservableRow) -> f64 {
    let obs = ObservableRow {
        ax: row.ax / model.lambda,
        ay: row.ay / model.lambda,
        ..*row
    };
    let (fa, fb) = force_components(&obs, flow_of(flow.0, flow.1), 1.0);
    fa.hypot(fb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flow_round_trip() {
        let f = flow_of(3.0 * 0.3f64.cos(), 3.0 * 0.3f64.sin());
        assert!((f.q - 3.0).abs() < 1e-14 && (f.alpha - 0.3).abs() < 1e-14);
        assert_eq!(flow_of(0.0, 0.0).alpha, 0.0);
    }

    #[test]
    fn model_whisker_round_trip() {
        let w = Whisker::new(0.5, 0.2, -0.3, 20.0);
        let m = Model::of(&w);
        assert_eq!(m.whisker(), w);
        assert_eq!(Model::of(&Whisker::uniform()).whisker(), Whisker::uniform());
    }

    /// A rotation of a tapered, pre-curved whisker on a spring under a flow past `profile`
    /// (issue 38): the truth, the sweep and its poses.
    fn whisking(profile: Profile) -> (Whisker, FluidLoad, contact_sim::SweepResult) {
        use contact_sim::{sweep, BaseMotion, SweepSettings};
        let truth = Whisker::new(0.55, 0.3, -0.2, 20.0);
        let flow = FluidLoad { q: 1.2, alpha: 0.3 };
        let settings = SweepSettings {
            points: 20,
            pre_contact_rows: 3,
            motion: BaseMotion::Rotate {
                x0: 0.1,
                y0: -0.05,
                gamma0: -0.3,
            },
            ..SweepSettings::default()
        };
        let res = sweep(&truth, flow, &profile, &settings).expect("the whisking sweep");
        (truth, flow, res)
    }

    /// Independent truth: the sweep's own contact points `(xc, yc)` and its phases. At the
    /// true whisker and flow, every row of a rotation past a peg and past a disc has posed
    /// residuals at the integrator's floor and its lab point at the sweep's; the unposed
    /// residuals miss the follicle law by exactly the row's turn.
    #[test]
    fn wcal_posed_residuals_vanish_at_the_truth_of_a_rotation() {
        use crate::observables::from_sweep;
        use crate::pose::poses_of_sweep;
        use contact_sim::Phase;
        let (bx, by, d, ang) = (0.1f64, -0.05f64, 0.6f64, 0.2f64);
        let (px, py) = (bx - d * ang.sin(), by + d * ang.cos());
        let r = 0.15;
        for profile in [
            Profile::Peg { x: px, y: py },
            Profile::Disc {
                x: px - r * ang.sin(),
                y: py + r * ang.cos(),
                r,
            },
        ] {
            let (truth, flow, res) = whisking(profile.clone());
            let rows = from_sweep(&res);
            let poses = poses_of_sweep(&res);
            let model = Model::of(&truth);
            let integrator = Dop853::new(1e-13, 1e-13);
            let ctx = RowCtx {
                model: &model,
                flow: (flow.q * flow.alpha.cos(), flow.q * flow.alpha.sin()),
                profile: &profile,
                integrator: &integrator,
                pose: RowPose::TRANSLATE,
                shift: 0.0,
                law: ContactLaw::Normal,
            };
            let (mut worst, mut worst_point, mut contact, mut pre, mut turned) =
                (0.0f64, 0.0f64, 0, 0, 0);
            for ((row, pose), p) in rows.iter().zip(&poses).zip(&res.points) {
                let kind = match p.phase {
                    Phase::None => RowKind::Pre,
                    Phase::A => RowKind::A,
                    Phase::B => RowKind::B { s1: p.s1 },
                };
                if kind != RowKind::Pre && p.f < 1e-6 {
                    continue; // a touch row: no force, no information (RowKind::Skipped)
                }
                let posed = RowCtx { pose: *pose, ..ctx };
                let got = row_residuals(&posed, row, kind).expect("a row at the truth");
                let w = got.r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                worst = worst.max(w);
                assert!(
                    w < 1e-8,
                    "{}: {:?} at gamma {}: {:?}",
                    profile.name(),
                    kind,
                    pose.gamma,
                    got.r
                );
                if kind == RowKind::Pre {
                    pre += 1;
                } else {
                    contact += 1;
                    let e = (got.point.0 - p.xc).hypot(got.point.1 - p.yc);
                    worst_point = worst_point.max(e);
                    assert!(e < 1e-8, "point {:?} vs ({}, {})", got.point, p.xc, p.yc);
                    // the phase hypotheses hold the truth among them
                    let hyps = hypotheses(&posed, row);
                    assert!(
                        hyps.iter().any(|h| h.r.iter().all(|v| v.abs() < 1e-8)),
                        "{}: no hypothesis at the truth among {}",
                        profile.name(),
                        hyps.len()
                    );
                }
                // without its pose the row misses the follicle law by its turn (k = 20)
                let plain = row_residuals(&ctx, row, kind).expect("a row at the truth");
                if pose.gamma.abs() > 1e-3 {
                    turned += 1;
                    assert!(
                        (plain.r[0] - pose.gamma).abs() < 1e-8,
                        "{} vs gamma {}",
                        plain.r[0],
                        pose.gamma
                    );
                }
            }
            assert!(
                contact >= 10 && pre >= 1 && turned >= 10,
                "{contact} {pre} {turned}"
            );
            eprintln!(
                "{}: {contact} contact rows, {pre} free rows, worst residual {worst:.1e}, worst point {worst_point:.1e}",
                profile.name()
            );
        }
    }
}
