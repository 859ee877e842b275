//! The base motion of a sweep (spec/cli.md `--motion`, `--x0`, `--y0`, `--gamma-deg`; the
//! scene file's `motion`, `x0`, `y0`, `gamma_deg`, `path`; Python's `motion=`, `path=`)
//! resolved into the library's [`BaseMotion`] (spec/model.md, "Base motions").
//!
//! Units: the base's position (`x0`, `y0`, a path's `x0, y0` columns) is in the scene's
//! length unit (mm in a physical scene), the turn in degrees (`gamma_deg`; the model's gamma
//! is in radians, `gamma = gamma_deg pi / 180`), a path's `k` in the scene's stiffness unit
//! (N m/rad in a physical scene, as the scene's `whisker.k`; `k = K L / (E I_b)` [3.19]).
//!
//! A path table (`path:FILE.csv`, or the scene's `path`) is a CSV file (comma, tab or
//! semicolon separated) whose header names the columns `x0`, `y0`, `gamma` (with its unit:
//! `gamma_deg`, `gamma [deg]`, `gamma_rad`) and optionally `k`; units are allowed in the
//! names as in a `points:` table (`x0_mm`, `y0 [cm]`, `k [N mm/rad]`). Every problem names
//! the file, the line and the column.

use std::path::{Path, PathBuf};

use contact_sim::{BaseMotion, Pose, Poses};

use super::{LoadedScene, Value};
use crate::csvio::parse_table;
use crate::error::IoError;
use crate::units::{split_name_unit, Quantity, UnitSystem};

/// The motions `--motion` names.
pub const MOTIONS: &str = "translate, rotate or path:FILE.csv";

/// The columns of a path in the scene's units, as given in code (Python's `path=`, a Rust
/// program): the pose at each row, `gamma` in degrees, and the follicle stiffness where set.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathColumns {
    /// Base x at each row (length unit).
    pub x0: Vec<f64>,
    /// Base y at each row (length unit).
    pub y0: Vec<f64>,
    /// The turn at each row (degrees).
    pub gamma_deg: Vec<f64>,
    /// The follicle stiffness at each row (stiffness unit), where the path sets it.
    pub k: Option<Vec<f64>>,
}

/// The motion a caller gives over a scene file: `motion` (`translate`, `rotate`,
/// `path:FILE.csv`, or `path` with `path` given), the start pose of a rotation and a path's
/// columns given in code.
#[derive(Debug, Clone, Default)]
pub struct MotionGiven {
    /// `--motion` as typed.
    pub motion: Option<Value>,
    /// `--x0`.
    pub x0: Option<Value>,
    /// `--y0`.
    pub y0: Option<Value>,
    /// `--gamma-deg`.
    pub gamma_deg: Option<Value>,
    /// A path given in code (Python's `path=`).
    pub path: Option<PathColumns>,
}

/// The motion resolved: the library's value, and the keys that describe it in a written
/// scene file (`scene.ron` of an output folder).
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedMotion {
    /// The library's motion (dimensionless).
    pub motion: BaseMotion,
    /// `translate`, `rotate` or `path` (the scene key).
    pub label: &'static str,
    /// The start pose of a rotation, in the scene's units (`x0`, `y0`, `gamma_deg`).
    pub start: Option<(f64, f64, f64)>,
    /// The path table read from a file (to copy beside a written scene), if any.
    pub path_file: Option<PathBuf>,
    /// The path given inline in the scene (written back as is), if any.
    pub path_inline: Option<String>,
}

impl ResolvedMotion {
    /// The thesis's translating sweep.
    pub fn translate() -> Self {
        ResolvedMotion {
            motion: BaseMotion::Translate,
            label: "translate",
            start: None,
            path_file: None,
            path_inline: None,
        }
    }
}

/// Where the motion's kind came from, for messages.
enum Kind {
    Translate,
    Rotate,
    /// A path: from this file (flag or scene), else inline in the scene, else given in code.
    Path(Option<PathBuf>),
}

/// The base motion of a sweep: `given` (the flags, or Python's keywords) over the scene
/// file's keys, else the translation. Refusals name the flag as typed or the scene key with
/// its line (exit 2): an unknown motion, a non-finite pose, a start pose without a rotation,
/// a path without its table, a bad table (file, line, column).
pub fn sweep_motion(
    given: &MotionGiven,
    file: Option<&LoadedScene>,
    units: &UnitSystem,
) -> Result<ResolvedMotion, IoError> {
    let scene = file.map(|f| &f.file);
    let kind = match (&given.motion, scene.and_then(|s| s.motion.as_deref())) {
        (Some(v), _) => parse_kind(&v.raw(), None).ok_or_else(|| {
            IoError::invalid_argument(
                "--motion",
                v.raw(),
                format!("not a base motion: expected {MOTIONS}"),
            )
        })?,
        (None, Some(m)) => parse_kind(m, file).ok_or_else(|| {
            file.map_or_else(
                || IoError::invalid_argument("motion", m, MOTIONS),
                |f| {
                    f.error_at(
                        "motion",
                        format!("`{m}` is not a base motion: expected translate, rotate or path"),
                    )
                },
            )
        })?,
        (None, None) => Kind::Translate,
    };
    // The start pose: a flag (as typed) over the scene's key.
    let pose_value = |v: &Option<Value>,
                      flag: &'static str,
                      key: &'static str,
                      from_scene: Option<f64>|
     -> Result<Option<f64>, IoError> {
        match (v, from_scene) {
            (Some(v), _) => {
                let x = v.number(flag)?;
                if !x.is_finite() {
                    return Err(IoError::invalid_argument(flag, v.raw(), "must be finite"));
                }
                Ok(Some(x))
            }
            (None, Some(x)) if !x.is_finite() => Err(file.map_or_else(
                || IoError::invalid_argument(key, x.to_string(), "must be finite"),
                |f| f.error_at(key, format!("must be finite, got {x}")),
            )),
            (None, x) => Ok(x),
        }
    };
    let x0 = pose_value(&given.x0, "--x0", "x0", scene.and_then(|s| s.x0))?;
    let y0 = pose_value(&given.y0, "--y0", "y0", scene.and_then(|s| s.y0))?;
    let g0 = pose_value(
        &given.gamma_deg,
        "--gamma-deg",
        "gamma_deg",
        scene.and_then(|s| s.gamma_deg),
    )?;
    let rotate = matches!(kind, Kind::Rotate);
    if !rotate {
        // a start pose belongs to a rotation only
        for (v, flag, key, set) in [
            (&given.x0, "--x0", "x0", x0.is_some()),
            (&given.y0, "--y0", "y0", y0.is_some()),
            (&given.gamma_deg, "--gamma-deg", "gamma_deg", g0.is_some()),
        ] {
            if !set {
                continue;
            }
            let why = "the base pose where a rotation starts: give --motion rotate (a \
                       translation starts at y0 = 0, gamma = 0; a path sets its own poses)";
            return Err(match (v, file) {
                (Some(v), _) => IoError::invalid_argument(flag, v.raw(), why),
                (None, Some(f)) => f.error_at(key, why.to_string()),
                (None, None) => IoError::invalid_argument(key, "", why),
            });
        }
    }
    let scene_path = scene.and_then(|s| s.path.as_deref());
    if !matches!(kind, Kind::Path(_)) {
        if let (Some(f), Some(_)) = (file, scene_path) {
            if given.motion.is_none() {
                return Err(f.error_at(
                    "path",
                    "a path of poses needs `motion: \"path\"`".to_string(),
                ));
            }
        }
        if given.path.is_some() {
            return Err(IoError::invalid_argument(
                "path",
                "(columns)",
                "a path of poses needs motion=\"path\"",
            ));
        }
    }
    let l = units.scale(Quantity::Length);
    Ok(match kind {
        Kind::Translate => ResolvedMotion::translate(),
        Kind::Rotate => {
            let (x0, y0, g0) = (x0.unwrap_or(0.0), y0.unwrap_or(0.0), g0.unwrap_or(0.0));
            ResolvedMotion {
                motion: BaseMotion::Rotate {
                    x0: x0 / l,
                    y0: y0 / l,
                    gamma0: g0.to_radians(),
                },
                label: "rotate",
                start: Some((x0, y0, g0)),
                path_file: None,
                path_inline: None,
            }
        }
        Kind::Path(Some(path)) => {
            let text = std::fs::read_to_string(&path).map_err(|e| IoError::io(&path, e))?;
            ResolvedMotion {
                motion: BaseMotion::Path(read_path_table(&text, &path, units)?),
                label: "path",
                start: None,
                path_file: Some(path),
                path_inline: None,
            }
        }
        Kind::Path(None) => {
            if let Some(cols) = &given.path {
                ResolvedMotion {
                    motion: BaseMotion::Path(path_of_columns(cols, units)?),
                    label: "path",
                    start: None,
                    path_file: None,
                    path_inline: None,
                }
            } else if let (Some(f), Some(inline)) = (file, scene_path) {
                let poses = read_path_table(inline, &f.path, units).map_err(|e| match e {
                    IoError::Csv {
                        line,
                        column,
                        reason,
                        ..
                    } => f.error_at(
                        "path",
                        format!(
                            "inline table, line {line}{}: {reason}",
                            column.map_or(String::new(), |c| format!(", column `{c}`"))
                        ),
                    ),
                    other => other,
                })?;
                ResolvedMotion {
                    motion: BaseMotion::Path(poses),
                    label: "path",
                    start: None,
                    path_file: None,
                    path_inline: Some(inline.to_string()),
                }
            } else {
                let why = "a path motion needs its poses: --motion path:FILE.csv (columns \
                           x0,y0,gamma_deg[,k]), the scene's `path`, or Python's path=";
                return Err(match (&given.motion, file) {
                    (Some(v), _) => IoError::invalid_argument("--motion", v.raw(), why),
                    (None, Some(f)) => f.error_at("motion", why.to_string()),
                    (None, None) => IoError::invalid_argument("motion", "path", why),
                });
            }
        }
    })
}

/// `translate`, `rotate`, `path` or `path:FILE` (any case); a scene's file is relative to it,
/// and a scene's `path` key that is not an inline table (no line break) names a file.
fn parse_kind(text: &str, file: Option<&LoadedScene>) -> Option<Kind> {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    let relative = |p: &str| {
        let mut path = PathBuf::from(p.trim());
        if let Some(scene) = file {
            if path.is_relative() {
                if let Some(dir) = scene.path.parent() {
                    path = dir.join(path);
                }
            }
        }
        path
    };
    match lower.as_str() {
        "translate" => Some(Kind::Translate),
        "rotate" => Some(Kind::Rotate),
        "path" => {
            let key = file.and_then(|f| f.file.path.as_deref());
            Some(Kind::Path(key.filter(|p| !p.contains('\n')).map(relative)))
        }
        _ if lower.starts_with("path:") && !t[5..].trim().is_empty() => {
            Some(Kind::Path(Some(relative(&t[5..]))))
        }
        _ => None,
    }
}

/// The factor from a `k` column's unit to the model's dimensionless stiffness [3.19]: none
/// given is the scene's (N m/rad physical), else a moment unit per radian (`N m/rad`,
/// `N mm/rad`) or `1`.
fn stiffness_factor(unit: &str, units: &UnitSystem) -> Result<f64, String> {
    let u = unit.trim();
    let per_rad = u
        .strip_suffix("/rad")
        .or_else(|| u.strip_suffix("/ rad"))
        .unwrap_or(u);
    match (per_rad.trim(), units.is_physical()) {
        ("", true) => units.factor_from("N m", Quantity::Moment),
        ("", false) => Ok(1.0),
        (m, _) => units
            .factor_from(m, Quantity::Moment)
            .map_err(|_| format!("unit `{unit}` is not a stiffness (N m/rad, N mm/rad, 1)")),
    }
}

/// Reads a path table (see the module's notes) from `text`; `path` names the file in errors.
/// Returns the dimensionless poses (gamma in radians) and, where the table has a `k` column,
/// the dimensionless stiffnesses.
///
/// # Errors
/// [`IoError::Csv`] naming the file, the line and the column: a missing column, a cell that
/// is not a finite number, a unit that does not fit, a `k` that is not positive, fewer than
/// two rows.
pub fn read_path_table(text: &str, path: &Path, units: &UnitSystem) -> Result<Poses, IoError> {
    let err = |line: usize, column: Option<&str>, reason: String| IoError::Csv {
        path: path.to_path_buf(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let head = parse_table(text, path, &[], 0)?;
    let find = |sym: &str| {
        head.header
            .iter()
            .find(|h| split_name_unit(h).0.eq_ignore_ascii_case(sym))
            .cloned()
    };
    let mut names = Vec::new();
    for sym in ["x0", "y0", "gamma"] {
        match find(sym) {
            Some(n) => names.push(n),
            None => {
                return Err(err(
                    head.header_line,
                    Some(if sym == "gamma" { "gamma_deg" } else { sym }),
                    format!(
                        "missing column: a path's header names x0, y0, gamma_deg and \
                         optionally k (units allowed: x0_mm, gamma [rad]), found `{}`",
                        head.header.join(",")
                    ),
                ))
            }
        }
    }
    let kname = find("k");
    let mut required: Vec<&str> = names.iter().map(String::as_str).collect();
    if let Some(k) = &kname {
        required.push(k);
    }
    let table = parse_table(text, path, &required, 2)?;
    let col = |n: &str| table.column(n).map(<[f64]>::to_vec);
    let (Some(xs), Some(ys), Some(gs)) = (col(&names[0]), col(&names[1]), col(&names[2])) else {
        return Err(err(
            table.header_line,
            None,
            "the x0, y0 and gamma columns must hold numbers".to_string(),
        ));
    };
    let length = |name: &str| {
        let unit = split_name_unit(name).1;
        if unit.is_empty() {
            Ok(1.0 / units.scale(Quantity::Length))
        } else {
            units
                .factor_from(&unit, Quantity::Length)
                .map_err(|r| err(table.header_line, Some(name), r))
        }
    };
    let (fx, fy) = (length(&names[0])?, length(&names[1])?);
    let gunit = split_name_unit(&names[2]).1;
    if gunit.is_empty() {
        return Err(err(
            table.header_line,
            Some(&names[2]),
            "the turn's column needs its unit: gamma_deg (degrees) or gamma_rad".to_string(),
        ));
    }
    let fg = units
        .factor_from(&gunit, Quantity::Angle)
        .map_err(|r| err(table.header_line, Some(&names[2]), r))?;
    let k = match &kname {
        None => None,
        Some(name) => {
            let f = stiffness_factor(&split_name_unit(name).1, units)
                .map_err(|r| err(table.header_line, Some(name), r))?;
            let ks = col(name).ok_or_else(|| {
                err(
                    table.header_line,
                    Some(name),
                    "the k column must hold numbers".to_string(),
                )
            })?;
            for (i, v) in ks.iter().enumerate() {
                if *v <= 0.0 {
                    return Err(err(
                        table.lines[i],
                        Some(name),
                        format!("the follicle stiffness must be > 0, got {v}"),
                    ));
                }
            }
            Some(ks.iter().map(|v| v * f).collect::<Vec<f64>>())
        }
    };
    let poses = (0..xs.len())
        .map(|i| Pose {
            x0: xs[i] * fx,
            y0: ys[i] * fy,
            gamma: gs[i] * fg,
        })
        .collect::<Vec<Pose>>();
    // a segment that only tenses the follicle is singular where MA = 0 (contact-sim's
    // `K_ONLY_SEGMENT`): refused here naming the file's line of its second row
    if let (Some(ks), Some(name)) = (&k, &kname) {
        let tensing = (1..poses.len()).find(|&i| poses[i] == poses[i - 1] && ks[i] != ks[i - 1]);
        if let Some(i) = tensing {
            return Err(err(
                table.lines[i],
                Some(name),
                format!(
                    "this row changes only k from the row before, the pose fixed: {}",
                    contact_sim::motion::K_ONLY_SEGMENT
                ),
            ));
        }
    }
    Poses::new(poses, k).map_err(|e| err(table.header_line, None, e.to_string()))
}

/// The path of columns given in code (Python's `path=`), in the scene's units (gamma in
/// degrees, k in the stiffness unit), as the library's dimensionless [`Poses`].
///
/// # Errors
/// [`IoError::InvalidArgument`] naming `path` and the column: columns of unequal length,
/// fewer than two rows, a value that is not finite, a `k` that is not positive.
pub fn path_of_columns(cols: &PathColumns, units: &UnitSystem) -> Result<Poses, IoError> {
    let n = cols.x0.len();
    let bad = |column: &str, value: String, why: String| {
        IoError::invalid_argument("path", format!("{column} = {value}"), why)
    };
    for (name, c) in [("y0", &cols.y0), ("gamma_deg", &cols.gamma_deg)] {
        if c.len() != n {
            return Err(bad(
                name,
                format!("{} values", c.len()),
                format!("every column needs one value per pose: x0 has {n}"),
            ));
        }
    }
    if n < 2 {
        return Err(bad(
            "x0",
            format!("{n} values"),
            "a path needs at least 2 poses".into(),
        ));
    }
    for (name, c) in [
        ("x0", &cols.x0),
        ("y0", &cols.y0),
        ("gamma_deg", &cols.gamma_deg),
    ] {
        if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(bad(
                name,
                format!("{v:?}"),
                format!("row {i} must be finite"),
            ));
        }
    }
    let l = units.scale(Quantity::Length);
    let k = match &cols.k {
        None => None,
        Some(k) => {
            if k.len() != n {
                return Err(bad(
                    "k",
                    format!("{} values", k.len()),
                    format!("every column needs one value per pose: x0 has {n}"),
                ));
            }
            if let Some((i, v)) = k.iter().enumerate().find(|(_, v)| v.is_nan() || **v <= 0.0) {
                return Err(bad(
                    "k",
                    format!("{v:?}"),
                    format!("row {i}: the follicle stiffness must be > 0 (inf: rigid)"),
                ));
            }
            let f = stiffness_factor("", units).unwrap_or(1.0);
            Some(k.iter().map(|v| v * f).collect())
        }
    };
    let poses = (0..n)
        .map(|i| Pose {
            x0: cols.x0[i] / l,
            y0: cols.y0[i] / l,
            gamma: cols.gamma_deg[i].to_radians(),
        })
        .collect();
    Poses::new(poses, k).map_err(|e| IoError::invalid_argument("path", "(columns)", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beta() -> UnitSystem {
        UnitSystem::new(Some(
            beam_model::Preset::from_name("beta").unwrap().whisker(),
        ))
    }

    /// A table in mm and degrees reads as the same dimensionless poses as the table in
    /// whisker lengths and radians (L of the beta whisker), and as its columns given in code.
    #[test]
    fn path_tables_in_any_units_give_the_same_poses() {
        let u = beta();
        let l = u.length_mm().unwrap();
        let rows = [
            (-3.0, 1.5, -10.0, 2e-4),
            (-4.0, 2.0, 5.0, 5e-4),
            (-6.5, 0.0, 30.0, 1e-3),
        ];
        let mut mm = String::from("x0_mm;y0 [mm];gamma_deg;k\n");
        let mut nd = String::from("x0 [cm],y0 [cm],gamma_rad,k [N mm/rad]\n");
        for (x, y, g, k) in rows {
            mm += &format!("{x};{y};{g};{k}\n");
            nd += &format!(
                "{},{},{},{}\n",
                x / 10.0,
                y / 10.0,
                f64::to_radians(g),
                k * 1e3
            );
        }
        let a = read_path_table(&mm, Path::new("p.csv"), &u).unwrap();
        let p = beam_model::Preset::from_name("beta").unwrap().whisker();
        let b = read_path_table(&nd, Path::new("q.csv"), &u).unwrap();
        let c = path_of_columns(
            &PathColumns {
                x0: rows.iter().map(|r| r.0).collect(),
                y0: rows.iter().map(|r| r.1).collect(),
                gamma_deg: rows.iter().map(|r| r.2).collect(),
                k: Some(rows.iter().map(|r| r.3).collect()),
            },
            &u,
        )
        .unwrap();
        for (i, (x, y, g, k)) in rows.iter().enumerate() {
            for poses in [&a, &b, &c] {
                let q = poses.poses[i];
                assert!((q.x0 - x / l).abs() < 1e-14, "{q:?}");
                assert!((q.y0 - y / l).abs() < 1e-14);
                assert!((q.gamma - g.to_radians()).abs() < 1e-15);
                let kk = poses.k.as_ref().unwrap()[i];
                let want = p.dimensionless_stiffness(*k);
                assert!((kk / want - 1.0).abs() < 1e-14, "{kk} {want}");
            }
        }
    }

    /// Bad tables name the file, the line and the column.
    #[test]
    fn bad_path_tables_name_file_line_and_column() {
        let u = UnitSystem::DIMENSIONLESS;
        let e = |t: &str| {
            read_path_table(t, Path::new("p.csv"), &u)
                .unwrap_err()
                .to_string()
        };
        let m = e("x0,y0,gamma_deg\n0,0,0\n0,x,1\n");
        assert!(
            m.contains("p.csv") && m.contains(":3") && m.contains("y0"),
            "{m}"
        );
        let m = e("x0,y0\n0,0\n0,1\n");
        assert!(m.contains("gamma_deg") && m.contains(":1"), "{m}");
        let m = e("x0,y0,gamma\n0,0,0\n0,1,1\n");
        assert!(m.contains("unit") && m.contains("gamma"), "{m}");
        let m = e("x0,y0,gamma_deg,k\n0,0,0,5\n0,1,1,-2\n");
        assert!(
            m.contains(":3") && m.contains("`k`") || m.contains("k"),
            "{m}"
        );
        assert!(m.contains("> 0"), "{m}");
        let m = e("x0,y0,gamma_deg\n0,0,0\n");
        assert!(m.contains("at least 2"), "{m}");
        // a segment that only tenses the follicle (issue 38, item 3): refused naming the
        // line of its second row and the k column; a moving one with k changing is taken
        let m = e("x0,y0,gamma_deg,k\n0,0,0,5\n0,0,10,5\n0,0,10,20\n0,0,20,20\n");
        assert!(
            m.contains("p.csv:4") && m.contains("only k") && m.contains("MA = 0"),
            "{m}"
        );
        let ok = read_path_table(
            "x0,y0,gamma_deg,k\n0,0,0,5\n0,0,10,20\n",
            Path::new("p.csv"),
            &u,
        )
        .unwrap();
        assert_eq!(ok.k, Some(vec![5.0, 20.0]));
        let m = e("x0_mm,y0,gamma_deg\n0,0,0\n1,1,1\n");
        assert!(m.contains("physical"), "{m}");
        // tabs and semicolons with decimal commas
        let p =
            read_path_table("x0\ty0\tgamma_deg\n0\t0\t0\n1\t2\t90\n", Path::new("t"), &u).unwrap();
        assert_eq!(
            p.poses[1],
            Pose {
                x0: 1.0,
                y0: 2.0,
                gamma: f64::to_radians(90.0)
            }
        );
        let p = read_path_table("x0;y0;gamma_deg\n0;0;0\n1,5;2;90\n", Path::new("t"), &u).unwrap();
        assert_eq!(p.poses[1].x0, 1.5);
    }

    /// `--motion` and the start pose: as typed, refusals naming the flag.
    #[test]
    fn motion_flags_resolve_or_name_the_flag() {
        let u = beta();
        let l = u.length_mm().unwrap();
        let given = MotionGiven {
            motion: Some(Value::Text("Rotate".into())),
            x0: Some(Value::Text("-2".into())),
            y0: Some(Value::Number(1.0)),
            gamma_deg: Some(Value::Text("-30".into())),
            path: None,
        };
        let r = sweep_motion(&given, None, &u).unwrap();
        assert_eq!(
            r.motion,
            BaseMotion::Rotate {
                x0: -2.0 / l,
                y0: 1.0 / l,
                gamma0: f64::to_radians(-30.0)
            }
        );
        assert_eq!(r.start, Some((-2.0, 1.0, -30.0)));
        let code = |g: MotionGiven| sweep_motion(&g, None, &u).unwrap_err();
        let e = code(MotionGiven {
            motion: Some(Value::Text("whisk".into())),
            ..Default::default()
        });
        assert!(
            e.to_string()
                .starts_with("invalid value `whisk` for `--motion`"),
            "{e}"
        );
        assert_eq!(e.exit_code(), 2);
        let e = code(MotionGiven {
            y0: Some(Value::Text("1".into())),
            ..Default::default()
        });
        assert!(
            e.to_string().contains("`--y0`") && e.to_string().contains("rotate"),
            "{e}"
        );
        let e = code(MotionGiven {
            motion: Some(Value::Text("rotate".into())),
            gamma_deg: Some(Value::Text("nan".into())),
            ..Default::default()
        });
        assert!(e.to_string().contains("`--gamma-deg`"), "{e}");
        let e = code(MotionGiven {
            motion: Some(Value::Text("path".into())),
            ..Default::default()
        });
        assert!(
            e.to_string().contains("`--motion`") && e.to_string().contains("poses"),
            "{e}"
        );
        let e = code(MotionGiven {
            motion: Some(Value::Text("path:/nonexistent/p.csv".into())),
            ..Default::default()
        });
        assert!(e.to_string().contains("/nonexistent/p.csv"), "{e}");
        assert_eq!(
            sweep_motion(&MotionGiven::default(), None, &u).unwrap(),
            ResolvedMotion::translate()
        );
    }
}
