//! Helpers shared by the chapter reproductions: a small parallel map, file output recorded
//! in the report entries, number formatting and the chapter-5 sweeps shared with chapter 6.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use contact_sim::cases::SweepCase;
use contact_sim::{SweepResult, SweepSettings};
use vibrissa_io::atomic::{write_atomic, OutputDir};
use vibrissa_io::csvio::CsvWriter;
use vibrissa_plot::{Chart, FigureFormats, FigureSize, FigureStyle, Heading, Panel};

use crate::Entry;

/// How the reproduced figures are written: the thesis's figures span the page, so they are
/// drawn for both columns (175 mm) at print, as SVG and PNG.
pub const PAGE: FigureStyle = FigureStyle::new(FigureSize::Page, FigureFormats::All);

/// A one-panel figure one journal column (85 mm) wide among the page-wide ones.
pub const COLUMN: FigureStyle = PAGE.sized(FigureSize::Column);

/// Contact points per chapter-5 sweep (the 200).
pub const SWEEP_POINTS: usize = 200;

/// Worker threads of [`par_map`]: those of rayon's global pool (the available
/// parallelism, or `RAYON_NUM_THREADS`).
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// The step being computed, named in the progress lines of [`par_map`].
static STEP: Mutex<String> = Mutex::new(String::new());

/// Starts a step of a chapter: prints `xtask: chapter C [i/n] what ...` on stderr and names
/// the step in the progress counts of the parallel maps that follow.
pub fn step(chapter: u32, i: usize, n: usize, what: &str) {
    let label = format!("chapter {chapter} [{i}/{n}] {what}");
    eprintln!("xtask: {label} ...");
    if let Ok(mut g) = STEP.lock() {
        *g = label;
    }
}

/// Maps `f` over `items` on rayon's pool ([`threads`] threads), keeping the order. A panic
/// inside `f` is caught and gives `None` for that item (the others continue). A map that
/// runs longer than a second prints its count of items done on stderr, at most once a
/// second.
pub fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<Option<R>> {
    let n = items.len();
    let done = AtomicUsize::new(0);
    let started = Instant::now();
    let last_print = Mutex::new(started);
    let label = STEP.lock().map(|g| g.clone()).unwrap_or_default();
    let report = |k: usize| {
        if let Ok(mut last) = last_print.lock() {
            if last.elapsed().as_secs_f64() >= 1.0
                || (k == n && started.elapsed().as_secs_f64() >= 1.0)
            {
                *last = Instant::now();
                eprintln!(
                    "xtask:   {label}: {k}/{n} done ({:.0} s)",
                    started.elapsed().as_secs_f64()
                );
            }
        }
    };
    items
        .par_iter()
        // one item a job: the items are whole solves or sweeps, of very unequal cost
        .with_max_len(1)
        .map(|item| {
            let r = catch_unwind(AssertUnwindSafe(|| f(item))).ok();
            report(done.fetch_add(1, Ordering::Relaxed) + 1);
            r
        })
        .collect()
}

/// Writes a figure of chart panels to `name` (staged, [`PAGE`]) and records it in `entry`.
pub fn svg(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    cols: usize,
) -> Result<(), String> {
    let panels: Vec<Panel<'_>> = charts.iter().map(Panel::Chart).collect();
    svg_panels_in(PAGE, out, entry, name, &panels, cols)
}

/// Writes a figure of panels (charts or maps) to `name` ([`PAGE`]) and records it in
/// `entry`.
pub fn svg_panels(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    panels: &[Panel<'_>],
    cols: usize,
) -> Result<(), String> {
    svg_panels_in(PAGE, out, entry, name, panels, cols)
}

/// Writes a figure of panels to `name` as `style` says and records it in `entry`.
fn svg_panels_in(
    style: FigureStyle,
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    panels: &[Panel<'_>],
    cols: usize,
) -> Result<(), String> {
    let cols = cols.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let size = (560 * cols as u32, 420 * rows as u32);
    let path = staged_path(out, name)?;
    style
        .write_figure(panels, cols, &path, size)
        .map_err(|e| e.to_string())?;
    entry.file(path);
    Ok(())
}

/// Writes one chart as a figure one journal column (85 mm) wide instead of the page
/// ([`COLUMN`]), to `name`, and records it in `entry`.
pub fn svg_column(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    chart: &Chart,
) -> Result<(), String> {
    svg_panels_in(COLUMN, out, entry, name, &[Panel::Chart(chart)], 1)
}

/// The staged path of the output file `name`, its directory created.
fn staged_path(out: &OutputDir, name: &str) -> Result<PathBuf, String> {
    let path = out.path_for(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    Ok(path)
}

/// Writes a CSV table to `name` and records it in `entry`.
pub fn csv(out: &OutputDir, entry: &mut Entry, name: &str, w: &CsvWriter) -> Result<(), String> {
    text(out, entry, name, w.as_str())
}

/// Writes a text file to `name` and records it in `entry`.
pub fn text(out: &OutputDir, entry: &mut Entry, name: &str, body: &str) -> Result<(), String> {
    let path = staged_path(out, name)?;
    write_atomic(&path, body.as_bytes()).map_err(|e| e.to_string())?;
    entry.file(path);
    Ok(())
}

/// Records the error of a figure part in `entry` (the figure's other parts continue).
pub fn note_err(entry: &mut Entry, what: &str, r: Result<(), String>) {
    if let Err(e) = r {
        entry.fail(format!("{what}: {e}"));
    }
}

/// A number with `digits` significant digits, plain or scientific.
pub fn sig(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".to_string();
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = digits.saturating_sub(1))
    }
}

/// A number in scientific notation with 2 decimals (errors).
pub fn sci(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if v.is_finite() {
        format!("{v:.2e}")
    } else {
        format!("{v}")
    }
}

/// A markdown table from a header and rows.
pub fn md_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("| {} |\n|", header.join(" | "));
    for _ in header {
        s.push_str("---|");
    }
    s.push('\n');
    for r in rows {
        let cells: Vec<String> = r.iter().map(|c| c.replace('|', "\\|")).collect();
        s.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    s
}

/// The file stem of a thesis figure: `fig4_3` for `"4.3"`.
pub fn fig_stem(fig: &str) -> String {
    format!("fig{}", fig.replace('.', "_"))
}

/// A file-name-safe form of a label.
pub fn slug(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
            out.push(c);
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.trim_matches('_').to_string()
}

/// One chapter-5 sweep: the case, its result (or error) and its wall time.
#[derive(Debug, Clone)]
pub struct SweepRun {
    /// The case of `contact_sim::cases::chapter5()`.
    pub case: SweepCase,
    /// The sweep, or why it failed.
    pub result: Result<SweepResult, String>,
    /// Wall time of the sweep (s).
    pub seconds: f64,
}

impl SweepRun {
    /// `"1 g1 q=5"`.
    pub fn name(&self) -> String {
        format!(
            "{} {} {}",
            self.case.case, self.case.profile_name, self.case.label
        )
    }

    /// The file name of its observables CSV (relative to the chapter directory).
    pub fn csv_name(&self) -> String {
        format!(
            "sweeps/case{}_{}_{}.csv",
            self.case.case,
            self.case.profile_name,
            slug(&self.case.label)
        )
    }
}

/// State shared between the chapters of one run (chapter 6 reuses the sweeps of chapter 5).
#[derive(Debug, Default)]
pub struct Ctx {
    sweeps: Option<Vec<SweepRun>>,
}

impl Ctx {
    /// The sweeps of every chapter-5 case, computed on first use.
    pub fn sweeps(&mut self) -> &[SweepRun] {
        self.sweeps.get_or_insert_with(run_sweeps)
    }
}

fn run_sweeps() -> Vec<SweepRun> {
    let cases = contact_sim::cases::chapter5();
    let settings = SweepSettings {
        points: SWEEP_POINTS,
        ..SweepSettings::default()
    };
    let t0 = Instant::now();
    let runs = par_map(&cases, |c| {
        let t = Instant::now();
        let result = contact_sim::sweep(
            &c.whisker,
            beam_model::FluidLoad { q: c.q, alpha: 0.0 },
            &c.profile,
            &settings,
        )
        .map_err(|e| e.to_string());
        (result, t.elapsed().as_secs_f64())
    });
    eprintln!(
        "xtask: {} sweeps in {:.1} s",
        cases.len(),
        t0.elapsed().as_secs_f64()
    );
    cases
        .into_iter()
        .zip(runs)
        .map(|(case, r)| {
            let (result, seconds) =
                r.unwrap_or_else(|| (Err("the sweep panicked".to_string()), f64::NAN));
            SweepRun {
                case,
                result,
                seconds,
            }
        })
        .collect()
}

/// A case label for print: `theta=0.25 alpha=0deg` becomes `θ = 0.25, α = 0°`.
pub fn pretty(label: &str) -> String {
    label
        .split_whitespace()
        .map(|t| match t.split_once('=') {
            Some((name, value)) => {
                let name = match name {
                    "theta" => "θ",
                    "alpha" => "α",
                    "beta" => "β",
                    n => n,
                };
                let value = match value {
                    "inf" => "∞".to_string(),
                    v => match v.strip_suffix("deg") {
                        Some(d) => format!("{d}°"),
                        None => v.to_string(),
                    },
                };
                // No-break spaces: a title wraps between parameters, not inside one.
                format!("{name}\u{a0}=\u{a0}{}", value.replacen('-', "−", 1))
            }
            None => t.to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Writes charts as the panels of one figure, `cols` per row with plots `aspect` as high
/// as wide, under a heading `title` and one legend for all of them (the first chart's
/// entries), and records the file in `entry`.
pub fn svg_keyed(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    cols: usize,
    aspect: f64,
    title: &str,
) -> Result<(), String> {
    let cols = cols.clamp(1, charts.len().max(1));
    let rows = charts.len().div_ceil(cols).max(1);
    let layout = Layout {
        cols,
        size: (560 * cols as u32, (560.0 * aspect) as u32 * rows as u32),
        title,
        note: "",
    };
    svg_headed(PAGE, out, entry, name, charts, &layout)
}

/// How the panels of a figure under one heading are laid out.
#[derive(Debug, Clone, Copy)]
pub struct Layout<'a> {
    /// Panels per row.
    pub cols: usize,
    /// The figure's size in pixels (width, height).
    pub size: (u32, u32),
    /// The heading above the key.
    pub title: &'a str,
    /// A note under the key.
    pub note: &'a str,
}

/// Writes charts as the panels of one figure laid out by `layout`, under its heading and
/// one key for all panels (the first chart's legend), written as `style` says, and records
/// the file in `entry`.
pub fn svg_headed(
    style: FigureStyle,
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    layout: &Layout<'_>,
) -> Result<(), String> {
    let path = staged_path(out, name)?;
    let heading = Heading {
        title: layout.title.to_string(),
        note: layout.note.to_string(),
    };
    style
        .write_panels_with_heading(charts, layout.cols, &heading, &path, layout.size)
        .map_err(|e| e.to_string())?;
    entry.file(path);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn par_map_keeps_order_and_survives_panics() {
        let items: Vec<u32> = (0..20).collect();
        let out = par_map(&items, |&i| {
            if i == 7 {
                panic!("boom");
            }
            i * 2
        });
        assert_eq!(out.len(), 20);
        assert_eq!(out[7], None);
        assert_eq!(out[3], Some(6));
        assert_eq!(out[19], Some(38));
    }

    #[test]
    fn formats_numbers_and_names() {
        assert_eq!(sig(0.301721, 3), "0.302");
        assert_eq!(sig(47.1817, 4), "47.18");
        assert_eq!(sig(2.5e-8, 3), "2.50e-8");
        assert_eq!(sci(0.0), "0");
        assert_eq!(sci(1.234e-7), "1.23e-7");
        assert_eq!(slug("A=0 B=-0.5"), "A_0_B_-0.5");
        assert_eq!(
            md_table(&["a", "b"], &[vec!["1".into(), "x|y".into()]]),
            "| a | b |\n|---|---|\n| 1 | x\\|y |\n"
        );
    }
}
