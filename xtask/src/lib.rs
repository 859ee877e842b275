//! The library half of `cargo xtask`: the chapter-4 studies behind the charts (timing,
//! thread pool, CSV and ANSYS tables), kept out of the model's public API.

pub mod study;
