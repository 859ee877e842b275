//! The files every output folder shares: the units sidecar of a CSV, the folder's
//! `scene.ron` (the scene as resolved, with comment lines stating its units) and the list
//! of written files in the summaries.

use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::csvio::{units_sidecar_path, write_units_sidecar};
use crate::error::IoError;
use crate::resolve::Resolved;
use crate::scene_file::{self, LoadSpec, MethodSpec, SceneFile, SweepSpec, WhiskerSpec};
use crate::units::{Quantity, UnitSystem};

/// Writes the units sidecar of the CSV file `csv` (see [`crate::csvio::units_sidecar_path`]).
pub fn write_units_of(
    csv: &Path,
    header: &[&str],
    quantities: &[Quantity],
    units: &UnitSystem,
) -> Result<(), IoError> {
    let u: Vec<&str> = quantities.iter().map(|q| units.unit(*q)).collect();
    write_units_sidecar(&units_sidecar_path(csv), header, &u)
}

/// The scene that produced an output folder, with every parameter as resolved (flags over
/// the scene file over the defaults) in the scene's units.
pub fn output_scene(r: &Resolved, profile: Option<String>, points: Option<usize>) -> SceneFile {
    let g = &r.given;
    // The unit system exactly as the scene file gave it (a preset name stays a preset name;
    // the resolved dimensions are stated in the comment lines of [`scene_unit_notes`]).
    let units = r
        .file
        .as_ref()
        .map(|f| f.file.units.clone())
        .unwrap_or_default();
    SceneFile {
        units,
        whisker: WhiskerSpec {
            theta: g.theta.value,
            a: g.a.value,
            b: g.b.value,
            k: g.k.value.is_finite().then_some(g.k.value),
        },
        loads: LoadSpec {
            f: g.f.value,
            beta_deg: g.beta_deg.value,
            load: match g.load {
                beam_model::LoadKind::Dp => scene_file::LoadKind::Dp,
                beam_model::LoadKind::Ap => scene_file::LoadKind::Ap,
            },
            q: g.q.value,
            alpha_deg: g.alpha_deg.value,
        },
        profile,
        mu: 0.0,
        motion: None,
        x0: None,
        y0: None,
        gamma_deg: None,
        path: None,
        sweep: points.map(|points| SweepSpec { points, tol: None }),
        method: MethodSpec {
            name: r.method.name().to_string(),
            n: g.n.as_ref().map(|n| n.value as usize),
            tol: match r.method {
                beam_model::Method::Auto { tol, .. }
                | beam_model::Method::Collocation { tol, .. } => Some(tol),
                _ => None,
            },
        },
    }
}

/// Writes `scene.ron`: `notes` as comment lines, then the scene. Checks that the text
/// parses back to the same scene.
pub fn write_scene_ron(path: &Path, scene: &SceneFile, notes: &[String]) -> Result<(), IoError> {
    let mut text = String::new();
    for n in notes {
        for line in n.lines() {
            text.push_str("// ");
            text.push_str(line);
            text.push('\n');
        }
    }
    text.push_str(&scene.to_ron()?);
    text.push('\n');
    let back = SceneFile::parse(&text, path)?;
    if &back != scene {
        return Err(IoError::invalid_argument(
            "scene.ron",
            path.display().to_string(),
            "the written scene does not read back identically",
        ));
    }
    write_atomic(path, text.as_bytes())
}

/// The comment lines of a written scene that state its units.
pub fn scene_unit_notes(units: &UnitSystem) -> Vec<String> {
    match units.physical {
        None => vec![
            "units: dimensionless (thesis variables): lengths in whisker lengths L, f in E·Ib/L², \
             q in E·Ib/L³, k in E·Ib/L, a in 1/L², b in 1/L; angles in degrees"
                .to_string(),
        ],
        Some(_) => vec![format!(
            "units: {}; loads.f in N, loads.q in N/m, whisker.k in N m/rad, whisker.a in 1/m², \
             whisker.b in 1/m; profile numbers (parabola, cosh, circle) in mm; angles in degrees",
            units.describe()
        )],
    }
}
/// Formats a list of written files relative to nothing (as the OS returned them).
pub fn list_files(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_notes_and_file_lists_read_as_one_line_each() {
        let notes = scene_unit_notes(&UnitSystem::DIMENSIONLESS);
        assert_eq!(notes.len(), 1);
        assert!(notes[0].starts_with("units: dimensionless"));
        let files = [PathBuf::from("a/x.csv"), PathBuf::from("a/y.svg")];
        assert_eq!(list_files(&files), "a/x.csv, a/y.svg");
    }
}
