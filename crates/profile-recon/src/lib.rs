//! # profile-recon
//!
//! Fluid-load identification and obstacle contour reconstruction (thesis ch. 6).
//! Skeleton: filled by the profile-recon issue.
