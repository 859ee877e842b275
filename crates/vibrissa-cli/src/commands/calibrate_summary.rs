//! The summary step of `vibrissa calibrate`: the fitted parameters in the scene's units,
//! the `--json` object (also the Python package's answer) and the text summary.

use std::path::Path;

use beam_model::PhysicalWhisker;
use profile_recon::calibrate::{Calibration, ParamEstimate};
use vibrissa_io::calibration::CalibrationReport;

use crate::commands::calibrate_inputs::LogInput;
use crate::commands::json::json_opt;
use crate::units::{Quantity, UnitSystem};

pub(crate) use vibrissa_io::calibration::{in_units, unit_of};

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

/// The `--json` object (spec/cli.md): the library's [`CalibrationReport`] serialised.
pub fn json_of(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    phys: Option<&PhysicalWhisker>,
    out: Option<&Path>,
) -> serde_json::Value {
    serde_json::to_value(CalibrationReport::of(cal, inputs, units, phys, out)).unwrap_or_default()
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
    if let Some(fr) = &cal.friction {
        let bound = if fr.stick_ratio.is_finite() {
            format!(" (their |ft|/fn up to {:.4})", fr.stick_ratio)
        } else {
            String::new()
        };
        println!(
            "  mu from {} sliding row(s); {} sticking row(s){bound}",
            fr.sliding_rows, fr.stick_rows
        );
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
