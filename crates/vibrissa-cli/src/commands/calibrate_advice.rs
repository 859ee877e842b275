//! `vibrissa calibrate --advise P...`: which object to calibrate on, before any experiment
//! (profile-recon's [`design()`](profile_recon::calibrate::design())): the standard errors a
//! sweep of the start whisker past each candidate would give.

use profile_recon::calibrate::{design, DesignSettings};

use crate::cli::{CalibrateArgs, ModelFlags};
use crate::commands::calibrate::{in_units, num, parse_fit, unit_of};
use crate::error::CliError;
use crate::resolve::{parse_count, parse_number, resolve_model, LoadedScene, ProfileArg};

/// Runs the advice.
pub fn run(args: &CalibrateArgs) -> Result<(), CliError> {
    if !args.logs.is_empty() {
        return Err(CliError::Usage {
            reason: "--advise plans an experiment: give no LOG with it".to_string(),
        });
    }
    let file = LoadedScene::load_opt(args.scene.as_deref())?;
    let flags = ModelFlags {
        whisker: args.whisker.clone(),
        fluid: args.fluid.clone(),
        ..ModelFlags::default()
    };
    let r = resolve_model(&flags, file)?;
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
                        let (v, sd) = in_units(e, 1.0, phys.as_ref());
                        params.insert(
                            e.param.name().to_string(),
                            serde_json::json!({
                                "value": v.map_or(serde_json::Value::Null, num),
                                "stderr": sd.map_or(serde_json::Value::Null, num),
                                "identifiable": e.identifiable,
                                "unit": unit_of(e.param, phys.is_some()),
                            }),
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
