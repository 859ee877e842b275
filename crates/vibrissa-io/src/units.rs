//! The units of everything the command line writes and reads.
//!
//! A dimensionless scene (the default) writes the thesis's variables: lengths in whisker
//! lengths L, forces in E I_b / L^2, moments in E I_b / L, line loads in E I_b / L^3. A
//! physical scene (`units: Physical(...)`) writes positions and arc lengths in mm, forces in
//! N, moments in N mm, line loads in N/m, curvatures in 1/mm; angles are in rad in both.
//!
//! Every CSV file gets a units sidecar (`NAME.units.csv`, see
//! [`crate::csvio::units_sidecar_path`]); the readers use it to convert a log back to the
//! model's variables, so a log in mm and N is reconstructed correctly, and a log whose units
//! do not fit the scene is refused naming the file and column.

use std::path::Path;

use beam_model::PhysicalWhisker;
use contact_sim::Profile;

use crate::error::IoError;

/// The kind of a quantity, which fixes its unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// A position or arc length.
    Length,
    /// A force.
    Force,
    /// A moment.
    Moment,
    /// A force per length (the fluid load).
    LineLoad,
    /// An angle.
    Angle,
    /// A curvature.
    Curvature,
    /// A pure number in every unit system (a residual, a count).
    Number,
    /// A text column (no unit).
    Text,
}

/// The unit system of a command's outputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitSystem {
    /// The physical whisker, or `None` for dimensionless outputs.
    pub physical: Option<PhysicalWhisker>,
}

impl UnitSystem {
    /// Dimensionless outputs.
    pub const DIMENSIONLESS: UnitSystem = UnitSystem { physical: None };

    /// The unit system of a resolved scene.
    pub fn new(physical: Option<PhysicalWhisker>) -> Self {
        UnitSystem { physical }
    }

    /// Whether outputs are in physical units.
    pub fn is_physical(&self) -> bool {
        self.physical.is_some()
    }

    /// The whisker length in mm (physical scenes).
    pub fn length_mm(&self) -> Option<f64> {
        self.physical.map(|p| p.length * 1e3)
    }

    /// The factor from the dimensionless value to the output unit.
    pub fn scale(&self, q: Quantity) -> f64 {
        let Some(p) = &self.physical else {
            return 1.0;
        };
        match q {
            Quantity::Length => p.length * 1e3,
            Quantity::Force => p.force_scale(),
            Quantity::Moment => p.moment_scale() * 1e3,
            Quantity::LineLoad => p.line_load_scale(),
            Quantity::Curvature => 1.0 / (p.length * 1e3),
            Quantity::Angle | Quantity::Number | Quantity::Text => 1.0,
        }
    }

    /// The output unit of a quantity as written in units sidecars (`1` = dimensionless).
    pub fn unit(&self, q: Quantity) -> &'static str {
        match (q, self.is_physical()) {
            (Quantity::Text, _) => "",
            (Quantity::Angle, _) => "rad",
            (Quantity::Number, _) | (_, false) => "1",
            (Quantity::Length, true) => "mm",
            (Quantity::Force, true) => "N",
            (Quantity::Moment, true) => "N mm",
            (Quantity::LineLoad, true) => "N/m",
            (Quantity::Curvature, true) => "1/mm",
        }
    }

    /// An axis label: `symbol [unit]`, with `[–]` for dimensionless quantities.
    pub fn label(&self, symbol: &str, q: Quantity) -> String {
        match self.unit(q) {
            "" => symbol.to_string(),
            "1" => format!("{symbol} [–]"),
            u => format!("{symbol} [{u}]"),
        }
    }

    /// One line for figure notes and summaries naming the unit system.
    pub fn describe(&self) -> String {
        match &self.physical {
            None => "dimensionless: lengths in L, forces in E·Ib/L², moments in E·Ib/L".into(),
            Some(p) => format!(
                "physical: L = {} mm, d_b = {} mm, E = {} GPa",
                round_sig(p.length * 1e3),
                round_sig(p.base_diameter * 1e3),
                round_sig(p.youngs_modulus * 1e-9)
            ),
        }
    }

    /// The factor that turns a value in `unit` into the model's dimensionless variable of
    /// kind `q`, or why it cannot. Accepted: `1`, `-`, empty (dimensionless); lengths `mm`,
    /// `cm`, `m`, `um`; forces `N`, `mN`, `uN`; moments `N mm`, `N m`, `mN mm`; line loads
    /// `N/m`, `N/mm`; angles `rad`, `deg`.
    pub fn factor_from(&self, unit: &str, q: Quantity) -> Result<f64, String> {
        let u: String = unit
            .trim()
            .chars()
            .filter(|c| !c.is_whitespace() && *c != '*' && *c != '·')
            .collect::<String>()
            .replace('µ', "u");
        if q == Quantity::Angle {
            return match u.as_str() {
                "" | "rad" | "1" => Ok(1.0),
                "deg" | "°" => Ok(std::f64::consts::PI / 180.0),
                _ => Err(format!("unit `{unit}` is not an angle (rad or deg)")),
            };
        }
        if matches!(u.as_str(), "" | "1" | "-" | "–") {
            return Ok(1.0);
        }
        let si = match (q, u.as_str()) {
            (Quantity::Length, "mm") => 1e-3,
            (Quantity::Length, "cm") => 1e-2,
            (Quantity::Length, "m") => 1.0,
            (Quantity::Length, "um") => 1e-6,
            (Quantity::Force, "N") => 1.0,
            (Quantity::Force, "mN") => 1e-3,
            (Quantity::Force, "uN") => 1e-6,
            (Quantity::Moment, "Nmm") => 1e-3,
            (Quantity::Moment, "Nm") => 1.0,
            (Quantity::Moment, "mNmm") => 1e-6,
            (Quantity::LineLoad, "N/m") => 1.0,
            (Quantity::LineLoad, "N/mm") => 1e3,
            _ => {
                return Err(format!(
                    "unit `{unit}` does not fit a {}",
                    match q {
                        Quantity::Length => "length (mm, cm, m, um)",
                        Quantity::Force => "force (N, mN, uN)",
                        Quantity::Moment => "moment (N mm, N m)",
                        Quantity::LineLoad => "line load (N/m, N/mm)",
                        _ => "quantity of this column",
                    }
                ))
            }
        };
        let Some(p) = &self.physical else {
            return Err(format!(
                "values in `{unit}` need a physical scene (units: Physical(preset: ...)) to be \
                 converted; this scene is dimensionless"
            ));
        };
        Ok(match q {
            Quantity::Length => si / p.length,
            Quantity::Force => si / p.force_scale(),
            Quantity::Moment => si / p.moment_scale(),
            Quantity::LineLoad => si / p.line_load_scale(),
            _ => 1.0,
        })
    }

    /// The contour `p`, parsed from the spec `spec`, as the model's dimensionless contour: in
    /// a physical scene the numbers of `parabola`, `cosh`, `circle`, `peg` and `disc` are in mm (`a` of a
    /// parabola in 1/mm); the thesis's named contours g1, g2, ge ([5.2, 5.3, 5.11]) are in
    /// whisker lengths in every unit system, so they pass unchanged.
    pub fn dimensionless_profile(&self, spec: &str, p: Profile) -> Profile {
        let Some(l) = self.length_mm() else {
            return p;
        };
        if Profile::is_named(spec) {
            return p;
        }
        match p {
            Profile::Parabola { a, xv, yv } => Profile::Parabola {
                a: a * l,
                xv: xv / l,
                yv: yv / l,
            },
            Profile::Cosh { a, c, xv, d } => Profile::Cosh {
                a: a / l,
                c: c / l,
                xv: xv / l,
                d: d / l,
            },
            Profile::Circle { xc, yc, r } => Profile::Circle {
                xc: xc / l,
                yc: yc / l,
                r: r / l,
            },
            Profile::Peg { x, y } => Profile::Peg { x: x / l, y: y / l },
            Profile::Disc { x, y, r } => Profile::Disc {
                x: x / l,
                y: y / l,
                r: r / l,
            },
            other => other,
        }
    }
}

/// A number rounded to 6 significant digits for display (e.g. `66.2` instead of
/// `66.19999999999999`).
pub fn round_sig(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let mag = 10f64.powi(5 - v.abs().log10().floor() as i32);
    (v * mag).round() / mag
}

/// Splits a column name of a points file into its symbol and unit: `x_mm`, `x (mm)`,
/// `x [mm]`, `x/mm` and `x mm` all give `("x", "mm")`; `y` gives `("y", "")`.
pub fn split_name_unit(name: &str) -> (String, String) {
    let name = name.trim();
    let cut = name.find(['_', ' ', '(', '[', '/']).unwrap_or(name.len());
    let (sym, rest) = name.split_at(cut);
    let unit = rest
        .trim_matches(['_', ' ', '(', ')', '[', ']', '/'])
        .to_string();
    (sym.trim().to_string(), unit)
}

/// The units of the columns of a table as read from its sidecar, checked against the
/// expected quantity of each column: returns the factor to dimensionless per column.
pub fn column_factors(
    units: &std::collections::BTreeMap<String, String>,
    columns: &[(&str, Quantity)],
    system: &UnitSystem,
    sidecar: &Path,
) -> Result<Vec<f64>, IoError> {
    columns
        .iter()
        .map(|(name, q)| match units.get(*name) {
            None => Ok(1.0 / system.scale(*q)),
            Some(u) => system.factor_from(u, *q).map_err(|reason| IoError::Csv {
                path: sidecar.to_path_buf(),
                line: 2,
                column: Some(name.to_string()),
                reason,
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_units_split() {
        assert_eq!(split_name_unit("x_mm"), ("x".into(), "mm".into()));
        assert_eq!(split_name_unit(" y (mm) "), ("y".into(), "mm".into()));
        assert_eq!(split_name_unit("x [m]"), ("x".into(), "m".into()));
        assert_eq!(split_name_unit("y"), ("y".into(), "".into()));
    }

    #[test]
    fn physical_factors_invert_the_output_scales() {
        let p = beam_model::Preset::from_name("beta").unwrap().whisker();
        let u = UnitSystem::new(Some(p));
        for (q, unit) in [
            (Quantity::Length, "mm"),
            (Quantity::Force, "N"),
            (Quantity::Moment, "N mm"),
            (Quantity::LineLoad, "N/m"),
        ] {
            assert_eq!(u.unit(q), unit);
            let f = u.factor_from(unit, q).unwrap();
            assert!((f * u.scale(q) - 1.0).abs() < 1e-14, "{unit}");
        }
        assert!(UnitSystem::DIMENSIONLESS
            .factor_from("mm", Quantity::Length)
            .unwrap_err()
            .contains("physical scene"));
        assert!(u.factor_from("N", Quantity::Length).is_err());
    }

    /// A peg and a disc given in mm in a physical scene are the dimensionless obstacle of
    /// the same numbers divided by the whisker's length (the radius too); in a
    /// dimensionless scene they pass unchanged: both ways round to the bit pattern's last
    /// digit.
    #[test]
    fn pegs_and_discs_scale_with_the_length_unit() {
        let p = beam_model::Preset::from_name("beta").unwrap().whisker();
        let u = UnitSystem::new(Some(p));
        let l = u.length_mm().unwrap();
        for (spec_mm, want) in [
            (
                "peg:-10,30".to_string(),
                Profile::Peg {
                    x: -10.0 / l,
                    y: 30.0 / l,
                },
            ),
            (
                "disc:5,40,3.5".to_string(),
                Profile::Disc {
                    x: 5.0 / l,
                    y: 40.0 / l,
                    r: 3.5 / l,
                },
            ),
        ] {
            let got = u.dimensionless_profile(&spec_mm, Profile::parse(&spec_mm).unwrap());
            assert_eq!(got, want, "{spec_mm}");
            // written back in mm and read again: the same obstacle
            let back = match got {
                Profile::Peg { x, y } => format!("peg:{},{}", x * l, y * l),
                Profile::Disc { x, y, r } => format!("disc:{},{},{}", x * l, y * l, r * l),
                _ => unreachable!(),
            };
            let again = u.dimensionless_profile(&back, Profile::parse(&back).unwrap());
            let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs();
            match (again, want) {
                (Profile::Peg { x, y }, Profile::Peg { x: wx, y: wy }) => {
                    assert!(close(x, wx) && close(y, wy))
                }
                (
                    Profile::Disc { x, y, r },
                    Profile::Disc {
                        x: wx,
                        y: wy,
                        r: wr,
                    },
                ) => {
                    assert!(close(x, wx) && close(y, wy) && close(r, wr))
                }
                other => panic!("{other:?}"),
            }
            // dimensionless: unchanged
            let d = UnitSystem::DIMENSIONLESS;
            let p = Profile::parse(&spec_mm).unwrap();
            assert_eq!(d.dimensionless_profile(&spec_mm, p.clone()), p);
        }
    }
}
