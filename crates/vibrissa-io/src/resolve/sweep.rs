//! The settings of a sweep from a scene file and the values typed over it: the number of
//! contact rows, the accuracy asked for of every row, the loads a sweep accepts and the
//! obstacle it needs; each refusal names its culprit (the flag as typed, or the scene
//! file's field with its line).

use contact_sim::contact_law::MAX_MU;
use contact_sim::{ContactLaw, SweepSettings};

use super::{LoadedScene, Resolved, Value};
use crate::error::IoError;

/// Default number of contact points.
pub const DEFAULT_POINTS: usize = 200;

/// The accuracy asked for of a sweep's rows: `--tol` (typed as `raw`), else the scene
/// file's `sweep.tol`, else none; in [1e-12, 1e-2].
pub fn sweep_tol(raw: Option<&Value>, file: Option<&LoadedScene>) -> Result<Option<f64>, IoError> {
    const RANGE: &str = "the accuracy asked for must be in [1e-12, 1e-2]";
    let ok = |t: f64| {
        (contact_sim::accuracy::ACCURACY_MIN..=contact_sim::accuracy::ACCURACY_MAX).contains(&t)
    };
    match (raw, file) {
        (Some(raw), _) => {
            let t = raw.number("--tol")?;
            if !ok(t) {
                return Err(IoError::invalid_argument("--tol", raw.raw(), RANGE));
            }
            Ok(Some(t))
        }
        (None, Some(f)) => match f.file.sweep.as_ref().and_then(|s| s.tol) {
            Some(t) if !ok(t) => Err(f.error_at("sweep.tol", format!("{RANGE}, got {t}"))),
            t => Ok(t),
        },
        (None, None) => Ok(None),
    }
}

/// The library's settings of a sweep of `points` contact rows at the accuracy `tol` (none:
/// the sweep's own).
pub fn sweep_settings(points: usize, tol: Option<f64>) -> SweepSettings {
    SweepSettings {
        points,
        accuracy: tol,
        ..SweepSettings::default()
    }
}

/// The law of the contact force of a sweep (spec/model.md, "Friction at the contact"):
/// Coulomb friction with the coefficient `--mu` (typed as `raw`), else the scene file's `mu`,
/// else none. `mu` is dimensionless in every unit system and must lie in `[0, 10]` (refused
/// naming `--mu` as typed, or the scene's `mu` with its line). `mu = 0` (also `-0`) is
/// [`ContactLaw::Frictionless`]: the frictionless sweep, bit for bit.
pub fn sweep_contact_law(
    raw: Option<&Value>,
    file: Option<&LoadedScene>,
) -> Result<ContactLaw, IoError> {
    const RANGE: &str = "the friction coefficient must lie in [0, 10]";
    let mu = match (raw, file) {
        (Some(raw), _) => {
            let mu = raw.number("--mu")?;
            if !(0.0..=MAX_MU).contains(&mu) {
                return Err(IoError::invalid_argument("--mu", raw.raw(), RANGE));
            }
            mu
        }
        (None, Some(f)) => {
            let mu = f.file.mu;
            if !(0.0..=MAX_MU).contains(&mu) {
                return Err(f.error_at("mu", format!("{RANGE}, got {mu}")));
            }
            mu
        }
        (None, None) => 0.0,
    };
    Ok(contact_law_of(mu))
}

/// The law of a coefficient already checked: [`ContactLaw::Frictionless`] for `mu == 0`,
/// else [`ContactLaw::Coulomb`].
pub fn contact_law_of(mu: f64) -> ContactLaw {
    if mu == 0.0 {
        ContactLaw::Frictionless
    } else {
        ContactLaw::Coulomb { mu }
    }
}

/// The settings of [`sweep_settings`] under the contact law `law`.
pub fn sweep_settings_with(points: usize, tol: Option<f64>, law: ContactLaw) -> SweepSettings {
    SweepSettings {
        contact_law: law,
        ..sweep_settings(points, tol)
    }
}

/// The error of a sweep without an obstacle (`file`: the scene file given, if any).
pub fn missing_profile(file: Option<&LoadedScene>) -> IoError {
    const KINDS: &str = "g1, g2, ge, parabola:a,xv,yv, cosh:a,c,xv,d, circle:xc,yc,r or \
                         points:FILE.csv";
    match file {
        Some(f) => f.error_at(
            "profile",
            format!("the scene has no obstacle: add `profile: Some(\"g1\")` (or {KINDS}) or give --profile"),
        ),
        None => IoError::Usage {
            reason: format!("a sweep needs an obstacle: give --profile P ({KINDS})"),
        },
    }
}

/// The number of contact rows: `--points` (typed as `raw`), else the scene file's
/// `sweep.points`, else [`DEFAULT_POINTS`]; at least 2 and at most
/// [`contact_sim::sweep::MAX_POINTS`].
pub fn sweep_points(raw: Option<&Value>, file: Option<&LoadedScene>) -> Result<usize, IoError> {
    let points = match (raw, file.and_then(|f| f.file.sweep.as_ref())) {
        (Some(raw), _) => {
            let n = raw.count("--points", 2)?;
            if n > contact_sim::sweep::MAX_POINTS {
                return Err(IoError::invalid_argument(
                    "--points",
                    raw.raw(),
                    "at most 100000 contact rows",
                ));
            }
            n
        }
        (None, Some(s)) => s.points,
        (None, None) => DEFAULT_POINTS,
    };
    if points > super::MAX_COUNT {
        return Err(IoError::invalid_argument(
            "sweep.points",
            points.to_string(),
            format!(
                "must be at most {} (the memory and time of one run are bounded)",
                super::MAX_COUNT
            ),
        ));
    }
    Ok(points)
}

/// The sweep computes the contact force itself: refuses a tip force, and a flow angle outside
/// (-90, 90) degrees (the flow must push the whisker towards the obstacle's side, +x).
pub fn check_sweep_loads(r: &Resolved) -> Result<(), IoError> {
    use super::Origin;
    // The sweep's phase solves are adaptive shooting with exact sensitivities (tolerance
    // 1e-12); a fixed-grid method or grid size would be silently ignored, so it is refused.
    if !matches!(r.method, beam_model::Method::Accurate { .. }) {
        return Err(IoError::invalid_argument(
            "--method",
            r.method.name().to_string(),
            "the sweep always solves its contact phases with `accurate` shooting; leave --method at accurate",
        ));
    }
    if let Some(n) = &r.given.n {
        if let super::Origin::Flag { flag, raw } = &n.origin {
            return Err(IoError::invalid_argument(
                *flag,
                raw.clone(),
                "the sweep uses adaptive shooting and has no grid: --n does not apply",
            ));
        }
    }
    let alpha = r.given.alpha_deg.value;
    let checks = [
        (
            &r.given.f,
            "loads.f",
            r.given.f.value != 0.0,
            "a sweep computes the contact force itself; leave the tip force at 0",
        ),
        (
            &r.given.alpha_deg,
            "loads.alpha_deg",
            !(alpha > -90.0 && alpha < 90.0),
            "the sweep's flow angle must lie in (-90, 90) degrees (a flow towards +x)",
        ),
    ];
    for (p, field, bad, what) in checks {
        if bad {
            return Err(match (&p.origin, &r.file) {
                (Origin::Flag { flag, raw }, _) => {
                    IoError::invalid_argument(*flag, raw.clone(), what)
                }
                (_, Some(file)) => file.error_at(field, format!("{what}, got {}", p.value)),
                _ => IoError::invalid_argument(field, p.value.to_string(), what),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--mu` as typed: 0 (and -0) is the frictionless law, a coefficient in [0, 10] the
    /// Coulomb law with its bits, anything else refused naming `--mu` and the text.
    #[test]
    fn mu_resolves_to_the_contact_law() {
        let law = |t: &str| sweep_contact_law(Some(&Value::Text(t.to_string())), None);
        assert_eq!(law("0").unwrap(), ContactLaw::Frictionless);
        assert_eq!(law("-0").unwrap(), ContactLaw::Frictionless);
        assert_eq!(
            sweep_contact_law(None, None).unwrap(),
            ContactLaw::Frictionless
        );
        assert_eq!(law("0.5").unwrap(), ContactLaw::Coulomb { mu: 0.5 });
        assert_eq!(law("10").unwrap(), ContactLaw::Coulomb { mu: 10.0 });
        let x = 0.1 + 0.2;
        assert_eq!(
            sweep_contact_law(Some(&Value::Number(x)), None).unwrap(),
            ContactLaw::Coulomb { mu: x }
        );
        for bad in ["-1e-300", "10.000001", "NaN", "inf", "-inf", "x", ""] {
            let e = law(bad).unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(
                e.to_string()
                    .starts_with(&format!("invalid value `{bad}` for `--mu`")),
                "{e}"
            );
        }
        let s = sweep_settings_with(7, Some(1e-6), ContactLaw::Coulomb { mu: 0.3 });
        assert_eq!((s.points, s.accuracy), (7, Some(1e-6)));
        assert_eq!(s.contact_law.mu(), 0.3);
    }
}
