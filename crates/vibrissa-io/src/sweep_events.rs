//! What happened along a sweep and how its rows are counted: the events (first contact,
//! phase switches, the separation), the stick/slip switches of a frictional sweep
//! ([`friction_switches`]), their names, [`RowCounts`] and the one-line summary; the text,
//! the JSON and the figures all take them from here.

use contact_sim::{FrictionEvent, FrictionEventKind, Phase, SweepResult};

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
    // a sweep that turns the base names its rows by the turn, a translation by x0
    let turns = res.points.iter().any(|p| p.gamma != 0.0);
    let at = |row: Option<usize>| {
        row.map_or(String::new(), |r| {
            let p = &res.points[r - 1];
            if turns {
                format!(" at row {r} (gamma = {:.6}°)", p.gamma.to_degrees())
            } else {
                format!(" at row {r} (x0 = {:.6}{lu})", p.x0 * l)
            }
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

/// The label of a stick/slip switch: `stick→slip` or `slip→stick`.
pub fn friction_label(kind: FrictionEventKind) -> &'static str {
    match kind {
        FrictionEventKind::StickToSlip => "stick→slip",
        FrictionEventKind::SlipToStick => "slip→stick",
    }
}

/// A stick/slip switch of a frictional sweep with the 0-based index of its row (each switch
/// has a row of its own, at the event's base position and contact point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSwitch {
    /// The 0-based index of its row in the sweep's rows.
    pub index: usize,
    /// The event as the sweep located it (dimensionless).
    pub event: FrictionEvent,
}

/// The stick/slip switches of a sweep in the order of the motion, each with its row: the
/// contact row at the event's base position, contact point and forces (the nearest contact
/// row in `x0` should none match exactly). Empty without friction.
pub fn friction_switches(res: &SweepResult) -> Vec<FrictionSwitch> {
    let contact: Vec<usize> = (0..res.points.len())
        .filter(|&i| res.points[i].phase != Phase::None)
        .collect();
    res.friction_events
        .iter()
        .filter_map(|e| {
            let exact = contact.iter().copied().find(|&i| {
                // x0 and xc alone do not tell rows apart where the base turns (x0 fixed)
                // past a peg (xc fixed): the row's forces, which the event takes, do
                let p = &res.points[i];
                p.x0 == e.x0 && p.xc == e.xc && p.f == e.f && p.ft == e.ft
            });
            let index = exact.or_else(|| {
                contact.iter().copied().min_by(|&a, &b| {
                    let d = |i: usize| (res.points[i].x0 - e.x0).abs();
                    d(a).total_cmp(&d(b))
                })
            })?;
            Some(FrictionSwitch { index, event: *e })
        })
        .collect()
}

/// How the rows of a frictional sweep stick and slip, for the summary line: `; friction mu
/// = 0.5: rows stick 120, slip 80; switches stick→slip 1, slip→stick 0`; nothing without friction
/// (`mu == 0`), so that a frictionless sweep's line stays as it was.
pub fn friction_note(res: &SweepResult, mu: f64) -> String {
    if mu == 0.0 {
        return String::new();
    }
    let count = |s: contact_sim::SlipState| res.points.iter().filter(|p| p.slip == s).count();
    let switches =
        |k: FrictionEventKind| res.friction_events.iter().filter(|e| e.kind == k).count();
    format!(
        "; friction mu = {mu}: rows stick {}, slip {}; switches {} {}, {} {}",
        count(contact_sim::SlipState::Stick),
        count(contact_sim::SlipState::Slip),
        friction_label(FrictionEventKind::StickToSlip),
        switches(FrictionEventKind::StickToSlip),
        friction_label(FrictionEventKind::SlipToStick),
        switches(FrictionEventKind::SlipToStick),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use beam_model::{FluidLoad, Whisker};
    use contact_sim::{ContactLaw, Profile, SlipState, SweepSettings};

    /// A bent whisker past a small circle with mu = 0.25 slides, sticks for a moment where
    /// its sliding reverses, and slides again: each switch is found on its own row (the
    /// row's x0 and contact point those of the event, the slip state changing there), the
    /// JSON record carries them with mu, and the summary counts them.
    #[test]
    fn friction_switches_sit_on_their_rows() {
        let w = Whisker::new(0.5, 0.0, 0.5, f64::INFINITY);
        let settings = SweepSettings {
            points: 16,
            contact_law: ContactLaw::Coulomb { mu: 0.25 },
            ..SweepSettings::default()
        };
        let profile = Profile::parse("circle:0.3,1.2,0.3").unwrap();
        let res =
            contact_sim::sweep(&w, FluidLoad { q: 0.0, alpha: 0.0 }, &profile, &settings).unwrap();
        let switches = friction_switches(&res);
        assert_eq!(switches.len(), res.friction_events.len());
        assert!(!switches.is_empty());
        for s in &switches {
            let p = &res.points[s.index];
            assert_eq!((p.x0, p.xc), (s.event.x0, s.event.xc));
            let (before, after) = (res.points[s.index - 1].slip, res.points[s.index + 1].slip);
            match s.event.kind {
                FrictionEventKind::StickToSlip => assert_eq!(after, SlipState::Slip),
                FrictionEventKind::SlipToStick => assert_eq!(before, SlipState::Slip),
            }
            assert!(s.event.ft.abs() <= 0.25 * s.event.f * (1.0 + 1e-9));
        }
        let summary = crate::summary::SweepSummary::of(
            &res,
            16,
            settings.contact_law,
            &crate::units::UnitSystem::DIMENSIONLESS,
        );
        assert_eq!(summary.mu, 0.25);
        assert_eq!(summary.friction_events.len(), switches.len());
        assert_eq!(summary.friction_events[0].row, switches[0].index + 1);
        let note = friction_note(&res, 0.25);
        assert!(
            note.starts_with("; friction mu = 0.25: rows stick "),
            "{note}"
        );
        assert_eq!(friction_note(&res, 0.0), "");
    }
}
