//! # vibrissa
//!
//! Facade over the workspace crates of the vibrissa toolkit, a Rust implementation of
//! whisker-inspired tactile sensing (large-deflection elastica, obstacle sweeps under flow,
//! fluid-load identification and contour reconstruction).
//!
//! | crate | concept |
//! |---|---|
//! | [`bvp_solvers`] | generic non-linear two-point BVP toolkit (FDM, shooting, integrators, roots) |
//! | [`beam_model`] | the whisker elastica [3.25] and its solution methods |
//! | [`contact_sim`] | quasi-static sweep past a convex obstacle (thesis ch. 5) |
//! | [`profile_recon`] | fluid-load identification and contour reconstruction (thesis ch. 6) |

pub use beam_model;
pub use bvp_solvers;
pub use contact_sim;
pub use profile_recon;
