//! Chapter 6: fluid-load identification (Table 6.1) and contour reconstruction errors of
//! both methods (Figs. 6.2-6.13) from the chapter-5 sweeps.

use std::time::Instant;

use profile_recon::{
    contour_error, from_sweep, identify, reconstruct, KnownFlow, ReconMethod, ReconPoint,
    ReconSettings,
};
use vibrissa_io::atomic::OutputDir;
use vibrissa_io::csvio::{Cell, CsvWriter};
use vibrissa_plot::{Chart, Marker, Series, Style};

use crate::captions::caption;
use crate::common::{self, md_table, note_err, par_map, pretty, sci, svg_keyed, Ctx, SweepRun};
use crate::{Failure, Report};

/// Figures of the reconstruction errors: `(figure, case, profile)`.
const FIGURES: [(&str, &str, &str); 12] = [
    ("6.2", "1", "g1"),
    ("6.3", "1", "g2"),
    ("6.4", "2", "g1"),
    ("6.5", "2", "g2"),
    ("6.6", "3", "g1"),
    ("6.7", "3", "g2"),
    ("6.8", "4A", "g1"),
    ("6.9", "4A", "g2"),
    ("6.10", "4B", "g2"),
    ("6.11", "5", "g1"),
    ("6.12", "5", "g2"),
    ("6.13", "exp", "ge"),
];

/// Thesis Table 6.1: `(case, profile or "" if the thesis does not say, label, Δq)`, as
/// printed (cases 1-4A list one value per parameter, without naming the contour).
const TABLE_6_1: [(&str, &str, &str, &str); 28] = [
    ("1", "", "q=0", "2.34E+07"),
    ("1", "", "q=1", "-5.75E-08"),
    ("1", "", "q=5", "-3.14E-07"),
    ("1", "", "q=10", "5.01E-10"),
    ("2", "", "theta=1", "-3.14E-07"),
    ("2", "", "theta=0.75", "1.22E-09"),
    ("2", "", "theta=0.5", "4.09E-10"),
    ("2", "", "theta=0.25", "8.89E-10"),
    ("3", "", "k=inf", "-3.14E-07"),
    ("3", "", "k=20", "-2.87E-07"),
    ("3", "", "k=10", "-3.63E-07"),
    ("3", "", "k=5", "-3.83E-07"),
    ("4A", "", "A=0 B=-0.5", "1.37E-07"),
    ("4A", "", "A=0 B=-1", "4.02E-07"),
    ("4A", "", "A=-1 B=0", "-7.55E-08"),
    ("4A", "", "A=-2 B=0", "4.31E-07"),
    ("4B", "g2", "A=0 B=0.5", "6.90E-07"),
    ("4B", "g2", "A=0 B=1", "3.34E-06"),
    ("4B", "g2", "A=1 B=0", "5.05E-12"),
    ("4B", "g2", "A=2 B=0", "2.03E-11"),
    ("5", "g1", "theta=0.75 k=20", "5.86E-07"),
    ("5", "g1", "theta=0.5 k=20", "-2.36E-12"),
    ("5", "g1", "theta=0.75 k=10", "5.36E-09"),
    ("5", "g1", "theta=0.5 k=10", "1.87E-12"),
    ("5", "g2", "theta=0.75 k=20", "1.12E-09"),
    ("5", "g2", "theta=0.5 k=20", "2.10E-09"),
    ("5", "g2", "theta=0.75 k=10", "9.48E-10"),
    ("5", "g2", "theta=0.5 k=10", "2.58E-09"),
];

fn thesis_dq(case: &str, profile: &str, label: &str) -> Option<&'static str> {
    TABLE_6_1
        .iter()
        .find(|(c, p, l, _)| *c == case && (p.is_empty() || *p == profile) && *l == label)
        .map(|t| t.3)
}

/// The methods compared in Figs. 6.2-6.13.
const METHODS: [ReconMethod; 2] = [ReconMethod::Accurate, ReconMethod::Thesis];

/// One reconstruction: the points (or the error) and the wall time.
struct Recon {
    points: Result<Vec<ReconPoint>, String>,
    seconds: f64,
}

/// Runs chapter 6.
pub fn run(out: &OutputDir, report: &mut Report, ctx: &mut Ctx) -> Result<(), Failure> {
    common::step(6, 1, 3, "the chapter-5 sweeps (shared with chapter 5)");
    let runs = ctx.sweeps().to_vec();
    common::step(6, 2, 3, "Table 6.1");
    table_6_1(out, report, &runs);
    common::step(6, 3, 3, "reconstructions (both methods, every case)");
    // Reconstruct every case with both methods (in parallel).
    let jobs: Vec<(usize, ReconMethod)> = (0..runs.len())
        .flat_map(|i| METHODS.iter().map(move |&m| (i, m)))
        .collect();
    let t0 = Instant::now();
    let res = par_map(&jobs, |&(i, method)| {
        let t = Instant::now();
        let points = match &runs[i].result {
            Ok(s) => {
                let rows = from_sweep(s);
                let settings = ReconSettings {
                    method,
                    consistency_tol: None,
                    ..ReconSettings::default()
                };
                reconstruct(&runs[i].case.whisker, &rows, None, &settings)
                    .map(|r| r.points)
                    .map_err(|e| e.to_string())
            }
            Err(e) => Err(format!("no sweep: {e}")),
        };
        Recon {
            points,
            seconds: t.elapsed().as_secs_f64(),
        }
    });
    eprintln!(
        "xtask: {} reconstructions in {:.1} s",
        jobs.len(),
        t0.elapsed().as_secs_f64()
    );
    let mut recons: Vec<Vec<Recon>> = runs.iter().map(|_| Vec::new()).collect();
    for (&(i, _), r) in jobs.iter().zip(res) {
        recons[i].push(r.unwrap_or(Recon {
            points: Err("the reconstruction panicked".to_string()),
            seconds: f64::NAN,
        }));
    }
    for (fig, case, profile) in FIGURES {
        let idx: Vec<usize> = (0..runs.len())
            .filter(|&i| runs[i].case.case == case && runs[i].case.profile_name == profile)
            .collect();
        error_figure(out, report, fig, &runs, &recons, &idx);
    }
    Ok(())
}

fn table_6_1(out: &OutputDir, report: &mut Report, runs: &[SweepRun]) {
    let entry = report.entry("Table 6.1", caption("Table 6.1"));
    let mut rows = Vec::new();
    let mut w = CsvWriter::new(&[
        "case",
        "profile",
        "label",
        "q",
        "q_identified",
        "dq",
        "dq_thesis",
    ]);
    let mut max_dq: f64 = 0.0;
    for r in runs {
        let thesis = thesis_dq(r.case.case, r.case.profile_name, &r.case.label);
        let (qi, dq) = match &r.result {
            Ok(s) => match identify(
                &r.case.whisker,
                &from_sweep(s),
                KnownFlow::default(),
                &ReconSettings::default(),
            ) {
                Ok(id) => (id.q, r.case.q - id.q),
                Err(e) => {
                    entry.fail(format!("identify {}: {e}", r.name()));
                    (f64::NAN, f64::NAN)
                }
            },
            Err(e) => {
                entry.fail(format!("sweep {}: {e}", r.name()));
                (f64::NAN, f64::NAN)
            }
        };
        if dq.is_finite() {
            max_dq = max_dq.max(dq.abs());
        }
        let _ = w.push_row(&[
            Cell::Text(r.case.case),
            Cell::Text(r.case.profile_name),
            Cell::Text(&r.case.label),
            Cell::Num(r.case.q),
            Cell::Num(qi),
            Cell::Num(dq),
            Cell::Text(thesis.unwrap_or("")),
        ]);
        rows.push(vec![
            r.case.case.to_string(),
            r.case.profile_name.to_string(),
            r.case.label.clone(),
            format!("{}", r.case.q),
            format!("{qi:.12}"),
            sci(dq),
            thesis.unwrap_or("-").to_string(),
        ]);
    }
    entry.block(md_table(
        &[
            "case",
            "contour",
            "parameters",
            "applied q",
            "identified q",
            "Δq (ours)",
            "Δq (thesis)",
        ],
        &rows,
    ));
    entry.block(
        "The thesis's Table 6.1 lists one Δq per case and parameter for cases 1-4A without \
         naming the contour; its value is shown next to both g1 and g2. Its case-1 q = 0 \
         value (2.34E+07) is printed as such in the thesis.",
    );
    entry.number(
        "largest |Δq| (ours)",
        sci(max_dq),
        Some("3.34E-06 (excl. 2.34E+07)"),
    );
    let r = common::csv(out, entry, "table6_1.csv", &w);
    note_err(entry, "table6_1.csv", r);
}

/// Figs. 6.2-6.13: the contour error of both methods along the reconstructed contour, one
/// panel per sweep `idx` of `runs`, with the CSV of every point and a table of the largest
/// errors.
fn error_figure(
    out: &OutputDir,
    report: &mut Report,
    fig: &str,
    runs: &[SweepRun],
    recons: &[Vec<Recon>],
    idx: &[usize],
) {
    let entry = report.entry(fig, caption(fig));
    if idx.is_empty() {
        entry.fail("no sweep cases");
        return;
    }
    let mut charts = Vec::new();
    let mut w = CsvWriter::new(&[
        "case", "method", "row", "x0", "x_rec", "y_rec", "g_x_rec", "e", "phase", "residual",
    ]);
    let mut rows = Vec::new();
    for &i in idx {
        let r = &runs[i];
        let mut chart = Chart::new(
            format!(
                "{} ({})",
                pretty(&r.case.label),
                profile_symbol(r.case.profile_name)
            ),
            "reconstructed x_{rec} [–]",
            "e = |y_{rec} − g(x_{rec})| [–]",
        )
        .log(false, true);
        let mut row = vec![r.case.label.clone()];
        for (m, method) in METHODS.iter().enumerate() {
            let rec = &recons[i][m];
            match &rec.points {
                Ok(points) => {
                    let (series, cell) = method_errors(&mut w, r, *method, points, rec.seconds);
                    chart.series.push(series);
                    row.push(cell);
                }
                Err(e) => {
                    entry.fail(format!(
                        "{} reconstruction of {}: {e}",
                        method.name(),
                        r.name()
                    ));
                    row.push(format!("failed ({:.2} s)", rec.seconds));
                }
            }
        }
        rows.push(row);
        charts.push(chart);
    }
    entry.block(md_table(
        &[
            "case",
            "max e, accurate (points, time)",
            "max e, thesis method (points, time)",
        ],
        &rows,
    ));
    let stem = common::fig_stem(fig);
    // Two rows at most on the page (three columns for five or six panels); a lone panel
    // is drawn one column (85 mm) wide.
    let cols = match charts.len() {
        1 => 1,
        2 | 4 => 2,
        _ => 3,
    };
    let r = if charts.len() == 1 {
        common::svg_column(out, entry, &format!("{stem}.svg"), &charts[0])
    } else {
        svg_keyed(out, entry, &format!("{stem}.svg"), &charts, cols, 0.75, "")
    }
    .and_then(|()| common::csv(out, entry, &format!("{stem}.csv"), &w));
    note_err(entry, &stem, r);
    entry.number(
        "thesis's reported error range",
        "-",
        Some("overall between 1e-4 and 1e-6 (§6.4)"),
    );
}

/// The contour errors of one reconstruction of sweep `r` by `method` (taking `seconds`):
/// writes its points to `w` and returns its series and its table cell (largest error,
/// points, time).
fn method_errors(
    w: &mut CsvWriter,
    r: &SweepRun,
    method: ReconMethod,
    points: &[ReconPoint],
    seconds: f64,
) -> (Series, String) {
    let e = contour_error(points, &r.case.profile);
    let pts: Vec<(f64, f64)> = points
        .iter()
        .zip(&e)
        .map(|(p, &e)| (p.x, e.max(1e-17)))
        .collect();
    for (p, &ev) in points.iter().zip(&e) {
        let _ = w.push_row(&[
            Cell::Text(&r.case.label),
            Cell::Text(method.name()),
            Cell::Num(p.row as f64),
            Cell::Num(p.x0),
            Cell::Num(p.x),
            Cell::Num(p.y),
            Cell::Num(r.case.profile.y(p.x)),
            Cell::Num(ev),
            Cell::Text(p.phase.label()),
            Cell::Num(p.residual),
        ]);
    }
    let max_e = e.iter().copied().fold(0.0, f64::max);
    let nan = e.iter().filter(|v| !v.is_finite()).count();
    let cell = format!(
        "{}{} ({} pts, {:.2} s)",
        sci(max_e),
        if nan > 0 {
            format!(", {nan} non-finite")
        } else {
            String::new()
        },
        points.len(),
        seconds
    );
    // The accurate errors are round-off, independent from point to point: markers. The
    // thesis method's are a smooth function of x: a line.
    let series = match method {
        ReconMethod::Accurate => Series::new("accurate", pts, Style::Points)
            .color(0)
            .marker(Marker::Circle),
        _ => Series::new("thesis method", pts, Style::Line).color(1),
    };
    (series, cell)
}

/// The contour's symbol with its index as a subscript: `g1` becomes `g_1`.
fn profile_symbol(name: &str) -> String {
    match name.strip_prefix('g') {
        Some(i) if i.chars().count() == 1 => format!("g_{i}"),
        _ => name.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_table_matches_the_case_labels() {
        let cases = contact_sim::cases::chapter5();
        // Every thesis value belongs to a case of `cases::chapter5()`.
        for (case, profile, label, _) in TABLE_6_1 {
            assert!(
                cases.iter().any(|c| c.case == case
                    && (profile.is_empty() || c.profile_name == profile)
                    && c.label == label),
                "{case} {profile} {label}"
            );
        }
        assert_eq!(thesis_dq("4B", "g2", "A=0 B=1"), Some("3.34E-06"));
        assert_eq!(thesis_dq("3", "g2", "k=inf"), Some("-3.14E-07"));
        assert_eq!(thesis_dq("5", "g2", "theta=0.5 k=20"), Some("2.10E-09"));
        assert_eq!(thesis_dq("4A", "g1", "A=0 B=0"), None);
    }
}
