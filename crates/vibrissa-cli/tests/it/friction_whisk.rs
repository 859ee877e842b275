//! `vibrissa sweep --motion rotate --mu` against a peg (issues 38/39 at their seam,
//! docs/friction-whisk.md): the frictional whisking sweep through the CLI, its log's `ft` and
//! `slip` columns, its shapes and figures. `cargo test -p vibrissa-cli --test it --
//! friction_whisk::`

use crate::common;

use std::collections::BTreeMap;
use std::fs;

use common::{col, json, num, run, stderr, stdout, table};

/// Whisking the default whisker (straight, uniform, rigid, no flow) past `peg:-0.2,0.6` at
/// `mu = 0.5`: exit 0; the JSON names the motion and `mu`; every contact row of the log has
/// its force on the cone's edge, `|ft| = mu f` (a straight whisker pinned at the peg cannot
/// stick: the chord of `[0, s1]` is `s1` itself, so any bending slides the material point,
/// `s1` rising), the contact point on the peg, `gamma` rising with the base fixed at the
/// origin, no switch; every contact row's shape in `shapes.csv` (integrated by the CLI from
/// the row's frictional force `fn n + ft t` and tip angle) has its base at the origin and its
/// point `s1` on the peg; the figures are drawn against the turn; the summary line counts the
/// rows. A pre-curved whisker under a flow at `mu = 1.5` sticks at the touch (inside the
/// cone) and switches to slip at once, `s1` unchanged over the switch, the JSON's switch row
/// that row.
#[test]
fn a_frictional_whisk_past_a_peg_through_the_cli() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(
        &[
            "sweep",
            "--motion",
            "rotate",
            "--profile",
            "peg:-0.2,0.6",
            "--mu",
            "0.5",
            "--figures",
            "svg",
            "--points",
            "20",
            "--shapes",
            "--json",
            "--out",
            "w",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v = json(&o);
    assert_eq!(v["motion"], "rotate");
    assert_eq!(v["mu"].as_f64(), Some(0.5));
    assert_eq!(v["phases"], "B");
    let events = v["friction_events"].as_array().unwrap();
    let (h, rows) = table(&dir.path().join("w/observables.csv"));
    let c = |n: &str| col(&h, n);
    let (f, ft, slip, phase, xc, yc, s1, gamma, x0, y0) = (
        c("f"),
        c("ft"),
        c("slip"),
        c("phase"),
        c("xc"),
        c("yc"),
        c("s1"),
        c("gamma"),
        c("x0"),
        c("y0"),
    );
    let (mut stick, mut sliding, mut last) = (0, 0, f64::NEG_INFINITY);
    let mut contact = BTreeMap::new();
    let mut first_s1: Option<f64> = None;
    for (i, r) in rows.iter().enumerate() {
        let g = num(&r[gamma]);
        assert!(g > last, "row {}: gamma {g} after {last}", i + 1);
        last = g;
        assert_eq!((num(&r[x0]), num(&r[y0])), (0.0, 0.0));
        if r[phase] == "none" {
            assert_eq!((r[ft].as_str(), r[slip].as_str()), ("0.0", "none"));
            continue;
        }
        let (fnorm, ftan) = (num(&r[f]), num(&r[ft]));
        assert!(fnorm >= -1e-12, "row {}: f {fnorm}", i + 1);
        assert!(
            ftan.abs() <= 0.5 * fnorm * (1.0 + 1e-12) + 1e-12,
            "row {}",
            i + 1
        );
        assert_eq!((num(&r[xc]), num(&r[yc])), (-0.2, 0.6), "row {}", i + 1);
        match r[slip].as_str() {
            "stick" => {
                stick += 1;
                // stuck from the touch: the material point s1 stays put
                let s = *first_s1.get_or_insert(num(&r[s1]));
                assert!((num(&r[s1]) - s).abs() < 1e-9, "row {}", i + 1);
            }
            "slip" => {
                sliding += 1;
                assert!((ftan.abs() - 0.5 * fnorm).abs() <= 1e-9 * fnorm.max(1.0));
            }
            s => panic!("row {}: slip {s}", i + 1),
        }
        contact.insert(i + 1, num(&r[s1]));
    }
    assert!(stick == 0 && sliding == 20, "stick {stick}, slip {sliding}");
    assert!(events.is_empty(), "{v}");
    let s1s: Vec<f64> = contact.values().copied().collect();
    assert!(s1s.windows(2).all(|w| w[1] > w[0]), "s1 must rise: {s1s:?}");
    // the shapes: base at the origin, the point s1 on the peg
    let (sh, shapes) = table(&dir.path().join("w/shapes.csv"));
    let (row, s, x, y) = (col(&sh, "row"), col(&sh, "s"), col(&sh, "x"), col(&sh, "y"));
    let mut worst = 0.0f64;
    for (&i, &s1) in &contact {
        let pts: Vec<_> = shapes
            .iter()
            .filter(|r| num(&r[row]) as usize == i)
            .map(|r| (num(&r[s]), num(&r[x]), num(&r[y])))
            .collect();
        let base = pts.iter().find(|p| p.0 == 0.0).unwrap();
        let at = pts
            .iter()
            .min_by(|a, b| (a.0 - s1).abs().total_cmp(&(b.0 - s1).abs()))
            .unwrap();
        assert!((at.0 - s1).abs() < 1e-12, "row {i}: no sample at s1");
        worst = worst
            .max(base.1.hypot(base.2))
            .max((at.1 + 0.2).hypot(at.2 - 0.6));
    }
    assert!(worst < 1e-7, "{worst:e}");
    // the summary line (without --json)
    let printed = stdout(&run(
        &[
            "sweep",
            "--motion",
            "rotate",
            "--profile",
            "peg:-0.2,0.6",
            "--mu",
            "0.5",
            "--points",
            "20",
            "--figures",
            "none",
            "--out",
            "w3",
        ],
        dir.path(),
    ));
    assert!(
        printed.contains(&format!(
            "friction mu = 0.5: rows stick {stick}, slip {sliding}; switches stick→slip 0, slip→stick 0"
        )),
        "{printed}"
    );
    let svg =
        |n: &str| common::svg_text(&fs::read_to_string(dir.path().join("w").join(n)).unwrap());
    assert!(svg("observables.svg").contains("base turn γ [°]"));
    let shapes_svg = svg("shapes.svg");
    assert!(
        shapes_svg.contains("base (fixed, turning)") && shapes_svg.contains("peg"),
        "{shapes_svg}"
    );
    // pre-curved, under a flow, mu = 1.5: stuck at the touch, then the switch
    let o = run(
        &[
            "sweep",
            "--motion",
            "rotate",
            "--profile",
            "peg:-0.2,0.6",
            "--mu",
            "1.5",
            "--theta",
            "0.5",
            "--a",
            "0.2",
            "--b",
            "0.1",
            "--k",
            "20",
            "--q",
            "0.5",
            "--points",
            "20",
            "--figures",
            "none",
            "--json",
            "--out",
            "w2",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v = json(&o);
    let events = v["friction_events"].as_array().unwrap();
    assert_eq!(events.len(), 1, "{v}");
    assert_eq!(events[0]["event"], "stick→slip");
    let (h, rows) = table(&dir.path().join("w2/observables.csv"));
    let (slip, s1, f, ft) = (col(&h, "slip"), col(&h, "s1"), col(&h, "f"), col(&h, "ft"));
    let first = rows.iter().position(|r| r[slip] != "none").unwrap();
    let at = events[0]["row"].as_u64().unwrap() as usize - 1;
    assert_eq!(rows[first][slip], "stick");
    assert_eq!((at, rows[at][slip].as_str()), (first + 1, "slip"));
    assert_eq!(
        num(&rows[at][s1]),
        num(&rows[first][s1]),
        "the material point moved"
    );
    assert!((num(&rows[at][ft]) - 1.5 * num(&rows[at][f])).abs() < 1e-9);
}
