//! `vibrissa calibrate --advise P...`: which object to calibrate on, before any experiment
//! (profile-recon's [`design()`](profile_recon::calibrate::design())): the standard errors a
//! sweep of the start whisker past each candidate would give.

use profile_recon::calibrate::{design, DesignSettings};

use crate::cli::CalibrateArgs;
use crate::commands::calibrate_inputs::{calib_model, parse_fit};
use crate::commands::calibrate_summary::{in_units, param_json};
use crate::commands::json::json_number as num;
use crate::error::CliError;
use crate::resolve::{parse_count, parse_number, ProfileArg};

/// Runs the advice.
pub fn run(args: &CalibrateArgs) -> Result<(), CliError> {
    if !args.logs.is_empty() {
        return Err(CliError::Io(vibrissa_io::IoError::Usage {
            reason: "--advise plans an experiment: give no LOG with it".to_string(),
        }));
    }
    let r = calib_model(args, args.scene.as_deref())?;
    let units = r.units();
    let noise = match &args.noise {
        Some(raw) => {
            let v = parse_number("--noise", raw)?;
            if !(v.is_finite() && v > 0.0) {
                return Err(CliError::invalid_argument(
                    "--noise",
                    raw,
                    "must be a positive number",
                ));
            }
            v
        }
        None => 1e-4,
    };
    let mut settings = DesignSettings {
        fit: parse_fit(args.fit.as_deref(), &units)?,
        noise,
        ..DesignSettings::default()
    };
    if let Some(raw) = &args.points {
        settings.sweep.points = parse_count("--points", raw, 2)?;
    }
    let whisker = r.scene.whisker;
    let flow = r.scene.loads.fluid;
    let phys = r.physical;
    let mut out = Vec::new();
    for spec in &args.advise {
        let profile = ProfileArg {
            spec: spec.clone(),
            file: None,
        }
        .parse(&units)?;
        let cand = [(spec.clone(), profile)];
        out.push((
            spec.clone(),
            design(&whisker, flow, &cand, &settings).map(|mut v| v.remove(0)),
        ));
    }
    if args.json {
        let items: Vec<serde_json::Value> = out
            .iter()
            .map(|(spec, res)| match res {
                Ok(p) => {
                    let mut params = serde_json::Map::new();
                    for e in &p.parameters {
                        params.insert(
                            e.param.name().to_string(),
                            param_json(e, 1.0, phys.as_ref()),
                        );
                    }
                    serde_json::json!({"profile": spec, "rows": p.rows, "contact": p.contact,
                        "parameters": params, "worst_relative": num(p.worst_relative)})
                }
                Err(e) => serde_json::json!({"profile": spec, "error": e.to_string()}),
            })
            .collect();
        println!("{}", serde_json::json!({"noise": noise, "advice": items}));
        return Ok(());
    }
    println!(
        "advice: predicted standard errors at relative noise {noise:e} (flow fitted too), best first"
    );
    let mut order: Vec<usize> = (0..out.len()).collect();
    let key = |i: &usize| {
        out[*i]
            .1
            .as_ref()
            .map_or(f64::INFINITY, |p| p.worst_relative)
    };
    order.sort_by(|a, b| key(a).total_cmp(&key(b)));
    for i in order {
        let (spec, res) = &out[i];
        match res {
            Ok(p) => {
                let parts: Vec<String> = p
                    .parameters
                    .iter()
                    .map(|e| match in_units(e, 1.0, phys.as_ref()) {
                        (_, Some(sd)) => format!("{} ± {sd:.2e}", e.param.name()),
                        _ => format!("{} not identifiable", e.param.name()),
                    })
                    .collect();
                println!("  {spec}: {} contact rows; {}", p.contact, parts.join(", "));
            }
            Err(e) => println!("  {spec}: no advice ({e})"),
        }
    }
    Ok(())
}
