//! The integration tests of `xtask`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p xtask --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

mod ansys;
mod study;
