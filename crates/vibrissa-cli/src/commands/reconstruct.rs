//! `vibrissa reconstruct`: identification of the fluid load and contour reconstruction from
//! an observables log (thesis ch. 6), written as `reconstruction.csv` and its figures.

use std::path::{Path, PathBuf};

use contact_sim::{Phase, Profile};
use profile_recon::{
    contour_error, reconstruct_with, KnownFlow, ObservableRow, ReconError, ReconMethod, ReconPoint,
    ReconSettings, Reconstruction, Streamer,
};

use crate::atomic::OutputDir;
use crate::cli::{ModelFlags, ReconstructArgs};
use crate::commands::recon_io;
use crate::csvio::{read_table, Table};
use crate::error::CliError;
use crate::plot::{write_svg, Chart, Series, Style};
use crate::resolve::{parse_number, resolve_model, LoadedScene, ProfileArg, Resolved};
use crate::units::{Quantity, UnitSystem};

/// The columns an observables log must have.
pub const REQUIRED_COLUMNS: [&str; 5] = ["x0", "Ax", "Ay", "MA", "phi0"];

/// The header of `reconstruction.csv` (spec/cli.md); `error` is appended with a profile.
pub const RECONSTRUCTION_HEADER: [&str; 7] = ["x0", "x", "y", "s1", "f", "psi", "phase"];

/// Default consistency tolerance of the accurate method (exact logs).
pub const DEFAULT_TOLERANCE_ACCURATE: f64 = 1e-6;

/// Default consistency tolerance of the thesis method (its least-squares residual stays at
/// about 1e-5..1e-4).
pub const DEFAULT_TOLERANCE_THESIS: f64 = 1e-3;

/// Runs `vibrissa reconstruct`.
pub fn run(args: &ReconstructArgs) -> Result<(), CliError> {
    if args.stream {
        return run_stream(args);
    }
    let (Some(observables), Some(out_dir)) = (&args.observables, &args.out) else {
        return Err(CliError::invalid_argument(
            "OBSERVABLES.csv",
            "",
            "the observables log and --out are needed (or --stream)",
        ));
    };
    let opts = ReconOptions::parse(args)?;
    let method = opts.method;
    let (log_path, scene_path) = recon_io::resolve_input(observables, args.scene.as_deref())?;
    crate::atomic::refuse_over_inputs(out_dir, &[("log", &log_path)])?;
    let file = LoadedScene::load_opt(scene_path.as_deref())?;
    let r = recon_model(args, file)?;
    let units = r.units();
    let truth = match &args.profile {
        Some(spec) => Some(
            ProfileArg {
                spec: spec.clone(),
                file: None,
            }
            .parse(&units)?,
        ),
        None => None,
    };

    let mut table = read_table(&log_path, &REQUIRED_COLUMNS, 2)?;
    let x0_given = recon_io::to_model_units(&mut table, &units)?;
    let rec = reconstruct_log(args, &opts, &r, &table)?;
    let errors = truth.as_ref().map(|p| contour_error(&rec.points, p));

    let out = OutputDir::create(out_dir)?;
    recon_io::write_reconstruction_csv_in(
        &rec.points,
        errors.as_deref(),
        &units,
        &x0_given,
        &out.path_for(RECON_CSV),
    )?;
    recon_io::write_recon_scene(
        &r,
        rec.identification.q,
        args.profile.clone(),
        &log_path,
        &out.path_for(recon_io::SCENE_RON),
    )?;
    let title = observables
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "observables".to_string());
    write_reconstruction_figures_in(
        &rec.points,
        truth.as_ref(),
        errors.as_deref(),
        &format!(
            "q = {:.6}{} {}",
            rec.identification.q * units.scale(Quantity::LineLoad),
            unit_suffix(&units, Quantity::LineLoad),
            if rec.q_given { "given" } else { "identified" }
        ),
        &units,
        |n| out.path_for(n),
    )?;
    let files = out.commit()?;

    let (na, nb) = phase_counts(&rec.points);
    let max_error = errors.as_deref().map(max_of);
    let max_residual = max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>());
    if args.json {
        let mut v = serde_json::json!({
            "q": rec.identification.q * units.scale(Quantity::LineLoad),
            "q_dimensionless": rec.identification.q,
            "q_given": rec.q_given,
            "units": if units.is_physical() { "physical" } else { "dimensionless" },
            "alpha_deg": rec.identification.alpha.to_degrees(),
            "alpha_given": rec.alpha_given,
            "noise": json_number(rec.identification.noise),
            "noise_estimated": rec.identification.noise_estimated,
            "max_sigma": json_number(max_of(&rec.points.iter().map(|p| p.sigma).collect::<Vec<_>>())),
            "points": rec.points.len(),
            "rows": table.rows(),
            "first_contact_row": rec.identification.first_contact_row + 1,
            "rows_without_force": row_ranges(&rows_without_points(&rec.points, table.rows())),
            "method": method.name(),
            "max_residual": json_number(max_residual),
            "phases": {"A": na, "B": nb},
            "out": out_dir.display().to_string(),
        });
        if let Some(e) = max_error {
            v["max_error"] = json_number(e * units.scale(Quantity::Length));
        }
        if !rec.q_given {
            v["model_mismatch"] = json_number(rec.identification.model_mismatch);
        }
        println!("{v}");
    } else {
        println!(
            "reconstruct {}: {}",
            title,
            summary_line_in(&rec, method, table.rows(), &units)
        );
        if let Some(e) = max_error {
            println!(
                "max contour error e = {:.3e}{} (eq. 6.11)",
                e * units.scale(Quantity::Length),
                unit_suffix(&units, Quantity::Length)
            );
        }
        println!("wrote {} files to {}", files.len(), out_dir.display());
    }
    Ok(())
}

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
        })
    }

    /// The options of a stream: as [`ReconOptions::parse`], the method `accurate` only (each
    /// row on its own).
    pub fn parse_stream(args: &ReconstructArgs) -> Result<Self, CliError> {
        let opts = Self::parse(args)?;
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
        whisker: args.whisker.clone(),
        ..ModelFlags::default()
    };
    flags.fluid.q = args.q.clone();
    resolve_model(&flags, file)
}

/// Identifies the flow (unless given) and reconstructs every contact row of the log
/// `table` (columns [`REQUIRED_COLUMNS`], already in the model's dimensionless variables)
/// with the whisker of `r`; a failure names its culprit (a line of the log, a flag, the
/// solver).
pub fn reconstruct_log(
    args: &ReconstructArgs,
    opts: &ReconOptions,
    r: &Resolved,
    table: &Table,
) -> Result<Reconstruction, CliError> {
    let rows = rows_of(table)?;
    reconstruct_with(
        &r.scene.whisker,
        &rows,
        opts.known_flow(args, r),
        &opts.settings(),
    )
    .map_err(|e| recon_culprit(e, table, r, args, opts.tol))
}

/// File name of the reconstruction table.
pub const RECON_CSV: &str = "reconstruction.csv";

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

/// The observable rows of a table read with [`REQUIRED_COLUMNS`].
pub(crate) fn rows_of(table: &Table) -> Result<Vec<ObservableRow>, CliError> {
    let col = |name: &str| {
        table.column(name).ok_or_else(|| CliError::Csv {
            path: table.path.clone(),
            line: 1,
            column: Some(name.to_string()),
            reason: "missing required column".to_string(),
        })
    };
    let (x0, ax, ay, ma, phi0) = (col("x0")?, col("Ax")?, col("Ay")?, col("MA")?, col("phi0")?);
    Ok((0..table.rows())
        .map(|i| ObservableRow {
            x0: x0[i],
            ax: ax[i],
            ay: ay[i],
            ma: ma[i],
            phi0: phi0[i],
        })
        .collect())
}

/// Maps a reconstruction error to its culprit: a line of the log, a flag, a model
/// parameter, or the solver.
fn recon_culprit(
    err: ReconError,
    table: &Table,
    r: &Resolved,
    args: &ReconstructArgs,
    tol: Option<f64>,
) -> CliError {
    let first_line = table.line_of(0).unwrap_or(1);
    let last_line = table
        .rows()
        .checked_sub(1)
        .and_then(|i| table.line_of(i))
        .unwrap_or(1);
    let at = |line: usize, column: Option<&str>, reason: String| CliError::Csv {
        path: table.path.clone(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    // `row` of the library's errors is the 0-based index of the data row.
    let line_of = |row: usize| table.line_of(row).unwrap_or(first_line);
    match err {
        ReconError::NonFinite { row, column, value } => at(
            line_of(row),
            Some(column),
            format!("value `{value}` is not finite"),
        ),
        ReconError::InconsistentRow {
            row,
            x0,
            residual,
            phase,
        } => at(
            line_of(row),
            None,
            format!(
                "x0 = {x0}: no consistent contact point (best residual {residual:.3e} \
                 with phase {phase}, tolerance {}); check the whisker parameters, or pass \
                 --tolerance none for a noisy log",
                tol.map_or("none".to_string(), |t| format!("{t:e}"))
            ),
        ),
        ReconError::TooFewRows { .. } => at(last_line, None, err.to_string()),
        ReconError::NoPreContactRows { .. } => at(
            first_line,
            None,
            "no row is the free whisker under a flow (no pre-contact row): the fluid load \
             cannot be identified; give it with --q and --alpha-deg (or check the whisker)"
                .to_string(),
        ),
        ReconError::NoContactRows { .. } => at(last_line, None, err.to_string()),
        ReconError::InvalidParameter {
            name: "q",
            value,
            reason,
        } => match &args.q {
            Some(raw) => CliError::invalid_argument("--q", raw.clone(), reason),
            None => at(
                first_line,
                Some("Ax"),
                format!("identified fluid load q = {value}: {reason}"),
            ),
        },
        ReconError::InvalidParameter {
            name: "alpha",
            reason,
            ..
        } => CliError::invalid_argument(
            "--alpha-deg",
            args.alpha_deg.clone().unwrap_or_default(),
            reason,
        ),
        ReconError::InvalidParameter {
            name: "noise",
            reason,
            ..
        } => CliError::invalid_argument("--noise", args.noise.clone().unwrap_or_default(), reason),
        ReconError::Model(e) => r.culprit(&e),
        other => CliError::solver(other),
    }
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

/// `vibrissa reconstruct --stream`: rows from standard input (a header line naming the
/// columns first), each contact point to standard output as soon as it is known, in the
/// scene's units (a physical scene's log in mm, N, N mm); rows are checked as in a file.
fn run_stream(args: &ReconstructArgs) -> Result<(), CliError> {
    use std::io::BufRead;
    let opts = ReconOptions::parse_stream(args)?;
    // the one positional argument is the scene (a sweep folder gives its scene.ron)
    let scene = stream_scene(args.scene.as_deref().or(args.observables.as_deref()))?;
    let file = LoadedScene::load_opt(scene.as_deref())?;
    let r = recon_model(args, file)?;
    let units = r.units();
    let (flow, settings) = (opts.known_flow(args, &r), opts.settings());
    let mut stream = Streamer::new(&r.scene.whisker, flow, &settings)
        .map_err(|e| stdin_err(1, e.to_string()))?;
    let mut out = StreamOut::new(&units)?;
    let mut columns: Option<(char, usize, [usize; 5])> = None;
    // line numbers of the data rows (the library's 0-based row index -> input line)
    let mut lines: Vec<usize> = Vec::new();
    let at_row = |lines: &[usize], e: ReconError| -> CliError {
        let row = match &e {
            ReconError::NonFinite { row, .. } | ReconError::InconsistentRow { row, .. } => {
                Some(*row)
            }
            _ => None,
        };
        let line = row.and_then(|r| lines.get(r).copied()).unwrap_or(1);
        stdin_err(line, e.to_string())
    };
    let scale = [
        units.scale(Quantity::Length),
        units.scale(Quantity::Force),
        units.scale(Quantity::Force),
        units.scale(Quantity::Moment),
        1.0,
    ];
    for (k, line) in std::io::stdin().lock().lines().enumerate() {
        let n = k + 1;
        let line = line.map_err(|e| stdin_err(n, format!("cannot read: {e}")))?;
        let line = line.trim_end_matches('\r').trim_start_matches('\u{feff}');
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let Some((sep, width, idx)) = columns else {
            columns = Some(stream_header(line, n)?);
            continue;
        };
        let cells: Vec<&str> = line.split(sep).map(str::trim).collect();
        if cells.len() != width {
            return Err(stdin_err(
                n,
                format!(
                    "{} fields where the header has {width} (the columns {})",
                    cells.len(),
                    REQUIRED_COLUMNS.join(", ")
                ),
            ));
        }
        let mut v = [0.0f64; 5];
        for (j, &c) in idx.iter().enumerate() {
            let cell = cells[c];
            v[j] = cell.parse::<f64>().map_err(|_| {
                stdin_err(
                    n,
                    format!("column `{}`: `{cell}` is not a number", REQUIRED_COLUMNS[j]),
                )
            })? / scale[j];
        }
        lines.push(n);
        let row = ObservableRow {
            x0: v[0],
            ax: v[1],
            ay: v[2],
            ma: v[3],
            phi0: v[4],
        };
        let points = stream.push(row).map_err(|e| at_row(&lines, e))?;
        out.write(&points)?;
    }
    if columns.is_none() {
        return Err(stdin_err(
            1,
            format!(
                "standard input is empty: --stream reads an observables log, a header line \
                 naming {} and then one row per line",
                REQUIRED_COLUMNS.join(", ")
            ),
        ));
    }
    let points = stream.finish().map_err(|e| at_row(&lines, e))?;
    out.write(&points)
}

/// An error at line `line` of standard input.
fn stdin_err(line: usize, reason: String) -> CliError {
    CliError::Csv {
        path: PathBuf::from("<stdin>"),
        line,
        column: None,
        reason,
    }
}

/// The scene of a stream: the file given, or the `scene.ron` of a sweep folder.
fn stream_scene(given: Option<&Path>) -> Result<Option<PathBuf>, CliError> {
    let Some(path) = given else { return Ok(None) };
    if !path.is_dir() {
        return Ok(Some(path.to_path_buf()));
    }
    let scene = path.join(recon_io::SCENE_RON);
    if !scene.is_file() {
        return Err(CliError::io(
            &scene,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "--stream reads the log from standard input and takes the whisker from a \
                 scene file; this folder has no scene.ron",
            ),
        ));
    }
    Ok(Some(scene))
}

/// The separator, field count and positions of the required columns of a stream's header.
fn stream_header(line: &str, n: usize) -> Result<(char, usize, [usize; 5]), CliError> {
    let sep = [',', '\t', ';']
        .into_iter()
        .find(|c| line.contains(*c))
        .unwrap_or(',');
    let names: Vec<&str> = line.split(sep).map(str::trim).collect();
    let mut idx = [0usize; 5];
    for (j, want) in REQUIRED_COLUMNS.iter().enumerate() {
        idx[j] = names.iter().position(|h| h == want).ok_or_else(|| {
            stdin_err(
                n,
                format!(
                    "missing required column {want} in the header (found `{line}`; a log \
                     starts with a header naming {})",
                    REQUIRED_COLUMNS.join(", ")
                ),
            )
        })?;
    }
    Ok((sep, names.len(), idx))
}

/// The stream's standard output: the header of `reconstruction.csv` (without `error`), then
/// each point as soon as it is known, flushed, in the scene's units.
struct StreamOut<'u> {
    out: std::io::StdoutLock<'static>,
    units: &'u UnitSystem,
}

impl<'u> StreamOut<'u> {
    fn new(units: &'u UnitSystem) -> Result<Self, CliError> {
        let mut s = StreamOut {
            out: std::io::stdout().lock(),
            units,
        };
        let mut header: Vec<&str> = RECONSTRUCTION_HEADER.to_vec();
        header.extend(recon_io::RECON_EXTRA_COLUMNS);
        s.line(&header.join(","))?;
        Ok(s)
    }

    fn line(&mut self, text: &str) -> Result<(), CliError> {
        use std::io::Write;
        writeln!(self.out, "{text}")
            .and_then(|_| self.out.flush())
            .map_err(|e| stdin_err(1, format!("cannot write to standard output: {e}")))
    }

    fn write(&mut self, points: &[ReconPoint]) -> Result<(), CliError> {
        for p in points {
            let v = recon_io::recon_values(p, self.units, &[]);
            let text = format!(
                "{},{},{},{},{},{},{},{},{},{}",
                v[0],
                v[1],
                v[2],
                v[3],
                v[4],
                v[5],
                p.phase.label(),
                p.sigma * self.units.scale(Quantity::Length),
                p.residual,
                p.alternatives
            );
            self.line(&text)?;
        }
        Ok(())
    }
}

/// Number of phase-A and phase-B points.
pub fn phase_counts(points: &[ReconPoint]) -> (usize, usize) {
    let na = points.iter().filter(|p| p.phase == Phase::A).count();
    let nb = points.iter().filter(|p| p.phase == Phase::B).count();
    (na, nb)
}

/// The largest value (NaN if any value is NaN, 0 for none).
pub fn max_of(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m: f64, &v| {
        if v.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(v)
        }
    })
}

fn json_number(v: f64) -> serde_json::Value {
    serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, serde_json::Value::Number)
}

/// The one-line summary of a reconstruction (without the error).
pub fn summary_line(rec: &Reconstruction, method: ReconMethod) -> String {
    let (na, nb) = phase_counts(&rec.points);
    let q = if rec.q_given {
        format!("q = {} (given)", rec.identification.q)
    } else {
        format!("q = {:.10} (identified)", rec.identification.q)
    };
    let q = if rec.alpha_given {
        format!(
            "{q}, alpha = {} deg (given)",
            rec.identification.alpha.to_degrees()
        )
    } else {
        format!(
            "{q}, alpha = {:.8} deg (identified)",
            rec.identification.alpha.to_degrees()
        )
    };
    format!(
        "{q}, contact from row {}, {} points ({method} method), phases A {na} / B {nb}, \
         max residual {:.2e}",
        rec.identification.first_contact_row + 1,
        rec.points.len(),
        max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>()),
        method = method.name(),
    )
}

/// `" mm"` etc., or nothing for dimensionless values.
fn unit_suffix(units: &UnitSystem, q: Quantity) -> String {
    match units.unit(q) {
        "1" | "" => String::new(),
        u => format!(" {u}"),
    }
}

/// The one-line summary of a reconstruction of a log of `rows` rows, q in `units`; rows
/// numbered from 1 as in the log (row r on line r + 1).
pub fn summary_line_in(
    rec: &Reconstruction,
    method: ReconMethod,
    rows: usize,
    units: &UnitSystem,
) -> String {
    let (na, nb) = phase_counts(&rec.points);
    let qs = units.scale(Quantity::LineLoad);
    let qu = unit_suffix(units, Quantity::LineLoad);
    let q = match (rec.q_given, units.is_physical()) {
        (true, _) => format!("q = {}{qu} (given)", rec.identification.q * qs),
        (false, true) => format!("q = {:.10e}{qu} (identified)", rec.identification.q * qs),
        (false, false) => format!("q = {:.10}{qu} (identified)", rec.identification.q * qs),
    };
    let free = rows_without_points(&rec.points, rows);
    let with: Vec<usize> = rec.points.iter().map(|p| p.row).collect();
    format!(
        "{q}; {rows} rows: {} without contact force (the free whisker under the flow: before \
         contact, at a touch or release with f = 0; rows {}), {} contact points (rows {}; \
         {method} method), phases A {na} / B {nb}, max residual {:.2e}",
        free.len(),
        row_ranges(&free),
        rec.points.len(),
        row_ranges(&with),
        max_of(&rec.points.iter().map(|p| p.residual).collect::<Vec<_>>()),
        method = method.name(),
    )
}

/// The 0-based rows of a log of `rows` rows that yield no contact point (the free whisker
/// under the flow: before contact, and a touch or release with f = 0).
pub fn rows_without_points(points: &[ReconPoint], rows: usize) -> Vec<usize> {
    let mut contact = vec![false; rows];
    for p in points {
        if let Some(c) = contact.get_mut(p.row) {
            *c = true;
        }
    }
    (0..rows).filter(|&i| !contact[i]).collect()
}

/// 0-based row indices as 1-based ranges, `1-11, 133` (`none` if empty).
pub fn row_ranges(rows: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < rows.len() {
        let mut j = i;
        while j + 1 < rows.len() && rows[j + 1] == rows[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            format!("{}", rows[i] + 1)
        } else {
            format!("{}-{}", rows[i] + 1, rows[j] + 1)
        });
        i = j + 1;
    }
    if parts.is_empty() {
        "none".to_string()
    } else {
        parts.join(", ")
    }
}

/// Writes `reconstruction.csv` dimensionless (with its units sidecar): `x0,x,y,s1,f,psi,
/// phase,sigma,residual,hypotheses` (+ `error`); see
/// [`recon_io::write_reconstruction_csv_in`], the one writer.
pub fn write_reconstruction_csv(
    points: &[ReconPoint],
    errors: Option<&[f64]>,
    path: &Path,
) -> Result<(), CliError> {
    recon_io::write_reconstruction_csv_in(points, errors, &UnitSystem::DIMENSIONLESS, &[], path)
}

/// Writes `reconstruction.svg` (the reconstructed points, with the true contour if known)
/// and, with errors, `error.svg` (e against x, log scale), dimensionless. Returns the file
/// names written.
pub fn write_reconstruction_figures(
    points: &[ReconPoint],
    truth: Option<&Profile>,
    errors: Option<&[f64]>,
    title: &str,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<Vec<&'static str>, CliError> {
    write_reconstruction_figures_in(
        points,
        truth,
        errors,
        title,
        &UnitSystem::DIMENSIONLESS,
        path_for,
    )
}

/// [`write_reconstruction_figures`] with the axes in `units` (SVG and PNG).
pub fn write_reconstruction_figures_in(
    points: &[ReconPoint],
    truth: Option<&Profile>,
    errors: Option<&[f64]>,
    title: &str,
    units: &UnitSystem,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<Vec<&'static str>, CliError> {
    let l = units.scale(Quantity::Length);
    let mut chart = Chart::new(
        format!("reconstructed contour ({title})"),
        units.label("x", Quantity::Length),
        units.label("y", Quantity::Length),
    )
    .equal_aspect()
    .note(format!(
        "each point from one contact row's base observables alone, bars ±σ; {}",
        units.describe()
    ));
    let mut true_line = None;
    if let Some(p) = truth {
        let xs = points.iter().map(|p| p.x).filter(|x| x.is_finite());
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        if lo.is_finite() && hi.is_finite() {
            let pad = 0.05 * (hi - lo).max(1e-3);
            let (dlo, dhi) = p.domain();
            let (a, b) = ((lo - pad).max(dlo), (hi + pad).min(dhi));
            let line: Vec<(f64, f64)> = (0..=300)
                .map(|i| {
                    let x = a + (b - a) * i as f64 / 300.0;
                    (x * l, p.y(x) * l)
                })
                .collect();
            // The obstacle (solid above its contour) under the points, its contour line
            // again on top of them.
            chart = chart.with(
                Series::new("obstacle (true contour)", line.clone(), Style::Obstacle).color(6),
            );
            true_line = Some(line);
        }
    }
    for (phase, color) in [(Phase::A, 0), (Phase::B, 1)] {
        let name = format!("reconstructed, {}", crate::commands::phase_name(phase));
        let sel: Vec<&ReconPoint> = points.iter().filter(|p| p.phase == phase).collect();
        if !sel.is_empty() {
            let pts = sel.iter().map(|p| (p.x * l, p.y * l)).collect();
            let err = sel.iter().map(|p| p.sigma * l).collect();
            chart = chart.with(
                Series::new(name, pts, Style::Points)
                    .color(color)
                    .errors(err),
            );
        }
    }
    if let Some(line) = true_line {
        chart = chart.with(Series::new("", line, Style::Line).color(6));
    }
    // The residual panel: the true error where the contour is known, and the estimate σ.
    let x_of = |p: &ReconPoint| p.x * l;
    let mut resid = Chart::new(
        "error of each point",
        units.label("x", Quantity::Length),
        units.label("error", Quantity::Length),
    )
    .log(false, true);
    if let Some(e) = errors {
        let pts = points
            .iter()
            .zip(e)
            .map(|(p, &e)| (x_of(p), e * l))
            .collect();
        resid = resid
            .note(
                "e = |y − g(x)| (thesis eq. 6.11); points with e = 0 are not shown on the log axis",
            )
            .with(Series::new("true error e", pts, Style::Points).color(3));
    }
    let sig = points.iter().map(|p| (x_of(p), p.sigma * l)).collect();
    resid = resid.with(
        Series::new("estimate σ", sig, Style::Points)
            .color(5)
            .marker(crate::plot::Marker::Triangle),
    );
    crate::plot::write_svg_panels(
        &[chart, resid.clone()],
        1,
        &path_for("reconstruction.svg"),
        (800, 900),
    )?;
    let mut written = vec!["reconstruction.svg"];
    if errors.is_some() {
        write_svg(&resid, &path_for("error.svg"), (800, 480))?;
        written.push("error.svg");
    }
    Ok(written)
}
