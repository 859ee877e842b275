//! `cargo xtask`: project automation (matklad's xtask pattern).
//!
//! ```text
//! cargo xtask reproduce chapter4|chapter5|chapter6|all [--out DIR]
//! ```
//!
//! `reproduce` regenerates the thesis figures and key numbers of a chapter: the files of
//! chapter N go to `DIR/chapterN/` (default `DIR` = `target/reproduce` of the workspace),
//! staged so that a failing chapter leaves nothing half-written, and `DIR/report.md` lists
//! every figure with its thesis caption, its files and its key numbers.

mod captions;
mod chapter4;
mod chapter5;
mod chapter6;
mod common;

use std::fmt;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use vibrissa_io::atomic::{write_atomic, OutputDir};
use vibrissa_io::IoError as CliError;

use common::Ctx;

const USAGE: &str = "usage: cargo xtask reproduce chapter4|chapter5|chapter6|all [--out DIR]";

/// The chapters that can be reproduced, in order.
const CHAPTERS: [Chapter; 3] = [Chapter::Four, Chapter::Five, Chapter::Six];

/// A thesis chapter with reproducible figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Chapter {
    /// Chapter 4: the elastica and its numerical methods.
    Four,
    /// Chapter 5: contact with an obstacle, sweeps and stability.
    Five,
    /// Chapter 6: contour reconstruction.
    Six,
}

impl Chapter {
    fn number(self) -> u32 {
        match self {
            Chapter::Four => 4,
            Chapter::Five => 5,
            Chapter::Six => 6,
        }
    }

    fn dir_name(self) -> String {
        format!("chapter{}", self.number())
    }
}

/// What went wrong in the xtask.
#[derive(Debug)]
enum Failure {
    /// Bad command line (exit code 2).
    Usage(String),
    /// A task failed (exit code 1).
    Run(String),
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Usage(m) => write!(f, "{m}\n{USAGE}"),
            Failure::Run(m) => f.write_str(m),
        }
    }
}

impl From<CliError> for Failure {
    fn from(e: CliError) -> Self {
        Failure::Run(e.to_string())
    }
}

impl From<vibrissa_plot::PlotError> for Failure {
    fn from(e: vibrissa_plot::PlotError) -> Self {
        Failure::Run(e.to_string())
    }
}

/// The parsed command line.
#[derive(Debug, PartialEq)]
enum Task {
    /// `reproduce`: the chapters and the output directory.
    Reproduce {
        chapters: Vec<Chapter>,
        out: PathBuf,
    },
    /// `--help`.
    Help,
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

fn parse_args(args: &[String]) -> Result<Task, Failure> {
    let mut it = args.iter();
    let task = match it.next().map(String::as_str) {
        None | Some("-h" | "--help" | "help") => return Ok(Task::Help),
        Some("reproduce") => "reproduce",
        Some(other) => return Err(Failure::Usage(format!("unknown task `{other}`"))),
    };
    debug_assert_eq!(task, "reproduce");
    let mut chapters = None;
    let mut out = None;
    while let Some(a) = it.next() {
        match a.as_str() {
            "-h" | "--help" => return Ok(Task::Help),
            "--out" => {
                let dir = it
                    .next()
                    .ok_or_else(|| Failure::Usage("`--out` needs a directory".to_string()))?;
                out = Some(PathBuf::from(dir));
            }
            s if s.starts_with("--out=") => out = Some(PathBuf::from(&s["--out=".len()..])),
            s if s.starts_with('-') => {
                return Err(Failure::Usage(format!("unknown flag `{s}`")));
            }
            s => {
                if chapters.is_some() {
                    return Err(Failure::Usage(format!("unexpected argument `{s}`")));
                }
                chapters = Some(match s {
                    "chapter4" => vec![Chapter::Four],
                    "chapter5" => vec![Chapter::Five],
                    "chapter6" => vec![Chapter::Six],
                    "all" => CHAPTERS.to_vec(),
                    other => return Err(Failure::Usage(format!("unknown chapter `{other}`"))),
                });
            }
        }
    }
    let chapters = chapters.ok_or_else(|| Failure::Usage("which chapter?".to_string()))?;
    Ok(Task::Reproduce {
        chapters,
        out: out.unwrap_or_else(|| workspace_root().join("target").join("reproduce")),
    })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = parse_args(&args).and_then(|task| match task {
        Task::Help => {
            println!("{USAGE}");
            Ok(())
        }
        Task::Reproduce { chapters, out } => reproduce(&chapters, &out),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::from(match e {
                Failure::Usage(_) => 2,
                Failure::Run(_) => 1,
            })
        }
    }
}

/// Runs the chapters (all of them, even after a failure), writes `out/report.md` and fails
/// if any chapter failed.
fn reproduce(chapters: &[Chapter], out: &Path) -> Result<(), Failure> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|e| CliError::io(out, e))?;
    let mut report = Report::new("vibrissa: reproduced thesis figures");
    let mut failed = Vec::new();
    let mut ctx = Ctx::default();
    let mut times = Vec::new();
    for &ch in chapters {
        let t0 = Instant::now();
        eprintln!("xtask: chapter {} ...", ch.number());
        let final_dir = out.join(ch.dir_name());
        let staged = OutputDir::create(&final_dir)?;
        let staging_root = staged.path_for("");
        let mut entries = Report::new("");
        let run = match ch {
            Chapter::Four => chapter4::run(&staged, &mut entries, &mut ctx),
            Chapter::Five => chapter5::run(&staged, &mut entries, &mut ctx),
            Chapter::Six => chapter6::run(&staged, &mut entries, &mut ctx),
        }
        .and_then(|()| staged.commit().map_err(Failure::from));
        times.push((ch.number(), t0.elapsed().as_secs_f64()));
        match run {
            Ok(_) => {
                report.failures.append(&mut entries.failures);
                // Files were recorded at their staging paths; point them at the final ones.
                for mut e in entries.entries {
                    e.files = e
                        .files
                        .iter()
                        .map(|f| match f.strip_prefix(&staging_root) {
                            Ok(rel) => final_dir.join(rel),
                            Err(_) => f.clone(),
                        })
                        .collect();
                    report.entries.push(e);
                }
                eprintln!("xtask: chapter {} done", ch.number());
            }
            Err(e) => {
                eprintln!("xtask: {e}");
                report.failure(format!("chapter {}", ch.number()), e.to_string());
                failed.push(ch.number());
            }
        }
    }
    let total = start.elapsed().as_secs_f64();
    report.preamble.push(format!(
        "Total run time: **{total:.1} s** ({}; {} thread(s); `cargo xtask reproduce`).",
        times
            .iter()
            .map(|(n, t)| format!("chapter {n}: {t:.1} s"))
            .collect::<Vec<_>>()
            .join(", "),
        common::threads()
    ));
    report.preamble.push(format!(
        "Figures and tables reproduced: {}; failed parts: {}.",
        report.entries.len(),
        report.all_failures().len()
    ));
    report.write(&out.join("report.md"))?;
    eprintln!("xtask: total {total:.1} s");
    eprintln!(
        "xtask: report written to {}",
        out.join("report.md").display()
    );
    if failed.is_empty() {
        Ok(())
    } else {
        let list: Vec<String> = failed.iter().map(u32::to_string).collect();
        Err(Failure::Run(format!(
            "chapter(s) {} failed, see {}",
            list.join(", "),
            out.join("report.md").display()
        )))
    }
}

/// One reproduced figure or table of the thesis.
#[derive(Debug, Clone, PartialEq, Default)]
struct Entry {
    /// The thesis's figure or table number (`"4.3"`, `"Table 4.2"`).
    figure: String,
    /// The thesis caption, abridged.
    caption: String,
    /// The files written for it.
    files: Vec<PathBuf>,
    /// Key numbers: quantity, this run's value, the thesis's value (if it states one).
    numbers: Vec<(String, String, Option<String>)>,
    /// Further markdown blocks (tables, notes), rendered after the numbers.
    blocks: Vec<String>,
    /// What failed for this figure (the other figures continue).
    failures: Vec<String>,
}

impl Entry {
    /// Records a written file.
    fn file(&mut self, path: impl Into<PathBuf>) -> &mut Self {
        self.files.push(path.into());
        self
    }

    /// Records a key number, with the thesis's value for comparison if there is one.
    fn number(
        &mut self,
        quantity: impl Into<String>,
        value: impl Into<String>,
        thesis: Option<&str>,
    ) -> &mut Self {
        self.numbers
            .push((quantity.into(), value.into(), thesis.map(str::to_string)));
        self
    }

    /// Adds a markdown block (a table or a note).
    fn block(&mut self, markdown: impl Into<String>) -> &mut Self {
        self.blocks.push(markdown.into());
        self
    }

    /// Records a failed part of this figure.
    fn fail(&mut self, message: impl Into<String>) -> &mut Self {
        self.failures.push(message.into());
        self
    }
}

/// The reproduction report, rendered as markdown.
#[derive(Debug, Clone, PartialEq, Default)]
struct Report {
    title: String,
    /// Paragraphs under the title (run time, summary).
    preamble: Vec<String>,
    entries: Vec<Entry>,
    /// Failed parts: (what, message).
    failures: Vec<(String, String)>,
}

impl Report {
    fn new(title: impl Into<String>) -> Self {
        Report {
            title: title.into(),
            ..Report::default()
        }
    }

    /// Starts the entry of a figure and returns it for adding files and numbers.
    fn entry(&mut self, figure: impl Into<String>, caption: impl Into<String>) -> &mut Entry {
        self.entries.push(Entry {
            figure: figure.into(),
            caption: caption.into(),
            ..Entry::default()
        });
        let last = self.entries.len() - 1;
        &mut self.entries[last]
    }

    /// The failed parts: those of the report, then those of each entry.
    fn all_failures(&self) -> Vec<(String, String)> {
        let mut all = self.failures.clone();
        for e in &self.entries {
            for f in &e.failures {
                all.push((e.figure.clone(), f.clone()));
            }
        }
        all
    }

    /// Records a failed part.
    fn failure(&mut self, what: impl Into<String>, message: impl Into<String>) {
        self.failures.push((what.into(), message.into()));
    }

    /// The markdown text; file paths are shown relative to `base` where possible.
    fn to_markdown(&self, base: &Path) -> String {
        let mut md = format!("# {}\n\n", self.title);
        for p in &self.preamble {
            md.push_str(p);
            md.push_str("\n\n");
        }
        for e in &self.entries {
            let heading = if e.figure.starts_with(|c: char| c.is_ascii_digit()) {
                format!("Figure {}", e.figure)
            } else {
                e.figure.clone()
            };
            md.push_str(&format!("## {heading}\n\n{}\n\n", e.caption));
            if !e.files.is_empty() {
                md.push_str("Files:\n\n");
                for f in &e.files {
                    let shown = f.strip_prefix(base).unwrap_or(f).display().to_string();
                    md.push_str(&format!("- [{shown}]({shown})\n"));
                }
                md.push('\n');
            }
            if !e.numbers.is_empty() {
                md.push_str("| quantity | this run | thesis |\n|---|---|---|\n");
                for (q, v, t) in &e.numbers {
                    md.push_str(&format!(
                        "| {} | {} | {} |\n",
                        cell(q),
                        cell(v),
                        t.as_deref().map_or_else(|| "-".to_string(), cell)
                    ));
                }
                md.push('\n');
            }
            for b in &e.blocks {
                md.push_str(b.trim_end());
                md.push_str("\n\n");
            }
            for f in &e.failures {
                md.push_str(&format!("**Failed:** {}\n\n", cell(f)));
            }
        }
        let all = self.all_failures();
        if !all.is_empty() {
            md.push_str("## Failures\n\n");
            for (what, msg) in &all {
                md.push_str(&format!("- **{what}**: {msg}\n"));
            }
            md.push('\n');
        }
        md
    }

    /// Writes the markdown to `path` atomically.
    fn write(&self, path: &Path) -> Result<(), vibrissa_io::IoError> {
        let base = path.parent().unwrap_or(Path::new(""));
        write_atomic(path, self.to_markdown(base).as_bytes())
    }
}

/// Escapes a markdown table cell.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn parses_the_command_line() {
        assert_eq!(
            parse_args(&args("reproduce all --out /tmp/x")).unwrap(),
            Task::Reproduce {
                chapters: CHAPTERS.to_vec(),
                out: PathBuf::from("/tmp/x")
            }
        );
        match parse_args(&args("reproduce chapter5")).unwrap() {
            Task::Reproduce { chapters, out } => {
                assert_eq!(chapters, vec![Chapter::Five]);
                assert!(out.ends_with("target/reproduce"));
            }
            other => panic!("{other:?}"),
        }
        let e = parse_args(&args("reproduce chapter7")).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("unknown chapter `chapter7`\n{USAGE}")
        );
        assert!(matches!(
            parse_args(&args("reproduce")),
            Err(Failure::Usage(_))
        ));
        assert!(matches!(
            parse_args(&args("reproduce all --out")),
            Err(Failure::Usage(_))
        ));
        assert_eq!(parse_args(&args("")).unwrap(), Task::Help);
    }

    #[test]
    fn report_renders_markdown() {
        let mut r = Report::new("Report");
        r.entry("4.3", "Elastica of a tapered whisker")
            .file("/out/chapter4/fig4_3.svg")
            .number("tip x", "0.8", Some("0.80"))
            .number("a|b", "1", None);
        r.failure("chapter 5", "chapter 5: not implemented yet");
        let md = r.to_markdown(Path::new("/out"));
        assert_eq!(
            md,
            "# Report\n\n## Figure 4.3\n\nElastica of a tapered whisker\n\nFiles:\n\n\
             - [chapter4/fig4_3.svg](chapter4/fig4_3.svg)\n\n\
             | quantity | this run | thesis |\n|---|---|---|\n| tip x | 0.8 | 0.80 |\n\
             | a\\|b | 1 | - |\n\n## Failures\n\n\
             - **chapter 5**: chapter 5: not implemented yet\n\n"
        );
    }

    #[test]
    fn report_renders_preamble_blocks_and_failures() {
        let mut r = Report::new("R");
        r.preamble.push("Total run time: 1.0 s".to_string());
        r.entry("Table 4.2", "Tip coordinates")
            .block("| a |\n|---|\n| 1 |")
            .fail("solve failed");
        let md = r.to_markdown(Path::new("/out"));
        assert_eq!(
            md,
            "# R\n\nTotal run time: 1.0 s\n\n## Table 4.2\n\nTip coordinates\n\n\
             | a |\n|---|\n| 1 |\n\n**Failed:** solve failed\n\n\
             ## Failures\n\n- **Table 4.2**: solve failed\n\n"
        );
    }
}
