//! The integration tests of `profile-recon`, one binary (issue 35, item 7): one link of the
//! crate and its dependencies instead of one per file. Each former `tests/NAME.rs` is the
//! module `NAME`; run its tests with `cargo test -p profile-recon --test it NAME::` (a filter
//! after `NAME::` narrows them further, `-- --ignored` as before).

mod accuracy;
mod battery;
mod calibrate;
mod calibrate_battery;
mod friction_calib;
mod friction_recon;
mod friction_stream;
mod noise;
mod path_calib;
mod roundtrip;
mod stream;
mod thesis;
mod whisk_calib;
mod whisk_recon;
#[path = "../../../contact-sim/tests/common/whisking.rs"]
mod whisking;
