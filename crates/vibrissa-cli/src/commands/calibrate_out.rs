//! The outputs of `vibrissa calibrate --out DIR`: the calibrated `scene.ron`, the residual
//! of every row (`residuals.csv`) and the figures (`contour-N.svg`, `residuals.svg`).

use std::path::{Path, PathBuf};

use beam_model::Whisker;
use profile_recon::calibrate::{CalibLog, Calibration};
use profile_recon::{KnownFlow, ReconSettings};

use crate::commands::calibrate_inputs::LogInput;
use crate::commands::outputs::{scene_unit_notes, write_scene_ron, write_units_of};
use crate::commands::phases::{is_contact_symbol, symbol_label};
use crate::csvio::{Cell, CsvWriter};
use crate::error::CliError;
use crate::plot::{Chart, FigureStyle, Series, Style};
use crate::resolve::Resolved;
use crate::scene_file::{LoadSpec, MethodSpec, SceneFile, Units, WhiskerSpec};
use crate::units::{Quantity, UnitSystem};
use vibrissa_io::recon_io::PoseColumns;

/// The file name of the residual table.
pub const RESIDUALS_CSV: &str = "residuals.csv";

/// The header of `residuals.csv`.
pub const RESIDUALS_HEADER: [&str; 10] = [
    "log", "row", "x0", "kind", "s1", "x", "y", "distance", "sigma", "chi",
];

const RESIDUALS_QUANTITIES: [Quantity; 10] = [
    Quantity::Number,
    Quantity::Number,
    Quantity::Length,
    Quantity::Text,
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Number,
];

/// Writes the calibrated `scene.ron`: the fitted whisker (unidentifiable parameters at their
/// start values), the first log's flow and contour, the fitted E I as the Young's modulus.
pub fn write_calibrated_scene(
    r: &Resolved,
    cal: &Calibration,
    inputs: &[LogInput],
    path: &Path,
) -> Result<(), CliError> {
    let w: &Whisker = &cal.whisker;
    let mut units = r
        .file
        .as_ref()
        .map(|f| f.file.units.clone())
        .unwrap_or_default();
    let (a, b, k, q) = match &r.physical {
        None => (w.a, w.b, w.support.stiffness(), cal.logs[0].q),
        Some(ph) => {
            let l = ph.length;
            if let Units::Physical {
                youngs_modulus_gpa, ..
            } = &mut units
            {
                *youngs_modulus_gpa = Some(ph.youngs_modulus * cal.lambda * 1e-9);
            }
            (
                w.a / (l * l),
                w.b / l,
                w.support.stiffness() * cal.lambda * ph.moment_scale(),
                cal.logs[0].q * cal.lambda * ph.line_load_scale(),
            )
        }
    };
    let scene = SceneFile {
        units,
        whisker: WhiskerSpec {
            theta: w.theta,
            a,
            b,
            k: k.is_finite().then_some(k),
        },
        loads: LoadSpec {
            q,
            alpha_deg: cal.logs[0].alpha.to_degrees(),
            ..LoadSpec::default()
        },
        profile: Some(inputs[0].profile.0.clone()),
        // a fitted, identifiable friction coefficient (issue 39); 0 otherwise
        mu: cal
            .parameter(profile_recon::calibrate::CalibParam::Mu)
            .and_then(|p| p.value)
            .unwrap_or(0.0),
        motion: None,
        x0: None,
        y0: None,
        gamma_deg: None,
        path: None,
        sweep: None,
        method: MethodSpec::default(),
    };
    let mut notes = vec![
        format!(
            "Written by vibrissa {} (`calibrate`): the whisker fitted to {}.",
            env!("CARGO_PKG_VERSION"),
            inputs
                .iter()
                .map(|i| i.arg.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!(
            "fitted: {}; not identifiable (start values kept): {}",
            names(cal, true),
            names(cal, false)
        ),
        "loads.q, loads.alpha_deg and profile are those of the first log.".to_string(),
    ];
    notes.extend(scene_unit_notes(&UnitSystem::new(r.physical)));
    Ok(write_scene_ron(path, &scene, &notes)?)
}

fn names(cal: &Calibration, identifiable: bool) -> String {
    let v: Vec<&str> = cal
        .parameters
        .iter()
        .filter(|p| p.identifiable == identifiable)
        .map(|p| p.param.name())
        .collect();
    if v.is_empty() {
        "none".to_string()
    } else {
        v.join(", ")
    }
}

/// Writes `residuals.csv` (one line per row of every log) and its units sidecar.
pub fn write_residuals(
    cal: &Calibration,
    inputs: &[LogInput],
    units: &UnitSystem,
    path: &Path,
) -> Result<(), CliError> {
    let l = units.scale(Quantity::Length);
    // the pose columns of the logs of any base motion (issue 38), those some log has
    let pose: Vec<&'static str> = PoseColumns::NAMES
        .into_iter()
        .filter(|n| inputs.iter().any(|i| i.pose_given.names().any(|m| m == *n)))
        .collect();
    let mut header = RESIDUALS_HEADER.to_vec();
    header.extend(&pose);
    let mut w = CsvWriter::new(&header);
    for r in &cal.rows {
        let x0 = inputs[r.log]
            .x0_given
            .get(r.row)
            .copied()
            .unwrap_or(f64::NAN);
        let kind = symbol_label(r.kind);
        let mut cells = vec![
            Cell::Num((r.log + 1) as f64),
            Cell::Num((r.row + 1) as f64),
            Cell::Num(x0),
            Cell::Text(kind),
            Cell::Num(r.s1 * l),
            Cell::Num(r.x * l),
            Cell::Num(r.y * l),
            Cell::Num(r.distance * l),
            Cell::Num(r.sigma * l),
            Cell::Num(r.chi),
        ];
        cells.extend(
            pose.iter()
                .map(|n| Cell::Num(pose_value(&inputs[r.log], n, r.row))),
        );
        w.push_row(&cells)?;
    }
    w.write(path)?;
    if pose.is_empty() {
        return Ok(write_units_of(
            path,
            &RESIDUALS_HEADER,
            &RESIDUALS_QUANTITIES,
            units,
        )?);
    }
    let mut u: Vec<&str> = RESIDUALS_QUANTITIES
        .iter()
        .map(|q| units.unit(*q))
        .collect();
    u.extend(pose.iter().map(|n| PoseColumns::unit_of(n, units)));
    Ok(vibrissa_io::csvio::write_units_sidecar(
        &vibrissa_io::csvio::units_sidecar_path(path),
        &header,
        &u,
    )?)
}

/// The pose column `name` of row `row` of a log as given: 0 for a `y0` or `gamma` the log
/// does not have (the translating sweep's pose), NaN for a `k` it does not set.
fn pose_value(input: &LogInput, name: &str, row: usize) -> f64 {
    match input.pose_given.columns().iter().find(|(n, _)| *n == name) {
        Some((_, c)) => c.get(row).copied().unwrap_or(f64::NAN),
        None if name == "k" => f64::NAN,
        None => 0.0,
    }
}

/// The figures: per log the known contour with the points reconstructed before (the start
/// whisker) and after calibration, and the residual of every row against x0, written as
/// `style` says.
pub fn write_figures(
    cal: &Calibration,
    inputs: &[LogInput],
    logs: &[CalibLog],
    start: &Whisker,
    units: &UnitSystem,
    style: FigureStyle,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<(), CliError> {
    let l = units.scale(Quantity::Length);
    let before_settings = ReconSettings {
        consistency_tol: None,
        ..ReconSettings::default()
    };
    let mut res_chart = Chart::new(
        "Distance of each reconstructed contact point to its known contour",
        units.label("base x_0", Quantity::Length),
        units.label("distance", Quantity::Length),
    );
    for (i, (input, log)) in inputs.iter().zip(logs).enumerate() {
        let after: Vec<(f64, f64)> = cal
            .rows
            .iter()
            .filter(|r| r.log == i && is_contact_symbol(r.kind))
            .map(|r| (r.x * l, r.y * l))
            .collect();
        // the start whisker under the fitted flow (a wrong whisker may find no free row)
        let flow = KnownFlow {
            q: Some(cal.logs[i].q * cal.lambda),
            alpha: Some(cal.logs[i].alpha),
        };
        let before: Vec<(f64, f64)> =
            profile_recon::reconstruct_with(start, &log.rows, flow, &before_settings)
                .map(|rec| rec.points.iter().map(|p| (p.x * l, p.y * l)).collect())
                .unwrap_or_default();
        let xs = after
            .iter()
            .chain(&before)
            .map(|p| p.0 / l)
            .filter(|v| v.is_finite());
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let mut chart = Chart::new(
            format!(
                "log {}: the known contour and the reconstructed contact points",
                i + 1
            ),
            units.label("x", Quantity::Length),
            units.label("y", Quantity::Length),
        )
        .equal_aspect()
        .note(format!("{} — contour {}", input.arg, input.profile.0));
        if lo.is_finite() && hi > lo {
            let pad = 0.1 * (hi - lo);
            let contour: Vec<(f64, f64)> = (0..=200)
                .map(|k| lo - pad + (hi - lo + 2.0 * pad) * k as f64 / 200.0)
                .map(|x| (x * l, input.profile.1.y(x) * l))
                .filter(|p| p.1.is_finite())
                .collect();
            // The object (solid above its contour) under the points, its contour on top.
            chart =
                chart.with(Series::new("known object", contour.clone(), Style::Obstacle).color(6));
            chart
                .series
                .push(Series::new("", contour, Style::Line).color(6));
        }
        if !before.is_empty() {
            chart =
                chart.with(Series::new("before (start whisker)", before, Style::Points).color(1));
        }
        chart = chart.with(Series::new("after calibration", after, Style::Points).color(0));
        if let Some(line) = chart.series.iter().position(|s| s.name.is_empty()) {
            let top = chart.series.remove(line);
            chart.series.push(top);
        }
        style.write_svg(
            &chart,
            &path_for(&format!("contour-{}.svg", i + 1)),
            (720, 640),
        )?;
        let res: Vec<(f64, f64)> = cal
            .rows
            .iter()
            .filter(|r| r.log == i && is_contact_symbol(r.kind))
            .map(|r| {
                (
                    input.x0_given.get(r.row).copied().unwrap_or(f64::NAN),
                    r.distance * l,
                )
            })
            .collect();
        res_chart =
            // Each row's distance is its own: points, not a line through them.
            res_chart.with(Series::new(format!("log {}", i + 1), res, Style::Points).color(i));
    }
    Ok(style.write_svg(&res_chart, &path_for("residuals.svg"), (900, 480))?)
}
