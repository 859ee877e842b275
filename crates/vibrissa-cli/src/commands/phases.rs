//! The contact phases as the outputs show them: one symbol per phase (`-`, `A`, `B`, the
//! row kinds of a calibration), their labels, and their colour, dash and legend text in
//! the figures. Every output that names or styles a phase asks here.

use contact_sim::Phase;

use crate::plot::Dash;

/// The symbol of a phase: `-` before contact (the flow alone), `A` tip contact, `B`
/// tangential contact (the row kinds of a calibration use the same symbols).
pub fn phase_symbol(p: Phase) -> char {
    p.letter()
}

/// The phase of a symbol of [`phase_symbol`] (`None` for any other symbol, e.g. a row left
/// out of a calibration).
pub fn phase_of_symbol(c: char) -> Option<Phase> {
    [Phase::None, Phase::A, Phase::B]
        .into_iter()
        .find(|&p| phase_symbol(p) == c)
}

/// Whether a symbol of [`phase_symbol`] is a contact phase (`A` or `B`).
pub fn is_contact_symbol(c: char) -> bool {
    phase_of_symbol(c).is_some_and(|p| p != Phase::None)
}

/// The text of a row kind in a CSV column: `none`, `A`, `B` as in `observables.csv`, and
/// `left-out` for a symbol that is no phase.
pub fn symbol_label(c: char) -> &'static str {
    phase_of_symbol(c).map_or("left-out", |p| p.label())
}

/// The index of a phase in per-phase arrays: none 0, A 1, B 2.
pub fn phase_slot(p: Phase) -> usize {
    match p {
        Phase::None => 0,
        Phase::A => 1,
        Phase::B => 2,
    }
}

/// The palette colour of a phase: no contact grey, tip contact blue, tangential orange.
pub fn phase_color(p: Phase) -> usize {
    match p {
        Phase::None => 7,
        Phase::A => 0,
        Phase::B => 1,
    }
}

/// The line of a phase: no contact dotted, tip contact solid, tangential contact dashed
/// (so phases differ in greyscale too).
pub fn phase_dash(p: Phase) -> Dash {
    match p {
        Phase::None => Dash::Dotted,
        Phase::A => Dash::Solid,
        Phase::B => Dash::Dashed,
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

/// A legend entry given once per phase: the first call for a phase returns `name`, later
/// ones an empty name (the series stays out of the legend).
#[derive(Debug, Default, Clone, Copy)]
pub struct NamedOnce([bool; 3]);

impl NamedOnce {
    /// `name` the first time `p` is named, an empty string afterwards.
    pub fn name(&mut self, p: Phase, name: &str) -> String {
        let seen = &mut self.0[phase_slot(p)];
        if *seen {
            String::new()
        } else {
            *seen = true;
            name.to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_round_trip_and_label_as_the_csv() {
        for p in [Phase::None, Phase::A, Phase::B] {
            assert_eq!(phase_of_symbol(phase_symbol(p)), Some(p));
            assert_eq!(symbol_label(phase_symbol(p)), p.label());
        }
        assert_eq!(phase_symbol(Phase::None), '-');
        assert_eq!(symbol_label('x'), "left-out");
        assert!(is_contact_symbol('A') && is_contact_symbol('B'));
        assert!(!is_contact_symbol('-') && !is_contact_symbol('?'));
    }

    #[test]
    fn styles_differ_per_phase_and_names_come_once() {
        let all = [Phase::None, Phase::A, Phase::B];
        for (i, a) in all.iter().enumerate() {
            assert_eq!(phase_slot(*a), i);
            for b in &all[i + 1..] {
                assert_ne!(phase_color(*a), phase_color(*b));
                assert_ne!(phase_dash(*a), phase_dash(*b));
            }
        }
        let mut once = NamedOnce::default();
        assert_eq!(once.name(Phase::A, "a"), "a");
        assert_eq!(once.name(Phase::A, "a"), "");
        assert_eq!(once.name(Phase::B, "b"), "b");
    }
}
