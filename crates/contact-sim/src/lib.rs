//! # contact-sim
//!
//! Quasi-static sweep of a whisker past a convex obstacle under flow (thesis ch. 5).
//! Skeleton: filled by the contact-sim issue.
