//! The integration tests of `bvp-solvers`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p bvp-solvers --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

#[path = "../bratu/mod.rs"]
mod bratu;

mod beam_examples;
mod collocation;
mod continuation;
mod integrators;
mod roots;
mod shooting;
