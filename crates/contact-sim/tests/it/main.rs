//! The integration tests of `contact-sim`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p contact-sim --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

#[path = "../common/random_scene.rs"]
mod random_scene;
#[path = "../common/whisking.rs"]
mod whisking;

mod accuracy;
mod battery;
mod friction;
mod friction_whisk;
mod path;
mod precurved;
mod sweep;
mod whisk;
