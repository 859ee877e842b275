//! Beyond the thesis (issue 39, item 6; the thesis's ch. 7 names frictional contact as the
//! model's next step): the base observables of one scene swept with Coulomb friction
//! mu = 0, 0.25, 0.5, 1 (spec/model.md, "Friction at the contact"), the README's friction
//! figure. A sweep the contact model cannot finish (friction in tangential contact, a
//! dynamic slip) is reported in the entry with its message, and the figure shows the others.

use beam_model::{FluidLoad, Whisker};
use contact_sim::{ContactLaw, Profile, SlipState, SweepPoint, SweepResult, SweepSettings};
use vibrissa_io::atomic::OutputDir;
use vibrissa_plot::{Chart, Dash, Series, Style};

use super::style::figure;
use crate::common::{md_table, note_err, sig, Layout};
use crate::Report;

/// The friction coefficients of the figure.
pub const MUS: [f64; 4] = [0.0, 0.25, 0.5, 1.0];

/// The scene: a tapered whisker (theta = 0.5) on a spring (k = 20) under q = 0.5, swept past
/// the circle of radius 0.3 at (0.3, 1.2), 80 contact rows. Its contact stays at the tip
/// (phase A) to the snap for every coefficient of [`MUS`], the case the frictional contact
/// model solves today.
pub const SCENE: &str = "circle:0.3,1.2,0.3, θ = 0.5, k = 20, q = 0.5";

/// The line width of stuck rows (sliding rows: 1), as the CLI's sweep figures draw them.
const STICK_WIDTH: f64 = 2.4;

/// Sweeps the scene of [`SCENE`] with Coulomb friction `mu` (0: frictionless).
pub fn sweep_at(mu: f64) -> Result<SweepResult, String> {
    let whisker = Whisker::new(0.5, 0.0, 0.0, 20.0);
    let profile = Profile::parse("circle:0.3,1.2,0.3").map_err(|e| e.to_string())?;
    let settings = SweepSettings {
        points: 80,
        contact_law: if mu == 0.0 {
            ContactLaw::Frictionless
        } else {
            ContactLaw::Coulomb { mu }
        },
        ..SweepSettings::default()
    };
    contact_sim::sweep(
        &whisker,
        FluidLoad { q: 0.5, alpha: 0.0 },
        &profile,
        &settings,
    )
    .map_err(|e| e.to_string())
}

type Obs = fn(&SweepPoint) -> f64;

/// The panels: symbol, axis label, value.
const PANELS: [(&str, &str, Obs); 4] = [
    ("A_x", "horizontal base force A_x [–]", |p| p.ax),
    ("A_y", "vertical base force A_y [–]", |p| p.ay),
    ("M_A", "base moment M_A [–]", |p| p.ma),
    ("f", "normal contact force f [–]", |p| p.f),
];

/// The colour and dash of the i-th coefficient.
fn mu_style(i: usize) -> (usize, Dash) {
    [
        (7, Dash::Dotted),
        (0, Dash::Solid),
        (1, Dash::Dashed),
        (2, Dash::DashDot),
    ][i % 4]
}

/// One panel: `get` against x0 for every finished sweep, one line per run of equal slip
/// state (stuck rows heavy), one legend entry per coefficient.
fn panel(runs: &[(f64, Result<SweepResult, String>)], k: usize) -> Chart {
    let (sym, label, get) = PANELS[k];
    let mut c = Chart::new(sym, "base position x_0 [–]", label);
    for (i, (mu, res)) in runs.iter().enumerate() {
        let Ok(res) = res else { continue };
        let (color, dash) = mu_style(i);
        let mut named = false;
        let mut end = 0;
        for run in res.points.chunk_by(|a, b| a.slip == b.slip) {
            end += run.len();
            let mut pts: Vec<(f64, f64)> = run.iter().map(|p| (p.x0, get(p))).collect();
            if let Some(next) = res.points.get(end) {
                pts.push((next.x0, get(next)));
            }
            let name = if named {
                String::new()
            } else {
                format!("μ = {mu}")
            };
            named = true;
            let mut s = Series::new(name, pts, Style::Line).color(color).dash(dash);
            if run[0].slip == SlipState::Stick {
                s = s.width(STICK_WIDTH);
            }
            c.series.push(s);
        }
    }
    let sticks = runs.iter().any(|(_, r)| {
        r.as_ref()
            .is_ok_and(|s| s.points.iter().any(|p| p.slip == SlipState::Stick))
    });
    if k == 0 && sticks {
        // the key's entry for the line width of stuck rows (only where a row sticks: a key
        // entry for nothing drawn is refused by journals)
        c.series.push(
            Series::new("stick (heavy line)", Vec::new(), Style::Line)
                .color(7)
                .width(STICK_WIDTH),
        );
    }
    c
}

/// The README's friction figure (`friction-observables.svg`, one column wide) and the
/// per-coefficient table: rows, rows stuck and sliding, switches, separation, or the
/// message of a sweep that ended early.
pub(super) fn friction(out: &OutputDir, report: &mut Report) {
    let runs: Vec<(f64, Result<SweepResult, String>)> =
        MUS.iter().map(|&mu| (mu, sweep_at(mu))).collect();
    let entry = report.entry(
        "friction",
        format!(
            "Beyond the thesis: the base observables of one sweep ({SCENE}) with Coulomb \
             friction μ = 0, 0.25, 0.5, 1 at the contact; stuck rows drawn heavy"
        ),
    );
    let mut rows = Vec::new();
    for (mu, res) in &runs {
        match res {
            Ok(s) => {
                let n = |st: SlipState| s.points.iter().filter(|p| p.slip == st).count();
                let last = s.points.last();
                rows.push(vec![
                    sig(*mu, 3),
                    s.points.len().to_string(),
                    n(SlipState::Stick).to_string(),
                    n(SlipState::Slip).to_string(),
                    s.friction_events.len().to_string(),
                    s.separation.to_string(),
                    last.map_or("-".into(), |p| sig(p.x0, 6)),
                    last.map_or("-".into(), |p| sig(p.ma, 6)),
                ]);
            }
            Err(e) => {
                entry.number(format!("μ = {mu}"), format!("ended early: {e}"), None);
                rows.push(vec![
                    sig(*mu, 3),
                    "0".into(),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                    format!("ended early: {e}"),
                    "-".into(),
                    "-".into(),
                ]);
            }
        }
    }
    entry.block(md_table(
        &[
            "μ",
            "rows",
            "stick",
            "slip",
            "switches",
            "separation",
            "last x0",
            "last M_A",
        ],
        &rows,
    ));
    let charts: Vec<Chart> = (0..PANELS.len()).map(|k| panel(&runs, k)).collect();
    let layout = Layout {
        cols: 2,
        size: (1000, 860),
        title: "Friction at the contact: the base observables",
        note: "base moving to −x (right to left); tip contact (phase A) throughout",
    };
    let res = figure(
        out,
        entry,
        "friction-observables.svg",
        &charts,
        &layout,
        true,
    );
    note_err(entry, "friction-observables.svg", res);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The README's figure alone (SVG and PNG, one column wide) into
    /// `target/friction-figure/`: `cargo test -p xtask friction_figure -- --ignored`.
    #[test]
    #[ignore = "four sweeps of 80 rows: run with --ignored"]
    fn friction_figure() {
        let dir =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/friction-figure");
        let _ = std::fs::remove_dir_all(&dir);
        let out = OutputDir::create(&dir).unwrap();
        let mut report = crate::Report::new("friction");
        friction(&out, &mut report);
        out.commit().unwrap();
        assert!(dir.join("friction-observables.svg").is_file());
    }

    /// mu = 0 is the frictionless sweep (no friction columns), and every coefficient of the
    /// figure finishes with ft inside the cone on every row.
    #[test]
    #[ignore = "four sweeps of 80 rows: run with --ignored"]
    fn every_coefficient_finishes_inside_the_cone() {
        for mu in MUS {
            let s = sweep_at(mu).unwrap();
            for p in s.contact_points() {
                assert!(p.ft.abs() <= mu * p.f * (1.0 + 1e-9) + 1e-12);
                assert_eq!(p.slip == SlipState::None, mu == 0.0);
            }
        }
    }
}
