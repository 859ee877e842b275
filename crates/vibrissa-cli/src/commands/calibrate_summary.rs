//! The summary step of `vibrissa calibrate`: the fitted parameters in the scene's units,
//! the `--json` object (also the Python package's answer) and the text summary.

use std::path::Path;

use beam_model::PhysicalWhisker;
use profile_recon::calibrate::{CalibParam, Calibration, ParamEstimate};

use crate::commands::calibrate_inputs::LogInput;
use crate::commands::json::{json_number as num, json_opt};
use crate::units::{Quantity, UnitSystem};

/// A fitted parameter in the scene's units: `(value, stderr)` (None when not identifiable).
/// Physical: a in 1/m², b in 1/m, k in N m/rad, ei in N m² (k scaled with the fitted E I).
pub(crate) fn in_units(
    p: &ParamEstimate,
    lambda: f64,
    phys: Option<&PhysicalWhisker>,
) -> (Option<f64>, Option<f64>) {
    let Some(ph) = phys else {
        return (p.value, p.stderr);
    };
    let l = ph.length;
    let f = match p.param {
        CalibParam::Theta => 1.0,
        CalibParam::A => 1.0 / (l * l),
        CalibParam::B => 1.0 / l,
        CalibParam::K => lambda * ph.moment_scale(),
        CalibParam::Ei => ph.bending_stiffness(),
    };
    (p.value.map(|v| v * f), p.stderr.map(|v| v * f))
}

/// The unit of a parameter in the scene's units.
pub(crate) fn unit_of(p: CalibParam, physical: bool) -> &'static str {
    match (p, physical) {
        (_, false) | (CalibParam::Theta, _) => "1",
        (CalibParam::A, true) => "1/m²",
        (CalibParam::B, true) => "1/m",
        (CalibParam::K, true) => "N m/rad",
        (CalibParam::Ei, true) => "N m²",
    }
}

/// The JSON object of a parameter in the scene's units (`lambda` as in [`in_units`]):
/// value, standard error, whether it is identifiable, and its unit.
pub(crate) fn param_json(
    p: &ParamEstimate,
    lambda: f64,
    phys: Option<&PhysicalWhisker>,
) -> serde_json::Value {
    let (v, sd) = in_units(p, lambda, phys);
    serde_json::json!({
        "value": json_opt(v),
        "stderr": json_opt(sd),
        "identifiable": p.identifiable,
        "unit": unit_of(p.param, phys.is_some()),
    })
}

/// The `--json` object (spec/cli.md): parameters, logs, rms_residual and the details.
pub fn json_of(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    phys: Option<&PhysicalWhisker>,
    out: Option<&Path>,
) -> serde_json::Value {
    let mut params = serde_json::Map::new();
    for p in &cal.parameters {
        let (v, sd) = in_units(p, cal.lambda, phys);
        let mut o = param_json(p, cal.lambda, phys);
        if p.param == CalibParam::K {
            // a rigid fit: k = inf is written as null, with rigid = true; the compliance 1/k
            // (what is fitted) is finite either way
            o["rigid"] = serde_json::json!(p.value.is_some_and(f64::is_infinite));
            if let (Some(k), Some(sd)) = (v, sd) {
                o["compliance"] = num(1.0 / k);
                o["compliance_stderr"] = num(if k.is_finite() {
                    sd / (k * k)
                } else {
                    f64::NAN
                });
            }
        }
        params.insert(p.param.name().to_string(), o);
    }
    let qs = units.scale(Quantity::LineLoad) * cal.lambda;
    let logs: Vec<serde_json::Value> = cal
        .logs
        .iter()
        .zip(inputs)
        .map(|(l, i)| {
            serde_json::json!({
                "log": i.arg,
                "profile": i.profile.0,
                "q": num(l.q * qs),
                "q_stderr": num(l.q_stderr * qs),
                "alpha_deg": num(l.alpha.to_degrees()),
                "alpha_deg_stderr": num(l.alpha_stderr.to_degrees()),
                "rows": l.rows,
                "pre_contact": l.pre_contact,
                "contact": l.contact,
                "left_out": l.skipped,
            })
        })
        .collect();
    let names: Vec<&str> = cal.parameters.iter().map(|p| p.param.name()).collect();
    let corr: Vec<Vec<serde_json::Value>> = cal
        .correlation
        .iter()
        .map(|r| r.iter().map(|v| num(*v)).collect())
        .collect();
    let w = &cal.whisker;
    let (a, b, k) = match phys {
        None => (w.a, w.b, w.support.stiffness()),
        Some(ph) => (
            w.a / (ph.length * ph.length),
            w.b / ph.length,
            w.support.stiffness() * cal.lambda * ph.moment_scale(),
        ),
    };
    let mut whisker = serde_json::json!({"theta": w.theta, "a": num(a), "b": num(b), "k": num(k)});
    if let Some(ph) = phys {
        whisker["ei"] = num(cal.lambda * ph.bending_stiffness());
    }
    serde_json::json!({
        "parameters": params,
        "whisker": whisker,
        "logs": logs,
        "rms_residual": num(cal.rms_distance * units.scale(Quantity::Length)),
        "rms_residual_unit": units.unit(Quantity::Length),
        "noise_level": num(cal.noise_level),
        "log_noise": num(cal.log_noise),
        "correlation": {"parameters": names, "matrix": corr},
        "determined": cal.determined.iter().map(|c| c.describe()).collect::<Vec<_>>(),
        "singular_values": cal.singular_values.iter().map(|v| num(*v)).collect::<Vec<_>>(),
        "units": if units.is_physical() { "physical" } else { "dimensionless" },
        "local_fits": cal.fits.len(),
        "iterations": cal.iterations,
        "warnings": cal.warnings,
        "out": out.map(|p| p.display().to_string()),
    })
}

/// The human summary.
pub(crate) fn print_summary(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    phys: Option<&PhysicalWhisker>,
) {
    let rows: usize = cal.logs.iter().map(|l| l.rows).sum();
    let contact: usize = cal.logs.iter().map(|l| l.contact).sum();
    let left: usize = cal.logs.iter().map(|l| l.skipped).sum();
    let lu = match units.unit(Quantity::Length) {
        "1" => String::new(),
        u => format!(" {u}"),
    };
    println!(
        "calibrate: {} log(s), {rows} rows ({contact} contact rows fitted, {left} left out); \
         rms distance to the contours {:.3e}{lu}; relative noise level {:.2e}",
        cal.logs.len(),
        cal.rms_distance * units.scale(Quantity::Length),
        cal.noise_level
    );
    for p in &cal.parameters {
        let (v, sd) = in_units(p, cal.lambda, phys);
        let unit = match unit_of(p.param, phys.is_some()) {
            "1" => String::new(),
            u => format!(" {u}"),
        };
        match (v, sd) {
            (Some(v), Some(sd)) => println!("  {:<5} = {v:.10} ± {sd:.2e}{unit}", p.param.name()),
            _ => println!("  {:<5} = not identifiable from these logs", p.param.name()),
        }
    }
    for c in &cal.determined {
        println!("  determined: {}", c.describe());
    }
    let qs = units.scale(Quantity::LineLoad) * cal.lambda;
    for (l, i) in cal.logs.iter().zip(inputs) {
        println!(
            "  log {}: q = {:.6e} ± {:.1e}{}, alpha = {:.6}° ± {:.1e}°",
            i.arg,
            l.q * qs,
            l.q_stderr * qs,
            match units.unit(Quantity::LineLoad) {
                "1" => String::new(),
                u => format!(" {u}"),
            },
            l.alpha.to_degrees(),
            l.alpha_stderr.to_degrees()
        );
    }
    for w in &cal.warnings {
        println!("  warning: {w}");
    }
}
