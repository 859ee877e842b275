//! The integration tests of `beam-model`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p beam-model --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

#[path = "../support/mod.rs"]
mod support;

mod auto;
mod battery;
mod colloc;
mod folds;
mod forward;
mod scenarios;
