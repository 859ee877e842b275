//! Property tests of the parsers a user's input meets first (issue #34 item 8): RON scenes,
//! CSV observables logs (the file reader and the stream's line reader), profile strings.
//!
//! Each parser is fed arbitrary text and text near the valid (valid inputs cut, spliced,
//! with hostile literals) and must never panic: it returns a value or one-line error. Where
//! a writer exists the round trip is exact: a scene written by `to_ron` parses back to the
//! same scene bit for bit, a table of any finite numbers written with `format_f64` (any
//! delimiter) parses back bit for bit, a profile string formatted from its numbers parses
//! back to the same numbers. Seeded by proptest (`PROPTEST_CASES`, failures persisted
//! nowhere: the regressions are the explicit cases of `tests/hostile.rs`).

use std::path::Path;

use contact_sim::Profile;
use proptest::prelude::*;
use vibrissa_cli::csvio::{format_f64, parse_f64, parse_table, LineReader};
use vibrissa_cli::resolve::ProfileArg;
use vibrissa_cli::scene_file::{
    LoadKind, LoadSpec, MethodSpec, SceneFile, SweepSpec, Units, WhiskerSpec,
};
use vibrissa_cli::units::UnitSystem;

const REQUIRED: [&str; 5] = ["x0", "Ax", "Ay", "MA", "phi0"];

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// An error is one line (the binary prints it as is).
fn one_line(e: &impl std::fmt::Display) -> Result<(), TestCaseError> {
    let text = e.to_string();
    prop_assert!(!text.contains('\n'), "a message of several lines: {text:?}");
    prop_assert!(!text.is_empty());
    Ok(())
}

/// Text near a valid scene: fragments of RON, numbers and hostile literals.
fn scene_like() -> impl Strategy<Value = String> {
    let token = prop_oneof![
        Just("(".to_string()),
        Just(")".to_string()),
        Just(",".to_string()),
        Just(": ".to_string()),
        Just("whisker: (".to_string()),
        Just("theta".to_string()),
        Just("k: Some(".to_string()),
        Just("loads: (".to_string()),
        Just("units: Physical(".to_string()),
        Just("length_mm".to_string()),
        Just("preset: \"beta\"".to_string()),
        Just("profile: Some(\"".to_string()),
        Just("sweep: Some((points: ".to_string()),
        Just("method: (name: \"".to_string()),
        Just("\"".to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("1e300".to_string()),
        Just("-0.0".to_string()),
        Just("None".to_string()),
        Just("// comment\n".to_string()),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        any::<i64>().prop_map(|v| v.to_string()),
        "[a-z_]{1,8}",
        "\\PC{0,4}",
    ];
    prop::collection::vec(token, 0..40).prop_map(|t| t.concat())
}

fn finite() -> impl Strategy<Value = f64> {
    any::<f64>().prop_filter("finite", |v| v.is_finite())
}

/// A scene whose values pass validation.
fn valid_scene() -> impl Strategy<Value = SceneFile> {
    (
        (
            0.01f64..=1.0,
            -10.0f64..10.0,
            -10.0f64..10.0,
            prop::option::of(0.1f64..1e3),
        ),
        (
            -10.0f64..10.0,
            -360.0f64..360.0,
            any::<bool>(),
            -10.0f64..10.0,
            -89.0f64..89.0,
        ),
        prop::option::of(prop::sample::select(vec![
            "g1",
            "g2",
            "ge",
            "parabola:2,0.4,0.5",
        ])),
        prop::option::of(2usize..500),
        prop::option::of((1.0f64..200.0, 0.01f64..2.0, 0.1f64..10.0)),
    )
        .prop_map(
            |((theta, a, b, k), (f, beta_deg, ap, q, alpha_deg), profile, points, phys)| {
                let mut s = SceneFile::with_whisker(WhiskerSpec { theta, a, b, k });
                s.loads = LoadSpec {
                    f,
                    beta_deg,
                    load: if ap { LoadKind::Ap } else { LoadKind::Dp },
                    q,
                    alpha_deg,
                };
                s.profile = profile.map(str::to_string);
                s.sweep = points.map(|points| SweepSpec { points, tol: None });
                s.method = MethodSpec::default();
                if let Some((l, d, e)) = phys {
                    s.units = Units::Physical {
                        preset: None,
                        length_mm: Some(l),
                        base_diameter_mm: Some(d),
                        youngs_modulus_gpa: Some(e),
                    };
                }
                s
            },
        )
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn scene_parser_never_panics_on_any_text(text in "\\PC{0,200}") {
        if let Err(e) = SceneFile::parse(&text, Path::new("s.ron")) {
            one_line(&e)?;
            prop_assert!(e.to_string().starts_with("s.ron:"), "{e}");
        }
    }

    #[test]
    fn scene_parser_never_panics_near_valid_scenes(text in scene_like()) {
        match SceneFile::parse(&text, Path::new("s.ron")) {
            Err(e) => {
                one_line(&e)?;
                prop_assert!(e.to_string().starts_with("s.ron:"), "{e}");
            }
            // whatever parses writes back and reads back the same
            Ok(scene) => {
                let again = SceneFile::parse(&scene.to_ron().unwrap(), Path::new("t.ron"));
                prop_assert_eq!(again.unwrap(), scene);
            }
        }
    }

    #[test]
    fn scenes_round_trip_bit_for_bit(scene in valid_scene()) {
        let text = scene.to_ron().unwrap();
        let back = SceneFile::parse(&text, Path::new("s.ron"))
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(&back, &scene);
        // the floats themselves, bit for bit (PartialEq would take -0 for 0)
        prop_assert_eq!(back.whisker.a.to_bits(), scene.whisker.a.to_bits());
        prop_assert_eq!(back.loads.q.to_bits(), scene.loads.q.to_bits());
    }

    #[test]
    fn scene_with_one_field_replaced_by_a_hostile_literal_fails_naming_the_file(
        scene in valid_scene(),
        lit in prop::sample::select(vec![
            "NaN", "inf", "-inf", "1e999", "\"x\"", "()", "[1]", "true", "", "-", "0x1p3",
        ]),
        which in 0usize..4,
    ) {
        let text = scene.to_ron().unwrap();
        let field = ["theta: ", "a: ", "q: ", "alpha_deg: "][which];
        let Some(at) = text.find(field) else { return Ok(()) };
        let start = at + field.len();
        let end = start + text[start..].find([',', '\n', ')']).unwrap();
        let mut t = text.clone();
        t.replace_range(start..end, lit);
        match SceneFile::parse(&t, Path::new("bad.ron")) {
            Err(e) => {
                one_line(&e)?;
                prop_assert!(e.to_string().starts_with("bad.ron:"), "{e}");
            }
            Ok(s) => prop_assert!(false, "`{}{lit}` accepted: {s:?}", field.trim()),
        }
    }

    #[test]
    fn csv_parser_never_panics(text in "\\PC{0,300}", min_rows in 0usize..4) {
        if let Err(e) = parse_table(&text, Path::new("log.csv"), &REQUIRED, min_rows) {
            one_line(&e)?;
            prop_assert!(e.to_string().starts_with("log.csv:"), "{e}");
        }
    }

    #[test]
    fn csv_parser_never_panics_near_valid_logs(
        rows in prop::collection::vec(
            prop::collection::vec(
                prop_oneof![
                    finite().prop_map(format_f64),
                    prop::sample::select(vec![
                        "NaN", "inf", "", "abc", "1,5", "\"1\"", "-0", "1e999", " 2 ",
                    ]).prop_map(str::to_string),
                ],
                3..7,
            ),
            0..8,
        ),
        header in prop::sample::subsequence(vec!["x0", "Ax", "Ay", "MA", "phi0", "f", "x0"], 0..7),
        sep in prop::sample::select(vec![",", ";", "\t"]),
    ) {
        let mut text = header.join(sep) + "\n";
        for r in &rows {
            text += &(r.join(sep) + "\n");
        }
        match parse_table(&text, Path::new("log.csv"), &REQUIRED, 2) {
            Err(e) => {
                one_line(&e)?;
                prop_assert!(e.to_string().starts_with("log.csv:"), "{e}");
            }
            Ok(t) => {
                // accepted: every required column is there, finite, one value a row
                for c in REQUIRED {
                    let col = t.column(c).unwrap();
                    prop_assert_eq!(col.len(), t.rows());
                    prop_assert!(col.iter().all(|v| v.is_finite()));
                }
            }
        }
    }

    #[test]
    fn logs_round_trip_bit_for_bit(
        rows in prop::collection::vec(prop::array::uniform5(finite()), 2..10),
        sep in prop::sample::select(vec![",", ";", "\t"]),
    ) {
        let mut text = REQUIRED.join(sep) + "\n";
        for r in &rows {
            text += &(r.map(format_f64).join(sep) + "\n");
        }
        let t = parse_table(&text, Path::new("log.csv"), &REQUIRED, 2)
            .map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert_eq!(t.rows(), rows.len());
        for (j, c) in REQUIRED.iter().enumerate() {
            let col = t.column(c).unwrap();
            for (i, r) in rows.iter().enumerate() {
                prop_assert_eq!(col[i].to_bits(), r[j].to_bits(), "{} row {}", c, i);
            }
        }
        // and the stream's line reader reads every row the same
        let mut lines = text.lines();
        let reader = LineReader::header(lines.next().unwrap(), &REQUIRED).unwrap();
        for (line, r) in lines.zip(&rows) {
            let v = reader.values(line).unwrap();
            for j in 0..5 {
                prop_assert_eq!(v[j].to_bits(), r[j].to_bits());
            }
        }
    }

    #[test]
    fn stream_line_reader_never_panics(header in "\\PC{0,60}", line in "\\PC{0,80}") {
        if let Ok(reader) = LineReader::header(&header, &REQUIRED) {
            let _ = reader.values(&line);
        }
    }

    #[test]
    fn numbers_format_and_parse_back_exactly(v in any::<f64>()) {
        let s = format_f64(v);
        let back = parse_f64(&s, b',').unwrap();
        if v.is_nan() {
            prop_assert!(back.is_nan());
        } else {
            prop_assert_eq!(back.to_bits(), v.to_bits(), "{}", s);
        }
    }

    #[test]
    fn profile_strings_never_panic(spec in "\\PC{0,40}") {
        let arg = ProfileArg { spec: spec.clone(), file: None };
        if let Err(e) = arg.parse(&UnitSystem::DIMENSIONLESS) {
            one_line(&e)?;
        }
        let _ = Profile::parse(&spec);
    }

    #[test]
    fn profile_strings_near_valid_never_panic(
        kind in prop::sample::select(vec!["parabola", "cosh", "circle", "peg", "disc", "g1", "points", ""]),
        args in prop::collection::vec(
            prop_oneof![
                any::<f64>().prop_map(|v| format!("{v:?}")),
                prop::sample::select(vec!["", " ", "nan", "inf", "1e999", "x", "-"]).prop_map(str::to_string),
            ],
            0..6,
        ),
        colon in any::<bool>(),
    ) {
        let spec = if colon { format!("{kind}:{}", args.join(",")) } else { kind.to_string() };
        let arg = ProfileArg { spec: spec.clone(), file: None };
        if let Err(e) = arg.parse(&UnitSystem::DIMENSIONLESS) {
            one_line(&e)?;
            // the flag, or the table a points: profile names
            let file = spec.strip_prefix("points:").map(str::trim);
            let text = e.to_string();
            prop_assert!(
                text.contains("--profile") || file.is_some_and(|f| text.contains(f)),
                "{text}"
            );
        }
    }

    #[test]
    fn profile_strings_round_trip(a in 1e-6f64..1e6, xv in finite(), yv in finite(), r in 1e-6f64..1e6) {
        let p = Profile::parse(&format!("parabola:{a:?},{xv:?},{yv:?}")).unwrap();
        prop_assert_eq!(p, Profile::Parabola { a, xv, yv });
        let p = Profile::parse(&format!("circle: {xv} , {yv} , {r} ")).unwrap();
        prop_assert_eq!(p, Profile::Circle { xc: xv, yc: yv, r });
        let p = Profile::parse(&format!("cosh:{a},{r},{xv},{yv}")).unwrap();
        prop_assert_eq!(p, Profile::Cosh { a, c: r, xv, d: yv });
    }
}
