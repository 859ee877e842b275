//! The events a frictional branch is watched for (their conditions are in
//! [`super::events`]).

/// Penetration depth from which a second contact counts (as in the frictionless sweep).
pub(super) const PENETRATION_MARGIN: f64 = 1e-10;

/// The events checked after each step of the frictional trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ev {
    /// `mu fn - |ft|` (stick only).
    Cone,
    /// The material point's sliding speed against `ft` (slip only): `-s dt/dpath` in phase
    /// A, `-s (dsigma - ds1)/dpath` in phase B.
    Sliding,
    /// `fn`.
    Release,
    /// The phase's validity: `phi1 - psi` in phase A (tangential contact follows), `1 - s1`
    /// in phase B (tip contact follows).
    PhaseEnd,
    /// The whisker next to the contact point touching: `cos((phi1 - psi) / 2)` in phase A
    /// (the segment next to the tip), `kappa_c - kappa0(s1)` in phase B (the whisker bending
    /// more sharply than the contour), as `crate::events::near_margin`.
    Touch,
    /// `s1 - BASE_CONTACT` in phase B: the contact slid down to the base.
    AtBase,
    /// `-dx0/dpath`.
    Snap,
    /// `margin - depth`.
    Depth,
    /// `c - floor`: the coordinate reaching the end of a path segment's frame (its next row;
    /// [`crate::motion::Frame::floor`]); never for a translation or a rotation.
    Corner,
}
