//! The frictional reconstruction of a log without a command line (spec/cli.md, "Friction,
//! base motions and obstacles"; issue 39 item 3): the request `--mu` ([`MuRequest`]), the
//! compute ([`reconstruct_frictional_log`], each failure named by its culprit as
//! [`crate::recon::reconstruct_log`] does), the reconstruction without `--mu`
//! ([`reconstruct_default_log`]: mu identified beside today's points, the frictional points
//! where the log proves friction), the `ft` column of
//! `reconstruction.csv` and the serialisable `mu` / evidence part of the JSON summary
//! ([`FrictionSummary`]).

use std::path::Path;

use profile_recon::friction::MU_MAX;
use profile_recon::{
    reconstruct_frictional, FrictionEvidence, FrictionalReconstruction, Reconstruction,
};
use serde::Serialize;

use crate::csvio::{Cell, CsvWriter, Table};
use crate::error::IoError;
use crate::outputs::write_units_of;
use crate::recon::{recon_culprit, reconstruct_log, rows_of, ReconFlags, ReconOptions};
use crate::recon_io::{recon_cells, reconstruction_header, RECON_QUANTITIES};
use crate::resolve::Resolved;
use crate::units::{Quantity, UnitSystem};

/// What `--mu` asks of a reconstruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MuRequest {
    /// `--mu identify`: mu identified from the sliding rows, with its standard error.
    Identify,
    /// `--mu MU`: mu given (`0` is the frictionless reconstruction, checked for friction).
    Fixed(f64),
}

impl MuRequest {
    /// Parses the value of `--mu`: a number in `[0, 10]` or the word `identify`.
    ///
    /// # Errors
    /// [`IoError::InvalidArgument`] naming `--mu` and the value.
    pub fn parse(raw: &str) -> Result<Self, IoError> {
        if raw.trim() == "identify" {
            return Ok(MuRequest::Identify);
        }
        let bad = |reason: &str| IoError::invalid_argument("--mu", raw, reason);
        let v: f64 = raw
            .trim()
            .parse()
            .map_err(|_| bad("expected a number in [0, 10] or the word identify"))?;
        if !(0.0..=MU_MAX).contains(&v) {
            return Err(bad("the friction coefficient must lie in [0, 10]"));
        }
        Ok(MuRequest::Fixed(v))
    }

    /// The given mu, if any.
    pub fn given(&self) -> Option<f64> {
        match self {
            MuRequest::Identify => None,
            MuRequest::Fixed(v) => Some(*v),
        }
    }
}

/// The answer of a reconstruction asked with `--mu`: the points (frictional, or the
/// frictionless ones with their error estimates widened when the log proves friction),
/// each point's `ft` (NaN where unknown), the frictional reconstruction and, for `--mu 0`
/// on a log that proves friction, the evidence to warn about.
#[derive(Clone, Debug)]
pub struct FrictionalAnswer {
    /// The points as written (`reconstruction.csv`, the figures).
    pub rec: Reconstruction,
    /// `ft` of each point of `rec` (the frictional reconstruction's of the same row).
    pub ft: Vec<f64>,
    /// The frictional reconstruction.
    pub frictional: FrictionalReconstruction,
    /// `--mu 0` on a log that proves friction: the evidence (warn: the points are biased).
    pub biased: Option<FrictionEvidence>,
}

/// Reconstructs the log `table` as `--mu` asks (module docs): `identify` and `MU > 0` give
/// the frictional points (their `ft`, mu identified or `MU`'s violations counted); `0` gives
/// the frictionless points, which on a log that proves friction are computed without the
/// consistency check (its rows are inconsistent by the friction) and get error estimates
/// widened to cover the frictional points ([`profile_recon::widen_frictionless`]).
///
/// # Errors
/// `--method thesis` and `--tol` are refused with `--mu` (method accurate, its own error
/// estimates); otherwise the errors of [`reconstruct_log`].
pub fn reconstruct_frictional_log(
    flags: &ReconFlags,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
    mu: MuRequest,
) -> Result<FrictionalAnswer, IoError> {
    if opts.method != profile_recon::ReconMethod::Accurate {
        return Err(IoError::invalid_argument(
            "--mu",
            format!("{mu:?}"),
            "a frictional reconstruction uses the method accurate (not with --method thesis)",
        ));
    }
    if opts.accuracy.is_some() {
        return Err(IoError::invalid_argument(
            "--mu",
            format!("{mu:?}"),
            "not with --tol: the frictional points carry their own error estimates",
        ));
    }
    let fr = frictional_of(flags, opts, r, table, mu.given())?;
    let ft_of = |row: usize| {
        fr.points
            .iter()
            .find(|p| p.row == row)
            .map_or(f64::NAN, |p| p.ft)
    };
    match mu {
        MuRequest::Fixed(0.0) => {
            let proves = fr.evidence.is_some_and(|e| e.proves_friction());
            let mut rec = if proves {
                let mut plain = *opts;
                plain.tol = None;
                reconstruct_log(flags, &plain, r, table)?
            } else {
                reconstruct_log(flags, opts, r, table)?
            };
            let biased = profile_recon::widen_frictionless(&mut rec, &fr);
            let ft = rec.points.iter().map(|p| ft_of(p.row)).collect();
            Ok(FrictionalAnswer {
                rec,
                ft,
                frictional: fr,
                biased,
            })
        }
        _ => {
            let rec = fr.to_reconstruction();
            let ft = fr.points.iter().map(|p| p.ft).collect();
            Ok(FrictionalAnswer {
                rec,
                ft,
                frictional: fr,
                biased: None,
            })
        }
    }
}

/// The frictional reconstruction of `table` (method accurate, no consistency check: the
/// phases of a frictional log are not tangency-consistent), `mu` given or identified.
fn frictional_of(
    flags: &ReconFlags,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
    mu: Option<f64>,
) -> Result<FrictionalReconstruction, IoError> {
    // friction is swept along translations only (contact-sim refuses the other motions):
    // a log with a turned or lifted base has no frictional reconstruction yet
    if let Some(i) = crate::recon::poses_of(table)
        .iter()
        .position(|p| p.y0 != 0.0 || p.gamma != 0.0)
    {
        return Err(IoError::InvalidArgument {
            flag: "--mu".to_string(),
            value: format!("row {} with y0, gamma", table.line_of(i).unwrap_or(i + 2)),
            reason: "the frictional reconstruction of a log of a turned or lifted base (y0, \
                     gamma) is not implemented"
                .to_string(),
        });
    }
    let rows = rows_of(table)?;
    let (whisker, known) = (&r.scene.whisker, opts.known_flow(flags, r));
    let settings = profile_recon::ReconSettings {
        consistency_tol: None,
        ..opts.settings()
    };
    reconstruct_frictional(whisker, &rows, known, &settings, mu)
        .map_err(|e| recon_culprit(e, table, r, flags, None))
}

/// The answer of `reconstruct` without `--mu` (spec/cli.md: "its JSON gives `mu`
/// (identified, with its standard error) unless `--mu` fixes it").
#[derive(Clone, Debug)]
pub struct DefaultAnswer {
    /// Today's frictionless points (error estimates widened where the log proves friction).
    pub rec: Reconstruction,
    /// The frictional reconstruction (mu identified with its standard error, the evidence),
    /// or why there is none (`--method thesis`, `--tol`, or its failure).
    pub frictional: Result<FrictionalReconstruction, String>,
    /// The log proves friction: the evidence (warn: the frictionless points are biased,
    /// their error estimates widened; `--mu identify` gives the frictional points).
    pub biased: Option<FrictionEvidence>,
}

/// `reconstruct` without `--mu` (module docs; docs/friction-recon.md, "reconstruct without
/// --mu"): today's frictionless points, their numbers, consistency check and errors
/// unchanged, and beside them mu identified with its standard error by the frictional
/// reconstruction. Where the log proves friction ([`FrictionEvidence::proves_friction`]:
/// some `|ft|` beyond 6 standard deviations) the frictionless points are biased: their error
/// estimates are widened to cover the frictional points and the evidence is returned for a
/// warning, as `--mu 0` does; a row the frictionless reconstruction finds inconsistent is
/// still an error, its message naming the friction found. The frictional points are not
/// chosen on their own: a wrong whisker also shows a tangential force (docs), so they come
/// only with `--mu identify`. With `--method thesis` or `--tol` (refused with `--mu`) mu is
/// not identified; a frictional reconstruction that fails leaves the answer as it was (its
/// reason in `frictional`).
///
/// # Errors
/// Those of [`reconstruct_log`].
pub fn reconstruct_default_log(
    flags: &ReconFlags,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
) -> Result<DefaultAnswer, IoError> {
    let frictional = if opts.method != profile_recon::ReconMethod::Accurate {
        Err("mu is identified by the method accurate (not with --method thesis)".to_string())
    } else if opts.accuracy.is_some() {
        Err("mu is not identified with --tol".to_string())
    } else if crate::recon::poses_of(table)
        .iter()
        .any(|p| p.y0 != 0.0 || p.gamma != 0.0)
    {
        Err(
            "mu is not identified from a log of a turned or lifted base (y0, gamma): \
             friction is swept along translations only"
                .to_string(),
        )
    } else {
        frictional_of(flags, opts, r, table, None).map_err(|e| e.to_string())
    };
    match reconstruct_log(flags, opts, r, table) {
        Ok(mut rec) => {
            let biased = frictional
                .as_ref()
                .ok()
                .and_then(|fr| profile_recon::widen_frictionless(&mut rec, fr));
            Ok(DefaultAnswer {
                rec,
                frictional,
                biased,
            })
        }
        Err(mut e) => {
            if let (Ok(fr), IoError::Csv { reason, .. }) = (&frictional, &mut e) {
                if let Some(ev) = fr.evidence.filter(|e| e.proves_friction()) {
                    let mu = fr.mu.map_or(String::new(), |m| {
                        format!(
                            ", mu = {:.4} +- {:.1e} from {} sliding rows",
                            m.value, m.stderr, m.rows
                        )
                    });
                    let line = table.line_of(ev.row).unwrap_or(ev.row + 2);
                    reason.push_str(&format!(
                        "; or friction: with a tangential contact force the log fits (line \
                         {line}: ft {:.1} standard deviations from 0{mu}): reconstruct with \
                         --mu identify if the whisker is right",
                        ev.z()
                    ));
                }
            }
            Err(e)
        }
    }
}

/// The warning of `--mu 0` on a log that proves friction (the row numbered as the log's
/// line `line`).
pub fn biased_warning(ev: &FrictionEvidence, line: usize) -> String {
    format!(
        "warning: the log shows friction (line {line}, x0 = {}: tangential contact force ft = {:.3e}, {:.1} standard deviations from 0); the frictionless points are biased, their error estimates widened (reconstruct with --mu identify for the frictional points and mu)",
        ev.x0,
        ev.ft,
        ev.z()
    )
}

/// `mu` in the JSON summary: identified (value and standard error) or given.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MuSummary {
    /// The value.
    pub value: f64,
    /// Its standard error (0 when given).
    pub stderr: f64,
    /// Whether it was given (`--mu MU`) rather than identified.
    pub given: bool,
    /// The sliding rows it is identified from (0 when given).
    pub rows: usize,
    /// `chi^2 / (n - 1)` of the sliding rows' ratios about it (about 1 when they follow
    /// Coulomb's law; NaN, written null, when given or from one row).
    pub chi2_dof: f64,
}

/// The friction part of `reconstruct --json` (spec/cli.md: `mu` with its standard error).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrictionSummary {
    /// `mu` (null when it could not be identified: no sliding row with a force).
    pub mu: Option<MuSummary>,
    /// Rows marked sliding.
    pub sliding_rows: usize,
    /// Rows whose force breaks the given mu's cone (or a sliding row off its edge).
    pub mu_violations: usize,
    /// The largest `|ft|` over its standard deviation (NaN without a tangent).
    pub friction_z: f64,
    /// The log's line of that row.
    pub friction_line: Option<usize>,
    /// Whether the log proves friction (`friction_z` > 6).
    pub proves_friction: bool,
}

impl FrictionSummary {
    /// The summary of `fr` (rows numbered as the lines of `table`).
    pub fn of(fr: &FrictionalReconstruction, table: &Table) -> Self {
        let mu = match (fr.mu_given, fr.mu) {
            (Some(v), _) => Some(MuSummary {
                value: v,
                stderr: 0.0,
                given: true,
                rows: 0,
                chi2_dof: f64::NAN,
            }),
            (None, Some(m)) => Some(MuSummary {
                value: m.value,
                stderr: m.stderr,
                given: false,
                rows: m.rows,
                chi2_dof: m.chi2_dof,
            }),
            (None, None) => None,
        };
        FrictionSummary {
            mu,
            sliding_rows: fr
                .points
                .iter()
                .filter(|p| p.slip == contact_sim::SlipState::Slip)
                .count(),
            mu_violations: fr.violations,
            friction_z: fr.evidence.map_or(f64::NAN, |e| e.z()),
            friction_line: fr.evidence.and_then(|e| table.line_of(e.row)),
            proves_friction: fr.evidence.is_some_and(|e| e.proves_friction()),
        }
    }
}

/// Writes `reconstruction.csv` with the column `ft` after the others (before `error`): as
/// [`write_reconstruction_csv`](crate::recon_io::write_reconstruction_csv), one more number
/// per point (a force).
pub fn write_reconstruction_csv_ft(
    rec: &Reconstruction,
    ft: &[f64],
    errors: Option<&[f64]>,
    units: &UnitSystem,
    x0_given: &[f64],
    path: &Path,
) -> Result<(), IoError> {
    let mut header = reconstruction_header(false);
    header.push("ft");
    let mut quantities: Vec<Quantity> = RECON_QUANTITIES[..header.len() - 1].to_vec();
    quantities.push(Quantity::Force);
    if errors.is_some() {
        header.push("error");
        quantities.push(Quantity::Length);
    }
    let fs = units.scale(Quantity::Force);
    let mut w = CsvWriter::new(&header);
    for (i, p) in rec.points.iter().enumerate() {
        let mut cells = recon_cells(p, units, x0_given, None);
        cells.push(Cell::Num(ft.get(i).copied().unwrap_or(f64::NAN) * fs));
        if let Some(e) = errors {
            cells.push(Cell::Num(
                e.get(i).copied().unwrap_or(f64::NAN) * units.scale(Quantity::Length),
            ));
        }
        w.push_row(&cells)?;
    }
    w.write(path)?;
    write_units_of(path, &header, &quantities, units)
}
