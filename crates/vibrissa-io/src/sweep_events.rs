//! What happened along a sweep and how its rows are counted: the events (first contact,
//! phase switches, the separation), their names, [`RowCounts`] and the one-line summary;
//! the text, the JSON and the figures all take them from here.

use contact_sim::{Phase, SweepResult};

use crate::units::{Quantity, UnitSystem};

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
        label: format!("first contact ({})", res.first_contact.label()),
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
            label: res.separation.to_string(),
        });
    }
    out
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
pub fn sweep_summary(res: &SweepResult, requested: usize, units: &UnitSystem) -> String {
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
        ref s => s.to_string(),
    };
    format!(
        "{} rows ({} before contact + {} in contact: {} requested + {} at events), first \
         contact {}{}, separation {}{}, phases {}",
        n.rows,
        n.pre_contact,
        n.contact,
        n.requested,
        n.event_rows,
        res.first_contact.label(),
        at(n.first_contact_row),
        sep,
        at(n.separation_row),
        res.phase_pattern()
    )
}
