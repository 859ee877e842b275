//! The values a caller gives over a scene file, as typed (text): the command line's flags,
//! kept as text so that a bad value is reported naming the flag with the value as typed
//! ([`super::parse_number`]), and `inf`, `nan` or negative numbers reach the model's own
//! range checks. Plain structs, no command-line parser: the CLI fills them from its flags.

use crate::scene_file::LoadKind;

/// Whisker values (`--theta`, `--a`, `--b`, `--k`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WhiskerFlags {
    /// Taper, the diameter ratio tip/base.
    pub theta: Option<String>,
    /// Slope A of the pre-curvature kappa0(s) = A s + B.
    pub a: Option<String>,
    /// Offset B of the pre-curvature.
    pub b: Option<String>,
    /// Base stiffness (`inf` for a rigid support).
    pub k: Option<String>,
}

/// Tip-force values (`--f`, `--beta-deg`, `--load`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TipFlags {
    /// Tip force magnitude.
    pub f: Option<String>,
    /// Tip force angle in degrees.
    pub beta_deg: Option<String>,
    /// Direction- or angle-preserving tip force.
    pub load: Option<LoadKind>,
}

/// Fluid-load values (`--q`, `--alpha-deg`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FluidFlags {
    /// Fluid load per unit length.
    pub q: Option<String>,
    /// Fluid load angle in degrees.
    pub alpha_deg: Option<String>,
}

/// Method values (`--method`, `--n`, `--tol`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodFlags {
    /// Method name (`accurate`, `auto`, `rk4`, `fdm`, `fdm-richardson`,
    /// `multiple-shooting`, `collocation`).
    pub method: Option<String>,
    /// Grid intervals.
    pub n: Option<String>,
    /// The accuracy asked of `auto`.
    pub tol: Option<String>,
}

/// All model values of `solve` and `sweep`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ModelFlags {
    /// Whisker values.
    pub whisker: WhiskerFlags,
    /// Tip force values.
    pub tip: TipFlags,
    /// Fluid load values.
    pub fluid: FluidFlags,
    /// Method values.
    pub method: MethodFlags,
}
