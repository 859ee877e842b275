//! The house style of the chapter-5 figures, shared by [`super::observables`] and
//! [`super::sketch`]: case labels, contact-phase lines and the figure with one key above its
//! panels.

use contact_sim::Phase;
use vibrissa_io::atomic::OutputDir;
use vibrissa_plot::{Chart, Dash};

use crate::common::{self, Layout};
use crate::Entry;

/// A legend label for a case label: `q=5` → `q = 5`, `theta=0.5 k=inf` → `ϑ = 0.5, k = ∞`,
/// `A=0 B=-0.5` → `A = 0, B = −0.5`.
pub(super) fn pretty_label(label: &str) -> String {
    label
        .split_whitespace()
        .map(|part| match part.split_once('=') {
            Some((name, value)) => {
                let name = if name == "theta" { "ϑ" } else { name };
                let value = match value {
                    "inf" => "∞".to_string(),
                    "-inf" => "−∞".to_string(),
                    v => v.replacen('-', "−", 1),
                };
                format!("{name} = {value}")
            }
            None => part.to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The colour, dash and legend text of a contact phase (the CLI's house style: no contact
/// dotted grey, phase A solid blue, phase B dashed orange).
pub(super) fn phase_style(p: Phase) -> (usize, usize, Dash, &'static str) {
    match p {
        Phase::None => (0, 7, Dash::Dotted, "no contact"),
        Phase::A => (1, 0, Dash::Solid, "phase A (tip)"),
        Phase::B => (2, 1, Dash::Dashed, "phase B (tangential)"),
    }
}

/// Writes `charts` as one figure `name` (SVG and PNG) laid out by `layout` (`cols` panels
/// a row, one key for all panels above them from the first chart's legend, and the note
/// under it); records the file. With `column`, the figure is one journal column wide
/// instead of the page.
pub(super) fn figure(
    out: &OutputDir,
    entry: &mut Entry,
    name: &str,
    charts: &[Chart],
    layout: &Layout<'_>,
    column: bool,
) -> Result<(), String> {
    let style = if column { common::COLUMN } else { common::PAGE };
    common::svg_headed(style, out, entry, name, charts, layout)
}
