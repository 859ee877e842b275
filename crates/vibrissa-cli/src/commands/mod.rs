//! The commands of the binary and the outputs they share.

pub mod calibrate;
pub mod calibrate_advice;
pub mod calibrate_out;
pub mod demo;
pub mod recon_io;
pub mod reconstruct;
pub mod solve;
pub mod sweep;

use std::path::{Path, PathBuf};

use beam_model::Solution;
use contact_sim::{Phase, SweepPoint, SweepResult};

use crate::atomic::write_atomic;
use crate::cli::Command;
use crate::csvio::{units_sidecar_path, write_units_sidecar, CsvWriter};
use crate::error::CliError;
use crate::plot::{write_panels_with_heading, write_svg, Chart, Heading, Mark, Series, Style};
use crate::resolve::Resolved;
use crate::scene_file::{self, LoadSpec, MethodSpec, SceneFile, SweepSpec, WhiskerSpec};
use crate::units::{Quantity, UnitSystem};

/// Runs one command.
pub fn run(command: Command) -> Result<(), CliError> {
    match command {
        Command::Solve(args) => solve::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Reconstruct(args) => reconstruct::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Calibrate(args) => calibrate::run(&args),
    }
}

/// The header of `elastica.csv`.
pub const ELASTICA_HEADER: [&str; 6] = ["s", "x", "y", "phi", "kappa", "m"];

/// The header of `observables.csv` (spec/cli.md).
pub const OBSERVABLES_HEADER: [&str; 11] = [
    "x0", "Ax", "Ay", "MA", "phi0", "f", "s1", "phase", "xc", "yc", "psi",
];

/// The quantities of the `elastica.csv` columns.
pub const ELASTICA_QUANTITIES: [Quantity; 6] = [
    Quantity::Length,
    Quantity::Length,
    Quantity::Length,
    Quantity::Angle,
    Quantity::Curvature,
    Quantity::Moment,
];

/// The quantities of the `observables.csv` columns.
pub const OBSERVABLES_QUANTITIES: [Quantity; 11] = [
    Quantity::Length,
    Quantity::Force,
    Quantity::Force,
    Quantity::Moment,
    Quantity::Angle,
    Quantity::Force,
    Quantity::Length,
    Quantity::Text,
    Quantity::Length,
    Quantity::Length,
    Quantity::Angle,
];

/// Writes the units sidecar of the CSV file `csv` (see [`crate::csvio::units_sidecar_path`]).
pub fn write_units_of(
    csv: &Path,
    header: &[&str],
    quantities: &[Quantity],
    units: &UnitSystem,
) -> Result<(), CliError> {
    let u: Vec<&str> = quantities.iter().map(|q| units.unit(*q)).collect();
    write_units_sidecar(&units_sidecar_path(csv), header, &u)
}

/// Writes `elastica.csv` of a solution to `path` (dimensionless).
pub fn write_elastica_csv(sol: &Solution, path: &Path) -> Result<(), CliError> {
    write_elastica_csv_in(sol, &UnitSystem::DIMENSIONLESS, path)
}

/// Writes `elastica.csv` of a solution in `units`, with its units sidecar.
pub fn write_elastica_csv_in(
    sol: &Solution,
    units: &UnitSystem,
    path: &Path,
) -> Result<(), CliError> {
    let e = &sol.elastica;
    let sc: Vec<f64> = ELASTICA_QUANTITIES
        .iter()
        .map(|q| units.scale(*q))
        .collect();
    let mut w = CsvWriter::new(&ELASTICA_HEADER);
    for i in 0..e.len() {
        w.push_numbers(&[
            e.s[i] * sc[0],
            e.x[i] * sc[1],
            e.y[i] * sc[2],
            e.phi[i],
            e.kappa[i] * sc[4],
            e.m[i] * sc[5],
        ])?;
    }
    w.write(path)?;
    write_units_of(path, &ELASTICA_HEADER, &ELASTICA_QUANTITIES, units)
}

/// Writes the elastica figure (equal aspect), with the unloaded shape dashed if given.
pub fn write_elastica_svg(
    sol: &Solution,
    unloaded: Option<&Solution>,
    title: &str,
    path: &Path,
) -> Result<(), CliError> {
    write_elastica_figure(sol, unloaded, None, title, &UnitSystem::DIMENSIONLESS, path)
}

/// Writes the elastica figure in `units` (SVG at `path` and a PNG beside it), with the
/// `loads` drawn as arrows if given: the tip force at the loaded end (direction [3.16],
/// rotated with the end if angle preserving) and the flow, `q (cos α, −sin α)`, along the
/// loaded part.
pub fn write_elastica_figure(
    sol: &Solution,
    unloaded: Option<&Solution>,
    loads: Option<&beam_model::Loads>,
    title: &str,
    units: &UnitSystem,
    path: &Path,
) -> Result<(), CliError> {
    let l = units.scale(Quantity::Length);
    let pts = |s: &Solution| -> Vec<(f64, f64)> {
        s.elastica
            .x
            .iter()
            .zip(&s.elastica.y)
            .map(|(x, y)| (x * l, y * l))
            .collect()
    };
    let mut chart = Chart::new(
        title,
        units.label("x", Quantity::Length),
        units.label("y", Quantity::Length),
    )
    .equal_aspect()
    .note(units.describe());
    if let Some(u) = unloaded {
        chart = chart.with(Series::new("unloaded", pts(u), Style::Dashed).color(7));
    }
    chart = chart.with(Series::new("loaded", pts(sol), Style::Line).color(0));
    let base = (sol.elastica.x[0] * l, sol.elastica.y[0] * l);
    chart = chart.mark(Mark::point(base.0, base.1, "base", 7));
    if let Some(loads) = loads {
        chart = load_arrows(chart, sol, loads, l);
    }
    write_svg(&chart, path, (640, 640))
}

/// The loads of a solve as arrows ending on the whisker (0.2 whisker lengths for the tip
/// force, 0.1 for the flow).
fn load_arrows(mut chart: Chart, sol: &Solution, loads: &beam_model::Loads, l: f64) -> Chart {
    let tip = &loads.tip;
    if tip.f > 0.0 {
        let end = &sol.loaded_end;
        let ang = match tip.kind {
            beam_model::LoadKind::Dp => -tip.beta,
            beam_model::LoadKind::Ap => end.phi - std::f64::consts::FRAC_PI_2 - tip.beta,
        };
        let (dx, dy) = (0.2 * ang.cos(), 0.2 * ang.sin());
        chart = chart.mark(Mark::arrow(
            (end.x - dx) * l,
            (end.y - dy) * l,
            dx * l,
            dy * l,
            "tip force f",
            3,
        ));
    }
    let fl = &loads.fluid;
    let e = &sol.elastica;
    if fl.q > 0.0 && e.x.len() > 4 {
        let (dx, dy) = (0.1 * fl.alpha.cos(), -0.1 * fl.alpha.sin());
        let n = e.x.len() - 1;
        let loaded =
            e.s.iter()
                .filter(|&&s| s <= loads.s1 + 1e-12)
                .count()
                .max(2)
                - 1;
        for k in 0..4 {
            let i = ((2 * k + 1) * loaded / 8).min(n);
            let label = if k == 0 { "flow q" } else { "" };
            chart = chart.mark(Mark::arrow(
                (e.x[i] - dx) * l,
                (e.y[i] - dy) * l,
                dx * l,
                dy * l,
                label,
                5,
            ));
        }
    }
    chart
}

/// One row of `observables.csv` (serde names = the contract's column names).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct ObservableRecord<'a> {
    /// Base position.
    pub x0: f64,
    /// Horizontal base force.
    #[serde(rename = "Ax")]
    pub ax: f64,
    /// Vertical base force.
    #[serde(rename = "Ay")]
    pub ay: f64,
    /// Base moment.
    #[serde(rename = "MA")]
    pub ma: f64,
    /// Base angle.
    pub phi0: f64,
    /// Contact force.
    pub f: f64,
    /// Loaded arc length.
    pub s1: f64,
    /// `none`, `A` or `B`.
    pub phase: &'a str,
    /// Contact point x.
    pub xc: f64,
    /// Contact point y.
    pub yc: f64,
    /// Contour angle at the contact point.
    pub psi: f64,
}

impl ObservableRecord<'static> {
    /// The row of the sweep point `p` in `units` (mm, N, N mm for a physical scene): the one
    /// place where a sweep row is scaled for output (CSV, Python).
    pub fn of(p: &SweepPoint, units: &UnitSystem) -> Self {
        let (l, f, m) = (
            units.scale(Quantity::Length),
            units.scale(Quantity::Force),
            units.scale(Quantity::Moment),
        );
        ObservableRecord {
            x0: p.x0 * l,
            ax: p.ax * f,
            ay: p.ay * f,
            ma: p.ma * m,
            phi0: p.phi0,
            f: p.f * f,
            s1: p.s1 * l,
            phase: p.phase.label(),
            xc: p.xc * l,
            yc: p.yc * l,
            psi: p.psi,
        }
    }
}

/// The rows of `observables.csv` (header [`OBSERVABLES_HEADER`]) for sweep points,
/// dimensionless.
pub fn observables_csv(points: &[SweepPoint]) -> Result<CsvWriter, CliError> {
    observables_csv_in(points, &UnitSystem::DIMENSIONLESS)
}

/// The rows of `observables.csv` in `units` (mm, N, N mm for a physical scene).
pub fn observables_csv_in(
    points: &[SweepPoint],
    units: &UnitSystem,
) -> Result<CsvWriter, CliError> {
    let mut w = CsvWriter::new(&OBSERVABLES_HEADER);
    for p in points {
        w.push_record(&ObservableRecord::of(p, units))?;
    }
    Ok(w)
}

/// Writes `observables.csv` of a sweep to `path` (dimensionless).
pub fn write_observables_csv(res: &SweepResult, path: &Path) -> Result<(), CliError> {
    observables_csv(&res.points)?.write(path)
}

/// Writes `observables.csv` of a sweep in `units` and its units sidecar.
pub fn write_observables_csv_in(
    res: &SweepResult,
    units: &UnitSystem,
    path: &Path,
) -> Result<(), CliError> {
    observables_csv_in(&res.points, units)?.write(path)?;
    write_units_of(path, &OBSERVABLES_HEADER, &OBSERVABLES_QUANTITIES, units)
}

/// The scene that produced an output folder, with every parameter as resolved (flags over
/// the scene file over the defaults) in the scene's units.
pub fn output_scene(r: &Resolved, profile: Option<String>, points: Option<usize>) -> SceneFile {
    let g = &r.given;
    // The unit system exactly as the scene file gave it (a preset name stays a preset name;
    // the resolved dimensions are stated in the comment lines of [`scene_unit_notes`]).
    let units = r
        .file
        .as_ref()
        .map(|f| f.file.units.clone())
        .unwrap_or_default();
    SceneFile {
        units,
        whisker: WhiskerSpec {
            theta: g.theta.value,
            a: g.a.value,
            b: g.b.value,
            k: g.k.value.is_finite().then_some(g.k.value),
        },
        loads: LoadSpec {
            f: g.f.value,
            beta_deg: g.beta_deg.value,
            load: match g.load {
                beam_model::LoadKind::Dp => scene_file::LoadKind::Dp,
                beam_model::LoadKind::Ap => scene_file::LoadKind::Ap,
            },
            q: g.q.value,
            alpha_deg: g.alpha_deg.value,
        },
        profile,
        sweep: points.map(|points| SweepSpec { points }),
        method: MethodSpec {
            name: r.method.name().to_string(),
            n: g.n.as_ref().map(|n| n.value as usize),
            tol: match r.method {
                beam_model::Method::Auto { tol, .. } => Some(tol),
                _ => None,
            },
        },
    }
}

/// Writes `scene.ron`: `notes` as comment lines, then the scene. Checks that the text
/// parses back to the same scene.
pub fn write_scene_ron(path: &Path, scene: &SceneFile, notes: &[String]) -> Result<(), CliError> {
    let mut text = String::new();
    for n in notes {
        for line in n.lines() {
            text.push_str("// ");
            text.push_str(line);
            text.push('\n');
        }
    }
    text.push_str(&scene.to_ron()?);
    text.push('\n');
    let back = SceneFile::parse(&text, path)?;
    if &back != scene {
        return Err(CliError::invalid_argument(
            "scene.ron",
            path.display().to_string(),
            "the written scene does not read back identically",
        ));
    }
    write_atomic(path, text.as_bytes())
}

/// The comment lines of a written scene that state its units.
pub fn scene_unit_notes(units: &UnitSystem) -> Vec<String> {
    match units.physical {
        None => vec![
            "units: dimensionless (thesis variables): lengths in whisker lengths L, f in E·Ib/L², \
             q in E·Ib/L³, k in E·Ib/L, a in 1/L², b in 1/L; angles in degrees"
                .to_string(),
        ],
        Some(_) => vec![format!(
            "units: {}; loads.f in N, loads.q in N/m, whisker.k in N m/rad, whisker.a in 1/m², \
             whisker.b in 1/m; profile numbers (parabola, cosh, circle) in mm; angles in degrees",
            units.describe()
        )],
    }
}

fn phase_color(p: Phase) -> usize {
    match p {
        Phase::None => 7,
        Phase::A => 0,
        Phase::B => 1,
    }
}

/// The line of a phase: no contact dotted, tip contact solid, tangential contact dashed
/// (so phases differ in greyscale too).
fn phase_dash(p: Phase) -> crate::plot::Dash {
    match p {
        Phase::None => crate::plot::Dash::Dotted,
        Phase::A => crate::plot::Dash::Solid,
        Phase::B => crate::plot::Dash::Dashed,
    }
}

/// The legend text of a phase.
pub fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::None => "no contact (flow only)",
        Phase::A => "phase A: tip contact",
        Phase::B => "phase B: tangential contact",
    }
}

/// Series of `value` against x0, one per run of equal phase (coloured by phase; runs
/// touch so the curve is continuous, except at the jump of a tangential first contact),
/// only contact rows if `contact_only`.
fn phase_series(
    res: &SweepResult,
    x_scale: f64,
    value: impl Fn(&contact_sim::SweepPoint) -> f64,
    contact_only: bool,
) -> Vec<Series> {
    let rows: Vec<_> = res
        .points
        .iter()
        .filter(|p| !contact_only || p.phase != Phase::None)
        .collect();
    let mut out: Vec<Series> = Vec::new();
    let mut named = [false; 3];
    let mut i = 0;
    while i < rows.len() {
        let phase = rows[i].phase;
        let mut j = i;
        while j < rows.len() && rows[j].phase == phase {
            j += 1;
        }
        let mut pts: Vec<(f64, f64)> = rows[i..j]
            .iter()
            .map(|p| (p.x0 * x_scale, value(p)))
            .collect();
        if j < rows.len() {
            // At a tangential first contact the observables jump (the flow beyond s1 is
            // dropped): the free whisker's values run on to that x0, and no line joins them
            // to the contact's.
            let jump =
                phase == Phase::None && res.first_contact == contact_sim::FirstContact::Tangential;
            let v = if jump {
                value(rows[j - 1])
            } else {
                value(rows[j])
            };
            pts.push((rows[j].x0 * x_scale, v));
        }
        let idx = match phase {
            Phase::None => 0,
            Phase::A => 1,
            Phase::B => 2,
        };
        let name = if named[idx] {
            String::new()
        } else {
            named[idx] = true;
            phase_name(phase).to_string()
        };
        out.push(
            Series::new(name, pts, Style::Line)
                .color(phase_color(phase))
                .dash(phase_dash(phase)),
        );
        i = j;
    }
    out
}

/// An event of a sweep: first contact, a phase switch, the separation.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepEvent {
    /// The 0-based index of its row in the sweep's rows.
    pub index: usize,
    /// Short label (`first contact (tip)`, `A→B`, `snap`, ...).
    pub label: String,
}

/// The events of a sweep in row order: first contact, every phase switch, the separation.
pub fn sweep_events(res: &SweepResult) -> Vec<SweepEvent> {
    let mut out = Vec::new();
    let Some(first) = res.points.iter().position(|p| p.phase != Phase::None) else {
        return out;
    };
    out.push(SweepEvent {
        index: first,
        label: format!("first contact ({})", first_contact_name(res.first_contact)),
    });
    for i in first + 1..res.points.len() {
        let (a, b) = (res.points[i - 1].phase, res.points[i].phase);
        if a != b && a != Phase::None && b != Phase::None {
            out.push(SweepEvent {
                index: i,
                label: format!("{}→{}", a.label(), b.label()),
            });
        }
    }
    if let Some(last) = res.points.iter().rposition(|p| p.phase != Phase::None) {
        out.push(SweepEvent {
            index: last,
            label: separation_name(&res.separation),
        });
    }
    out
}

/// `tip` or `tangential`.
pub fn first_contact_name(f: contact_sim::FirstContact) -> &'static str {
    match f {
        contact_sim::FirstContact::Tip => "tip",
        contact_sim::FirstContact::Tangential => "tangential",
    }
}

/// `snap`, `release`, `second contact` or `end of contour`.
pub fn separation_name(s: &contact_sim::Separation) -> String {
    match s {
        contact_sim::Separation::Snap => "snap".to_string(),
        contact_sim::Separation::Release => "release".to_string(),
        contact_sim::Separation::MultiContact { .. } => "second contact".to_string(),
        contact_sim::Separation::EndOfContour => "end of contour".to_string(),
        contact_sim::Separation::ContactAtBase => "contact at the base".to_string(),
        contact_sim::Separation::NotReached { steps } => {
            format!("not reached within {steps} steps")
        }
    }
}

fn event_marks(res: &SweepResult, x_scale: f64) -> Vec<Mark> {
    sweep_events(res)
        .into_iter()
        .map(|e| Mark::vline(res.points[e.index].x0 * x_scale, e.label, 6))
        .collect()
}

fn chart_of(
    title: &str,
    y_label: &str,
    series: Vec<Series>,
    x_label: &str,
    marks: &[Mark],
) -> Chart {
    let mut c = Chart::new(title, x_label, y_label);
    for s in series {
        c = c.with(s);
    }
    for m in marks {
        c = c.mark(m.clone());
    }
    c
}

/// What the figures of a sweep need to know besides the rows.
#[derive(Debug, Clone)]
pub struct FigureContext {
    /// The unit system of the axes.
    pub units: UnitSystem,
    /// Names the scene in the titles, e.g. `contour g1, q = 5`.
    pub scene: String,
    /// A rigid support: phi0 is pi/2 throughout and its panel is left out.
    pub rigid: bool,
}

/// Whether phi0 varies beyond rounding over the rows.
fn phi0_varies(res: &SweepResult) -> bool {
    let (lo, hi) = res
        .points
        .iter()
        .map(|p| p.phi0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    hi - lo > 1e-8
}

/// Writes the figures of a sweep into `dir` (staging paths), in the formats of
/// [`crate::plot::figure_formats`]:
/// `observables.svg` (Ax, Ay, MA and, unless the support is rigid, phi0 against x0, thesis
/// Figs. 5.9/5.10) and `contact.svg` (f and s1 against x0, Fig. 5.11), with the events
/// marked. Returns the SVG file names written.
pub fn write_sweep_figures(
    res: &SweepResult,
    ctx: &FigureContext,
    path_for: impl Fn(&str) -> PathBuf,
) -> Result<Vec<&'static str>, CliError> {
    let u = &ctx.units;
    let (l, fs, ms) = (
        u.scale(Quantity::Length),
        u.scale(Quantity::Force),
        u.scale(Quantity::Moment),
    );
    let x_label = u.label("base x_0", Quantity::Length);
    let marks = event_marks(res, l);
    let mut charts = vec![
        chart_of(
            "horizontal base force",
            &u.label("A_x", Quantity::Force),
            phase_series(res, l, |p| p.ax * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "vertical base force",
            &u.label("A_y", Quantity::Force),
            phase_series(res, l, |p| p.ay * fs, false),
            &x_label,
            &marks,
        ),
        chart_of(
            "base moment",
            &u.label("M_A", Quantity::Moment),
            phase_series(res, l, |p| p.ma * ms, false),
            &x_label,
            &marks,
        ),
    ];
    if !ctx.rigid && phi0_varies(res) {
        charts.push(chart_of(
            "base angle",
            &u.label("φ_0", Quantity::Angle),
            phase_series(res, l, |p| p.phi0, false),
            &x_label,
            &marks,
        ));
    }
    let mut note = format!(
        "{}; the base moves towards −x (right to left); {}",
        ctx.scene,
        u.describe()
    );
    if charts.len() == 3 {
        note += "; φ_0 = π/2 throughout (rigid support, no panel)";
    }
    let heading = Heading {
        title: "Base observables along the sweep".to_string(),
        note: note.clone(),
    };
    let (cols, size) = if charts.len() == 4 {
        (2, (1100, 860))
    } else {
        (3, (1500, 480))
    };
    let observables_path = path_for("observables.svg");
    let observables =
        || write_panels_with_heading(&charts, cols, &heading, &observables_path, size);
    let mut written = vec!["observables.svg"];
    let has_contact = res.contact_points().next().is_some();
    let contact = || -> Result<(), CliError> {
        if !has_contact {
            return Ok(());
        }
        let charts = [
            chart_of(
                "contact force",
                &u.label("f", Quantity::Force),
                phase_series(res, l, |p| p.f * fs, true),
                &x_label,
                &marks,
            )
            .y_from_zero(),
            chart_of(
                "contact on the whisker",
                &u.label("s_1", Quantity::Length),
                phase_series(res, l, |p| p.s1 * l, true),
                &x_label,
                &marks,
            ),
            chart_of(
                "contact on the obstacle",
                &u.label("x_c", Quantity::Length),
                phase_series(res, l, |p| p.xc * l, true),
                &x_label,
                &marks,
            ),
        ];
        let heading = Heading {
            title: "Contact force and contact point along the sweep".to_string(),
            note,
        };
        write_panels_with_heading(&charts, 3, &heading, &path_for("contact.svg"), (1500, 480))
    };
    crate::plot::both(observables, contact)?;
    if has_contact {
        written.push("contact.svg");
    }
    Ok(written)
}

/// How the rows of a sweep are counted, the same way in the text, the JSON and the CSV:
/// rows are the data rows of `observables.csv`, numbered from 1 (row r is on line r + 1,
/// below the header).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RowCounts {
    /// All rows.
    pub rows: usize,
    /// Rows before contact (flow only).
    pub pre_contact: usize,
    /// Rows in contact.
    pub contact: usize,
    /// Contact rows requested (`--points`).
    pub requested: usize,
    /// Contact rows added at events (phase switches, the exactly located separation).
    pub event_rows: usize,
    /// The 1-based row of the first contact, if any.
    pub first_contact_row: Option<usize>,
    /// The 1-based row of the separation (the last contact row), if any.
    pub separation_row: Option<usize>,
}

impl RowCounts {
    /// Counts the rows of a sweep run with `requested` contact points.
    pub fn of(res: &SweepResult, requested: usize) -> Self {
        let pre = res.points.iter().filter(|p| p.phase == Phase::None).count();
        let contact = res.points.len() - pre;
        RowCounts {
            rows: res.points.len(),
            pre_contact: pre,
            contact,
            requested,
            event_rows: contact.saturating_sub(requested),
            first_contact_row: res
                .points
                .iter()
                .position(|p| p.phase != Phase::None)
                .map(|i| i + 1),
            separation_row: res
                .points
                .iter()
                .rposition(|p| p.phase != Phase::None)
                .map(|i| i + 1),
        }
    }
}

/// A one-line description of a sweep's outcome, with the rows counted as in
/// [`RowCounts`] and the positions in `units`.
pub fn sweep_summary_in(res: &SweepResult, requested: usize, units: &UnitSystem) -> String {
    let n = RowCounts::of(res, requested);
    let l = units.scale(Quantity::Length);
    let lu = match units.unit(Quantity::Length) {
        "1" => String::new(),
        u => format!(" {u}"),
    };
    let at = |row: Option<usize>| {
        row.map_or(String::new(), |r| {
            format!(" at row {r} (x0 = {:.6}{lu})", res.points[r - 1].x0 * l)
        })
    };
    let sep = match res.separation {
        contact_sim::Separation::MultiContact { xc } => {
            format!("second contact at xc = {:.6}{lu} (stopped)", xc * l)
        }
        ref s => separation_name(s),
    };
    format!(
        "{} rows ({} before contact + {} in contact: {} requested + {} at events), first \
         contact {}{}, separation {}{}, phases {}",
        n.rows,
        n.pre_contact,
        n.contact,
        n.requested,
        n.event_rows,
        first_contact_name(res.first_contact),
        at(n.first_contact_row),
        sep,
        at(n.separation_row),
        res.phase_pattern()
    )
}

/// A one-line description of a sweep's outcome (dimensionless, the contact rows counted as
/// requested).
pub fn sweep_summary(res: &SweepResult) -> String {
    let contact = res.contact_points().count();
    sweep_summary_in(res, contact, &UnitSystem::DIMENSIONLESS)
}

/// Formats a list of written files relative to nothing (as the OS returned them).
pub fn list_files(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_model::{FluidLoad, Whisker};
    use contact_sim::{FirstContact, Profile, SweepSettings};

    /// Thesis case 2 (conical whisker past g1 under q = 5): the first contact is
    /// tangential and the observables jump there (the flow beyond s1 is dropped). The free
    /// whisker's run of Ax ends at that x0 with its own value, and the contact run starts
    /// from the contact's: no line joins the two.
    #[test]
    fn a_tangential_first_contact_is_drawn_as_a_jump() {
        let w = Whisker::new(0.5, 0.0, 0.0, f64::INFINITY);
        let settings = SweepSettings {
            points: 40,
            ..SweepSettings::default()
        };
        let res = contact_sim::sweep(
            &w,
            FluidLoad { q: 5.0, alpha: 0.0 },
            &Profile::g1(),
            &settings,
        )
        .unwrap();
        assert_eq!(res.first_contact, FirstContact::Tangential);
        let first = res
            .points
            .iter()
            .position(|p| p.phase != Phase::None)
            .unwrap();
        let (free, touch) = (&res.points[first - 1], &res.points[first]);
        assert!(
            (touch.ax - free.ax).abs() > 0.1,
            "no jump: {} {}",
            free.ax,
            touch.ax
        );
        let series = phase_series(&res, 1.0, |p| p.ax, false);
        let end = *series[0].points.last().unwrap();
        assert_eq!(end, (touch.x0, free.ax), "the free run ends at the jump");
        assert_eq!(series[1].points[0], (touch.x0, touch.ax));
        // Elsewhere the runs touch: the contact runs share their switch rows.
        for w in series[1..].windows(2) {
            assert_eq!(w[0].points.last(), w[1].points.first());
        }
    }
}
