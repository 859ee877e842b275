//! The integration tests of `vibrissa-cli`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p vibrissa-cli --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

#[path = "../common/mod.rs"]
mod common;

mod accuracy;
mod calibrate;
mod cli;
mod figures;
mod folders;
mod friction;
mod friction_whisk;
mod hostile;
mod io;
mod parsers;
mod path_calib;
mod physical;
mod points_files;
mod reconstruct;
mod reconstruct_friction;
mod reconstruct_whisk;
mod safety;
mod whisking_io;
