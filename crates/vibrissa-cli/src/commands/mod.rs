//! The commands of the binary and the outputs they share.
//!
//! Each command reads as parse -> resolve -> compute -> write -> summary; the building
//! blocks live in one module per concept:
//!
//! - [`solve`], [`sweep`], [`reconstruct`], [`calibrate`], [`demo`]: the commands
//!   ([`calibrate_inputs`], [`calibrate_out`], [`calibrate_summary`] and [`calibrate_advice`]:
//!   the steps of `calibrate`);
//! - [`outputs`]: units sidecars, `scene.ron` and the list of written files;
//! - [`elastica`]: `elastica.csv` and the elastica figure of `solve`;
//! - [`observables`]: `observables.csv`, the log of a sweep;
//! - [`sweep_events`](mod@sweep_events): a sweep's events, row counts and summary line;
//! - [`sweep_figures`], [`shapes`]: the figures of a sweep (observables, contact, shapes);
//! - [`recon_io`]: a reconstruction's inputs (sweep folders, units) and `reconstruction.csv`;
//! - [`phases`]: a phase's symbol, label, colour, dash and legend text;
//! - [`json`]: numbers for the `--json` outputs.
//!
//! The items that the Python bindings and `xtask` use from this module keep their paths
//! (re-exported below).

pub mod calibrate;
pub mod calibrate_advice;
pub mod calibrate_inputs;
pub mod calibrate_out;
pub mod calibrate_summary;
pub mod demo;
pub mod elastica;
pub mod json;
pub mod phases;
pub mod reconstruct;
pub mod shapes;
pub mod solve;
pub mod sweep;
pub mod sweep_figures;

pub use vibrissa_io::{observables, outputs, recon_io, sweep_events};

pub use elastica::{
    write_elastica_csv, write_elastica_figure, ELASTICA_HEADER, ELASTICA_QUANTITIES,
};
pub use observables::{
    observables_csv, observables_csv_in, write_observables_csv, ObservableRecord, SweepRow,
    OBSERVABLES_HEADER, OBSERVABLES_QUANTITIES,
};
pub use outputs::{list_files, output_scene, scene_unit_notes, write_scene_ron, write_units_of};
pub use phases::phase_name;
pub use sweep_events::{sweep_events, sweep_summary, RowCounts, SweepEvent};
pub use sweep_figures::{write_sweep_figures, FigureContext};

use crate::cli::Command;
use crate::error::CliError;
use crate::plot::FigureStyle;

/// Runs one command, its figures written as `style` says (`--size`, `--figures`:
/// [`crate::cli::Cli::figure_style`]).
pub fn run(command: Command, style: FigureStyle) -> Result<(), CliError> {
    match command {
        Command::Solve(args) => solve::run(&args, style),
        Command::Sweep(args) => sweep::run(&args, style),
        Command::Reconstruct(args) => reconstruct::run(&args, style),
        Command::Demo(args) => demo::run(&args, style),
        Command::Calibrate(args) => calibrate::run(&args, style),
    }
}
