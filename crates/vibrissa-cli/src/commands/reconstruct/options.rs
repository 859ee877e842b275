//! The parse and resolve steps of `vibrissa reconstruct`: its flags checked one by one
//! ([`ReconOptions`]: method, consistency tolerance, flow angle, noise level) and the whisker
//! resolved from the scene file under the flags ([`recon_model`]).

use profile_recon::{KnownFlow, ReconMethod, ReconSettings};

use crate::cli::ReconstructArgs;
use crate::error::CliError;
use crate::resolve::{parse_number, resolve_model, LoadedScene, ModelFlags, Resolved};

/// Default consistency tolerance of the accurate method (exact logs).
pub const DEFAULT_TOLERANCE_ACCURATE: f64 = 1e-6;

/// Default consistency tolerance of the thesis method (its least-squares residual stays at
/// about 1e-5..1e-4).
pub const DEFAULT_TOLERANCE_THESIS: f64 = 1e-3;
/// The options of a reconstruction given as flags: method, consistency tolerance, flow
/// angle and noise level, each checked against its flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReconOptions {
    /// `--method`.
    pub method: ReconMethod,
    /// `--tolerance` (`None`: no consistency check).
    pub tol: Option<f64>,
    /// `--alpha-deg` in radians, if given.
    pub alpha: Option<f64>,
    /// `--noise`, if given.
    pub noise: Option<f64>,
    /// `--tol`, the accuracy asked for of every point, if given.
    pub accuracy: Option<f64>,
}

impl ReconOptions {
    /// Parses the flags of `args`.
    pub fn parse(args: &ReconstructArgs) -> Result<Self, CliError> {
        let method = parse_method(args.method.as_deref())?;
        Ok(ReconOptions {
            method,
            tol: parse_tolerance(args.tolerance.as_deref(), method)?,
            alpha: parse_alpha(args.alpha_deg.as_deref())?,
            noise: parse_noise(args.noise.as_deref())?,
            accuracy: parse_accuracy(args.tol.as_deref(), method)?,
        })
    }

    /// The options of a stream: as [`ReconOptions::parse`], the method `accurate` only (each
    /// row on its own).
    pub fn parse_stream(args: &ReconstructArgs) -> Result<Self, CliError> {
        let opts = Self::parse(args)?;
        if let Some(out) = &args.out {
            return Err(CliError::invalid_argument(
                "--out",
                out.display().to_string(),
                "the stream writes each contact point to standard output; leave --out out \
                 with --stream (or reconstruct the log as a file into --out)",
            ));
        }
        if let Some(raw) = &args.tol {
            return Err(CliError::invalid_argument(
                "--tol",
                raw,
                "the stream returns each point as soon as it is known, at the integrator \
                 tolerance 1e-12, without the second evaluation an estimate needs; leave \
                 --tol out with --stream",
            ));
        }
        if opts.method != ReconMethod::Accurate {
            return Err(CliError::invalid_argument(
                "--method",
                opts.method.name(),
                "the stream reconstructs each row on its own: method accurate only",
            ));
        }
        Ok(opts)
    }

    /// The library's settings of these options.
    pub fn settings(&self) -> ReconSettings {
        ReconSettings {
            method: self.method,
            consistency_tol: self.tol,
            noise: self.noise,
            ..ReconSettings::default()
        }
    }

    /// The flow as far as it is given: `--q` (resolved in the scene's units by `r`) and
    /// `--alpha-deg`.
    pub fn known_flow(&self, args: &ReconstructArgs, r: &Resolved) -> KnownFlow {
        KnownFlow {
            q: args.q.as_ref().map(|_| r.q()),
            alpha: self.alpha,
        }
    }
}

/// The whisker of a reconstruction (and `--q`, if given): the scene file under the flags,
/// through the same resolution as `solve` so that physical units and range checks apply.
pub fn recon_model(
    args: &ReconstructArgs,
    file: Option<LoadedScene>,
) -> Result<Resolved, CliError> {
    let mut flags = ModelFlags {
        whisker: (&args.whisker).into(),
        ..ModelFlags::default()
    };
    flags.fluid.q = args.q.clone();
    Ok(resolve_model(&flags, file)?)
}
fn parse_method(raw: Option<&str>) -> Result<ReconMethod, CliError> {
    match raw.map(str::trim) {
        None | Some("accurate") => Ok(ReconMethod::Accurate),
        Some("thesis") => Ok(ReconMethod::Thesis),
        Some(other) => Err(CliError::invalid_argument(
            "--method",
            other,
            "unknown reconstruction method: expected accurate or thesis",
        )),
    }
}

fn parse_tolerance(raw: Option<&str>, method: ReconMethod) -> Result<Option<f64>, CliError> {
    let Some(raw) = raw else {
        return Ok(Some(match method {
            ReconMethod::Accurate => DEFAULT_TOLERANCE_ACCURATE,
            ReconMethod::Thesis => DEFAULT_TOLERANCE_THESIS,
        }));
    };
    if raw.trim().eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let t = parse_number("--tolerance", raw)?;
    if !(t.is_finite() && t > 0.0) {
        return Err(CliError::invalid_argument(
            "--tolerance",
            raw,
            "must be a positive number or `none`",
        ));
    }
    Ok(Some(t))
}
fn parse_accuracy(raw: Option<&str>, method: ReconMethod) -> Result<Option<f64>, CliError> {
    let Some(raw) = raw else { return Ok(None) };
    let t = parse_number("--tol", raw)?;
    if !(profile_recon::accuracy::ACCURACY_MIN..=profile_recon::accuracy::ACCURACY_MAX).contains(&t)
    {
        return Err(CliError::invalid_argument(
            "--tol",
            raw,
            "the accuracy asked for must be in [1e-12, 1e-2]",
        ));
    }
    if method != ReconMethod::Accurate {
        return Err(CliError::invalid_argument(
            "--tol",
            raw,
            "an accuracy is asked of the method accurate only (thesis, on FDM grids, stays \
             near 1e-5); leave --method at accurate",
        ));
    }
    Ok(Some(t))
}

fn parse_alpha(raw: Option<&str>) -> Result<Option<f64>, CliError> {
    let Some(raw) = raw else { return Ok(None) };
    let d = parse_number("--alpha-deg", raw)?;
    if !(d.is_finite() && d.abs() < 90.0) {
        return Err(CliError::invalid_argument(
            "--alpha-deg",
            raw,
            "the flow angle must lie in (-90, 90) degrees",
        ));
    }
    Ok(Some(d.to_radians()))
}

fn parse_noise(raw: Option<&str>) -> Result<Option<f64>, CliError> {
    let Some(raw) = raw else { return Ok(None) };
    let l = parse_number("--noise", raw)?;
    if !(l.is_finite() && l >= 0.0) {
        return Err(CliError::invalid_argument(
            "--noise",
            raw,
            "the relative noise level must be a number >= 0",
        ));
    }
    Ok(Some(l))
}
