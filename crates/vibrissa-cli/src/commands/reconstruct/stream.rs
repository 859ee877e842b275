//! `vibrissa reconstruct --stream`: a sensor's log on standard input, one row per line,
//! each contact point on standard output as soon as it is known. The rows are read by the
//! CSV reader of the files ([`LineReader`]) and converted from the scene's units by the
//! factors of a file's columns ([`recon_io::input_factors`]); each point is a row of
//! `reconstruction.csv` ([`recon_io::recon_cells`]).

use std::io::BufRead;
use std::path::{Path, PathBuf};

use profile_recon::{
    FrictionalPoint, FrictionalStreamer, ObservableRow, ReconError, ReconPoint, RowPose, Streamer,
};
use vibrissa_io::recon_friction::MuRequest;

use super::options::{recon_model, ReconOptions};
use super::REQUIRED_COLUMNS;
use crate::cli::ReconstructArgs;
use crate::commands::recon_io;
use crate::csvio::{Cell, HeaderProblemKind, LineProblem, LineReader};
use crate::error::CliError;
use crate::printer::Printer;
use crate::resolve::LoadedScene;
use crate::units::UnitSystem;

/// The name of standard input in messages.
const STDIN: &str = "<stdin>";

/// Runs the stream: rows from standard input (a header line naming the columns first),
/// each contact point to standard output as soon as it is known, in the scene's units (a
/// physical scene's log in mm, N, N mm); rows are checked as in a file.
pub fn run_stream(args: &ReconstructArgs) -> Result<(), CliError> {
    // parse and resolve: the one positional argument is the scene (a sweep folder gives
    // its scene.ron)
    if let Some(out) = &args.out {
        return Err(CliError::invalid_argument(
            "--out",
            out.display().to_string(),
            "the stream writes each contact point to standard output; leave --out out \
             with --stream (or reconstruct the log as a file into --out)",
        ));
    }
    let opts = ReconOptions::parse_stream(&args.into())?;
    let mu = args.mu.as_deref().map(MuRequest::parse).transpose()?;
    let scene = stream_scene(args.scene.as_deref().or(args.observables.as_deref()))?;
    let file = LoadedScene::load_opt(scene.as_deref())?;
    let r = recon_model(args, file)?;
    let units = r.units();
    let factor = recon_io::input_factors(&Default::default(), &units, Path::new(STDIN))?;
    let (flow, settings) = (opts.known_flow(&args.into(), &r), opts.settings());
    let mut stream = match mu {
        None => Stream::Plain(
            Streamer::new(&r.scene.whisker, flow, &settings)
                .map_err(|e| stdin_err(1, e.to_string()))?,
        ),
        Some(m) => Stream::Frictional(
            FrictionalStreamer::new(&r.scene.whisker, flow, &settings, m.given())
                .map_err(|e| stdin_err(1, e.to_string()))?,
        ),
    };
    // compute and write, row by row
    let mut out = StreamOut::new(&units, mu.is_some())?;
    let mut reader: Option<LineReader> = None;
    // the pose columns y0, gamma where the header has them (a log of any base motion)
    let mut pose_readers: [Option<LineReader>; 2] = [None, None];
    // line numbers of the data rows (the library's 0-based row index -> input line)
    let mut lines: Vec<usize> = Vec::new();
    for (k, line) in std::io::stdin().lock().lines().enumerate() {
        let n = k + 1;
        let line = line.map_err(|e| stdin_err(n, format!("cannot read: {e}")))?;
        let line = line.trim_end_matches('\r').trim_start_matches('\u{feff}');
        if LineReader::skips(line) {
            continue;
        }
        let Some(rows) = &reader else {
            reader = Some(
                LineReader::header(line, &REQUIRED_COLUMNS).map_err(|p| line_err(n, line, p))?,
            );
            pose_readers = ["y0", "gamma"].map(|c| LineReader::header(line, &[c]).ok());
            continue;
        };
        let v = rows.values(line).map_err(|p| line_err(n, line, p))?;
        lines.push(n);
        let row = ObservableRow {
            x0: v[0] * factor[0],
            ax: v[1] * factor[1],
            ay: v[2] * factor[2],
            ma: v[3] * factor[3],
            phi0: v[4] * factor[4],
        };
        let mut pose = [0.0; 2];
        for (k, r) in pose_readers.iter().enumerate() {
            if let Some(r) = r {
                let v = r.values(line).map_err(|p| pose_err(n, p))?;
                // y0 a length as x0, gamma an angle as phi0
                pose[k] = v[0] * factor[if k == 0 { 0 } else { 4 }];
            }
        }
        let pose = RowPose::new(pose[0], pose[1]);
        match &mut stream {
            Stream::Plain(s) => {
                out.write(&s.push_posed(row, pose).map_err(|e| at_row(&lines, e))?)?;
            }
            // friction is swept along translations only (contact-sim refuses the others)
            Stream::Frictional(_) if pose.y0 != 0.0 || pose.gamma != 0.0 => {
                return Err(stdin_err(
                    n,
                    "--mu with a log of a turned or lifted base (y0, gamma) is not implemented"
                        .to_string(),
                ));
            }
            Stream::Frictional(s) => {
                out.write_ft(&s.push(row).map_err(|e| at_row(&lines, e))?)?;
            }
        }
    }
    if reader.is_none() {
        return Err(stdin_err(
            1,
            format!(
                "standard input is empty: --stream reads an observables log, a header line \
                 naming {} and then one row per line",
                REQUIRED_COLUMNS.join(", ")
            ),
        ));
    }
    match stream {
        Stream::Plain(s) => out.write(&s.finish().map_err(|e| at_row(&lines, e))?),
        Stream::Frictional(s) => {
            let end = s.finish().map_err(|e| at_row(&lines, e))?;
            out.write_ft(&end.held)?;
            // standard output is the CSV: mu (the batch's, over every row) on standard error
            eprintln!("{}", end_line(&end));
            Ok(())
        }
    }
}

/// The stream's reconstruction: frictionless (without `--mu`, today's) or frictional (one
/// value per run: the sizes do not matter).
#[allow(clippy::large_enum_variant)]
enum Stream {
    Plain(Streamer),
    Frictional(FrictionalStreamer),
}

/// The last line of a frictional stream (on standard error): mu identified over every row
/// with its standard error, or the given mu's violations.
fn end_line(end: &profile_recon::FrictionalStreamEnd) -> String {
    match end.mu {
        Some(m) => format!(
            "mu = {:.6} +- {:.2e} (identified from {} sliding rows of {} contact rows)",
            m.value,
            m.stderr,
            m.rows,
            end.points.len()
        ),
        None if end.violations > 0 => format!(
            "warning: {} rows break the given mu (their |ft| / fn beyond the cone, or sliding \
             rows off its edge)",
            end.violations
        ),
        None => format!(
            "mu not identified ({} contact rows, none sliding with a contact force, or mu given)",
            end.points.len()
        ),
    }
}

/// An error at line `line` of standard input.
fn stdin_err(line: usize, reason: String) -> CliError {
    CliError::Io(vibrissa_io::IoError::Csv {
        path: PathBuf::from(STDIN),
        line,
        column: None,
        reason,
    })
}

/// The message of a problem of the reader at line `n` (`line`: its text).
fn line_err(n: usize, line: &str, p: LineProblem) -> CliError {
    let columns = REQUIRED_COLUMNS.join(", ");
    let reason = match p {
        LineProblem::Header(want, HeaderProblemKind::Missing) => format!(
            "missing required column {want} in the header (found `{line}`; a log starts with \
             a header naming {columns})"
        ),
        LineProblem::Header(i, HeaderProblemKind::Empty) => format!("header field {i} is empty"),
        LineProblem::Header(h, HeaderProblemKind::Twice) => {
            format!("column `{h}`: the column appears twice in the header")
        }
        LineProblem::Fields { found, expected } => {
            format!("{found} fields where the header has {expected} (the columns {columns})")
        }
        LineProblem::Cell(j, value, problem) => {
            format!(
                "column `{}`: {}",
                REQUIRED_COLUMNS[j],
                problem.reason(&value)
            )
        }
        LineProblem::Csv(reason) => reason,
    };
    stdin_err(n, reason)
}

/// A library error at the input line of its row.
/// A bad cell of a pose column (`y0`, `gamma`).
fn pose_err(n: usize, p: LineProblem) -> CliError {
    let reason = match p {
        LineProblem::Cell(_, value, problem) => {
            format!("pose column (y0 or gamma): {}", problem.reason(&value))
        }
        // (the required columns' reader has seen the line's fields first)
        other => return line_err(n, "", other),
    };
    stdin_err(n, reason)
}

fn at_row(lines: &[usize], e: ReconError) -> CliError {
    let row = match &e {
        ReconError::NonFinite { row, .. } | ReconError::InconsistentRow { row, .. } => Some(*row),
        _ => None,
    };
    let line = row.and_then(|r| lines.get(r).copied()).unwrap_or(1);
    stdin_err(line, e.to_string())
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

/// A row of cells as the stream prints it: numbers in Rust's plain notation (`{}`, as the
/// stream always printed them; the file writes the shortest round-trip form), texts as
/// they are (phase labels, never quoted).
fn plain_line(cells: &[Cell<'_>]) -> String {
    cells
        .iter()
        .map(|c| match c {
            Cell::Num(v) => v.to_string(),
            Cell::Text(s) => (*s).to_string(),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// The stream's standard output: the header of `reconstruction.csv` (without `error`), then
/// each point as soon as it is known, flushed, in the scene's units.
/// A write that fails (the reader closed the pipe) ends the stream with
/// [`CliError::Stdout`].
struct StreamOut<'u> {
    out: Printer,
    units: &'u UnitSystem,
}

impl<'u> StreamOut<'u> {
    /// The header; with `ft`, the column `ft` last (a frictional stream, as the file).
    fn new(units: &'u UnitSystem, ft: bool) -> Result<Self, CliError> {
        let mut s = StreamOut {
            out: Printer::stdout(),
            units,
        };
        let mut header = recon_io::reconstruction_header(false);
        if ft {
            header.push("ft");
        }
        s.line(&header.join(","))?;
        Ok(s)
    }

    /// Frictional points: the row of the file with `ft` (a force) last.
    fn write_ft(&mut self, points: &[FrictionalPoint]) -> Result<(), CliError> {
        let fs = self.units.scale(crate::units::Quantity::Force);
        for p in points {
            let mut cells = recon_io::recon_cells(&p.to_recon_point(), self.units, &[], None);
            cells.push(Cell::Num(p.ft * fs));
            let text = plain_line(&cells);
            self.line(&text)?;
        }
        Ok(())
    }

    fn line(&mut self, text: &str) -> Result<(), CliError> {
        self.out.line(text)
    }

    fn write(&mut self, points: &[ReconPoint]) -> Result<(), CliError> {
        for p in points {
            let text = plain_line(&recon_io::recon_cells(p, self.units, &[], None));
            self.line(&text)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stream_lines_are_plain_and_problems_name_the_line() {
        let cells = [Cell::Num(1e-12), Cell::Text("A"), Cell::Num(3.0)];
        assert_eq!(plain_line(&cells), "0.000000000001,A,3");
        let e = line_err(
            2,
            "1,2,3",
            LineProblem::Fields {
                found: 3,
                expected: 5,
            },
        );
        assert!(e.to_string().contains("<stdin>:2:"), "{e}");
        assert!(
            e.to_string().contains("3 fields where the header has 5"),
            "{e}"
        );
    }
}
