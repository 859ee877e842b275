//! The RON scene file: the whisker, its loads, an optional obstacle sweep and the method.
//!
//! ```ron
//! // A scene: the whisker, its loads, optional obstacle sweep and method settings.
//! (
//!     units: Dimensionless,            // or Physical(preset: "beta")
//!     whisker: (theta: 1.0, a: 0.0, b: 0.0, k: None),   // k: None = rigid, Some(20.0) = spring
//!     loads: (f: 0.0, beta_deg: 0.0, load: Dp, q: 5.0, alpha_deg: 0.0),
//!     profile: Some("g1"),             // the profile spec strings of cli.md
//!     mu: 0.0,                         // Coulomb friction at the contact (dimensionless)
//!     motion: "translate",             // or "rotate" (from x0, y0, gamma_deg), or "path"
//!     // x0: -0.1, y0: 0.0, gamma_deg: -10.0,   // where a rotation starts (length unit, deg)
//!     // path: "poses.csv",            // a path's poses (x0,y0,gamma_deg[,k]), or inline
//!     sweep: Some((points: 200)),
//!     method: (name: "accurate", n: None),
//! )
//! ```
//!
//! Every field except `whisker` may be left out (defaults: dimensionless units, no load, no
//! profile, no sweep, the accurate method). Unknown fields are refused. Optional values may
//! be written with or without `Some(...)`. Quantities in physical units (f in N, q in N/m)
//! are carried as given; the model crate converts them.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::IoError;

/// A whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The unit system of lengths and loads.
    #[serde(default)]
    pub units: Units,
    /// The whisker geometry and support.
    pub whisker: WhiskerSpec,
    /// Tip force and fluid load.
    #[serde(default)]
    pub loads: LoadSpec,
    /// The obstacle contour, as a profile spec string of the CLI (`g1`, `parabola:a,xv,yv`, ...).
    #[serde(default)]
    pub profile: Option<String>,
    /// The Coulomb friction coefficient at the contact (spec/model.md, "Friction at the
    /// contact"; `sweep --mu`), dimensionless in every unit system, in `[0, 10]`. Default 0
    /// (frictionless); left out of a written scene when 0, so that a frictionless scene is
    /// written as before.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub mu: f64,
    /// How the base moves (`sweep --motion`): `translate` (the default), `rotate` or `path`
    /// (spec/model.md, "Base motions"). Left out of a written scene when not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<String>,
    /// The base x where a rotation starts (`--x0`), in the scene's length unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x0: Option<f64>,
    /// The base y where a rotation starts (`--y0`), in the scene's length unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y0: Option<f64>,
    /// The turn where a rotation starts (`--gamma-deg`), in degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gamma_deg: Option<f64>,
    /// The poses of a path motion: a CSV file relative to the scene file (columns
    /// `x0,y0,gamma_deg`, optionally `k`; `vibrissa_io::resolve::motion`), or the table
    /// itself inline (a string with line breaks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
    /// Sweep settings, if the scene describes a sweep.
    #[serde(default)]
    pub sweep: Option<SweepSpec>,
    /// The numerical method.
    #[serde(default)]
    pub method: MethodSpec,
}

/// The unit system of a scene.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Units {
    /// Lengths in whisker lengths, loads scaled by E I_base / L^2 (the thesis's variables).
    #[default]
    Dimensionless,
    /// Physical units: a named whisker preset and/or explicit dimensions. Without a preset,
    /// all three dimensions are required; with one, given dimensions override the preset's.
    Physical {
        /// A named whisker preset (e.g. `"beta"`, the rat beta whisker of Table 2.2).
        #[serde(default)]
        preset: Option<String>,
        /// Whisker length in mm.
        #[serde(default)]
        length_mm: Option<f64>,
        /// Base diameter in mm.
        #[serde(default)]
        base_diameter_mm: Option<f64>,
        /// Young's modulus in GPa.
        #[serde(default)]
        youngs_modulus_gpa: Option<f64>,
    },
}

/// The whisker: taper, pre-curvature and base support.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhiskerSpec {
    /// Diameter ratio tip/base, in (0, 1]. Default 1.
    #[serde(default = "one")]
    pub theta: f64,
    /// Slope `A` of the Cesaro pre-curvature kappa0(s) = A s + B. Default 0.
    #[serde(default)]
    pub a: f64,
    /// Offset `B` of the pre-curvature. Default 0.
    #[serde(default)]
    pub b: f64,
    /// Base spring stiffness; `None` for a rigid support.
    #[serde(default)]
    pub k: Option<f64>,
}

fn one() -> f64 {
    1.0
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// How the tip force turns with the tip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LoadKind {
    /// Direction preserving.
    #[default]
    Dp,
    /// Angle preserving.
    Ap,
}

/// Tip force and distributed fluid load.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Tip force magnitude.
    #[serde(default)]
    pub f: f64,
    /// Tip force angle in degrees.
    #[serde(default)]
    pub beta_deg: f64,
    /// Direction- or angle-preserving tip force.
    #[serde(default)]
    pub load: LoadKind,
    /// Fluid load per length.
    #[serde(default)]
    pub q: f64,
    /// Fluid load angle in degrees.
    #[serde(default)]
    pub alpha_deg: f64,
}

/// Sweep settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// Number of contact points along the contour, at least 2. Default 200.
    #[serde(default = "default_points")]
    pub points: usize,
    /// The accuracy asked for of every row (`sweep --tol`); `None`: the sweep's own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
}

impl Default for SweepSpec {
    fn default() -> Self {
        SweepSpec {
            points: default_points(),
            tol: None,
        }
    }
}

fn default_points() -> usize {
    200
}

/// The numerical method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// Method name as for `--method` (`accurate`, `fdm`, `rk4`, ...). Default `accurate`.
    #[serde(default = "default_method")]
    pub name: String,
    /// Grid intervals for fixed-step methods (at least 4); `None` for the method's default.
    #[serde(default)]
    pub n: Option<usize>,
    /// The accuracy asked of `auto` (default 1e-8); only with `name: "auto"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
}

impl Default for MethodSpec {
    fn default() -> Self {
        MethodSpec {
            name: default_method(),
            n: None,
            tol: None,
        }
    }
}

fn default_method() -> String {
    "accurate".to_string()
}

/// The RON options used for reading scene files: `Some(..)` may be left out.
fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

impl SceneFile {
    /// A scene with the given whisker and every other field at its default.
    pub fn with_whisker(whisker: WhiskerSpec) -> Self {
        SceneFile {
            units: Units::default(),
            whisker,
            loads: LoadSpec::default(),
            profile: None,
            mu: 0.0,
            motion: None,
            x0: None,
            y0: None,
            gamma_deg: None,
            path: None,
            sweep: None,
            method: MethodSpec::default(),
        }
    }

    /// Reads, parses and validates the scene file `path`.
    pub fn load(path: &Path) -> Result<SceneFile, IoError> {
        let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
        Self::parse(&text, path)
    }

    /// Parses and validates scene `text`; `path` only names the source in errors.
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile, IoError> {
        // a byte-order mark (as some editors write) is not part of the scene
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let scene: SceneFile = ron_options()
            .from_str(text)
            .map_err(|e| map_ron_error(e, path))?;
        scene.validate(text, path)?;
        Ok(scene)
    }

    /// Renders the scene as pretty RON that [`SceneFile::parse`] reads back identically.
    pub fn to_ron(&self) -> Result<String, IoError> {
        ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .map_err(|e| IoError::invalid_argument("scene", format!("{self:?}"), e.to_string()))
    }

    /// Checks every value's range. `text` is the file's text, used to find the line of the
    /// offending field; `path` names the file in errors.
    pub fn validate(&self, text: &str, path: &Path) -> Result<(), IoError> {
        let fail = |field: &str, reason: String| {
            // The field itself, else the nearest enclosing field that is written out.
            let segments: Vec<&str> = field.split('.').collect();
            let (line, column) = (1..=segments.len())
                .rev()
                .find_map(|n| locate_field(text, &segments[..n]))
                .unwrap_or((1, 1));
            IoError::Scene {
                path: path.to_path_buf(),
                line,
                column,
                field: Some(field.to_string()),
                reason,
            }
        };
        let finite = |field: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(fail(field, format!("must be finite, got {v}")))
            }
        };
        let w = &self.whisker;
        if !(w.theta > 0.0 && w.theta <= 1.0) {
            return Err(fail(
                "whisker.theta",
                format!("must be in (0, 1], got {}", w.theta),
            ));
        }
        finite("whisker.a", w.a)?;
        finite("whisker.b", w.b)?;
        if let Some(k) = w.k {
            if !(k > 0.0 && k.is_finite()) {
                return Err(fail(
                    "whisker.k",
                    format!("must be positive and finite (None for a rigid support), got {k}"),
                ));
            }
        }
        let l = &self.loads;
        finite("loads.f", l.f)?;
        finite("loads.beta_deg", l.beta_deg)?;
        finite("loads.q", l.q)?;
        finite("loads.alpha_deg", l.alpha_deg)?;
        if let Units::Physical {
            preset,
            length_mm,
            base_diameter_mm,
            youngs_modulus_gpa,
        } = &self.units
        {
            if let Some(p) = preset {
                if p.trim().is_empty() {
                    return Err(fail("units.preset", "must not be empty".to_string()));
                }
            }
            for (name, v) in [
                ("units.length_mm", length_mm),
                ("units.base_diameter_mm", base_diameter_mm),
                ("units.youngs_modulus_gpa", youngs_modulus_gpa),
            ] {
                match v {
                    Some(v) if !(*v > 0.0 && v.is_finite()) => {
                        return Err(fail(name, format!("must be positive and finite, got {v}")))
                    }
                    None if preset.is_none() => {
                        return Err(fail(
                            name,
                            "is required when no preset is given".to_string(),
                        ))
                    }
                    _ => {}
                }
            }
        }
        if let Some(p) = &self.profile {
            if p.trim().is_empty() {
                return Err(fail("profile", "must not be empty".to_string()));
            }
        }
        if !(0.0..=contact_sim::contact_law::MAX_MU).contains(&self.mu) {
            return Err(fail(
                "mu",
                format!(
                    "the friction coefficient must lie in [0, {}], got {}",
                    contact_sim::contact_law::MAX_MU,
                    self.mu
                ),
            ));
        }
        if let Some(s) = &self.sweep {
            if s.points < 2 {
                return Err(fail(
                    "sweep.points",
                    format!("must be at least 2, got {}", s.points),
                ));
            }
        }
        if self.method.name.trim().is_empty() {
            return Err(fail("method.name", "must not be empty".to_string()));
        }
        if let Some(n) = self.method.n {
            if n < 4 {
                return Err(fail("method.n", format!("must be at least 4, got {n}")));
            }
        }
        Ok(())
    }
}

/// Maps a RON parse error to [`IoError::Scene`], naming unknown, missing or duplicate fields
/// with their dotted path where the struct is known.
fn map_ron_error(e: ron::error::SpannedError, path: &Path) -> IoError {
    use ron::error::Error as E;
    let prefix = |outer: &Option<String>| -> String {
        match outer.as_deref() {
            Some("WhiskerSpec") => "whisker.".into(),
            Some("LoadSpec") => "loads.".into(),
            Some("SweepSpec") => "sweep.".into(),
            Some("MethodSpec") => "method.".into(),
            Some("Physical") => "units.".into(),
            _ => String::new(),
        }
    };
    let field = match &e.code {
        E::NoSuchStructField { found, outer, .. } => Some(format!("{}{found}", prefix(outer))),
        E::MissingStructField { field, outer } | E::DuplicateStructField { field, outer } => {
            Some(format!("{}{field}", prefix(outer)))
        }
        _ => None,
    };
    IoError::Scene {
        path: path.to_path_buf(),
        line: e.position.line.max(1),
        column: e.position.col.max(1),
        field,
        reason: e.code.to_string(),
    }
}

/// Finds the 1-based (line, column) of a field given by its path segments
/// (`["whisker", "theta"]`): each segment is searched as `name:` after the previous one,
/// ignoring comments and string contents.
pub fn locate_field(text: &str, segments: &[&str]) -> Option<(usize, usize)> {
    let clean = blank_comments_and_strings(text);
    let bytes = clean.as_bytes();
    let mut from = 0;
    let mut found = None;
    for seg in segments {
        let mut pos = None;
        let mut start = from;
        while let Some(off) = clean[start..].find(seg) {
            let i = start + off;
            let before_ok = i == 0 || !is_ident_byte(bytes[i - 1]);
            let after = i + seg.len();
            let after_ok = after >= bytes.len() || !is_ident_byte(bytes[after]);
            let colon = clean[after..].trim_start().starts_with(':');
            if before_ok && after_ok && colon {
                pos = Some(i);
                break;
            }
            start = i + seg.len();
        }
        let i = pos?;
        found = Some(i);
        from = i + seg.len();
    }
    let i = found?;
    let line = text[..i].matches('\n').count() + 1;
    let line_start = text[..i].rfind('\n').map_or(0, |p| p + 1);
    let column = text[line_start..i].chars().count() + 1;
    Some((line, column))
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// Replaces comments and the insides of string literals by spaces (byte positions kept).
fn blank_comments_and_strings(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let blank = |out: &mut String, c: char| {
        if c == '\n' {
            out.push('\n');
        } else {
            out.extend(std::iter::repeat_n(' ', c.len_utf8()));
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '/' if chars.peek() == Some(&'/') => {
                blank(&mut out, c);
                for d in chars.by_ref() {
                    blank(&mut out, d);
                    if d == '\n' {
                        break;
                    }
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                blank(&mut out, c);
                let mut prev = ' ';
                for d in chars.by_ref() {
                    blank(&mut out, d);
                    if prev == '*' && d == '/' {
                        break;
                    }
                    prev = d;
                }
            }
            '"' => {
                out.push('"');
                let mut escaped = false;
                for d in chars.by_ref() {
                    if !escaped && d == '"' {
                        out.push('"');
                        break;
                    }
                    escaped = !escaped && d == '\\';
                    blank(&mut out, d);
                }
            }
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `mu`: default 0 and left out of a written scene; a coefficient round-trips bit for
    /// bit; outside [0, 10] or NaN refused naming `mu` at its line.
    #[test]
    fn mu_defaults_to_zero_round_trips_and_is_checked() {
        let path = Path::new("s.ron");
        let plain = SceneFile::parse("(whisker: ())", path).unwrap();
        assert_eq!(plain.mu, 0.0);
        assert!(!plain.to_ron().unwrap().contains("mu"));
        for mu in [0.25f64, 1e-9, 10.0, 0.1 + 0.2] {
            let text = format!("(whisker: (), mu: {mu:?})");
            let s = SceneFile::parse(&text, path).unwrap();
            assert_eq!(s.mu.to_bits(), mu.to_bits());
            let back = SceneFile::parse(&s.to_ron().unwrap(), path).unwrap();
            assert_eq!(back, s);
        }
        for bad in ["-0.5", "10.5", "NaN", "inf"] {
            let text = format!("(\n  whisker: (),\n  mu: {bad},\n)");
            let e = SceneFile::parse(&text, path).unwrap_err().to_string();
            assert!(e.contains("s.ron:3:") && e.contains("mu"), "{bad}: {e}");
            assert!(e.contains("[0, 10]"), "{bad}: {e}");
        }
    }

    #[test]
    fn locate_skips_comments_and_strings() {
        let text =
            "// theta: 3\n(\n  profile: \"theta: x\",\n  whisker: (a: 1.0,\n    theta: 2.0),\n)";
        assert_eq!(locate_field(text, &["whisker", "theta"]), Some((5, 5)));
        assert_eq!(locate_field(text, &["whisker", "a"]), Some((4, 13)));
        assert_eq!(locate_field(text, &["loads", "q"]), None);
    }
}
