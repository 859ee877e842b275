//! [`Scene::sweep`]: the whisker swept past the scene's obstacle under its flow [ch. 5], the
//! rows of `observables.csv` in the scene's units, and its events.

use contact_sim::{FirstContact, Separation, SweepResult};
use vibrissa_io::observables::SweepRow;
use vibrissa_io::resolve::sweep::{
    check_sweep_loads, missing_profile, sweep_contact_law, sweep_points, sweep_settings_with,
    sweep_tol,
};
use vibrissa_io::resolve::{profile_arg, ModelFlags};
use vibrissa_io::summary::FrictionEventSummary;
use vibrissa_io::sweep_events::{sweep_events, RowCounts};
use vibrissa_io::units::{Quantity, UnitSystem};

use crate::{Error, Scene};

/// A finished sweep: its rows (those of `observables.csv`, in the scene's units), its
/// events and the model's dimensionless result.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    rows: Vec<SweepRow>,
    result: SweepResult,
    units: UnitSystem,
    requested: usize,
    profile: String,
    mu: f64,
}

/// A row where something happens along a sweep: its 1-based row number (row r is line
/// r + 1 of `observables.csv`) and base position in the scene's length unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// What happens: `first contact (tip)`, `A→B`, `snap`, ...
    pub label: String,
    /// The 1-based row.
    pub row: usize,
    /// The base position x0 of that row.
    pub x0: f64,
}

impl Sweep {
    /// The rows in the order of the motion (x0 decreasing), 10 before contact first; a row
    /// before contact holds NaN where `observables.csv` is empty.
    pub fn rows(&self) -> &[SweepRow] {
        &self.rows
    }

    /// How the contact began (at the tip: phase A; tangential: phase B) and its first row.
    pub fn first_contact(&self) -> (FirstContact, Option<Event>) {
        let event = RowCounts::of(&self.result, self.requested)
            .first_contact_row
            .map(|row| {
                self.event(
                    row,
                    format!("first contact ({})", self.result.first_contact.label()),
                )
            });
        (self.result.first_contact, event)
    }

    /// How the contact ended (a snap, a release, a second contact) and its last contact row.
    pub fn separation(&self) -> (Separation, Option<Event>) {
        let event = RowCounts::of(&self.result, self.requested)
            .separation_row
            .map(|row| self.event(row, self.result.separation.to_string()));
        (self.result.separation, event)
    }

    /// The events in row order: first contact, every phase switch, the separation.
    pub fn events(&self) -> Vec<Event> {
        sweep_events(&self.result)
            .into_iter()
            .map(|e| self.event(e.index + 1, e.label))
            .collect()
    }

    /// The friction coefficient at the contact (the scene's `mu`; 0: frictionless).
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The stick/slip switches of a frictional sweep in the order of the motion (which,
    /// row, x0, contact point, fn and ft in the scene's units), as `sweep --json` lists
    /// them; empty without friction.
    pub fn friction_events(&self) -> Vec<FrictionEventSummary> {
        FrictionEventSummary::of(&self.result, &self.units)
    }

    /// How the rows are counted (before contact, in contact, requested, at events).
    pub fn counts(&self) -> RowCounts {
        RowCounts::of(&self.result, self.requested)
    }

    /// The unit system of the rows.
    pub fn units(&self) -> &UnitSystem {
        &self.units
    }

    /// The obstacle's profile spec, as the scene gives it.
    pub fn profile(&self) -> &str {
        &self.profile
    }

    /// The model's result, dimensionless (the thesis's variables), with the accuracy
    /// asked for and every row's error estimate when the scene's `sweep.tol` is set.
    pub fn result(&self) -> &SweepResult {
        &self.result
    }

    fn event(&self, row: usize, label: String) -> Event {
        Event {
            label,
            row,
            x0: self.result.points[row - 1].x0 * self.units.scale(Quantity::Length),
        }
    }
}

impl Scene {
    /// Sweeps the scene's whisker past its `profile` under its flow, with `sweep.points`
    /// contact rows at `sweep.tol` and Coulomb friction `mu` at the contact (spec/model.md,
    /// "Friction at the contact"; 0: frictionless), the base moving as its `motion` says
    /// (translate, rotate from `x0`, `y0`, `gamma_deg`, or a `path`; "Base motions") (as
    /// `vibrissa sweep SCENE.ron`): the rows of
    /// `observables.csv`, bit for bit, in the scene's units. A whisker that never touches
    /// is [`Error::NoContact`].
    pub fn sweep(&self) -> Result<Sweep, Error> {
        let loaded = self.loaded()?;
        let profile =
            profile_arg(&None, Some(&loaded)).ok_or_else(|| missing_profile(Some(&loaded)))?;
        let requested = sweep_points(None, Some(&loaded))?;
        let tol = sweep_tol(None, Some(&loaded))?;
        let law = sweep_contact_law(None, Some(&loaded))?;
        let (_, r) = self.resolved(&ModelFlags::default())?;
        check_sweep_loads(&r)?;
        let units = r.units();
        let contour = profile.parse(&units)?;
        // the scene's base motion (`motion`, `x0`, `y0`, `gamma_deg`, `path`)
        let motion = vibrissa_io::resolve::motion::sweep_motion(
            &vibrissa_io::resolve::motion::MotionGiven::default(),
            Some(&loaded),
            &units,
        )?;
        let settings = contact_sim::SweepSettings {
            motion: motion.motion,
            ..sweep_settings_with(requested, tol, law)
        };
        let result = contact_sim::sweep(&r.scene.whisker, r.scene.loads.fluid, &contour, &settings)
            .map_err(|e| r.contact_culprit(e, &profile))?;
        let rows = result
            .points
            .iter()
            .map(|p| SweepRow::of(p, &units))
            .collect();
        Ok(Sweep {
            rows,
            result,
            units,
            requested,
            profile: profile.spec,
            mu: law.mu(),
        })
    }
}
