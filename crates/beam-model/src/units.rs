//! Conversion between physical units and the dimensionless form [3.16-3.19].

use crate::error::{finite, ModelError, Result};
use serde::{Deserialize, Serialize};

/// A physical whisker of circular cross-section (diameter at the base `db`), length `L` and
/// Young's modulus `E`. All quantities in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalWhisker {
    /// Arc length L (m).
    pub length: f64,
    /// Base diameter d_b (m).
    pub base_diameter: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
}

/// The rat whiskers of thesis Table 2.2 (Birdwell et al. 2007).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Preset {
    /// beta whisker: L = 66.2 mm, d = 0.225 mm, E = 1.40 GPa.
    Beta,
    /// gamma whisker: L = 60.3 mm, d = 0.199 mm, E = 3.75 GPa.
    Gamma,
    /// A1 whisker: L = 51.7 mm, d = 0.16 mm, E = 2.75 GPa.
    A1,
    /// E2 whisker: L = 48.1 mm, d = 0.232 mm, E = 1.9 GPa.
    E2,
}

impl Preset {
    /// All presets, in table order.
    pub const ALL: [Preset; 4] = [Preset::Beta, Preset::Gamma, Preset::A1, Preset::E2];

    /// The preset's name as used in scene files and the CLI.
    pub fn name(&self) -> &'static str {
        match self {
            Preset::Beta => "beta",
            Preset::Gamma => "gamma",
            Preset::A1 => "A1",
            Preset::E2 => "E2",
        }
    }

    /// Looks a preset up by name (case-insensitive).
    pub fn from_name(name: &str) -> Option<Preset> {
        Preset::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(name))
    }

    /// The physical whisker of Table 2.2.
    pub fn whisker(&self) -> PhysicalWhisker {
        let (l_mm, d_mm, e_gpa) = match self {
            Preset::Beta => (66.2, 0.225, 1.40),
            Preset::Gamma => (60.3, 0.199, 3.75),
            Preset::A1 => (51.7, 0.16, 2.75),
            Preset::E2 => (48.1, 0.232, 1.9),
        };
        PhysicalWhisker {
            length: l_mm * 1e-3,
            base_diameter: d_mm * 1e-3,
            youngs_modulus: e_gpa * 1e9,
        }
    }
}

impl PhysicalWhisker {
    /// A physical whisker, all values > 0 and finite.
    pub fn new(length: f64, base_diameter: f64, youngs_modulus: f64) -> Result<Self> {
        for (name, v) in [
            ("length", length),
            ("base_diameter", base_diameter),
            ("youngs_modulus", youngs_modulus),
        ] {
            finite(name, v)?;
            if v <= 0.0 {
                return Err(ModelError::InvalidParameter {
                    name,
                    value: v,
                    reason: "must be > 0",
                });
            }
        }
        Ok(PhysicalWhisker {
            length,
            base_diameter,
            youngs_modulus,
        })
    }

    /// Second moment of area at the base, `I_b = pi d_b^4 / 64` (m^4).
    pub fn second_moment(&self) -> f64 {
        std::f64::consts::PI * self.base_diameter.powi(4) / 64.0
    }

    /// Bending stiffness at the base `E I_b` (N m^2).
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs_modulus * self.second_moment()
    }

    /// Force scale `f0 = E I_b / L^2` (N) [3.16]: `F = f f0`.
    pub fn force_scale(&self) -> f64 {
        self.bending_stiffness() / (self.length * self.length)
    }

    /// Line-load scale `q0 = E I_b / L^3` (N/m) [3.17]: `Q = q q0`.
    pub fn line_load_scale(&self) -> f64 {
        self.bending_stiffness() / self.length.powi(3)
    }

    /// Moment and torsional-stiffness scale `E I_b / L` (N m, N m/rad) [3.18, 3.19]:
    /// `M = m EI_b/L`, `K = k EI_b/L`.
    pub fn moment_scale(&self) -> f64 {
        self.bending_stiffness() / self.length
    }

    /// Dimensionless tip force `f = F L^2 / (E I_b)` [3.16].
    pub fn dimensionless_force(&self, force_n: f64) -> f64 {
        force_n / self.force_scale()
    }

    /// Dimensionless fluid load `q = Q L^3 / (E I_b)` [3.17].
    pub fn dimensionless_line_load(&self, q_n_per_m: f64) -> f64 {
        q_n_per_m / self.line_load_scale()
    }

    /// Dimensionless spring `k = K L / (E I_b)` [3.19].
    pub fn dimensionless_stiffness(&self, k_nm_per_rad: f64) -> f64 {
        k_nm_per_rad / self.moment_scale()
    }

    /// Dimensionless pre-curvature coefficients from physical ones: `A = A_phys L^2`,
    /// `B = B_phys L` (kappa0 in 1/m, s in m).
    pub fn dimensionless_curvature(&self, a_per_m2: f64, b_per_m: f64) -> (f64, f64) {
        (a_per_m2 * self.length * self.length, b_per_m * self.length)
    }

    /// Physical length from a dimensionless one (m).
    pub fn length_of(&self, s: f64) -> f64 {
        s * self.length
    }
}
