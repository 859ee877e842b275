//! Logs of any base motion (spec/model.md, "Base motions"; issue 38): each row carries the
//! pose of its base, `(x0, y0, gamma)`, besides the observables `(Ax, Ay, MA, phi0)`.
//!
//! **The frame seam.** The reconstruction integrates the first-order system from the base
//! with the row's observables as initial values [3.25, 6.8, 6.9]. In the lab frame, with the
//! reactions `(Ax, Ay)` and the flow `q (cos alpha, -sin alpha)` in the lab frame and `phi0`
//! the lab angle of the base tangent (as every log of `contact_sim` writes them), that system
//! is covariant under rotations (every term of `m' = f sin(phi + beta) + q (s1 - s)
//! sin(phi + alpha)` is a difference of two angles that turn together) and under
//! translations (`x`, `y` enter nothing but themselves). So the moment and the angle along
//! the whisker, the contact arc `s1`, the force `f` and the contour angle `psi`, the phase
//! and every residual of a row do not depend on its pose at all; `gamma` enters only the
//! follicle law `phi0 = pi/2 + gamma - MA/k`, which reconstruction does not use (`phi0` is
//! measured), and the pose's position enters only the contact point, by translation:
//!
//! ```text
//! (x, y)_lab = (x, y)_base run from (x0, 0) + (0, y0)
//! ```
//!
//! The "base frame" of this crate is therefore the lab frame translated so that the base
//! lies on `y = 0` ([`in_base_frame`]): no rotation (a rotation would turn the flow of every
//! row by its own `-gamma`, out of the range `(-pi/2, pi/2)` the identification and the
//! stream check, and would differ row by row where the identified flow is one), and every
//! existing method (`accurate`, `thesis`, accuracy on demand, the stream) runs unchanged in
//! it. The frictional reconstruction ([`crate::friction`]) returns its own type and is not
//! wired through [`in_base_frame`] yet: its rows' points move the same way (`contact_sim`
//! refuses friction with a rotation, so its logs are translations today). The angles `phi - psi` are compared wrapped to `(-pi, pi]`
//! ([`base_shot`](crate::base_shot)), so a base turned by any `gamma` needs no unwrapping.
//!
//! What a pose changes besides the point: the order of the rows along the motion. The
//! identification's model-free noise reference (third differences of the columns along the
//! sweep) and the thesis method's rule [6.10] read the rows in the order of the motion's
//! coordinate, `x0` for a translation; a rotation holds `x0` fixed and moves in `gamma`. In
//! the base frame every row's `x0` is therefore replaced by the motion coordinate
//! ([`motion_coordinate`]: the pose component that varies most, falling as the motion goes,
//! `-gamma` for a rotation as `contact_sim` itself follows it), which moves the whole
//! whisker along `x` by a constant and changes nothing else; the points are moved back and
//! every `x0` written out is the row's own, copied exactly.
//!
//! A translate log (`y0 = 0`, `gamma = 0` on every row, or no pose columns at all) skips the
//! frame altogether: bit for bit the reconstruction of the thesis's sweep.

use crate::common::KnownFlow;
use crate::error::{ReconError, Result};
use crate::observables::ObservableRow;
use crate::result::{ReconPoint, Reconstruction};
use crate::ReconSettings;
use beam_model::{Support, Whisker};
use serde::{Deserialize, Serialize};

/// The pose of a row's base besides `x0` (spec/model.md, "Base motions"): `(y0, gamma)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RowPose {
    /// Base y (0 for the thesis's translation).
    pub y0: f64,
    /// The turn of the follicle (rad; the unloaded base direction is `pi/2 + gamma`).
    pub gamma: f64,
    /// The follicle stiffness of the row where the motion sets it (a path's `k` column,
    /// dimensionless [3.19], `inf` rigid): a known value of the row, used by the
    /// calibration's follicle law instead of the fitted whisker's `k`
    /// ([`RowPose::support_or`]); `None` where the log has no `k`.
    #[serde(default)]
    pub k: Option<f64>,
}

impl RowPose {
    /// The pose of the thesis's translating sweep, `y0 = 0`, `gamma = 0`.
    pub const TRANSLATE: RowPose = RowPose {
        y0: 0.0,
        gamma: 0.0,
        k: None,
    };

    /// The pose `(y0, gamma)` without a known `k`.
    pub const fn new(y0: f64, gamma: f64) -> Self {
        RowPose { y0, gamma, k: None }
    }

    /// Whether this is the translating sweep's pose (`y0 = 0`, `gamma = 0` exactly, no
    /// known `k`).
    pub fn is_translate(&self) -> bool {
        self.y0 == 0.0 && self.gamma == 0.0 && self.k.is_none()
    }

    /// Checks that `y0` and `gamma` are finite and a known `k` positive (`inf`: rigid),
    /// naming the row (0-based) and the column.
    pub fn validate(&self, row: usize) -> Result<()> {
        for (column, value) in [("y0", self.y0), ("gamma", self.gamma)] {
            if !value.is_finite() {
                return Err(ReconError::NonFinite { row, column, value });
            }
        }
        match self.k {
            Some(value) if value.is_nan() => Err(ReconError::NonFinite {
                row,
                column: "k",
                value,
            }),
            Some(value) if value <= 0.0 => Err(ReconError::InvalidParameter {
                name: "k",
                value,
                reason: "a row's follicle stiffness must be > 0 (inf: rigid)",
            }),
            _ => Ok(()),
        }
    }

    /// The follicle of this row: a spring of the row's known `k` (rigid for `inf`) where the
    /// motion sets it, else `fitted` (the whisker's own) [3.21, 3.22]. A path whose `k`
    /// changes along it makes `k` a known column of the log, not a parameter of the whisker
    /// (docs/whisking-recon.md, "Paths in the calibration").
    pub fn support_or(&self, fitted: Support) -> Support {
        match self.k {
            Some(k) if k.is_infinite() => Support::Rigid,
            Some(k) => Support::Spring { k },
            None => fitted,
        }
    }

    /// A height `y` of a whisker integrated with its base on `y = 0`, in the lab frame of a
    /// base at height `y0`: `y + y0` (exactly `y` for `y0 = 0`).
    pub fn lift(&self, y: f64) -> f64 {
        if self.y0 != 0.0 {
            y + self.y0
        } else {
            y
        }
    }

    /// The base angle `phi0` of a row with this pose seen from the unturned follicle,
    /// `phi0 - gamma` (exactly `phi0` for `gamma = 0`): the argument of the follicle law
    /// `phi0 - gamma = pi/2 - MA/k` [3.21, 3.22].
    pub fn unturned(&self, phi0: f64) -> f64 {
        if self.gamma != 0.0 {
            phi0 - self.gamma
        } else {
            phi0
        }
    }

    /// Residual of the turned follicle law `phi0 = pi/2 + gamma - MA/k` [3.21, 3.22] of `row`
    /// for a follicle of stiffness `k` (`INFINITY`: rigid), the row's own `k` where known.
    pub fn follicle_residual(&self, row: &ObservableRow, k: f64) -> f64 {
        row.phi0 - std::f64::consts::FRAC_PI_2 - self.gamma + row.ma / self.k.unwrap_or(k)
    }
}

/// The poses of a simulated sweep's rows (`SweepPoint::{y0, gamma}`).
pub fn poses_of_sweep(sweep: &contact_sim::SweepResult) -> Vec<RowPose> {
    sweep
        .points
        .iter()
        .map(|p| RowPose {
            y0: p.y0,
            gamma: p.gamma,
            k: p.k,
        })
        .collect()
}

/// The coordinate along which a log's motion goes, falling as it goes (module docs): of the
/// pose components `x0`, `y0`, `gamma`, the one with the largest range over the rows, as
/// `x0`, `-y0` or `-gamma` (a translation moves towards -x, a rotation turns
/// counter-clockwise); `x0` when no component varies. Ties go to `x0`, then `gamma`.
pub fn motion_coordinate(rows: &[ObservableRow], poses: &[RowPose]) -> Vec<f64> {
    let range = |v: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        if hi >= lo {
            hi - lo
        } else {
            0.0
        }
    };
    let rx = range(&mut rows.iter().map(|r| r.x0));
    let ry = range(&mut poses.iter().map(|p| p.y0));
    let rg = range(&mut poses.iter().map(|p| p.gamma));
    if rx >= rg && rx >= ry {
        rows.iter().map(|r| r.x0).collect()
    } else if rg >= ry {
        poses.iter().map(|p| -p.gamma).collect()
    } else {
        poses.iter().map(|p| -p.y0).collect()
    }
}

/// Moves a point reconstructed in the base frame (its base at `(c, 0)`) back to the lab frame
/// of a row with base at `(x0, y0)`: `x - c + x0`, `y + y0`, and `x0` copied.
pub fn point_to_lab(p: &mut ReconPoint, c: f64, x0: f64, pose: &RowPose) {
    if c != x0 {
        p.x = p.x - c + x0;
    }
    p.y = pose.lift(p.y);
    p.x0 = x0;
}

/// Runs `recon` (any reconstruction of this crate taking the rows) on the rows of a log of any
/// motion in the base frame (module docs) and returns its points in the lab frame, in the
/// input's order; errors that name a row's `x0` name the row's own.
///
/// A log whose every pose is the translation's is handed to `recon` as it is (bit for bit).
///
/// # Errors
/// [`ReconError::TooFewRows`] when `poses` and `rows` differ in length;
/// [`ReconError::NonFinite`] for a non-finite pose; the errors of `recon`.
pub fn in_base_frame<F>(
    rows: &[ObservableRow],
    poses: &[RowPose],
    recon: F,
) -> Result<Reconstruction>
where
    F: FnOnce(&[ObservableRow]) -> Result<Reconstruction>,
{
    check_poses(rows, poses)?;
    if poses.iter().all(RowPose::is_translate) {
        return recon(rows);
    }
    let c = motion_coordinate(rows, poses);
    let base: Vec<ObservableRow> = rows
        .iter()
        .zip(&c)
        .map(|(r, &c)| ObservableRow { x0: c, ..*r })
        .collect();
    let mut rec = recon(&base).map_err(|e| lab_error(e, rows))?;
    for p in &mut rec.points {
        point_to_lab(p, c[p.row], rows[p.row].x0, &poses[p.row]);
    }
    Ok(rec)
}

/// [`ReconError::TooFewRows`] unless there is one pose per row; the first non-finite pose.
pub(crate) fn check_poses(rows: &[ObservableRow], poses: &[RowPose]) -> Result<()> {
    if poses.len() != rows.len() {
        return Err(ReconError::TooFewRows {
            found: poses.len(),
            needed: rows.len(),
            what: "one pose (y0, gamma) per observables row",
        });
    }
    poses
        .iter()
        .enumerate()
        .try_for_each(|(i, p)| p.validate(i))
}

/// An error of the base frame with the row's own `x0` put back.
fn lab_error(e: ReconError, rows: &[ObservableRow]) -> ReconError {
    let own = |row: usize, x0: f64| rows.get(row).map_or(x0, |r| r.x0);
    match e {
        ReconError::InconsistentRow {
            row,
            x0,
            residual,
            phase,
        } => ReconError::InconsistentRow {
            row,
            x0: own(row, x0),
            residual,
            phase,
        },
        ReconError::AccuracyNotMet {
            row,
            x0,
            estimate,
            tol,
        } => ReconError::AccuracyNotMet {
            row,
            x0: own(row, x0),
            estimate,
            tol,
        },
        other => other,
    }
}

/// [`reconstruct_with`](crate::reconstruct_with) on a log of any motion (module docs): the
/// flow identified (unless known) from the pre-contact rows, one point per contact row in the
/// lab frame.
///
/// # Errors
/// As [`in_base_frame`] and [`reconstruct_with`](crate::reconstruct_with).
pub fn reconstruct_posed(
    whisker: &Whisker,
    rows: &[ObservableRow],
    poses: &[RowPose],
    known: KnownFlow,
    settings: &ReconSettings,
) -> Result<Reconstruction> {
    in_base_frame(rows, poses, |r| {
        crate::reconstruct_with(whisker, r, known, settings)
    })
}

/// [`reconstruct_to`](crate::reconstruct_to) (an accuracy asked for) on a log of any motion.
///
/// # Errors
/// As [`in_base_frame`] and [`reconstruct_to`](crate::reconstruct_to).
pub fn reconstruct_posed_to(
    whisker: &Whisker,
    rows: &[ObservableRow],
    poses: &[RowPose],
    known: KnownFlow,
    settings: &ReconSettings,
    tol: f64,
) -> Result<Reconstruction> {
    in_base_frame(rows, poses, |r| {
        crate::reconstruct_to(whisker, r, known, settings, tol)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x0: f64) -> ObservableRow {
        ObservableRow {
            x0,
            ax: -1.0,
            ay: 0.0,
            ma: 0.1,
            phi0: 1.5,
        }
    }

    #[test]
    fn the_motion_coordinate_is_the_pose_component_that_varies_most() {
        let rows = [row(0.3), row(0.3), row(0.3)];
        let poses = [0.1, 0.2, 0.4].map(|g| RowPose::new(0.05, g));
        assert_eq!(motion_coordinate(&rows, &poses), vec![-0.1, -0.2, -0.4]);
        let rows = [row(0.3), row(0.1), row(-0.5)];
        assert_eq!(motion_coordinate(&rows, &poses), vec![0.3, 0.1, -0.5]);
        let flat = [RowPose::TRANSLATE; 3];
        let rows = [row(0.3); 3];
        assert_eq!(motion_coordinate(&rows, &flat), vec![0.3; 3]);
    }

    #[test]
    fn a_point_goes_back_by_the_coordinate_and_y0() {
        let mut p = ReconPoint {
            row: 0,
            x0: -0.25,
            x: 0.5,
            y: 0.75,
            s1: 1.0,
            f: 1.0,
            psi: 0.0,
            phase: contact_sim::Phase::A,
            residual: 0.0,
            sigma: 0.0,
            alternatives: 0,
            evaluations: 1,
        };
        point_to_lab(&mut p, -0.25, 0.125, &RowPose::new(0.5, 0.3));
        assert_eq!((p.x0, p.x, p.y), (0.125, 0.875, 1.25));
    }

    #[test]
    fn poses_are_checked_for_length_and_finiteness() {
        let rows = [row(0.0), row(0.1)];
        let e = check_poses(&rows, &[RowPose::TRANSLATE]).unwrap_err();
        assert!(
            matches!(
                e,
                ReconError::TooFewRows {
                    found: 1,
                    needed: 2,
                    ..
                }
            ),
            "{e}"
        );
        let bad = [RowPose::TRANSLATE, RowPose::new(0.0, f64::NAN)];
        let e = check_poses(&rows, &bad).unwrap_err();
        assert!(
            matches!(
                e,
                ReconError::NonFinite {
                    row: 1,
                    column: "gamma",
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn the_turned_follicle_law_is_zero_on_its_own_rows() {
        let pose = RowPose::new(0.0, 0.4);
        let (k, ma) = (20.0, 0.3);
        let r = ObservableRow {
            phi0: std::f64::consts::FRAC_PI_2 + 0.4 - ma / k,
            ma,
            ..row(0.0)
        };
        assert!(pose.follicle_residual(&r, k).abs() < 1e-15);
        // a row whose k the path sets: its own k, whatever the whisker's
        let known = RowPose { k: Some(k), ..pose };
        assert!(known.follicle_residual(&r, 1e3).abs() < 1e-15);
        assert_eq!(known.support_or(Support::Rigid), Support::Spring { k });
        let rigid = RowPose {
            k: Some(f64::INFINITY),
            ..pose
        };
        assert_eq!(rigid.support_or(Support::Spring { k }), Support::Rigid);
        assert_eq!(pose.support_or(Support::Rigid), Support::Rigid);
        assert!(!known.is_translate() && RowPose::TRANSLATE.is_translate());
        let bad = RowPose {
            k: Some(-1.0),
            ..pose
        };
        assert!(bad.validate(3).unwrap_err().to_string().contains("k = -1"));
    }
}
